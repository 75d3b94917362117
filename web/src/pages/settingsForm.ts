// The setup form's model: every setting of /api/defaults as an input, read back into the
// nested settings mapping StartSession carries. Values are sent as typed as far as they
// parse; anything else goes as text so the server (the one validator) names the problem.

import type { Defaults, FieldProblem, SettingInfo } from "../protocol";

export interface FieldControl {
  info: SettingInfo;
  input: HTMLInputElement | HTMLSelectElement;
  problem: HTMLElement;
  row: HTMLElement;
}

function formatDefault(value: unknown): string {
  if (Array.isArray(value)) return value.map((v) => String(v)).join(", ");
  if (typeof value === "number" && Number.isInteger(value)) return String(value);
  return String(value);
}

function parseNumber(text: string, kind: "int" | "float"): number | string {
  const trimmed = text.trim();
  if (trimmed === "") return text;
  const value = Number(trimmed);
  if (!Number.isFinite(value)) return text;
  if (kind === "int" && !Number.isInteger(value)) return text;
  return value;
}

export function readValue(control: FieldControl): unknown {
  const { info, input } = control;
  switch (info.kind) {
    case "bool":
      return (input as HTMLInputElement).checked;
    case "int":
    case "float":
      return parseNumber(input.value, info.kind);
    case "int_list":
    case "float_list": {
      const kind = info.kind === "int_list" ? "int" : "float";
      const parts = input.value.split(/[,\s]+/).filter((p) => p !== "");
      return parts.map((p) => parseNumber(p, kind));
    }
    default:
      return input.value;
  }
}

export function writeValue(control: FieldControl, value: unknown): void {
  if (control.info.kind === "bool") (control.input as HTMLInputElement).checked = value === true;
  else control.input.value = formatDefault(value);
}

/** `{"task.mode": "practice"}` → `{task: {mode: "practice"}}`. */
export function nest(values: ReadonlyMap<string, unknown>): Record<string, unknown> {
  const root: Record<string, unknown> = {};
  for (const [key, value] of values) {
    const parts = key.split(".");
    let node = root;
    parts.slice(0, -1).forEach((part) => {
      const child = node[part];
      if (typeof child === "object" && child !== null && !Array.isArray(child)) {
        node = child as Record<string, unknown>;
      } else {
        const created: Record<string, unknown> = {};
        node[part] = created;
        node = created;
      }
    });
    const leaf = parts[parts.length - 1];
    if (leaf !== undefined) node[leaf] = value;
  }
  return root;
}

/** The setting a problem's path lands in: its names joined with dots, list indices
 * left out (`["task", "level_boxes", 1]` → `task.level_boxes`), cut back to the longest
 * leading part that is a known setting; null when no part is. */
export function fieldFor(problem: FieldProblem, keys: readonly string[]): string | null {
  const names = problem.path.filter((part): part is string => typeof part === "string");
  for (let n = names.length; n > 0; n -= 1) {
    const key = names.slice(0, n).join(".");
    if (keys.includes(key)) return key;
  }
  return null;
}

/** Where each problem is shown: the lines beside each setting's field (in the order the
 * server sent them), and the lines that name no known setting. */
export function placeProblems(
  problems: readonly FieldProblem[],
  keys: readonly string[],
): { byField: Map<string, string[]>; general: string[] } {
  const byField = new Map<string, string[]>();
  const general: string[] = [];
  for (const problem of problems) {
    const key = fieldFor(problem, keys);
    if (key === null) general.push(problem.message);
    else byField.set(key, [...(byField.get(key) ?? []), problem.message]);
  }
  return { byField, general };
}

/** Which section a field belongs to: the longest section key that prefixes it. */
export function sectionOf(field: SettingInfo, defaults: Defaults): string {
  const owner = defaults.sections
    .map((s) => s.key)
    .filter((k) => field.key.startsWith(`${k}.`))
    .sort((a, b) => b.length - a.length)[0];
  return owner ?? "";
}

export function buildControl(info: SettingInfo): FieldControl {
  const row = document.createElement("div");
  row.className = "field";
  row.dataset["field"] = info.key;
  const label = document.createElement("label");
  const id = `setting-${info.key.replace(/[^a-z0-9]+/gi, "-")}`;
  label.htmlFor = id;
  label.textContent = info.key.split(".").pop() ?? info.key;
  let input: HTMLInputElement | HTMLSelectElement;
  if (info.kind === "choice") {
    const select = document.createElement("select");
    for (const choice of info.choices ?? []) {
      const option = document.createElement("option");
      option.value = choice;
      option.textContent = choice;
      select.append(option);
    }
    input = select;
  } else {
    const text = document.createElement("input");
    text.type = info.kind === "bool" ? "checkbox" : "text";
    if (info.kind === "int" || info.kind === "float") text.inputMode = "decimal";
    text.spellcheck = false;
    input = text;
  }
  input.id = id;
  input.name = info.key;
  const doc = document.createElement("div");
  doc.className = "doc";
  doc.textContent = `${info.doc} — default ${formatDefault(info.default)}`;
  const problem = document.createElement("div");
  problem.className = "problem";
  problem.setAttribute("role", "alert");
  row.append(label, input, doc, problem);
  const control: FieldControl = { info, input, problem, row };
  writeValue(control, info.default);
  return control;
}
