// The setup page (the paper's Fig. 3): a first screen of a few choices (task, mode, grasp,
// name) with Start, and every other parameter with its default and allowed range under
// "Advanced"; Start sends StartSession and the server's objections are shown beside the
// fields they name (opening "Advanced" when they name a setting there).

import type { App } from "../app";
import type { Defaults, FieldProblem } from "../protocol";
import { fetchDefaults } from "../net/api";
import { applyHints, fetchSettingHints } from "./settingHints";
import { buildControl, nest, placeProblems, readValue, sectionOf, writeValue } from "./settingsForm";
import type { FieldControl } from "./settingsForm";
import { el } from "../util/dom";

const TASK_KEY = "task.kind";
const MODE_KEY = "task.mode";
const GRASP_KEY = "world.grasp";
const OPERATOR_KEY = "operator_id";
/** Settings only `workcell serve --study` sets (a participant's accepted consent, their
 * session's place in their plan): not on the form. */
const SET_BY_STUDY_SERVER: readonly string[] = ["consent", "study_step"];
const MODE_HELP: Record<string, string> = {
  practice: "one trial, one box, ends when the task is done",
  collection: "repeated one-box trials with automatic reset",
  challenge: "rounds of levels with more boxes and less time",
};

export function mountSetup(root: HTMLElement, app: App): () => void {
  const page = el("section", { className: "page setup-page" });
  const status = el("div", { className: "setup-status", textContent: "Loading settings…" });
  page.append(el("h1", { textContent: "New session" }), status);
  root.append(page);
  let controls = new Map<string, FieldControl>();
  let general: HTMLElement | null = null;
  let startButton: HTMLButtonElement | null = null;
  let advanced: HTMLDetailsElement | null = null;
  let disposed = false;

  const showProblems = (problems: readonly FieldProblem[]): void => {
    for (const control of controls.values()) {
      control.problem.textContent = "";
      control.row.classList.remove("invalid");
    }
    if (general !== null) general.textContent = "";
    const placed = placeProblems(problems, [...controls.keys()]);
    let first: FieldControl | null = null;
    for (const [key, lines] of placed.byField) {
      const control = controls.get(key);
      if (control === undefined) continue;
      control.row.classList.add("invalid");
      control.problem.textContent = lines.join("\n");
      // a setting under "Advanced" that the server objects to is shown, not left folded
      if (advanced !== null && advanced.contains(control.row)) advanced.open = true;
      first ??= control;
    }
    if (general !== null) general.textContent = placed.general.map((line) => `${line}\n`).join("");
    first?.input.focus();
    if (startButton !== null) {
      startButton.disabled = false;
      startButton.textContent = "Start";
    }
  };

  const render = (defaults: Defaults): void => {
    status.textContent = "";
    const form = el("form", { className: "setup-form", noValidate: true });
    const shown = defaults.fields.filter((info) => !SET_BY_STUDY_SERVER.includes(info.key));
    controls = new Map(shown.map((info) => [info.key, buildControl(info)]));
    const built = controls;
    fetchSettingHints()
      .then((hints) => {
        if (!disposed) applyHints(built, hints);
      })
      .catch((error: unknown) => console.warn("setting hints unavailable:", error));

    // The operator's first screen: the task, the mode (as large buttons: chosen there
    // alone), the grasp and their name, then Start; every other setting under "Advanced".
    const task = controls.get(TASK_KEY);
    const mode = controls.get(MODE_KEY);
    const grasp = controls.get(GRASP_KEY);
    const operator = controls.get(OPERATOR_KEY);
    const top = el("fieldset", { className: "top-choices" });
    top.append(el("legend", { textContent: "Task, mode, grasp and name" }));
    const first = (control: FieldControl | undefined, label: string): void => {
      if (control === undefined) return;
      const text = control.row.querySelector("label");
      if (text !== null) {
        text.textContent = label;
        text.title = control.info.key;
      }
      top.append(control.row);
    };
    first(task, "task");
    if (mode !== undefined) {
      const picker = el("div", { className: "mode-picker", role: "radiogroup" });
      picker.setAttribute("aria-label", "mode");
      for (const choice of mode.info.choices ?? []) {
        const button = el("button", {
          type: "button",
          className: "mode-choice",
          textContent: choice,
          title: MODE_HELP[choice] ?? "",
        });
        button.dataset["mode"] = choice;
        button.setAttribute("role", "radio");
        button.append(el("small", { textContent: MODE_HELP[choice] ?? "" }));
        button.addEventListener("click", () => {
          mode.input.value = choice;
          mode.input.dispatchEvent(new Event("change"));
        });
        picker.append(button);
      }
      const sync = (): void => {
        for (const b of picker.querySelectorAll<HTMLButtonElement>(".mode-choice")) {
          b.classList.toggle("selected", b.dataset["mode"] === mode.input.value);
          b.setAttribute("aria-checked", String(b.dataset["mode"] === mode.input.value));
        }
        form.dataset["mode"] = mode.input.value;
      };
      mode.input.addEventListener("change", sync);
      sync();
      // The buttons choose the mode; its field stays in the form (read on Start, where
      // the server's objections land) but is not shown a second time.
      mode.row.hidden = true;
      top.append(picker, mode.row);
    }
    first(grasp, "grasp");
    first(operator, "name");
    form.append(top);

    general = el("pre", { className: "problem general", role: "alert" });
    startButton = el("button", { type: "submit", className: "primary start", textContent: "Start" });
    const actions = el("div", { className: "actions" });
    actions.append(startButton, general);
    form.append(actions);

    // Every other setting, grouped by its section, in declaration order, folded away.
    advanced = el("details", { className: "advanced" });
    const rest = [...controls.values()].filter((c) => c !== task && c !== mode && c !== grasp && c !== operator);
    advanced.append(el("summary", { textContent: `Advanced: ${rest.length} more settings (defaults work)` }));
    const docs = new Map(defaults.sections.map((s) => [s.key, s.doc]));
    const groups = new Map<string, HTMLElement>();
    for (const control of rest) {
      const section = sectionOf(control.info, defaults);
      let group = groups.get(section);
      if (group === undefined) {
        group = el("fieldset", { className: "section" });
        group.dataset["section"] = section;
        const title = section === "" ? "Session" : section;
        const legend = el("legend", { textContent: title });
        const doc = docs.get(section);
        if (doc !== undefined) legend.append(el("span", { className: "doc", textContent: ` — ${doc}` }));
        group.append(legend);
        groups.set(section, group);
        advanced.append(group);
      }
      group.append(control.row);
    }
    const reset = el("button", { type: "button", className: "reset", textContent: "Reset to defaults" });
    reset.addEventListener("click", () => {
      for (const control of controls.values()) writeValue(control, control.info.default);
      mode?.input.dispatchEvent(new Event("change"));
      showProblems([]);
    });
    advanced.append(el("div", { className: "actions" }, reset));
    form.append(advanced);
    form.addEventListener("submit", (event) => {
      event.preventDefault();
      const values = new Map<string, unknown>();
      for (const [key, control] of controls) values.set(key, readValue(control));
      showProblems([]);
      if (!app.startSession(nest(values))) {
        if (general !== null) general.textContent = "Not connected to the server; retrying…";
        return;
      }
      if (startButton !== null) {
        startButton.disabled = true;
        startButton.textContent = "Starting…";
      }
    });
    page.append(form);
    updateRunning();
  };

  const running = el("div", { className: "running-banner" });
  page.insertBefore(running, status);
  const updateRunning = (): void => {
    running.replaceChildren();
    if (app.sessionActive) {
      running.append(
        "A session is running. ",
        el("a", { href: "#/teleop", textContent: "Open the teleoperation view" }),
      );
    } else if (!app.isOperator && app.connection.isOpen) {
      running.append("Every seat of this server has an operator: you can watch as a spectator.");
    }
  };

  const unsubscribe = app.subscribe((event) => {
    if (event.kind === "config_rejected") showProblems(event.problems);
    else if (event.kind === "session") {
      if (app.session !== null && app.sessionActive && startButton?.disabled === true) {
        window.location.hash = "#/teleop";
      }
      updateRunning();
    } else if (event.kind === "server_error" && startButton?.disabled === true) {
      if (general !== null) general.textContent = `${event.code}: ${event.message}`;
      startButton.disabled = false;
      startButton.textContent = "Start";
    } else if (event.kind === "link") updateRunning();
  });

  fetchDefaults()
    .then((defaults) => {
      if (!disposed) render(defaults);
    })
    .catch((error: unknown) => {
      status.textContent = `Could not load the settings: ${String(error)}`;
      status.classList.add("problem");
    });

  return () => {
    disposed = true;
    unsubscribe();
    page.remove();
  };
}
