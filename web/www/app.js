// gport-web's page: wires the live socket to the views and the controls.
import { $, api, attempt, say, fixed } from './api.js';
import { Live } from './live.js';
import { Plot } from './plot.js';
import { Horizon } from './horizon.js';
import { Jog } from './jog.js';
import { setupControl } from './control.js';
import { setupSetup, loadSetup } from './setup.js';
import { setupCaptures, loadCaptures, noteStatus, onCapture } from './captures.js';

const live = new Live();
const plot = new Plot($('plot'));
const horizon = new Horizon($('horizon'));
const jog = new Jog(live, document.querySelector('.jog'), $('jog-speed'));
let role = null; // from hello: "control" or "view"

// ---- controls: enabled only for a control login (and the jog only with the socket open)
function updateControls() {
  const control = role === 'control';
  for (const el of document.querySelectorAll('.control')) {
    const jogButton = el.classList.contains('jog-btn');
    el.disabled = !control || (jogButton && !live.open) || el.dataset.outside === 'yes';
  }
  jog.setEnabled(control && live.open);
}

function setBadge(testid, state, text) {
  const el = $(testid);
  el.dataset.state = state;
  el.textContent = text;
}

// ---- live values
function showAttitude(a) {
  if (!a || !a.imu || !a.hall) return;
  for (const axis of ['roll', 'pitch', 'yaw']) {
    $(`imu-${axis}`).textContent = fixed(a.imu[axis]);
    $(`hall-${axis}`).textContent = fixed(a.hall[axis]);
  }
  plot.add(a);
  horizon.set(a.imu);
}

function showLink(link) {
  if (!link) return;
  setBadge('link', link.state, `link ${link.state}`);
  $('link-reason').textContent = `${link.state}: ${link.reason || ''}`;
}

function describeMotion(m) {
  if (!m) return 'none';
  const who = m.owner ? ` by pid ${m.owner.pid}` : '';
  if (m.mode === 'speed' && m.speed) {
    return `speed${who}: roll ${fixed(m.speed.roll)} pitch ${fixed(m.speed.pitch)} yaw ${fixed(m.speed.yaw)} °/s`;
  }
  if (m.target) return `${m.mode}${who} to pitch ${fixed(m.target.pitch)} yaw ${fixed(m.target.yaw)} roll ${fixed(m.target.roll)}`;
  return `${m.mode}${who}`;
}

function showCounters(counters) {
  const list = $('counters');
  list.replaceChildren();
  for (const [key, value] of Object.entries(counters || {})) {
    const dt = document.createElement('dt');
    dt.textContent = key.replaceAll('_', ' ');
    const dd = document.createElement('dd');
    dd.dataset.testid = `counter-${key.replaceAll('_', '-')}`;
    dd.textContent = String(value);
    list.append(dt, dd);
  }
}

function showStatus(s) {
  if (!s) return;
  showLink(s.link);
  $('frame-age').textContent = s.attitude_age_ms === null ? '–' : String(s.attitude_age_ms);
  $('motion').textContent = describeMotion(s.motion);
  $('controller').textContent = s.controller ? `pid ${s.controller.pid} (uid ${s.controller.uid})` : 'nobody';
  $('recording').textContent = s.recording || 'unknown';
  $('record').dataset.recording = s.recording || 'unknown';
  $('record').textContent = s.recording === 'on' ? 'Stop recording' : 'Record';
  $('clients').textContent = String(s.clients);
  showCounters(s.counters);
  noteStatus(s);
}

// ---- the socket
live.on('state', (state) => {
  setBadge('conn', state, state === 'open' ? 'live' : state);
  updateControls();
});
live.on('closed', ({ opened }) => {
  // Refused before it opened: perhaps the session ended (api() then goes to the login).
  if (!opened) attempt('status', () => api('GET', '/api/status'));
});
live.on('hello', (params) => {
  role = params && params.role === 'control' ? 'control' : 'view';
  setBadge('role', role, role === 'control' ? 'control' : 'view only');
  updateControls();
});
live.on('attitude', showAttitude);
live.on('link', showLink);
live.on('status', showStatus);
live.on('motion', (m) => {
  $('motion').textContent = m.change === 'ended' ? `none (last: ${m.mode} ${m.reason})` : describeMotion(m);
});
live.on('capture', onCapture);
live.on('error', (params) => {
  jog.release('refused');
  say(params && params.message ? params.message : 'refused', 'error');
});

$('jog-speed').addEventListener('input', (event) => {
  $('jog-speed-value').textContent = event.target.value;
});
$('logout').addEventListener('click', async () => {
  await fetch('/logout', { method: 'POST', credentials: 'same-origin' }).catch(() => {});
  location.assign('/');
});

setupControl();
setupSetup();
setupCaptures();
updateControls();
live.start();

const status = await attempt('status', () => api('GET', '/api/status'));
showStatus(status);
await Promise.all([loadSetup(), loadCaptures()]);
