import { defineConfig } from "vite";

// The Python server serves web/dist statically; the dev server proxies its API and socket.
declare const process: { env: Record<string, string | undefined> };
const server = process.env.WORKCELL_SERVER ?? "http://127.0.0.1:8000";

export default defineConfig({
  base: "./",
  build: {
    outDir: "dist",
    emptyOutDir: true,
    target: "es2022",
    chunkSizeWarningLimit: 1500,
  },
  server: {
    proxy: {
      "/api": server,
      "/ws": { target: server.replace(/^http/, "ws"), ws: true },
    },
  },
});
