// A page of another local origin tries to drive the robot: it opens the server's WebSocket,
// says hello as operator and starts a session, and reads the JSON API. The pages are
// served here, on a second port, under two origins: http://localhost:PORT (not allowed:
// refused) and http://127.0.0.1:PORT (which the pytest wrapper passes to `workcell serve
// --allow-origin`: accepted, it only says hello as a spectator). Prints "RESULT {json}".
//
//   node web/tests/e2e/cross_origin.mjs http://127.0.0.1:8000 18009

import { createServer } from "node:http";
import { check, log, runScript, sleep } from "./lib.mjs";

const ATTACK_MS = 4000;

/** The attacking page: everything it manages to do goes into window.__attack. */
function attackPage(target, role) {
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
  check(port > 0, "usage: cross_origin.mjs <server url> <port for the other origin>");
  const pages = createServer((request, reply) => {
    const role = request.url.startsWith("/spectator") ? "spectator" : "operator";
    reply.writeHead(200, { "content-type": "text/html" });
    reply.end(attackPage(url, role));
  });
  await new Promise((resolve) => pages.listen(port, "127.0.0.1", resolve));
  try {
    const visits = {};
    for (const [name, address] of [
      ["foreign", `http://localhost:${port}/operator`],
      ["allowed", `http://127.0.0.1:${port}/spectator`],
    ]) {
      await page.goto(address);
      await sleep(ATTACK_MS);
      visits[name] = await page.evaluate(() => window.__attack);
      log(`${name} origin ${address}: ${JSON.stringify(visits[name])}`);
    }
    console.log(`RESULT ${JSON.stringify(visits)}`);
    check(!visits.foreign.opened && visits.foreign.messages.length === 0, "a foreign page opened the socket");
    check(visits.allowed.opened && visits.allowed.messages.includes("welcome"), "the allowed origin was refused");
  } finally {
    pages.close();
  }
});
