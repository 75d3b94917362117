// The 3D view: one renderer, the world model, lights, and a camera rig that follows the
// robot (first person: at the robot's head camera; third person: behind the robot). In
// WebXR the headset moves the camera inside the rig, so the rig is placed such that the
// headset lands on the robot head; the raw local-floor poses sent to the server are not
// affected by where the rig is.

import * as THREE from "three";
import { rigYawForHeading, yawOf } from "./frames";
import { WorldModel } from "./worldModel";
import { lowQuality } from "../util/env";
import { NO_RECENTER } from "../xr/recenter";
import type { Recenter } from "../xr/recenter";
import { FrameMeter } from "./frameMeter";
import type { FrameReport } from "./frameMeter";

export type ViewMode = "first" | "third";
export type FrameCallback = (time: number, frame: XRFrame | undefined) => void;

const UP = new THREE.Vector3(0, 1, 0);
const DESKTOP_CHASE = { distance: 2.2, height: 2.6, lookAhead: 1.0, lookHeight: 0.6 };
const XR_CHASE_DISTANCE = 1.7;
const ZOOM_RANGE: [number, number] = [0.5, 3];

export class Viewer {
  readonly renderer: THREE.WebGLRenderer;
  readonly scene = new THREE.Scene();
  readonly rig = new THREE.Group();
  readonly camera = new THREE.PerspectiveCamera(65, 1, 0.05, 200);
  readonly world = new WorldModel();
  viewMode: ViewMode = "third";
  /** Desktop chase-camera zoom factor (mouse wheel). */
  zoom = 1;
  private readonly callbacks: FrameCallback[] = [];
  private container: HTMLElement | null = null;
  private readonly resizeObserver: ResizeObserver;
  private frames = 0;
  /** Frame time and draw figures of what this view draws. */
  readonly frameMeter = new FrameMeter();
  private readonly reportListeners: ((report: FrameReport) => void)[] = [];

  constructor() {
    this.renderer = new THREE.WebGLRenderer({ antialias: !lowQuality(), preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    this.renderer.xr.enabled = true;
    this.renderer.xr.setReferenceSpaceType("local-floor");
    this.renderer.domElement.className = "viewer-canvas";
    this.renderer.domElement.tabIndex = 0;
    this.scene.background = new THREE.Color(0xcfd8e3);
    this.scene.fog = new THREE.Fog(0xcfd8e3, 18, 45);
    // The model's lights, roughly: an ambient sky (MuJoCo's headlight ambient) and the
    // sun from the model's sun direction (0.2, 0.3, -1) in the world, z-up; no shadows.
    this.scene.add(new THREE.HemisphereLight(0xf4f7ff, 0x5d5140, 1.25));
    const sun = new THREE.DirectionalLight(0xfffaf0, 2.4);
    sun.position.set(-2, 10, 3);
    this.scene.add(sun);
    this.scene.add(this.world.root);
    this.rig.name = "rig";
    this.rig.add(this.camera);
    this.scene.add(this.rig);
    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.renderer.setAnimationLoop((time, frame) => this.tick(time, frame));
  }

  get canvas(): HTMLCanvasElement {
    return this.renderer.domElement;
  }

  get presenting(): boolean {
    return this.renderer.xr.isPresenting;
  }

  /** Called with each frame report (every few seconds while drawing). */
  onFrameReport(listener: (report: FrameReport) => void): () => void {
    this.reportListeners.push(listener);
    return () => {
      const i = this.reportListeners.indexOf(listener);
      if (i >= 0) this.reportListeners.splice(i, 1);
    };
  }

  get frameCount(): number {
    return this.frames;
  }

  /** Put the canvas into `container` (it moves between pages). */
  mount(container: HTMLElement): void {
    if (this.container !== null) this.resizeObserver.unobserve(this.container);
    this.container = container;
    container.prepend(this.canvas);
    this.resizeObserver.observe(container);
    this.resize();
  }

  /** Take the canvas off the page; nothing is drawn until the next mount (or XR). */
  unmount(): void {
    if (this.container !== null) this.resizeObserver.unobserve(this.container);
    this.container = null;
    this.canvas.remove();
  }

  onFrame(callback: FrameCallback): () => void {
    this.callbacks.push(callback);
    return () => {
      const i = this.callbacks.indexOf(callback);
      if (i >= 0) this.callbacks.splice(i, 1);
    };
  }

  /**
   * Place the rig for this frame. `headsetLocal` is the headset position in local-floor
   * (XR only): the rig is offset so the operator's eyes sit at the robot's head camera.
   */
  placeRig(headsetLocal: THREE.Vector3 | null, recenter: Recenter = NO_RECENTER): void {
    const base = this.world.bodyPose("base");
    if (base === null) return;
    const yaw = yawOf(base);
    const basePosition = this.world.bodies.get("base")?.getWorldPosition(new THREE.Vector3());
    if (basePosition === undefined) return;
    const heading = new THREE.Quaternion().setFromAxisAngle(UP, rigYawForHeading(yaw));
    const forward = new THREE.Vector3(0, 0, -1).applyQuaternion(heading);
    this.world.setHeadVisible(this.viewMode === "third");
    const anchor = this.world.headCamera;
    if (this.presenting) {
      this.rig.quaternion.copy(heading);
      if (this.viewMode === "first" && anchor.parent !== null) {
        const eye = anchor.getWorldPosition(new THREE.Vector3());
        const offset = (headsetLocal ?? new THREE.Vector3(0, 1.6, 0)).clone().applyQuaternion(heading);
        this.rig.position.copy(eye.sub(offset));
      } else {
        this.rig.position.copy(basePosition.addScaledVector(forward, -XR_CHASE_DISTANCE));
        this.rig.position.y = 0;
      }
      if (recenter.yaw !== 0) {
        // The headset poses were recentered (turned by -yaw about the pivot); the camera
        // and the controllers in the rig are raw, so the rig turns them the same way:
        // rig = placement * T, T(p) = c + R (p - c).
        const turn = new THREE.Quaternion().setFromAxisAngle(UP, -recenter.yaw);
        const pivot = new THREE.Vector3(recenter.x, 0, recenter.z);
        const placed = this.rig.quaternion.clone();
        this.rig.quaternion.multiply(turn);
        this.rig.position
          .add(pivot.clone().applyQuaternion(placed))
          .sub(pivot.applyQuaternion(this.rig.quaternion));
      }
      this.camera.position.set(0, 0, 0);
      this.camera.quaternion.identity();
      return;
    }
    if (this.viewMode === "first" && anchor.parent !== null) {
      anchor.getWorldPosition(this.rig.position);
      anchor.getWorldQuaternion(this.rig.quaternion);
      this.camera.position.set(0, 0, 0);
      this.camera.quaternion.identity();
      return;
    }
    this.rig.position.copy(basePosition);
    this.rig.position.y = 0;
    this.rig.quaternion.copy(heading);
    this.rig.updateMatrixWorld();
    const d = DESKTOP_CHASE.distance * this.zoom;
    this.camera.position.set(0, DESKTOP_CHASE.height * Math.sqrt(this.zoom), d);
    this.camera.lookAt(
      this.rig.localToWorld(new THREE.Vector3(0, DESKTOP_CHASE.lookHeight, -DESKTOP_CHASE.lookAhead)),
    );
  }

  /** A fixed overview (replay, no robot yet). */
  placeOverview(target: THREE.Vector3, distance: number): void {
    this.rig.position.set(0, 0, 0);
    this.rig.quaternion.identity();
    this.camera.position.copy(target).add(new THREE.Vector3(distance * 0.6, distance * 0.7, distance * 0.8));
    this.camera.lookAt(target);
  }

  /** Stop drawing and free the GPU resources (a page-local viewer). */
  dispose(): void {
    this.renderer.setAnimationLoop(null);
    this.resizeObserver.disconnect();
    this.canvas.remove();
    this.renderer.dispose();
    this.renderer.forceContextLoss();
  }

  setZoom(factor: number): void {
    this.zoom = Math.min(ZOOM_RANGE[1], Math.max(ZOOM_RANGE[0], factor));
  }

  private tick(time: number, frame: XRFrame | undefined): void {
    this.frames += 1;
    for (const callback of this.callbacks) {
      try {
        callback(time, frame);
      } catch (error) {
        console.error("workcell: frame callback failed", error);
      }
    }
    if (this.container === null && !this.presenting) return;
    this.renderer.render(this.scene, this.camera);
    const { calls, triangles } = this.renderer.info.render;
    const report = this.frameMeter.frame(time, calls, triangles, this.presenting);
    if (report !== null) for (const listener of this.reportListeners) listener(report);
  }

  private resize(): void {
    const container = this.container;
    if (container === null || this.presenting) return;
    const width = Math.max(1, container.clientWidth);
    const height = Math.max(1, container.clientHeight);
    this.renderer.setSize(width, height, false);
    this.camera.aspect = width / height;
    this.camera.updateProjectionMatrix();
  }
}
