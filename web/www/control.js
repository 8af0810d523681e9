// Center, photo, recording on and off, stop, and angles (presets and typed)
// over the HTTP API.
import { $, api, attempt, say, fixed } from './api.js';

// Joint angles (pitch, yaw, roll in degrees).
const PRESETS = [
  { id: 'forward', label: 'Forward', pitch: 0, yaw: 0 },
  { id: 'down-30', label: 'Down 30°', pitch: -30, yaw: 0 },
  { id: 'down-45', label: 'Down 45°', pitch: -45, yaw: 0 },
  { id: 'nadir', label: 'Nadir', pitch: -90, yaw: 0 },
  { id: 'left-90', label: 'Left 90°', pitch: 0, yaw: -90 },
  { id: 'right-90', label: 'Right 90°', pitch: 0, yaw: 90 },
];

let ownMotionAt = 0; // when this page last asked for an angle or the centre
export const lastOwnMotion = () => ownMotionAt;

let recording = 'unknown'; // gportd's assumed state: on, off or unknown
let recordedAt = 0; // when this page last set it (a status read before may still say otherwise)
const STATUS_AGE_MS = 2000; // a status is at most a second old, plus its second's period

export function setupControl() {
  $('center').addEventListener('click', () => center());
  $('photo').addEventListener('click', () => photo());
  $('record-on').addEventListener('click', () => record(true));
  $('record-off').addEventListener('click', () => record(false));
  $('stop').addEventListener('click', () => attempt('stop', () => api('POST', '/api/stop', {})));
  presetButtons();
  $('angle-form').addEventListener('submit', (event) => {
    event.preventDefault();
    const form = event.currentTarget;
    const target = {};
    for (const axis of ['pitch', 'yaw', 'roll']) target[axis] = Number(form.elements[axis].value);
    angle(target, form.elements.wait.checked);
  });
}

function presetButtons() {
  const box = $('presets');
  for (const preset of PRESETS) {
    const button = document.createElement('button');
    button.type = 'button';
    button.className = 'control';
    button.textContent = preset.label;
    button.dataset.testid = `preset-${preset.id}`;
    button.dataset.pitch = preset.pitch;
    button.dataset.yaw = preset.yaw;
    button.addEventListener('click', () => {
      const form = $('angle-form');
      form.elements.pitch.value = preset.pitch;
      form.elements.yaw.value = preset.yaw;
      form.elements.roll.value = 0;
      angle({ pitch: preset.pitch, yaw: preset.yaw, roll: 0 }, form.elements.wait.checked);
    });
    box.append(button);
  }
}

// Presets outside the soft limits are disabled (gportd would refuse them).
export function applyLimits(limits) {
  for (const button of $('presets').querySelectorAll('button')) {
    const inside = ['pitch', 'yaw'].every((axis) => {
      const v = Number(button.dataset[axis]);
      return !limits[axis] || (v >= limits[axis].min && v <= limits[axis].max);
    });
    button.dataset.outside = inside ? '' : 'yes';
    button.title = inside ? '' : 'outside the soft limits';
  }
}

async function angle(target, wait) {
  const out = $('angle-result');
  out.textContent = wait ? 'moving…' : '';
  ownMotionAt = Date.now();
  const result = await attempt('angle', () => api('POST', '/api/angle', { ...target, wait }));
  if (!result) {
    out.textContent = 'refused';
    return;
  }
  const sent = result.angle || target;
  let text = `sent pitch ${fixed(sent.pitch)} yaw ${fixed(sent.yaw)} roll ${fixed(sent.roll)}`;
  if (result.clamped && result.clamped.length) text += ` (clamped: ${result.clamped.join(', ')})`;
  if (result.ended) text += `; ${result.ended.reason} after ${result.ended.elapsed_ms} ms`;
  out.textContent = text;
}

async function center() {
  ownMotionAt = Date.now();
  const result = await attempt('center', () => api('POST', '/api/center', { wait: false }));
  if (result) say('centering');
}

async function photo() {
  const result = await attempt('photo', () => api('POST', '/api/photo', {}));
  if (result) say(result.capture ? `photo: capture ${result.capture.index}` : 'photo sent');
}

// gportd's assumed recording state (the gimbal never reports it): `unknown`
// at start and whenever the gimbal's line reopens.
export function showRecording(state, fromStatus = true) {
  if (fromStatus && Date.now() - recordedAt < STATUS_AGE_MS) return;
  recording = state === 'on' || state === 'off' ? state : 'unknown';
  for (const testid of ['recording', 'record-state']) $(testid).dataset.state = recording;
  $('record-state').textContent = recording;
  $('recording').textContent = recording === 'unknown' ? 'unknown (the gimbal never says)' : recording;
}

// Recording on or off: gportd sends a toggle only when its assumed state
// differs. While it is unknown (or with "force") one toggle is sent and
// taken as the new state: the page asks first, unless "force" is ticked.
async function record(on) {
  let force = $('record-force').checked;
  if (recording === 'unknown' && !force) {
    force = window.confirm('gportd does not know whether the camera is recording (the gimbal never ' +
      `says). Send one record toggle and take recording as ${on ? 'ON' : 'OFF'} from now? If the ` +
      `camera was already ${on ? 'recording, this stops it' : 'stopped, this starts it'}: check the camera.`);
    if (!force) return;
  }
  const result = await attempt('record', () => api('POST', '/api/record', force ? { on, force } : { on }));
  if (!result) return;
  $('record-force').checked = false;
  recordedAt = Date.now();
  showRecording(result.recording, false);
  say(result.sent ? `record: toggle sent, recording ${result.recording}` : `recording is already ${result.recording}: nothing sent`);
}
