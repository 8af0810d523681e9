// The HTTP API (docs/web.md, "HTTP API") and the page's message line.
// Every call goes to the same origin with the session cookie; a 401 means
// the session is gone, so the page goes back to the login form.

export const $ = (testid, root = document) => root.querySelector(`[data-testid="${testid}"]`);

let messageTimer = 0;
// Shows a message under the bar; errors stay until the next message.
export function say(text, kind = 'info') {
  const el = $('message');
  el.textContent = text;
  el.dataset.kind = kind;
  el.hidden = false;
  clearTimeout(messageTimer);
  if (kind !== 'error') messageTimer = setTimeout(() => { el.hidden = true; }, 4000);
}

// Hides the message line when it shows an error: called when what failed
// works again (gport-web or gportd reachable again), so that no error stays
// that is no longer so.
export function clearError() {
  const el = $('message');
  if (el.dataset.kind === 'error') el.hidden = true;
}

export class ApiError extends Error {
  constructor(status, message, code) {
    super(message);
    this.status = status;
    this.code = code;
  }
}

// fetch + JSON; throws ApiError with gport-web's (or gportd's) message.
export async function api(method, path, body) {
  const init = { method, credentials: 'same-origin', headers: { Accept: 'application/json' } };
  if (body !== undefined) {
    init.headers['Content-Type'] = 'application/json';
    init.body = JSON.stringify(body);
  }
  let response;
  try {
    response = await fetch(path, init);
  } catch (e) {
    throw new ApiError(0, `gport-web is not reachable (${e.message})`);
  }
  if (response.status === 401) {
    location.assign('/');
    throw new ApiError(401, 'not logged in');
  }
  const data = await response.json().catch(() => null);
  if (!response.ok) {
    const error = data && data.error ? data.error : {};
    throw new ApiError(response.status, error.message || `HTTP ${response.status}`, error.code);
  }
  return data;
}

// Runs an action, showing its error (and returning undefined) instead of throwing.
export async function attempt(what, action) {
  try {
    return await action();
  } catch (e) {
    say(`${what}: ${e.message}`, 'error');
    return undefined;
  }
}

export const fixed = (value, digits = 2) =>
  (typeof value === 'number' && Number.isFinite(value) ? value.toFixed(digits) : '–');
