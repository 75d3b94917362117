// Whether the desktop key map starts open on the teleoperation page: open the first time
// (a new operator needs it), folded after that, and whatever the operator last chose with
// the Keys button from then on. Remembered in the browser's local storage.

export const KEYMAP_KEY = "workcell.keymap";

/** The part of `Storage` this needs (local storage, or a stand-in where there is none). */
export interface SmallStorage {
  getItem(key: string): string | null;
  setItem(key: string, value: string): void;
}

/** Whether the key map opens now; notes that it has been seen. */
export function keymapOpensAtStart(storage: SmallStorage): boolean {
  const remembered = storage.getItem(KEYMAP_KEY);
  if (remembered === null) {
    storage.setItem(KEYMAP_KEY, "seen");
    return true;
  }
  return remembered === "open";
}

/** The operator opened or folded the key map: keep it that way next time. */
export function rememberKeymap(storage: SmallStorage, open: boolean): void {
  storage.setItem(KEYMAP_KEY, open ? "open" : "folded");
}

/** The page's local storage, or none (a private window may refuse it). */
export function pageStorage(): SmallStorage {
  try {
    return window.localStorage;
  } catch {
    const kept = new Map<string, string>();
    return { getItem: (key) => kept.get(key) ?? null, setItem: (key, value) => void kept.set(key, value) };
  }
}
