// `window.__workcell`: read-only page state for end-to-end tests and for debugging in the
// browser console. Tests poll `window.__workcell.snapshot()` from outside the page.

import type { App } from "./app";
import type { DebugExtras, DebugSnapshot } from "./debugSnapshot";
import type { Pose } from "./protocol";

const extras = new Map<keyof DebugExtras, () => DebugExtras[keyof DebugExtras]>();
const captures = new Map<string, () => string>();

/** A picture a test may ask for by name (a data: URL), outside the polled snapshot. */
export function exposeCapture(name: string, capture: () => string): () => void {
  captures.set(name, capture);
  return () => {
    if (captures.get(name) === capture) captures.delete(name);
  };
}

/** A page adds what only it knows (view mode, last input sent, ...). */
export function exposeExtra<K extends keyof DebugExtras>(name: K, read: () => DebugExtras[K]): () => void {
  extras.set(name, read);
  return () => {
    if (extras.get(name) === read) extras.delete(name);
  };
}

/** Every dynamic body's newest world pose, by name. */
export function bodyPoses(app: App): Record<string, Pose> {
  const out: Record<string, Pose> = {};
  const scene = app.scene;
  const state = app.state;
  if (scene === null || state === null) return out;
  for (const body of scene.bodies) {
    const pose = body.dynamic ? state.poses[body.index] : body.pose;
    if (pose !== undefined) out[body.name] = pose;
  }
  return out;
}

export function exposeDebug(app: App): void {
  window.__workcell = {
    bodies: () => bodyPoses(app),
    dropLink: () => app.connection.dropForTest(),
    capture: (name) => captures.get(name)?.() ?? null,
    snapshot: () => {
      const state = app.state;
      const snapshot: DebugSnapshot = {
        page: window.location.hash,
        link: { ...app.connection.info },
        role: app.connection.role,
        session_id: app.sessionId,
        session_active: app.sessionActive,
        session: app.session,
        ended: app.ended,
        last_trial_end: app.lastTrialEnd,
        hud: app.hud,
        holding: app.holding,
        state:
          state === null
            ? null
            : {
                seq: state.seq,
                t_sim: state.t_sim,
                input_seq: state.input_seq,
                following: state.following,
                tcp_targets: state.tcp_targets,
              },
        stats: { ...app.stats },
        events: app.events.slice(-60),
        errors: app.errors.slice(-20),
        scene_bodies: app.scene?.bodies.length ?? 0,
        head_camera_body: app.scene?.head_camera_body ?? null,
      };
      return Object.assign(snapshot, Object.fromEntries([...extras].map(([name, read]) => [name, read()])));
    },
  };
}
