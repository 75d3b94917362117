// `?emulate=quest3`: an emulated Meta Quest 3 and its controllers (IWER), installed before
// the page asks for an XR session. Tests drive it through `window.__xrDevice`.

import type { XRDevice } from "iwer";

/** The emulated headset the tests drive (IWER's device). */
export type EmulatedDevice = XRDevice;

declare global {
  interface Window {
    __xrDevice?: EmulatedDevice;
  }
}

export async function installEmulatedDevice(name: string): Promise<boolean> {
  if (name !== "quest3") {
    console.warn(`workcell: unknown emulated device '${name}' (known: quest3)`);
    return false;
  }
  const { XRDevice, metaQuest3 } = await import("iwer");
  const device = new XRDevice(metaQuest3);
  device.installRuntime({ forceInstall: true });
  window.__xrDevice = device;
  return true;
}
