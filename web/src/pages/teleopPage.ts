// The teleoperation page: the 3D view, the HUD, the key map and the end screens; once per
// animation frame it reads the operator's devices (WebXR, or keyboard/mouse/gamepad) and
// sends them as one Input message, and draws the newest State.

import * as THREE from "three";
import type { App } from "../app";
import type { Act, Pose, Scene, State } from "../protocol";
import type { Viewer } from "../scene/viewer";
import type { XrController } from "../xr/xrSession";
import { xrAvailability } from "../xr/xrSession";
import { readXrFrame } from "../xr/xrInput";
import { DesktopInput } from "../input/desktop";
import { keymapPanel } from "./keymapPanel";
import { BUTTON, InputSequencer } from "../input/hands";
import type { DeviceFrame } from "../input/hands";
import { HudPanel } from "../hud/hudPanel";
import { BaseMotionMeter, hudPlacement, offAxisDegrees, vignetteStrength } from "../xr/comfort";
import type { HudMode, HudPlacement } from "../xr/comfort";
import { Vignette } from "../xr/vignette";
import { VrMenu } from "../xr/vrMenu";
import type { MenuItem } from "../xr/vrMenu";
import { applyRecenter, headingOf, NO_RECENTER, recenterOn, recenterPoint, undo } from "../xr/recenter";
import type { Recenter } from "../xr/recenter";
import { yawOf } from "../scene/frames";
import { hudLines, trialEndSummary } from "../hud/hudText";
import { linesToDom } from "../hud/endScreen";
import { SessionControls } from "../hud/sessionControls";
import { exposeCapture, exposeExtra } from "../debug";
import { el } from "../util/dom";
import { describeReport } from "../scene/frameMeter";
import { SnapTurn } from "../xr/snapTurn";
import { drivingLabel, GripHold } from "../xr/gripHold";
import { snapTurnRequested } from "../util/env";
import { ControllerMarkers } from "../xr/controllerMarkers";
import { hintText, linkBadgeText } from "../hud/statusText";
import type { TurnMode } from "../xr/snapTurn";

export interface TeleopShared {
  viewer: Viewer;
  xr: XrController;
  sequencer: InputSequencer;
}

const HUD_REFRESH_MS = 100;
/** The robot's default base limits, for the vignette's scale (m/s, rad/s). */
const BASE_LIMITS = { linear: 0.8, yaw: 1.2 };
/** A State older than this (ms) no longer tells how the base moves. */
const STATE_FRESH_MS = 300;

export function mountTeleop(root: HTMLElement, app: App, shared: TeleopShared): () => void {
  const { viewer, xr, sequencer } = shared;
  const page = el("section", { className: "page teleop-page" });
  const viewport = el("div", { className: "viewport" });
  const hud = el("div", { className: "hud", id: "hud" });
  const overlay = el("div", { className: "overlay hidden", id: "end-screen" });
  const bar = el("div", { className: "toolbar" });
  const linkBadge = el("span", { className: "link-badge" });
  const vrButton = el("button", { id: "enter-vr", textContent: "Enter VR", disabled: true });
  const viewButton = el("button", { id: "toggle-view", textContent: "View: third person" });
  const restartButton = el("button", { id: "restart-trial", textContent: "Restart trial" });
  const keysButton = el("button", { id: "toggle-keys", textContent: "Keys" });
  const frameBadge = el("span", { className: "frame-badge", id: "frame-badge", textContent: describeReport(null) });
  frameBadge.title = "how this page draws: frames per second (median), the slowest 5 % of frames, WebGL draw calls per frame";
  const controls = new SessionControls(app, viewport, overlay);
  bar.append(linkBadge, frameBadge, vrButton, viewButton, restartButton, controls.pauseButton, controls.stopButton, keysButton);
  const keymap = keymapPanel(keysButton);
  const hint = el("div", { className: "hint" });
  const notice = el("div", { className: "notice", role: "alert" });
  viewport.append(hud, bar, keymap, overlay, hint, notice);
  page.append(viewport);
  root.append(page);
  viewer.mount(viewport);

  const desktop = new DesktopInput(viewer.canvas);
  desktop.onZoom = (delta) => viewer.setZoom(viewer.zoom * Math.exp(delta * 0.001));
  const hudPanel = new HudPanel();
  hudPanel.mesh.visible = false;
  viewer.rig.add(hudPanel.mesh);
  const markers = new ControllerMarkers();
  for (const m of markers.meshes) viewer.rig.add(m);
  const vignette = new Vignette();
  let turnMode: TurnMode = snapTurnRequested() ? "snap" : "smooth";
  const snapTurn = new SnapTurn();
  const gripHold = new GripHold();
  viewer.camera.add(vignette.mesh);
  const baseMotion = new BaseMotionMeter();
  let hudMode: HudMode = "wrist";
  let hudPlaced: HudPlacement | null = null;
  let vignettePeak = 0;
  let lastStateAt = -Infinity;
  const menu = new VrMenu();
  viewer.rig.add(menu.mesh);
  let recenter: Recenter = NO_RECENTER;
  const actions: string[] = [];

  let builtScene: Scene | null = null;
  let appliedState: State | null = null;
  let lastTime: number | null = null;
  let lastHud = 0;
  let lastButtons = 0;
  let lastLeftButtons = 0;
  let lastFrame: DeviceFrame | null = null;
  let xrFrames = 0;
  let sent = 0;
  const headsetLocal = new THREE.Vector3(0, 1.6, 0);

  const setView = (mode: "first" | "third"): void => {
    viewer.viewMode = mode;
    viewButton.textContent = `View: ${mode} person`;
  };
  /** Switch the view and have the server record it. */
  const toggleView = (source: Act["source"]): void => {
    const next = viewer.viewMode === "first" ? "third" : "first";
    setView(next);
    act(next === "first" ? "view_first" : "view_third", source);
  };
  /** Switch the right stick between smooth and snap turns and have the server record it. */
  const toggleTurn = (source: Act["source"]): void => {
    turnMode = turnMode === "snap" ? "smooth" : "snap";
    act(turnMode === "snap" ? "turn_snap" : "turn_smooth", source);
  };
  const act = (action: Act["action"], source: Act["source"]): void => {
    actions.push(`${action}:${source}`);
    if (app.sessionActive && app.isOperator) app.act(action, source);
  };
  viewButton.addEventListener("click", () => toggleView("desktop"));
  restartButton.addEventListener("click", () => act("restart_trial", "desktop"));
  vrButton.addEventListener("click", () => {
    if (xr.presenting) {
      void xr.exit();
      return;
    }
    notice.textContent = "";
    xr.enter().catch((error: unknown) => {
      notice.textContent = `Could not enter VR: ${String(error)}`;
    });
  });
  xr.onChange = () => {
    vrButton.textContent = xr.presenting ? "Exit VR" : "Enter VR";
    hudPanel.mesh.visible = xr.presenting;
    if (xr.presenting) setView("first");
    markers.hide();
  };
  void xrAvailability().then((availability) => {
    vrButton.disabled = availability !== "supported";
    vrButton.title =
      availability === "insecure"
        ? "WebXR needs a secure context: open the page over https (workcell serve --tls) or localhost"
        : availability === "unsupported"
          ? "No WebXR headset available in this browser"
          : "Enter immersive VR";
  });

  const renderOverlay = (): void => controls.renderOverlay();

  const renderHud = (): void => {
    const info = app.connection.info;
    const role = app.connection.role;
    linkBadge.textContent = linkBadgeText(info, role);
    linkBadge.className = `link-badge ${info.status}`;
    controls.sync();
    restartButton.disabled = controls.stopButton.disabled;
    const h = app.ended === null ? app.hud : null; // after the end, the end screen says it
    hud.replaceChildren();
    if (h !== null) {
      if (h.instruction !== "") hud.append(el("p", { className: "hud-instruction", textContent: h.instruction }));
      hud.append(linesToDom(hudLines(h), "hud-lines"));
      if (h.phase === "countdown") hud.append(el("div", { className: "countdown", textContent: String(Math.ceil(h.countdown_s)) }));
    }
    const seat = app.connection.lastWelcome?.seat ?? "1";
    hint.textContent = hintText(role, seat, app.sessionActive, app.holding, lastFrame);
    if (xr.presenting) {
      const trialEnd = app.lastTrialEnd;
      if (app.ended !== null) {
        hudPanel.show("Session complete", [
          { label: "Successes", value: `${app.ended.successes}/${app.ended.trials}` },
          { label: "Total score", value: String(app.ended.total_score) },
        ]);
      } else if (controls.stopArmed || app.paused) {
        hudPanel.show(controls.stopArmed ? "Stop the session?" : "Paused", [
          { label: "Menu", value: controls.stopArmed ? "Confirm stop" : "Resume" },
        ]);
      } else if (trialEnd !== null) {
        hudPanel.show("Trial over", trialEndSummary(trialEnd));
      } else {
        hudPanel.show("Workcell", h !== null ? hudLines(h) : [{ label: "Status", value: info.status }], h?.instruction ?? "");
      }
    }
  };

  /** Carry out what the operator chose in the in-VR menu. */
  const choose = (item: MenuItem, headset: Pose | null): void => {
    if (item === "restart_trial") act("restart_trial", "xr_menu");
    else if (item === "recenter_view") {
      if (headset !== null) recenter = recenterOn(headset);
      act("recenter_view", "xr_menu");
    } else if (item === "toggle_view") toggleView("xr_menu");
    else if (item === "toggle_turn") toggleTurn("xr_menu");
    else if (item === "pause") controls.togglePause();
    else if (item === "take_over") app.toggleDriving();
    else if (item === "stop_session" && controls.chooseStopInVr()) menu.state.reopen();
  };

  const onFrame = (time: number, frame: XRFrame | undefined): void => {
    const dt = lastTime === null ? 0 : Math.min(0.1, (time - lastTime) / 1000);
    lastTime = time;
    if (app.scene !== null && app.scene !== builtScene) {
      viewer.world.build(app.scene);
      builtScene = app.scene;
      appliedState = null;
    }
    const state = app.state;
    if (state !== null && state !== appliedState && builtScene !== null) {
      viewer.world.applyPoses(state.poses);
      viewer.world.applyTargets(state.tcp_targets, state.following);
      appliedState = state;
      const base = viewer.world.bodyPose("base");
      if (base !== null) baseMotion.update(state.t_sim, base[0], base[1], yawOf(base));
      lastStateAt = time;
    }

    let reading: DeviceFrame;
    const space = xr.referenceSpace;
    if (viewer.presenting && frame !== undefined && space !== null) {
      xrFrames += 1;
      const raw = readXrFrame(frame, space);
      const recentered = (pose: Pose | null): Pose | null => (pose === null ? null : applyRecenter(pose, recenter));
      const xrReading = {
        ...raw,
        headset: recentered(raw.headset),
        left: { ...raw.left, pose: recentered(raw.left.pose) },
        right: { ...raw.right, pose: recentered(raw.right.pose) },
      };
      reading = xrReading;
      if (xrReading.headset !== null) headsetLocal.set(xrReading.headset[0], xrReading.headset[1], xrReading.headset[2]);
      // The in-VR menu: X opens it; while open the sticks do not drive and B closes it.
      const wasOpen = menu.state.open;
      const chosen = menu.state.update({
        open: (raw.left.buttons & BUTTON.primary) !== 0,
        choose: (raw.right.buttons & BUTTON.primary) !== 0,
        back: (raw.right.buttons & BUTTON.secondary) !== 0,
        stickY: raw.right.stick[1],
      });
      if (chosen !== null) choose(chosen, raw.headset);
      // Both grips squeezed for a moment while the driver drives: the person takes over.
      if (gripHold.update(raw.left.grip, raw.right.grip, time / 1000, app.autonomous && app.hud?.taken_over === false && !menu.state.open)) {
        app.setDriving(true);
      }
      const menuOpen = menu.state.open;
      if (!menuOpen) controls.stopArmed = false; // closing the menu cancels a stop
      if (menuOpen || chosen !== null) {
        reading = { ...xrReading, left: { ...xrReading.left, stick: [0, 0] }, right: { ...xrReading.right, stick: [0, 0] } };
      }
      // Snap turns: a flick of the right stick asks the server to turn the base by a
      // fixed angle, unseen; the stick itself no longer turns it.
      let blackout = false;
      if (turnMode === "snap" && !menuOpen) {
        const snapped = snapTurn.update(xrReading.right.stick[0], time / 1000, baseMotion.yawRate);
        reading = { ...reading, right: { ...reading.right, stick: [0, reading.right.stick[1]] } };
        if (snapped.ask !== null) act(snapped.ask, "xr_button");
        blackout = snapped.blackout;
      }
      const buttons = xrReading.left.buttons | xrReading.right.buttons;
      if (!wasOpen && !menuOpen && buttons & BUTTON.secondary && !(lastButtons & BUTTON.secondary)) {
        toggleView("xr_button");
      }
      // The left thumbstick press shows or hides the HUD.
      const leftStick = xrReading.left.buttons & BUTTON.stick;
      if (leftStick && !(lastLeftButtons & BUTTON.stick)) hudMode = hudMode === "wrist" ? "hidden" : "wrist";
      lastLeftButtons = xrReading.left.buttons;
      lastButtons = buttons;
      markers.update(raw.left, raw.right);
      const placed = hudPlacement(hudMode, xrReading.left.pose, [headsetLocal.x, headsetLocal.y, headsetLocal.z]);
      hudPlaced = placed;
      const rawEyes = raw.headsetPosition ?? { x: 0, y: 1.6, z: 0 };
      const eyesInRig = (): THREE.Vector3 => viewer.rig.localToWorld(new THREE.Vector3(rawEyes.x, rawEyes.y, rawEyes.z));
      hudPanel.mesh.visible = placed.visible && !menuOpen;
      hudPanel.mesh.position.set(...recenterPoint(placed.position, undo(recenter)));
      hudPanel.mesh.scale.setScalar(placed.where === "wrist" ? 0.5 : 1);
      hudPanel.mesh.lookAt(eyesInRig());
      menu.mesh.visible = menuOpen;
      if (menuOpen) {
        const views = viewer.viewMode === "first" ? "Third person" : "First person";
        const turns = turnMode === "snap" ? "Smooth turning" : "Snap turning";
        menu.draw(views, turns, app.paused ? "Resume" : "Pause", controls.stopArmed ? "Confirm stop" : "Stop session", drivingLabel(app.hud));
        // in front of where the operator looks now (raw local-floor, as the rig's children)
        const gaze = raw.headset === null ? 0 : headingOf(raw.headset);
        menu.mesh.position.set(rawEyes.x - 0.6 * Math.sin(gaze), rawEyes.y - 0.1, rawEyes.z - 0.6 * Math.cos(gaze));
        menu.mesh.lookAt(eyesInRig());
      }
      // Only while states arrive: after the session's end (or a stalled link) the last
      // measured motion is not what the base does.
      const moving = app.sessionActive && time - lastStateAt < STATE_FRESH_MS;
      const strength =
        viewer.viewMode === "first" && moving ? vignetteStrength(baseMotion.speed, baseMotion.yawRate, BASE_LIMITS) : 0;
      vignette.set(strength, blackout);
      vignettePeak = Math.max(vignettePeak, strength);
    } else {
      vignette.set(0);
      reading = desktop.read(dt);
      if (desktop.viewToggleRequested) {
        desktop.viewToggleRequested = false;
        toggleView("desktop");
      }
      if (desktop.pauseToggleRequested) {
        desktop.pauseToggleRequested = false;
        controls.togglePause();
      }
      if (desktop.driveToggleRequested) {
        desktop.driveToggleRequested = false;
        app.toggleDriving();
      }
    }
    lastFrame = reading;
    if (app.sessionActive && app.isOperator && app.connection.isOpen) {
      if (app.connection.send(sequencer.next(reading))) sent += 1;
    }
    viewer.placeRig(viewer.presenting ? headsetLocal : null, recenter);
    if (time - lastHud > HUD_REFRESH_MS) {
      lastHud = time;
      renderHud();
    }
  };

  const removeFrame = viewer.onFrame(onFrame);
  // Every few seconds: how this page draws, in the toolbar and (for the operator of a
  // running session) into the record.
  let reportsSent = 0;
  const removeReports = viewer.onFrameReport((report) => {
    frameBadge.textContent = describeReport(report);
    if (app.sessionActive && app.isOperator && app.connection.send({ type: "frame_stats", ...report })) reportsSent += 1;
  });
  const unsubscribe = app.subscribe((event) => {
    if (event.kind === "session" && app.ended !== null) controls.loadStudy(); // progress moved on
    if (event.kind === "session" || event.kind === "task_event") renderOverlay();
    if (event.kind === "link") renderHud();
  });
  controls.loadStudy();
  renderOverlay();
  renderHud();

  const removeExtra = exposeExtra("teleop", () => ({
    view: viewer.viewMode,
    presenting: viewer.presenting,
    xr_frames: xrFrames,
    frames: viewer.frameCount,
    draw_calls: viewer.renderer.info.render.calls,
    frame_report: viewer.frameMeter.latest,
    frame_reports_sent: reportsSent,
    inputs_sent: sent,
    last_input: sequencer.last,
    grips_latched: desktop.gripsLatched,
    triggers_latched: desktop.triggersLatched,
    overlay: overlay.className,
    hud: {
      mode: hudMode,
      where: hudPlaced?.where ?? null,
      visible: hudPanel.mesh.visible,
      off_axis_deg:
        hudPlaced === null ? null : offAxisDegrees([headsetLocal.x, headsetLocal.y, headsetLocal.z], hudPlaced.position),
    },
    comfort: {
      vignette: vignette.strength,
      vignette_peak: vignettePeak,
      base_speed: baseMotion.speed,
      turn: turnMode,
      snaps: snapTurn.snaps,
      blackout: vignette.blackedOut,
    },
    menu: { open: menu.state.open, index: menu.state.index, stop_armed: controls.stopArmed },
    paused: app.paused,
    study_next: controls.study?.next ?? null,
    recenter_yaw: recenter.yaw,
    actions: [...actions],
  }));

  const removeCapture = exposeCapture("hud_panel", () => hudPanel.canvas.toDataURL("image/png"));

  return () => {
    controls.dispose();
    removeCapture();
    removeExtra();
    removeFrame();
    removeReports();
    unsubscribe();
    desktop.dispose();
    viewer.rig.remove(hudPanel.mesh);
    viewer.camera.remove(vignette.mesh);
    viewer.rig.remove(menu.mesh);
    for (const m of markers.meshes) viewer.rig.remove(m);
    xr.onChange = null;
    void xr.exit();
    viewer.unmount();
    page.remove();
  };
}
