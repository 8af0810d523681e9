// The capture log: a paged table (GET /api/captures), and a scatter plot of
// where the photos were taken, in metres east and north of the first
// capture with a position (from /api/captures.geojson; no map tiles).
import { $, api, attempt, fixed } from './api.js';
import { fit, css, niceStep } from './canvas.js';

const PAGE = 20;
const EARTH_M = 6371008.8;

let since = null; // the page shown: its `since`, or null for the newest page
let page = null; // gportd's answer for it
let nextIndex = 1; // status.captures.next_index, as last seen

export function setupCaptures() {
  $('captures-older').addEventListener('click', () => {
    const first = page && page.captures.length ? page.captures[0].index : nextIndex;
    showPage(Math.max(0, first - PAGE));
  });
  $('captures-newer').addEventListener('click', () => {
    if (page && page.more) showPage(page.next);
  });
  $('captures-latest').addEventListener('click', () => showPage(null));
  new ResizeObserver(() => drawMap()).observe($('captures-map'));
}

export function noteStatus(status) {
  if (status && status.captures && typeof status.captures.next_index === 'number') {
    nextIndex = status.captures.next_index;
  }
}

// A new capture (the `capture` notification): the newest page follows it.
export function onCapture(capture) {
  if (capture && typeof capture.index === 'number') nextIndex = Math.max(nextIndex, capture.index + 1);
  if (since === null) showPage(null);
  loadMap();
}

export async function loadCaptures() {
  await Promise.all([showPage(null), loadMap()]);
}

const fetchPage = (start) => attempt('captures', () => api('GET', `/api/captures?since=${start}&limit=${PAGE}`));

async function showPage(from) {
  since = from;
  let start = from === null ? Math.max(0, nextIndex - PAGE) : from;
  let result = await fetchPage(start);
  // The newest page: when more were added than status said, move on to them
  // (a bounded number of times: the log keeps at most 4096).
  for (let hops = 0; result && from === null && result.more && hops < 256; hops += 1) {
    nextIndex = Math.max(nextIndex + PAGE, result.next + 1);
    start = Math.max(0, nextIndex - PAGE);
    result = await fetchPage(start);
  }
  if (!result || !Array.isArray(result.captures)) return;
  // Only objects are rows (gportd writes no other; a lying answer could).
  result.captures = result.captures.filter((c) => c !== null && typeof c === 'object');
  page = result;
  render(result.captures);
  const first = result.captures.length ? result.captures[0].index : start;
  $('captures-older').disabled = first <= 1;
  $('captures-newer').disabled = !result.more;
  $('captures-page').textContent = result.captures.length
    ? `#${first}–#${result.captures[result.captures.length - 1].index}` : 'no captures yet';
}

// A number when it is a finite one, else null.
const finite = (value) => (typeof value === 'number' && Number.isFinite(value) ? value : null);

// An accuracy (1σ, metres) when it is one: finite and not negative.
const accuracyOf = (value) => (finite(value) !== null && value >= 0 ? value : null);

// µs since the epoch as ISO 8601 UTC; null when it is no time a Date holds
// (the log is read back from files: a utc_us of 1e20 would make
// toISOString throw and end the table).
function isoTime(us) {
  const date = new Date(finite(us) === null ? NaN : us / 1000);
  return Number.isNaN(date.getTime()) ? null : date.toISOString();
}

// Where a capture was taken, by the rule the CSV, the GeoJSON (and so the
// plot) and gportctl geotag follow (libgport-client's capture_position;
// docs/api.md, "The capture log as CSV and GeoJSON"): gportd's stamp when
// it tagged the capture; nothing when it marked it untagged (the caller's
// meta is older still, so a place from it would be wrong, not approximate);
// the meta when gportd had no vehicle source. {from, text, title}: which of
// the three (`vehicle`, `untagged`, `meta`), the cell and its tooltip (none
// for the meta).
function position(capture) {
  const vehicle = capture.vehicle;
  // Absent, null, or a shape gportd never writes: no stamp, as the library
  // reads it (only a JSON object is one).
  if (vehicle === null || typeof vehicle !== 'object' || Array.isArray(vehicle)) {
    return { from: 'meta', text: metaPosition(capture.meta) };
  }
  // Anything but `tagged: true` is untagged, so an odd stamp never places
  // a capture.
  if (vehicle.tagged !== true) {
    const why = typeof vehicle.why === 'string' ? vehicle.why : 'untagged by gportd';
    const utc = isoTime(vehicle.utc_us);
    return { from: 'untagged', text: `untagged: ${why}`, title: `marked untagged by gportd${utc ? `\nGPS UTC ${utc}` : ''}` };
  }
  return stamped(vehicle);
}

// A tagged stamp: "lat, lon ±h m". Without a valid latitude and longitude
// it places nothing, like an untagged one (half a position is none).
function stamped(vehicle) {
  const lat = finite(vehicle.lat);
  const lon = finite(vehicle.lon);
  if (lat === null || lon === null || Math.abs(lat) > 90 || Math.abs(lon) > 180) {
    return { from: 'untagged', text: 'untagged: no position' };
  }
  const hAcc = accuracyOf(vehicle.h_acc_m);
  const accuracy = hAcc === null ? '' : ` ±${hAcc.toFixed(1)} m`;
  return { from: 'vehicle', text: `${lat.toFixed(6)}, ${lon.toFixed(6)}${accuracy}`, title: stampTitle(vehicle) };
}

// The rest of the stamp, a line for each member the source published.
function stampTitle(vehicle) {
  const alt = finite(vehicle.alt_msl_m);
  const hAcc = accuracyOf(vehicle.h_acc_m);
  const vAcc = accuracyOf(vehicle.v_acc_m);
  const heading = finite(vehicle.heading_deg);
  const age = finite(vehicle.age_ms);
  const utc = isoTime(vehicle.utc_us);
  const accuracy = [hAcc === null ? null : `±${hAcc.toFixed(1)} m horizontal`,
    vAcc === null ? null : `±${vAcc.toFixed(1)} m vertical`].filter(Boolean);
  const lines = [];
  if (alt !== null) lines.push(`altitude ${alt.toFixed(2)} m MSL`);
  if (accuracy.length) lines.push(`accuracy ${accuracy.join(', ')} (1σ)`);
  if (heading !== null) lines.push(`heading ${heading.toFixed(1)}°`);
  if (utc) lines.push(`GPS UTC ${utc}`);
  // The position was carried with the velocity from its sample to the shutter.
  lines.push(`stamped by gportd at the shutter${age === null ? '' : ` (position carried ${age} ms)`}`);
  return lines.join('\n');
}

// A capture's position as its meta gives it: both coordinates when they are
// numbers; whatever is there otherwise (a client's meta is its own: lat
// without lon, a string, null), never an exception that would end the table.
function coordinate(value) {
  if (typeof value === 'number' && Number.isFinite(value)) return value.toFixed(6);
  return value === undefined ? '?' : JSON.stringify(value);
}

function metaPosition(value) {
  const meta = value && typeof value === 'object' ? value : {};
  if (meta.lat === undefined && meta.lon === undefined) return '–';
  return `${coordinate(meta.lat)}, ${coordinate(meta.lon)}`;
}

function render(captures) {
  const body = $('captures-table').tBodies[0];
  body.replaceChildren();
  for (const c of captures.slice().reverse()) {
    const row = body.insertRow();
    row.dataset.testid = 'capture-row';
    row.dataset.index = c.index;
    row.dataset.kind = c.kind;
    const hall = c.attitude && c.attitude.hall ? c.attitude.hall : {};
    const utc = isoTime(c.utc_us);
    const where = position(c);
    const cells = [
      c.index,
      utc ? utc.slice(11, 23) : '–',
      c.kind,
      fixed(hall.pitch),
      fixed(hall.yaw),
      where.text,
      c.client ? `${c.client.name || ''} (pid ${c.client.pid})` : '–',
    ];
    // Text only: a reason, a meta and a client name are others' words.
    for (const text of cells) row.insertCell().textContent = String(text);
    if (utc) row.cells[1].title = utc;
    row.cells[5].dataset.position = where.from; // an untagged reason may wrap (style.css)
    if (where.title) row.cells[5].title = where.title;
  }
}

// ---- the scatter plot
let points = []; // {east, north, index}

async function loadMap() {
  const geo = await attempt('captures.geojson', () => api('GET', '/api/captures.geojson'));
  if (!geo) return;
  points = localMetres((Array.isArray(geo.features) ? geo.features : []).filter(placeable));
  $('captures-map-note').textContent = points.length
    ? `${points.length} capture(s) with a position; metres east and north of the first`
    : 'no capture has a position yet: it comes from gportd\'s stamp of the vehicle at the shutter '
      + '(when a source such as gport-mavlink publishes it), else from the photo\'s meta (lat/lon)';
  drawMap();
}

// A GeoJSON Point the plot can place: a finite longitude and latitude in
// their ranges. gport-web writes no other; one read back from a file, or a
// server that lies, never ends the plot or makes its scale NaN.
function placeable(f) {
  const c = f && f.geometry && f.geometry.type === 'Point' ? f.geometry.coordinates : null;
  if (!Array.isArray(c)) return false;
  const [lon, lat] = [finite(c[0]), finite(c[1])];
  return lon !== null && lat !== null && Math.abs(lon) <= 180 && Math.abs(lat) <= 90;
}

// Equirectangular projection around the first point: exact enough over the
// few kilometres a flight covers.
function localMetres(features) {
  if (features.length === 0) return [];
  const [lon0, lat0] = features[0].geometry.coordinates;
  const k = (Math.PI / 180) * EARTH_M;
  return features.map((f) => {
    const [lon, lat] = f.geometry.coordinates;
    return {
      east: (lon - lon0) * k * Math.cos((lat0 * Math.PI) / 180),
      north: (lat - lat0) * k,
      index: f.properties && typeof f.properties === 'object' ? f.properties.index : undefined,
    };
  });
}

function drawMap() {
  const canvas = $('captures-map');
  const { ctx, w, h } = fit(canvas);
  ctx.clearRect(0, 0, w, h);
  axes(ctx, w, h);
  if (points.length === 0) {
    ctx.textAlign = 'center';
    ctx.fillText('no positions yet', w / 2, h / 2 - 8);
    ctx.textAlign = 'start';
    return;
  }
  const span = Math.max(10, ...points.map((p) => Math.max(Math.abs(p.east), Math.abs(p.north))));
  const scale = (Math.min(w, h) / 2 - 20) / span; // px per metre, same both ways
  const x = (e) => w / 2 + e * scale;
  const y = (n) => h / 2 - n * scale;
  ctx.fillStyle = css('--accent');
  for (const p of points) {
    ctx.beginPath();
    ctx.arc(x(p.east), y(p.north), 3.5, 0, 2 * Math.PI);
    ctx.fill();
  }
  ctx.strokeStyle = css('--bad');
  ctx.lineWidth = 2;
  ctx.strokeRect(x(0) - 5, y(0) - 5, 10, 10); // the first capture
  scaleBar(ctx, w, h, scale);
}

function axes(ctx, w, h) {
  ctx.strokeStyle = css('--line');
  ctx.lineWidth = 1;
  ctx.beginPath();
  ctx.moveTo(w / 2, 0);
  ctx.lineTo(w / 2, h);
  ctx.moveTo(0, h / 2);
  ctx.lineTo(w, h / 2);
  ctx.stroke();
  ctx.fillStyle = css('--muted');
  ctx.font = '12px system-ui, sans-serif';
  ctx.fillText('N', w / 2 + 4, 14);
  ctx.fillText('E', w - 14, h / 2 - 4);
}

function scaleBar(ctx, w, h, scale) {
  const metres = niceStep(w / 4 / scale, 1);
  const px = metres * scale;
  const x0 = 12;
  const y0 = h - 14;
  ctx.strokeStyle = css('--fg');
  ctx.fillStyle = css('--fg');
  ctx.lineWidth = 2;
  ctx.beginPath();
  ctx.moveTo(x0, y0 - 5);
  ctx.lineTo(x0, y0);
  ctx.lineTo(x0 + px, y0);
  ctx.lineTo(x0 + px, y0 - 5);
  ctx.stroke();
  ctx.font = '12px system-ui, sans-serif';
  ctx.fillText(metres >= 1000 ? `${metres / 1000} km` : `${metres} m`, x0 + px + 6, y0);
}
