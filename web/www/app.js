// gport-web's page: wires the live socket to the views and the controls.
import { $, api, attempt, clearError, say, fixed } from './api.js';
import { Live } from './live.js';
import { Health } from './health.js';
import { Plot } from './plot.js';
import { Horizon } from './horizon.js';
import { Jog } from './jog.js';
import { setupControl, lastOwnMotion, showRecording } from './control.js';
import { setupSetup, loadSetup } from './setup.js';
import { setupCaptures, loadCaptures, noteStatus, onCapture } from './captures.js';

const live = new Live();
const health = new Health(live);
const plot = new Plot($('plot'));
const horizon = new Horizon($('horizon'));
const jog = new Jog(live, document.querySelector('.jog'), $('jog-speed'));
let role = null; // from hello: "control" or "view"
let webPid = null; // gport-web's pid at gportd (status.client): a motion by it is a browser's
let motionMine = false; // the running motion was started by this page

// ---- controls: a control login's, and only while gport-web and gportd are reachable
function updateControls() {
  const on = role === 'control' && health.up;
  for (const el of document.querySelectorAll('.control')) {
    el.disabled = !on || el.dataset.outside === 'yes';
  }
  jog.setEnabled(on);
}

// Everything read from gportd, read again: once gport-web and gportd are
// reachable, and each time they are again (gportd may be a new one, with
// another capture log and other settings). What failed meanwhile is past.
async function reload() {
  clearError();
  showStatus(await attempt('status', () => api('GET', '/api/status')));
  await Promise.all([loadSetup(), loadCaptures()]);
}

let wasUp = false;
let reloadTimer = 0;
function refresh() {
  health.render();
  updateControls();
  // After a hello, a `gportd` message says at once when gportd is away.
  if (health.up && !wasUp) {
    clearTimeout(reloadTimer);
    reloadTimer = setTimeout(() => { if (health.up) reload(); }, 100);
  }
  wasUp = health.up;
}

// ---- live values
function showAttitude(a) {
  if (!a || !a.imu || !a.hall) return;
  health.noteValues();
  for (const axis of ['roll', 'pitch', 'yaw']) {
    $(`imu-${axis}`).textContent = fixed(a.imu[axis]);
    $(`hall-${axis}`).textContent = fixed(a.hall[axis]);
  }
  plot.add(a);
  horizon.set(a.imu);
}

// This page's own motions: a jog while held, an angle or the centre just asked for.
const ownMotionNow = () => jog.held !== null || Date.now() - lastOwnMotion() < 1500;

// Who moves the gimbal: every browser's motion is gport-web's at gportd.
function who(owner) {
  if (!owner) return '';
  if (owner.pid !== webPid) return ` by pid ${owner.pid}`;
  return motionMine || jog.held !== null ? ' by this browser' : ' by another browser (through gport-web)';
}

function describeMotion(m) {
  if (!m) return 'none';
  const by = who(m.owner);
  if (m.mode === 'speed' && m.speed) {
    return `speed${by}: roll ${fixed(m.speed.roll)} pitch ${fixed(m.speed.pitch)} yaw ${fixed(m.speed.yaw)} °/s`;
  }
  if (m.target) return `${m.mode}${by} to pitch ${fixed(m.target.pitch)} yaw ${fixed(m.target.yaw)} roll ${fixed(m.target.roll)}`;
  return `${m.mode}${by}`;
}

function describeController(c) {
  if (!c) return 'nobody (no client holds exclusive control)';
  if (c.pid === webPid) return 'gport-web (for its browsers)';
  return `pid ${c.pid} (uid ${c.uid}), another client of gportd: this page's moves are refused`;
}

function showMotion(m) {
  if (m.change === 'started' || m.change === 'replaced') motionMine = ownMotionNow();
  if (m.change !== 'ended') {
    $('motion').textContent = describeMotion(m);
    return;
  }
  $('motion').textContent = `none (last: ${m.mode}${who(m.owner)}, ${m.reason})`;
  motionMine = false;
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
  health.noteValues();
  if (s.client && typeof s.client.pid === 'number') webPid = s.client.pid;
  health.setLink(s.link);
  $('frame-age').textContent = s.attitude_age_ms === null ? '–' : String(s.attitude_age_ms);
  $('motion').textContent = describeMotion(s.motion);
  $('controller').textContent = describeController(s.controller);
  showRecording(s.recording);
  $('clients').textContent = String(s.clients);
  showCounters(s.counters);
  noteStatus(s);
}

// ---- the socket
live.on('state', refresh);
live.on('closed', ({ opened }) => {
  health.lostSocket();
  refresh();
  // Refused before it opened: perhaps the session ended (unused for 12 h, or
  // a logout elsewhere); api() then goes to the login form. Unreachable: the banner says so.
  if (!opened) api('GET', '/api/status').catch(() => {});
});
live.on('hello', (params) => {
  role = params && params.role === 'control' ? 'control' : 'view';
  $('role').dataset.state = role;
  $('role').textContent = role === 'control' ? 'control' : 'view only';
  health.setGportd(true, 'connected'); // else a `gportd` message follows at once
  refresh();
});
live.on('gportd', (params) => {
  health.setGportd(Boolean(params && params.connected), params && params.reason);
  refresh();
});
live.on('attitude', showAttitude);
live.on('link', (link) => health.setLink(link));
live.on('status', showStatus);
live.on('motion', showMotion);
live.on('capture', onCapture);
live.on('error', (params) => {
  jog.release('refused');
  say(params && params.message ? params.message : 'refused', 'error');
});

$('retry').addEventListener('click', () => live.retryNow());
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
refresh();
live.start();
