// Entering and leaving immersive VR (hand tracking asked for, tracked hands drawn).

import { XRHandModelFactory } from "three/examples/jsm/webxr/XRHandModelFactory.js";
import type { Viewer } from "../scene/viewer";

export type XrAvailability = "supported" | "unsupported" | "insecure";

export async function xrAvailability(): Promise<XrAvailability> {
  if (!window.isSecureContext) return "insecure";
  const xr = navigator.xr;
  if (xr === undefined) return "unsupported";
  try {
    return (await xr.isSessionSupported("immersive-vr")) ? "supported" : "unsupported";
  } catch {
    return "unsupported";
  }
}

export class XrController {
  session: XRSession | null = null;
  referenceSpace: XRReferenceSpace | null = null;
  onChange: (() => void) | null = null;

  constructor(private readonly viewer: Viewer) {
    // Tracked hands are drawn as joint spheres (no model download), in the rig with the
    // camera so they sit where the operator's hands are.
    const factory = new XRHandModelFactory();
    for (const index of [0, 1]) {
      const hand = viewer.renderer.xr.getHand(index);
      hand.add(factory.createHandModel(hand, "spheres"));
      viewer.rig.add(hand);
    }
  }

  get presenting(): boolean {
    return this.session !== null;
  }

  /** Must be called from a user gesture (a click). */
  async enter(): Promise<void> {
    const xr = navigator.xr;
    if (xr === undefined) throw new Error("WebXR is not available in this browser");
    if (this.session !== null) return;
    const session = await xr.requestSession("immersive-vr", {
      requiredFeatures: ["local-floor"],
      optionalFeatures: ["hand-tracking"],
    });
    session.addEventListener("end", () => {
      this.session = null;
      this.referenceSpace = null;
      this.onChange?.();
    });
    await this.viewer.renderer.xr.setSession(session);
    this.session = session;
    this.referenceSpace = this.viewer.renderer.xr.getReferenceSpace();
    this.onChange?.();
  }

  async exit(): Promise<void> {
    await this.session?.end();
  }
}
