// The teleoperation page's status texts: the toolbar's link badge (connected, in which role
// and with what round trip, or reconnecting, refused, connecting) and the hint line under
// the view (what a spectator watches, or the operator's grips and triggers).

import type { LinkInfo } from "../net/connection";
import type { DeviceFrame } from "../input/hands";
import type { Role } from "../protocol";

export function linkBadgeText(info: LinkInfo, role: Role): string {
  return info.status === "open"
    ? `● connected (${role}${info.rttMs !== null ? `, ${Math.round(info.rttMs)} ms` : ""})`
    : info.status === "reconnecting"
      ? `● reconnecting (attempt ${info.attempts})…`
      : info.status === "refused"
        ? `● refused: ${info.reason ?? ""}`
        : "● connecting…";
}

export function hintText(role: Role, seat: string, sessionActive: boolean, holding: boolean, frame: DeviceFrame | null): string {
  const left = frame?.left;
  const right = frame?.right;
  return role === "spectator"
    ? `Spectating seat ${seat}: another client operates.`
    : sessionActive
      ? `grip L ${(left?.grip ?? 0).toFixed(1)} R ${(right?.grip ?? 0).toFixed(1)} · trigger L ${(left?.trigger ?? 0).toFixed(1)} R ${(right?.trigger ?? 0).toFixed(1)}${holding ? " · holding a box" : ""}`
      : "";
}
