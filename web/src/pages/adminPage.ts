// The study's admin page (#/admin, opened with the admin link `workcell serve --study`
// prints): every participant live — where they are, their condition, progress, link
// latency, the session's real-time factor and their outcomes — with their invite link and
// a button that stops their running session (confirmed, with a reason shown to the
// participant), a link that watches their session live (a spectator of their seat) and one
// to their recorded sessions. A line warns in words when sessions fall behind real time.

import type { App } from "../app";
import type { ParticipantRow, StudyOverview } from "../protocol";
import { askToStop } from "../hud/stopDialog";
import { fetchStudy, stopParticipant } from "../net/api";
import { el } from "../util/dom";
import { authToken } from "../util/env";
import { NO_FILTER, hashOf } from "./sessionFilter";

const REFRESH_MS = 1000;

function num(value: number | null, digits: number): string {
  return value === null ? "—" : value.toFixed(digits);
}

function inviteUrl(row: ParticipantRow): string {
  const url = new URL(row.invite, window.location.href);
  url.hash = "";
  return url.toString();
}

function participantRow(row: ParticipantRow, onStop: (participant: string) => void): HTMLTableRowElement {
  const tr = el("tr", { className: `participant state-${row.state}` });
  tr.dataset["participant"] = row.participant;
  const cells = [
    row.participant,
    row.state,
    `${row.done}/${row.total}`,
    row.condition ?? "—",
    num(row.rtt_ms, 0),
    num(row.real_time_factor, 2),
    `${row.successes}/${row.trials}`,
  ];
  for (const text of cells) tr.append(el("td", { textContent: text }));
  const invite = el("td");
  const link = el("a", { href: inviteUrl(row), textContent: "invite", className: "invite-link" });
  const copy = el("button", { type: "button", className: "small", textContent: "Copy" });
  copy.addEventListener("click", () => {
    void navigator.clipboard?.writeText(inviteUrl(row)).catch(() => undefined);
  });
  invite.append(link, " ", copy);
  const action = el("td");
  if (row.state === "running") {
    const stop = el("button", { type: "button", className: "small stop-session", textContent: "Stop" });
    stop.addEventListener("click", () => onStop(row.participant));
    action.append(stop);
  }
  tr.append(invite, researcherLinks(row), action);
  return tr;
}

/** The page that watches a participant's seat live, read-only (a spectator of it), in a
 * tab of its own: the admin's token goes along, since a new tab keeps no session storage. */
export function spectateUrl(participant: string, pageHref: string, token: string | null): string {
  const url = new URL(pageHref);
  url.search = "";
  if (token !== null) url.searchParams.set("token", token);
  url.searchParams.set("role", "spectator");
  url.searchParams.set("seat", participant);
  url.hash = "#/teleop";
  return url.toString();
}

/** Watch the participant's running session; open their recorded sessions. */
function researcherLinks(row: ParticipantRow): HTMLTableCellElement {
  const cell = el("td", { className: "researcher-links" });
  if (row.state === "running") {
    const watch = el("a", {
      href: spectateUrl(row.participant, window.location.href, authToken()),
      target: "_blank",
      className: "button small spectate-link",
      textContent: "Watch",
    });
    watch.title = `watch ${row.participant}'s session live, read-only`;
    cell.append(watch, " ");
  }
  cell.append(
    el("a", {
      href: hashOf({ ...NO_FILTER, participant: row.participant }),
      className: "button small sessions-link",
      textContent: "Sessions",
    }),
  );
  return cell;
}

export function mountAdmin(root: HTMLElement, _app: App): () => void {
  const page = el("section", { className: "page admin-page" });
  const heading = el("h1", { textContent: "Study" });
  const summary = el("p", { className: "admin-summary", textContent: "Loading…" });
  const notice = el("p", { className: "admin-notice", role: "status" });
  const warning = el("p", { className: "admin-warning", id: "admin-warning", role: "alert" });
  const table = el("table", { className: "participants" });
  const head = el("tr");
  const titles = ["participant", "state", "sessions", "condition", "RTT ms", "real time", "successes", "invite", "views", ""];
  for (const title of titles) head.append(el("th", { textContent: title }));
  const body = el("tbody");
  table.append(el("thead", {}, head), body);
  page.append(heading, summary, warning, notice, table);
  root.append(page);
  let disposed = false;
  let timer: number | null = null;

  const stop = (participant: string): void => {
    const question = {
      title: `Stop ${participant}'s session?`,
      explain: `${participant}'s trial under way ends, marked interrupted; their next start goes on from that trial. Your reason is shown to them.`,
      confirm: "Stop their session",
    };
    void askToStop(page, question).then((reason) => {
      if (reason === null) return;
      void stopParticipant(participant, reason).then((text) => {
        notice.textContent = text;
        load();
      });
    });
  };

  const show = (overview: StudyOverview): void => {
    heading.textContent = `Study ${overview.study}`;
    const finished = overview.participants.filter((p) => p.state === "finished").length;
    summary.textContent =
      `sessions running: ${overview.running} (at most ${overview.max_sessions} at once) · ` +
      `${finished} of ${overview.participants.length} participants finished`;
    const waiting = overview.waiting > 0 ? `${overview.waiting} start(s) wait for room on the machine. ` : "";
    warning.textContent = `${overview.behind}${overview.behind !== "" && waiting !== "" ? " · " : ""}${waiting}`.trim();
    body.replaceChildren(...overview.participants.map((row) => participantRow(row, stop)));
  };

  const load = (): void => {
    fetchStudy()
      .then((overview) => {
        if (!disposed) show(overview);
      })
      .catch((error: unknown) => {
        summary.textContent = `Could not load the study: ${String(error)}`;
      })
      .finally(() => {
        if (!disposed) {
          if (timer !== null) window.clearTimeout(timer);
          timer = window.setTimeout(load, REFRESH_MS);
        }
      });
  };
  load();
  return () => {
    disposed = true;
    if (timer !== null) window.clearTimeout(timer);
    page.remove();
  };
}
