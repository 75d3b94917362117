// The shape of `window.__workcell` (see debug.ts): what the end-to-end tests read from
// outside the page, typed here once for the page and the tests (web/tests/e2e) alike.

import type { LinkInfo } from "./net/connection";
import type { FrameReport } from "./scene/frameMeter";
import type {
  Hud,
  PlannedStep,
  Input,
  Pose,
  Role,
  SessionEnded,
  SessionStarted,
  State,
  TaskEvent,
  TrialEnded,
} from "./protocol";

/** What the teleoperation page adds (`teleop`). */
export interface TeleopDebug {
  view: "first" | "third";
  presenting: boolean;
  xr_frames: number;
  frames: number;
  draw_calls: number;
  /** The view's last frame report (every few seconds; null until the first). */
  frame_report: FrameReport | null;
  /** Frame reports sent to the server (as the operator of a running session). */
  frame_reports_sent: number;
  inputs_sent: number;
  last_input: Input | null;
  grips_latched: boolean;
  triggers_latched: boolean;
  overlay: string;
  /** The headset HUD: its mode, where it is this frame, and how far off the robot's
   * forward view (degrees) it sits. */
  hud: {
    mode: "wrist" | "hidden";
    where: "wrist" | "parked" | "hidden" | null;
    visible: boolean;
    off_axis_deg: number | null;
  };
  /** The tunnel vignette's strength now and its peak so far (0..0.75), and the base speed it follows (m/s). */
  comfort: {
    vignette: number;
    vignette_peak: number;
    base_speed: number;
    /** How the right stick turns the base in the headset, snaps made, and whether a snap
     * blacks the view out now. */
    turn: "smooth" | "snap";
    snaps: number;
    blackout: boolean;
  };
  /** The in-VR menu: open, the highlighted item's index, and whether "Stop session" was
   * chosen once (choosing it again stops). */
  menu: { open: boolean; index: number; stop_armed: boolean };
  /** Whether the running trial stands paused. */
  paused: boolean;
  /** A study participant's next planned session (null: none, or not a participant). */
  study_next: PlannedStep | null;
  /** The headset heading that recentering made forward (radians; 0: never recentered). */
  recenter_yaw: number;
  /** Every operator action this page sent, as `action:source`. */
  actions: string[];
}

/** What the replay page adds (`replay`). */
export interface ReplayDebug {
  trial_id: string;
  loaded: boolean;
  /** Frames the reply carries (every `every`-th recorded one). */
  frames: number;
  /** The trial's recorded frames (the count the Sessions page shows). */
  recorded_frames: number;
  index: number;
  /** The recorded frame shown (from 0). */
  recorded_index: number;
  playing: boolean;
  t: number | null;
  base: Pose | null;
  /** Frames drawn while playing, and frames passed over to keep time. */
  drawn: number;
  skipped: number;
  /** Trial seconds shown per wall second since play began, as the frames were drawn
   * (null before a second of playing). */
  rate: number | null;
}

/** What a page adds to the snapshot, by name. */
export interface DebugExtras {
  teleop: TeleopDebug;
  replay: ReplayDebug;
}

export interface DebugSnapshot extends Partial<DebugExtras> {
  page: string;
  link: LinkInfo;
  role: Role;
  session_id: string | null;
  session_active: boolean;
  session: SessionStarted | null;
  ended: SessionEnded | null;
  last_trial_end: TrialEnded | null;
  hud: Hud | null;
  holding: boolean;
  state: Pick<State, "seq" | "t_sim" | "input_seq" | "following" | "tcp_targets"> | null;
  stats: { states: number; stale: number };
  events: TaskEvent[];
  errors: { code: string; message: string }[];
  scene_bodies: number;
  head_camera_body: string | null;
}

export interface WorkcellDebug {
  snapshot: () => DebugSnapshot;
  bodies: () => Record<string, Pose>;
  dropLink: () => void;
  capture: (name: string) => string | null;
}

declare global {
  interface Window {
    __workcell?: WorkcellDebug;
  }
}
