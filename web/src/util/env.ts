// Where the server is and how to reach it: the page's own origin, the auth token from the
// page address (`?token=`), and test switches (`?emulate=quest3`).

const TOKEN_KEY = "workcell.token";

function queryParam(name: string): string | null {
  return new URLSearchParams(window.location.search).get(name);
}

/** The server's auth token: from `?token=` (remembered for this tab) or none on loopback. */
export function authToken(): string | null {
  const fromQuery = queryParam("token");
  if (fromQuery !== null && fromQuery !== "") {
    sessionStorage.setItem(TOKEN_KEY, fromQuery);
    return fromQuery;
  }
  return sessionStorage.getItem(TOKEN_KEY);
}

/** An address relative to the page (so a server mounted under a prefix works), with the token. */
export function serverUrl(path: string, protocol: "http" | "ws" = "http"): string {
  const url = new URL(path, window.location.href);
  url.hash = "";
  const token = authToken();
  if (token !== null) url.searchParams.set("token", token);
  if (protocol === "ws") url.protocol = url.protocol === "https:" ? "wss:" : "ws:";
  return url.toString();
}

/** `?emulate=quest3`: install the IWER emulated Meta Quest 3 (tests, development). */
export function emulatedDevice(): string | null {
  return queryParam("emulate");
}

/** `?seat=2`: the seat (session) a spectator watches on a server with several; none: the first. */
export function requestedSeat(): string | null {
  const seat = queryParam("seat");
  return seat === null || seat === "" ? null : seat;
}

/** `?role=spectator` joins a running session read-only. */
export function requestedRole(): "operator" | "spectator" {
  return queryParam("role") === "spectator" ? "spectator" : "operator";
}

/** `?quality=low` (and any emulated device): no antialiasing, for software-rendered tests. */
export function lowQuality(): boolean {
  return queryParam("quality") === "low" || queryParam("emulate") !== null;
}

/** `?turn=snap`: the headset starts with snap turns (the in-VR menu switches them). */
export function snapTurnRequested(): boolean {
  return queryParam("turn") === "snap";
}
