// The server's HTTP API: setup defaults, the session list, recorded trials for replay and
// a study's views (the participant's progress, the admin's overview).

import type { Defaults, ParticipantStatus, SessionList, StudyOverview, TrialReplay } from "../protocol";
import { serverUrl } from "../util/env";

async function getJson<T>(path: string): Promise<T> {
  const response = await fetch(serverUrl(path), { headers: { Accept: "application/json" } });
  if (!response.ok) {
    const body = await response.text().catch(() => "");
    throw new Error(`${path}: HTTP ${response.status} ${body.slice(0, 200)}`.trim());
  }
  return (await response.json()) as T;
}

export function fetchDefaults(): Promise<Defaults> {
  return getJson<Defaults>("api/defaults");
}

export function fetchSessions(): Promise<SessionList> {
  return getJson<SessionList>("api/sessions");
}

export function fetchReplay(trialId: string, every: number): Promise<TrialReplay> {
  const id = encodeURIComponent(trialId);
  return getJson<TrialReplay>(`api/trials/${id}/frames?every=${every}`);
}

/** The participant's study status, or null when the page was not opened with a study
 * participant's invite (no study, or the admin's link). */
export async function fetchParticipant(): Promise<ParticipantStatus | null> {
  const response = await fetch(serverUrl("api/study/me"), { headers: { Accept: "application/json" } });
  if (response.status === 204) return null;
  if (!response.ok) throw new Error(`api/study/me: HTTP ${response.status}`);
  return (await response.json()) as ParticipantStatus;
}

export function fetchStudy(): Promise<StudyOverview> {
  return getJson<StudyOverview>("api/study");
}

/** The admin ends a participant's running session, for `reason` (their words, shown to the
 * participant; may be empty); the server's answer as text. */
export async function stopParticipant(participant: string, reason = ""): Promise<string> {
  const id = encodeURIComponent(participant);
  const response = await fetch(serverUrl(`api/study/participants/${id}/stop`), {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ reason }),
  });
  const body = (await response.json().catch(() => ({}))) as { error?: string };
  return response.ok ? `stopped ${participant}` : (body.error ?? `HTTP ${response.status}`);
}
