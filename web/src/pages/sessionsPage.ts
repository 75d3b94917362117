// The sessions page: every recorded session and its trials (outcome, flags, score), with a
// replay link per trial.

import type { App } from "../app";
import type { SessionSummary, TrialSummary } from "../protocol";
import { fetchSessions } from "../net/api";
import { el } from "../util/dom";

function when(unixSeconds: number | null): string {
  if (unixSeconds === null) return "—";
  return new Date(unixSeconds * 1000).toLocaleString();
}

function num(value: number | null, digits = 0): string {
  return value === null ? "—" : value.toFixed(digits);
}

function trialRow(trial: TrialSummary): HTMLTableRowElement {
  const row = el("tr", { className: `trial outcome-${trial.outcome ?? "running"}` });
  row.dataset["trialId"] = trial.trial_id;
  const level = trial.level !== null ? `R${trial.round ?? "-"} L${trial.level}` : "—";
  const outcome = trial.outcome ?? "running";
  const reason = trial.interruption_reason !== null ? ` (${trial.interruption_reason})` : "";
  const flags = trial.quality_flags.length > 0 ? trial.quality_flags.join(", ") : "—";
  const included = trial.included === null ? "—" : trial.included ? "yes" : `no: ${trial.exclusion_reason ?? "not included"}`;
  const cells = [
    String(trial.trial_index + 1),
    trial.mode,
    level,
    outcome + reason,
    `${num(trial.boxes_delivered)}/${trial.required_boxes}`,
    num(trial.elapsed_s, 1),
    num(trial.score),
    num(trial.n_frames),
    flags,
    included,
  ];
  for (const text of cells) row.append(el("td", { textContent: text }));
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
  for (const title of ["#", "mode", "level", "outcome", "boxes", "time s", "score", "frames", "flags", "included", ""]) {
    head.append(el("th", { textContent: title }));
  }
  table.append(el("thead", {}, head));
  const body = el("tbody");
  for (const trial of session.trials) body.append(trialRow(trial));
  table.append(body);
  block.append(table);
  return block;
}

export function mountSessions(root: HTMLElement, _app: App): () => void {
  const page = el("section", { className: "page sessions-page" });
  const refresh = el("button", { textContent: "Refresh" });
  const list = el("div", { className: "session-list", textContent: "Loading…" });
  page.append(el("h1", { textContent: "Sessions" }), refresh, list);
  root.append(page);
  let disposed = false;

  const load = (): void => {
    fetchSessions()
      .then((result) => {
        if (disposed) return;
        list.replaceChildren();
        if (result.sessions.length === 0) {
          list.append(el("p", { textContent: "No sessions recorded yet." }));
          return;
        }
        for (const session of [...result.sessions].reverse()) list.append(sessionBlock(session));
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
