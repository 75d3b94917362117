// The setup form's hints, from GET /api/settings/hints (generated on the server from each
// setting's declaration, like the documentation /api/defaults carries, the TOML template
// and the README table): what a setting allows as the input's tooltip, and an early mark
// on a number typed outside the declared bounds. The server stays the one validator.

import { serverUrl } from "../util/env";
import { readValue } from "./settingsForm";
import type { FieldControl } from "./settingsForm";
import type { SettingHint, SettingHints } from "../protocol";


export async function fetchSettingHints(): Promise<SettingHints> {
  const response = await fetch(serverUrl("api/settings/hints"), { headers: { Accept: "application/json" } });
  if (!response.ok) throw new Error(`api/settings/hints: HTTP ${response.status}`);
  return (await response.json()) as SettingHints;
}

function numberAllowed(hint: SettingHint, value: unknown): boolean {
  if (typeof value !== "number" || !Number.isFinite(value)) return false;
  if (hint.whole && !Number.isInteger(value)) return false;
  if (hint.low !== null && (hint.low_open ? value <= hint.low : value < hint.low)) return false;
  return hint.high === null || value <= hint.high;
}

/** Whether a value read from the form lies outside the hint's bounds (a list: any item). */
export function outOfBounds(hint: SettingHint, value: unknown): boolean {
  if (hint.low === null && hint.high === null && !hint.whole) return false;
  if (Array.isArray(value)) return value.some((item) => !numberAllowed(hint, item));
  return !numberAllowed(hint, value);
}

/** Give every control its hint and mark a value outside its bounds as the operator types. */
export function applyHints(controls: ReadonlyMap<string, FieldControl>, hints: SettingHints): void {
  for (const hint of hints.hints) {
    const control = controls.get(hint.key);
    if (control === undefined) continue;
    control.input.title = hint.allowed;
    control.row.dataset["unit"] = hint.unit;
    const mark = (): void => {
      control.row.classList.toggle("invalid", outOfBounds(hint, readValue(control)));
    };
    control.input.addEventListener("input", mark);
  }
}
