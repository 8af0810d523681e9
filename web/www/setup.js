// Set-up: the gimbal's settings (read back from it, written after a
// confirm()), the soft limits, and the versions and config path.
import { $, api, attempt, say } from './api.js';
import { applyLimits } from './control.js';

let current = null; // the settings as last read from the gimbal

export function setupSetup() {
  $('settings-form').addEventListener('submit', (event) => {
    event.preventDefault();
    save(event.currentTarget);
  });
  $('settings-reload').addEventListener('click', () => loadSettings());
}

export async function loadSetup() {
  await Promise.all([loadSettings(), loadLimits(), loadVersion()]);
}

function show(settings) {
  current = settings;
  const form = $('settings-form');
  form.elements.dead_zone.value = settings.dead_zone;
  form.elements.follow_speed.value = settings.follow_speed;
  form.elements.inverted.checked = Boolean(settings.inverted);
}

const describe = (s) => `dead zone ${s.dead_zone}, follow speed ${s.follow_speed}, ${s.inverted ? 'inverted' : 'upright'}`;

async function loadSettings() {
  $('settings-readback').textContent = 'reading from the gimbal…';
  let viewOnly = false;
  const settings = await attempt('settings', () => api('GET', '/api/settings').catch((e) => {
    if (e.status !== 403) throw e;
    viewOnly = true; // reading them is a control login's (docs/web.md, "Roles")
    return undefined;
  }));
  if (viewOnly) {
    $('settings-readback').textContent = 'a control login reads the gimbal\'s settings';
    return;
  }
  if (!settings) {
    $('settings-readback').textContent = 'could not read the settings';
    return;
  }
  show(settings);
  $('settings-readback').textContent = `read from the gimbal: ${describe(settings)}`;
}

// Only the fields that differ from the gimbal's are written.
function changes(form) {
  const wanted = {
    dead_zone: Number(form.elements.dead_zone.value),
    follow_speed: Number(form.elements.follow_speed.value),
    inverted: form.elements.inverted.checked,
  };
  const diff = {};
  for (const [key, value] of Object.entries(wanted)) {
    if (!current || current[key] !== value) diff[key] = value;
  }
  return diff;
}

async function save(form) {
  const diff = changes(form);
  const keys = Object.keys(diff);
  if (keys.length === 0) {
    say('nothing changed');
    return;
  }
  const lines = keys.map((k) => `${k}: ${current ? current[k] : '?'} → ${diff[k]}`);
  if (!window.confirm(`Write to the gimbal?\n${lines.join('\n')}`)) return;
  $('settings-readback').textContent = 'writing…';
  const readBack = await attempt('settings', () => api('POST', '/api/settings', diff));
  if (!readBack) {
    $('settings-readback').textContent = 'not written';
    return;
  }
  show(readBack);
  const held = keys.every((k) => readBack[k] === diff[k]);
  $('settings-readback').textContent = `read back: ${describe(readBack)}${held ? '' : ' (differs from what was written!)'}`;
  say(held ? 'settings written and read back' : 'the gimbal holds other values than written', held ? 'info' : 'error');
}

async function loadLimits() {
  const limits = await attempt('limits', () => api('GET', '/api/limits'));
  if (!limits) return;
  const body = $('limits').tBodies[0];
  body.replaceChildren();
  for (const axis of ['roll', 'pitch', 'yaw']) {
    const range = limits[axis] || {};
    const row = body.insertRow();
    row.dataset.testid = `limits-${axis}`;
    for (const text of [axis, `${range.min}°`, `${range.max}°`]) row.insertCell().textContent = text;
  }
  $('limits-max-speed').textContent = limits.max_speed;
  $('limits-braking-margin').textContent = limits.braking_margin_deg;
  const speed = $('jog-speed');
  if (typeof limits.max_speed === 'number') speed.max = String(Math.min(90, limits.max_speed));
  applyLimits(limits);
}

async function loadVersion() {
  const version = await attempt('version', () => api('GET', '/api/version'));
  if (!version) return;
  const list = $('version');
  list.replaceChildren();
  // Whatever gport-web reports (its version, gportd's, the config path), key by key.
  for (const [key, value] of Object.entries(version)) {
    const dt = document.createElement('dt');
    dt.textContent = key.replaceAll('_', ' ');
    const dd = document.createElement('dd');
    dd.dataset.testid = `version-${key.replaceAll('_', '-')}`;
    dd.textContent = typeof value === 'object' && value !== null ? JSON.stringify(value) : String(value);
    list.append(dt, dd);
  }
}
