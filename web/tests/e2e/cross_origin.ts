// A page of another local origin tries to drive the robot: it opens the server's WebSocket,
// says hello as operator and starts a session, and reads the JSON API. The pages are
// served here, on a second port, under two origins: http://localhost:PORT (not allowed:
// refused) and http://127.0.0.1:PORT (which the pytest wrapper passes to `workcell serve
// --allow-origin`: accepted, it only says hello as a spectator). Prints "RESULT {json}".
//
//   npm run build:e2e && node build/e2e/tests/e2e/cross_origin.js http://127.0.0.1:8000 18009   (in web/)

import { createServer } from "node:http";
import { check, log, runScript, sleep } from "./lib.js";

/** What the attacking page managed to do. */
interface Attack {
  opened: boolean;
  messages: string[];
  close_code: number | null;
  errors: number;
  api: string | null;
}

declare global {
  interface Window {
    __attack?: Attack;
  }
}

const ATTACK_MS = 4000;

/** The attacking page: everything it manages to do goes into window.__attack. */
function attackPage(target: string, role: "operator" | "spectator"): string {
  const ws = target.replace(/^http/, "ws") + "/ws";
  return `<!doctype html><html><body><script>
    const attack = { opened: false, messages: [], close_code: null, errors: 0, api: null };
    window.__attack = attack;
    const socket = new WebSocket(${JSON.stringify(ws)}, ["workcell.v1"]);
    socket.onopen = () => {
      attack.opened = true;
      socket.send(JSON.stringify({ type: "hello", role: ${JSON.stringify(role)}, resume_token: null }));
      if (${JSON.stringify(role)} === "operator") {
        socket.send(JSON.stringify({ type: "start_session", settings: { task: { countdown_s: 0 } } }));
      }
    };
    socket.onmessage = (event) => attack.messages.push(JSON.parse(event.data).type);
    socket.onerror = () => { attack.errors += 1; };
    socket.onclose = (event) => { attack.close_code = event.code; };
    fetch(${JSON.stringify(target + "/api/sessions")})
      .then((reply) => reply.text()).then((text) => { attack.api = "read " + text.length + " bytes"; })
      .catch((error) => { attack.api = "refused: " + error.name; });
  </script></body></html>`;
}

await runScript("cross_origin", async ({ url, page }) => {
  const port = Number(process.argv[3]);
  check(port > 0, "usage: cross_origin.js <server url> <port for the other origin>");
  const pages = createServer((request, reply) => {
    const role = (request.url ?? "").startsWith("/spectator") ? "spectator" : "operator";
    reply.writeHead(200, { "content-type": "text/html" });
    reply.end(attackPage(url, role));
  });
  await new Promise<void>((resolve) => pages.listen(port, "127.0.0.1", resolve));
  try {
    const visit = async (name: string, address: string): Promise<Attack> => {
      await page.goto(address);
      await sleep(ATTACK_MS);
      const attack = await page.evaluate(() => window.__attack ?? null);
      log(`${name} origin ${address}: ${JSON.stringify(attack)}`);
      check(attack !== null, `the ${name} page did not run`);
      return attack;
    };
    const visits = {
      foreign: await visit("foreign", `http://localhost:${port}/operator`),
      allowed: await visit("allowed", `http://127.0.0.1:${port}/spectator`),
    };
    console.log(`RESULT ${JSON.stringify(visits)}`);
    check(!visits.foreign.opened && visits.foreign.messages.length === 0, "a foreign page opened the socket");
    check(visits.allowed.opened && visits.allowed.messages.includes("welcome"), "the allowed origin was refused");
  } finally {
    pages.close();
  }
});
