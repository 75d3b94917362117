// The desktop key map drawn over the teleoperation view (lower left), with its Hide button
// and the toolbar's Keys button: open the first time, then as the operator left it
// (src/input/keymapPreference.ts), so it does not cover the view for one who knows the keys.

import { KEY_MAP } from "../input/desktop";
import { keymapOpensAtStart, pageStorage, rememberKeymap } from "../input/keymapPreference";
import { el } from "../util/dom";

/** The key map panel, opened and folded by `toggle` (the toolbar's Keys button). */
export function keymapPanel(toggle: HTMLButtonElement): HTMLElement {
  const keymap = el("div", { className: "keymap", id: "keymap" });
  const hide = el("button", { type: "button", className: "small keymap-close", textContent: "Hide" });
  keymap.append(el("h2", { textContent: "Desktop controls" }, " ", hide));
  const keyTable = el("table");
  for (const entry of KEY_MAP) {
    const row = el("tr");
    row.append(el("th", { textContent: entry.keys }), el("td", { textContent: entry.action }));
    keyTable.append(row);
  }
  keymap.append(keyTable);
  const storage = pageStorage();
  const show = (open: boolean): void => {
    keymap.classList.toggle("hidden", !open);
    toggle.setAttribute("aria-expanded", String(open));
  };
  const choose = (open: boolean): void => {
    show(open);
    rememberKeymap(storage, open);
  };
  show(keymapOpensAtStart(storage));
  toggle.addEventListener("click", () => choose(keymap.classList.contains("hidden")));
  hide.addEventListener("click", () => choose(false));
  return keymap;
}
