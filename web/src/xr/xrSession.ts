// Entering and leaving immersive VR.

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

  constructor(private readonly viewer: Viewer) {}

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
