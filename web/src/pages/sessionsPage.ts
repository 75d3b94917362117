// The sessions page: every recorded session and its trials (who ran them, in which
// condition and study step, outcome, flags, score, inclusion), with a replay link per
// trial; filters by participant, condition, study step and outcome or inclusion (kept in
// the address: `#/sessions?participant=p01`); and downloads of what is shown (and a
// LeRobot dataset of the participant chosen).

import type { App } from "../app";
import type { SessionSummary, TrialSummary } from "../protocol";
import { fetchSessions } from "../net/api";
import { el } from "../util/dom";
import { serverUrl } from "../util/env";
import {
  NO_FILTER,
  TRIAL_KINDS,
  TRIAL_KIND_LABELS,
  applyFilter,
  filterChoices,
  filterFromHash,
  hashOf,
  trialsCsv,
} from "./sessionFilter";
import type { SessionFilter, TrialKind } from "./sessionFilter";

/** Most sessions the audit download names in its address (beyond: the page says so). */
const MOST_NAMED_SESSIONS = 300;

function when(unixSeconds: number | null): string {
  if (unixSeconds === null) return "—";
  return new Date(unixSeconds * 1000).toLocaleString();
}

function num(value: number | null, digits = 0): string {
  return value === null ? "—" : value.toFixed(digits);
}

function trialRow(session: SessionSummary, trial: TrialSummary): HTMLTableRowElement {
  const row = el("tr", { className: `trial outcome-${trial.outcome ?? "running"}` });
  row.dataset["trialId"] = trial.trial_id;
  const level = trial.level !== null ? `R${trial.round ?? "-"} L${trial.level}` : "—";
  const outcome = trial.outcome ?? "running";
  const reason = trial.interruption_reason !== null ? ` (${trial.interruption_reason})` : "";
  const flags = trial.quality_flags.length > 0 ? trial.quality_flags.join(", ") : "—";
  const included = trial.included === null ? "—" : trial.included ? "yes" : `no: ${trial.exclusion_reason ?? "not included"}`;
  const cells: [string, string][] = [
    ["participant", session.operator_id],
    ["condition", session.condition ?? "—"],
    ["step", session.study_step === null ? "—" : String(session.study_step)],
    ["index", String(trial.trial_index + 1)],
    ["mode", trial.mode],
    ["level", level],
    ["outcome", outcome + reason],
    ["boxes", `${num(trial.boxes_delivered)}/${trial.required_boxes}`],
    ["time", num(trial.elapsed_s, 1)],
    ["score", num(trial.score)],
    ["frames", num(trial.n_frames)],
    ["flags", flags],
    ["included", included],
  ];
  for (const [name, text] of cells) row.append(el("td", { className: `col-${name}`, textContent: text }));
  const action = el("td");
  if (trial.n_frames !== null && trial.n_frames > 0) {
    action.append(
      el("a", {
        href: `#/replay/${encodeURIComponent(trial.trial_id)}`,
        className: "button small replay-link",
        textContent: "Replay",
      }),
    );
  }
  row.append(action);
  return row;
}

function sessionBlock(session: SessionSummary): HTMLElement {
  const block = el("details", { className: "session", open: true });
  block.dataset["sessionId"] = session.session_id;
  const successes = session.trials.filter((t) => t.outcome === "success").length;
  const score = session.trials.reduce((sum, t) => sum + (t.score ?? 0), 0);
  const condition = session.condition !== null ? ` · condition ${session.condition}` : "";
  const step = session.study_step !== null ? ` · study step ${session.study_step}` : "";
  block.dataset["operatorId"] = session.operator_id;
  block.dataset["condition"] = session.condition ?? "";
  block.append(
    el(
      "summary",
      {},
      el("strong", { textContent: session.mode }),
      ` · ${session.operator_id}${condition}${step} · ${when(session.created_wall)} · ${session.status} · `,
      `${successes}/${session.trials.length} successful · score ${score} · `,
      el("code", { textContent: session.session_id }),
    ),
  );
  const table = el("table", { className: "trials" });
  const head = el("tr");
  const titles = ["participant", "condition", "step", "#", "mode", "level", "outcome", "boxes", "time s", "score", "frames", "flags", "included", ""];
  for (const title of titles) head.append(el("th", { textContent: title }));
  table.append(el("thead", {}, head));
  const body = el("tbody");
  for (const trial of session.trials) body.append(trialRow(session, trial));
  table.append(body);
  block.append(table);
  return block;
}

function choiceMenu(name: string, label: string, anyText: string): HTMLSelectElement {
  const select = el("select", { name, className: `filter-${name}` });
  select.setAttribute("aria-label", label);
  select.append(el("option", { value: "", textContent: anyText }));
  return select;
}

function fillMenu(select: HTMLSelectElement, values: readonly string[], chosen: string, label: (v: string) => string = (v) => v): void {
  const any = select.options[0];
  select.replaceChildren(...(any !== undefined ? [any] : []));
  const offered = chosen !== "" && !values.includes(chosen) ? [...values, chosen] : values;
  for (const value of offered) select.append(el("option", { value, textContent: label(value) }));
  select.value = chosen;
}

function download(name: string, text: string): void {
  const url = URL.createObjectURL(new Blob([text], { type: "text/csv" }));
  const link = el("a", { href: url, download: name });
  document.body.append(link);
  link.click();
  link.remove();
  window.setTimeout(() => URL.revokeObjectURL(url), 1000);
}

export function mountSessions(root: HTMLElement, _app: App): () => void {
  const page = el("section", { className: "page sessions-page" });
  const refresh = el("button", { textContent: "Refresh" });
  const participant = choiceMenu("participant", "participant", "every participant");
  const condition = choiceMenu("condition", "condition", "every condition");
  const step = choiceMenu("step", "study step", "every study step");
  const trials = choiceMenu("trials", "outcome or inclusion", TRIAL_KIND_LABELS[""]);
  fillMenu(trials, TRIAL_KINDS.filter((k) => k !== ""), "", (k) => TRIAL_KIND_LABELS[k as TrialKind]);
  const clear = el("button", { type: "button", className: "small filter-clear", textContent: "Clear filters" });
  const filters = el("div", { className: "session-filters" }, participant, condition, step, trials, clear);
  const shownCsv = el("button", { type: "button", className: "download-shown", textContent: "Shown trials (CSV)" });
  shownCsv.title = "the trials listed below, with their participant, condition and study step";
  const auditCsv = el("a", { className: "button download-audit", textContent: "Audit's trials.csv" });
  const auditTitle = "the audit's trials.csv (workcell audit) of the sessions listed below: every flag and disposition";
  const storeZip = el("a", { className: "button download-store", textContent: "Whole store (CSV export, zip)" });
  storeZip.title = "workcell export --format csv of every session, with its manifest (workcell verify --csv)";
  storeZip.href = serverUrl("api/export/csv.zip");
  const lerobotZip = el("a", { className: "button download-lerobot", textContent: "LeRobot dataset (zip)" });
  const downloads = el("div", { className: "session-downloads" }, "Download: ", shownCsv, auditCsv, storeZip, lerobotZip);
  const count = el("p", { className: "session-count" });
  const list = el("div", { className: "session-list", textContent: "Loading…" });
  page.append(el("h1", { textContent: "Sessions" }), el("div", { className: "session-tools" }, refresh, filters), downloads, count, list);
  root.append(page);
  let disposed = false;
  let all: SessionSummary[] = [];
  let shown: SessionSummary[] = [];
  let filter: SessionFilter = filterFromHash(window.location.hash);

  const show = (): void => {
    const choices = filterChoices(all);
    fillMenu(participant, choices.participants, filter.participant);
    fillMenu(condition, choices.conditions, filter.condition);
    fillMenu(step, choices.steps, filter.step);
    trials.value = filter.trials;
    shown = applyFilter(all, filter);
    const trialCount = shown.reduce((n, s) => n + s.trials.length, 0);
    count.textContent = `showing ${shown.length} of ${all.length} sessions, ${trialCount} trials`;
    const everything = shown.length === all.length && filter.trials === "";
    const named = everything ? "" : shown.map((s) => `session=${encodeURIComponent(s.session_id)}`).join("&");
    const url = new URL(serverUrl("api/export/trials.csv"));
    url.search = [url.search.replace(/^\?/, ""), named].filter((part) => part !== "").join("&");
    const tooMany = shown.length > MOST_NAMED_SESSIONS && !everything;
    auditCsv.href = url.toString();
    auditCsv.classList.toggle("disabled", shown.length === 0 || tooMany);
    auditCsv.title = tooMany ? `more than ${MOST_NAMED_SESSIONS} sessions: narrow the filter, or clear it for every session` : auditTitle;
    shownCsv.disabled = trialCount === 0;
    // The dataset export selects by operator (workcell export --operator), not by the
    // other filters: its included trials of the participant chosen, or of everyone.
    const lerobot = new URL(serverUrl("api/export/lerobot.zip"));
    if (filter.participant !== "") lerobot.searchParams.append("operator", filter.participant);
    lerobotZip.href = lerobot.toString();
    const whose = filter.participant !== "" ? filter.participant : "every participant";
    lerobotZip.title = `workcell export --format lerobot: the included trials of ${whose} (every condition and step), without camera images`;
    list.replaceChildren();
    if (all.length === 0) list.append(el("p", { textContent: "No sessions recorded yet." }));
    else if (shown.length === 0) list.append(el("p", { textContent: "No session matches the filters." }));
    for (const session of [...shown].reverse()) list.append(sessionBlock(session));
  };

  const choose = (): void => {
    filter = {
      participant: participant.value,
      condition: condition.value,
      step: step.value,
      trials: trials.value as TrialKind,
    };
    window.history.replaceState(null, "", hashOf(filter));
    show();
  };
  for (const menu of [participant, condition, step, trials]) menu.addEventListener("change", choose);
  clear.addEventListener("click", () => {
    filter = NO_FILTER;
    window.history.replaceState(null, "", hashOf(filter));
    show();
  });
  shownCsv.addEventListener("click", () => download("workcell-sessions-trials.csv", trialsCsv(shown)));
  auditCsv.addEventListener("click", (event) => {
    if (auditCsv.classList.contains("disabled")) event.preventDefault();
  });

  const load = (): void => {
    fetchSessions()
      .then((result) => {
        if (disposed) return;
        all = [...result.sessions];
        show();
      })
      .catch((error: unknown) => {
        list.textContent = `Could not load the sessions: ${String(error)}`;
      });
  };
  refresh.addEventListener("click", load);
  load();
  return () => {
    disposed = true;
    page.remove();
  };
}
