// The server's HTTP API: setup defaults, the session list and recorded trials for replay.

import type { Defaults, SessionList, TrialReplay } from "../protocol";
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
