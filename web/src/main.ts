// Entry point: one connection, one 3D viewer for live teleoperation, and a hash router
// over the pages (#/ setup, #/teleop, #/sessions, #/replay/<trial id>, #/admin). A study
// participant's invite shows their study's start page at #/ and no recorded sessions.

import "./style.css";
import { App } from "./app";
import { exposeDebug } from "./debug";
import { InputSequencer } from "./input/hands";
import { fetchParticipant } from "./net/api";
import { mountAdmin } from "./pages/adminPage";
import { mountReplay } from "./pages/replayPage";
import { mountSessions } from "./pages/sessionsPage";
import { mountSetup } from "./pages/setupPage";
import { mountStudyStart } from "./pages/studyStart";
import { mountTeleop } from "./pages/teleopPage";
import type { TeleopShared } from "./pages/teleopPage";
import { Viewer } from "./scene/viewer";
import { emulatedDevice } from "./util/env";
import { installEmulatedDevice } from "./xr/emulate";
import { XrController } from "./xr/xrSession";
import { el } from "./util/dom";

async function boot(): Promise<void> {
  const emulate = emulatedDevice();
  if (emulate !== null) await installEmulatedDevice(emulate);

  const app = new App();
  exposeDebug(app);
  const main = document.getElementById("app");
  if (main === null) throw new Error("index.html has no #app element");
  const nav = el("nav", { className: "topnav" });
  const participant = await fetchParticipant().catch(() => null);
  const links: [string, string][] =
    participant === null
      ? [
          ["#/", "Setup"],
          ["#/teleop", "Teleoperate"],
          ["#/sessions", "Sessions"],
        ]
      : [
          ["#/", "Study"],
          ["#/teleop", "Teleoperate"],
        ];
  nav.append(el("span", { className: "brand", textContent: "Workcell" }));
  for (const [href, label] of links) nav.append(el("a", { href, textContent: label }));
  const linkState = el("span", { className: "nav-link-state" });
  nav.append(linkState);
  const outlet = el("main", { className: "outlet" });
  // A start waiting for room on the server says so on every page, with its place in line.
  const queueBanner = el("div", { className: "queue-banner", id: "queue-banner", role: "status" });
  main.append(nav, queueBanner, outlet);
  app.subscribe((event) => {
    if (event.kind === "queued" || event.kind === "session" || event.kind === "server_error") {
      queueBanner.textContent = app.queued !== null && !app.sessionActive ? app.queued.message : "";
    }
  });

  let shared: TeleopShared | null = null;
  const teleopShared = (): TeleopShared => {
    if (shared === null) {
      const viewer = new Viewer();
      shared = { viewer, xr: new XrController(viewer), sequencer: new InputSequencer() };
    }
    return shared;
  };

  let unmount: (() => void) | null = null;
  const route = (): void => {
    unmount?.();
    unmount = null;
    const full = window.location.hash.replace(/^#/, "") || "/";
    const hash = full.split("?")[0] ?? full; // `#/sessions?participant=p01`: the page's filter
    for (const a of nav.querySelectorAll("a")) {
      a.classList.toggle("active", a.getAttribute("href") === `#${hash}`);
    }
    document.body.dataset["page"] = hash.split("/")[1] || "setup";
    if (hash.startsWith("/replay/") && participant === null) {
      unmount = mountReplay(outlet, decodeURIComponent(hash.slice("/replay/".length)));
    } else if (hash === "/teleop") {
      unmount = mountTeleop(outlet, app, teleopShared());
    } else if (hash === "/sessions" && participant === null) {
      unmount = mountSessions(outlet, app);
    } else if (hash === "/admin" && participant === null) {
      unmount = mountAdmin(outlet, app);
    } else if (participant !== null) {
      unmount = mountStudyStart(outlet, app);
    } else {
      unmount = mountSetup(outlet, app);
    }
  };
  window.addEventListener("hashchange", route);

  app.subscribe((event) => {
    if (event.kind !== "link") return;
    const info = app.connection.info;
    linkState.textContent = info.status === "open" ? "connected" : info.status;
    linkState.className = `nav-link-state ${info.status}`;
    linkState.title = info.reason ?? "";
  });
  app.subscribe((event) => {
    // A page opened while a session runs (or reloaded mid-trial) goes to the live view.
    if (event.kind === "session" && app.sessionActive && document.body.dataset["page"] === "setup" && app.session === null) {
      window.location.hash = "#/teleop";
    }
  });
  route();
  app.start();
}

void boot();
