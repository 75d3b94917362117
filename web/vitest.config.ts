import { defineConfig } from "vitest/config";

// The client's unit tests (tests/unit): plain node, no browser; the browser end-to-end
// scripts (tests/e2e) run from pytest against a real server instead.
export default defineConfig({
  test: {
    root: ".",
    include: ["tests/unit/**/*.test.ts"],
    environment: "node",
  },
});
