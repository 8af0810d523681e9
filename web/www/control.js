// Center, photo, record, stop, and angles (presets and typed) over the HTTP API.
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

export function setupControl() {
  $('center').addEventListener('click', () => center());
  $('photo').addEventListener('click', () => photo());
  $('record').addEventListener('click', () => record());
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
  const result = await attempt('center', () => api('POST', '/api/center', { wait: false }));
  if (result) say('centering');
}

async function photo() {
  const result = await attempt('photo', () => api('POST', '/api/photo', {}));
  if (result) say(result.capture ? `photo: capture ${result.capture.index}` : 'photo sent');
}

async function record() {
  const result = await attempt('record', () => api('POST', '/api/record', {}));
  if (result) say(`record: toggled; assumed ${result.recording || 'unknown'}`);
}
