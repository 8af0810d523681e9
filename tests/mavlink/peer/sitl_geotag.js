'use strict';
// sitl.js's mode "geotag" (issue 43, docs/performance.md, "Photos stamped at
// the shutter: ArduCopter SITL at 15 m/s"): how far from where the vehicle
// was is a photo's position, gportd's stamp (the capture's `vehicle`, the
// newest position carried with its velocity to the shutter) against the
// newest sample gport-mavlink had (the capture's `meta`, what a photo got
// before), in straight and level flight at 15 m/s and in a 30°/s turn.
//
// The ground station flies SITL in GUIDED with velocity targets
// (SET_POSITION_TARGET_LOCAL_NED at 20 Hz) and asks for GLOBAL_POSITION_INT
// at 50 Hz on its own link: the truth. gport-mavlink asks for it at 5 Hz
// on SERIAL1 (SET_MESSAGE_INTERVAL, as always) and publishes it to gportd.
// Photos every 0.617 s (out of step with the 5 Hz samples), alternately
// `gportctl photo` and IMAGE_START_CAPTURE to 1/100 (routed by ArduPilot to
// gport-mavlink's camera, which puts its newest position in the meta).
//
// One clock: CLOCK_MONOTONIC. node's process.hrtime and performance.now
// are it, and so are gportd's `line_mono_us`/`shutter_mono_us` and
// gport-sim's trace (its steady clock since it started: the start is
// found as the smallest read time minus t_ms over all its lines).
// gport-sim drains the line at 115200 baud (--baud), so the trace's time
// of a photo frame is its last byte's. The truth's boot times are put on
// the monotonic clock by the least delayed sample (arrival minus boot
// time, the smallest within 5 s once SITL's steady drift is taken out),
// and the 50 Hz track is interpolated at the instant gport-sim read the
// photo frame's last byte (and, for comparison, at gportd's
// shutter_mono_us). Figures and checks: see report(); every capture and
// the truth at it are kept in WORKDIR/geotag.json, the track in
// truth.jsonl.
const { execFile } = require('child_process');
const fs = require('fs');
const path = require('path');
const h = require('./harness');

const { check, figures, sleep, until } = h;
const MAV_CMD_NAV_TAKEOFF = 22;
const MAV_CMD_DO_SET_MODE = 176;
const MAV_CMD_COMPONENT_ARM_DISARM = 400;
const MAV_CMD_SET_MESSAGE_INTERVAL = 511;
const MAV_CMD_IMAGE_START_CAPTURE = 2000;
const GLOBAL_POSITION_INT = 33;
const GPS_RAW_INT = 24;
const GUIDED = 4;
const PARAM_INT16 = 4;
const PARAM_REAL32 = 9;

const SPEED = 15; // m/s
const TURN_RATE = 30; // °/s
const TURN_ASKED = 13.8; // m/s: what SITL turns at about 15 m/s with (see geotagRun)
const PERIOD_MS = 617; // between photos: not a multiple of the 200 ms position period
const PHOTOS = 20; // each phase
const ALTITUDE = 15; // m
const M_PER_DEG = 111318.84502145034; // ArduPilot's LOCATION_SCALING_FACTOR * 1e7

const monoUs = () => Number(process.hrtime.bigint() / 1000n);
// performance.now() (the trace's `hr`) on CLOCK_MONOTONIC, µs.
const perfToMonoUs = (() => {
  const offset = Number(process.hrtime.bigint()) / 1000 - performance.now() * 1000;
  return (ms) => ms * 1000 + offset;
})();

const percentile = (values, p) => {
  if (values.length === 0) return NaN;
  const sorted = [...values].sort((a, b) => a - b);
  return sorted[Math.min(sorted.length - 1, Math.max(0, Math.ceil(p * sorted.length) - 1))];
};
const stats = (values) => ({
  n: values.length, p50: percentile(values, 0.5), p95: percentile(values, 0.95),
  p99: percentile(values, 0.99), max: values.length ? Math.max(...values) : NaN,
});
const f2 = (v) => (Number.isFinite(v) ? v.toFixed(2) : '  - ');
const row = (label, s) => `${label.padEnd(34)} ${String(s.n).padStart(3)}  ${f2(s.p50).padStart(6)} ${f2(s.p95).padStart(6)} ` +
  `${f2(s.p99).padStart(6)} ${f2(s.max).padStart(6)}`;

// ---- the truth: SITL's GLOBAL_POSITION_INT at 50 Hz on the ground station's link
class Truth {
  constructor(gcs) { this.gcs = gcs; }
  samples() {
    return this.gcs.received.filter((r) => r.name === 'GLOBAL_POSITION_INT' && r.header.sysid === 1 && r.header.compid === 1);
  }
  // The track, by boot time, one sample per boot time, with each sample's
  // arrival minus boot time (µs).
  freeze() {
    const seen = new Set();
    this.track = this.samples().filter((r) => !seen.has(r.data.timeBootMs) && seen.add(r.data.timeBootMs))
      .map((r) => ({ boot: r.data.timeBootMs, mono: r.mono, lat: r.data.lat / 1e7, lon: r.data.lon / 1e7,
        alt: r.data.alt / 1000, vn: r.data.vx / 100, ve: r.data.vy / 100 }))
      .sort((a, b) => a.boot - b.boot);
    this.origin = this.track[0];
    // SITL's clock drifts against CLOCK_MONOTONIC (it fell behind by
    // 149-296 ppm, steadily, more under load): the drift is the slope of
    // the least squares line through the smallest arrival - boot time of
    // each second.
    const t0 = this.track[0].mono;
    const minima = [];
    for (const s of this.track) {
      const i = Math.floor((s.mono - t0) / 1e6);
      const off = s.mono - s.boot * 1000;
      if (!minima[i] || off < minima[i].off) minima[i] = { t: s.mono - t0, off };
    }
    const m = minima.filter(Boolean);
    const [mt, mo] = [m.reduce((a, x) => a + x.t, 0) / m.length, m.reduce((a, x) => a + x.off, 0) / m.length];
    this.drift = m.reduce((a, x) => a + (x.t - mt) * (x.off - mo), 0) / m.reduce((a, x) => a + (x.t - mt) ** 2, 0);
    this.t0 = t0;
  }
  // Boot time (ms, fractional) at a monotonic instant: the smallest
  // arrival - boot time, less the drift, of the samples that arrived
  // within 5 s of it, plus the drift at the instant.
  bootAt(monoUsAt) {
    let floor = Infinity;
    for (const s of this.track) {
      if (Math.abs(s.mono - monoUsAt) <= 5e6) floor = Math.min(floor, s.mono - s.boot * 1000 - this.drift * (s.mono - this.t0));
    }
    return (monoUsAt - floor - this.drift * (monoUsAt - this.t0)) / 1000;
  }
  // North/east metres from the first sample.
  ne(lat, lon) {
    return [(lat - this.origin.lat) * M_PER_DEG, (lon - this.origin.lon) * M_PER_DEG * Math.cos(h.rad(this.origin.lat))];
  }
  // The track interpolated at a monotonic instant: {n, e, alt, speed,
  // course, rate (°/s of the course over ±0.5 s), gap (ms between the two
  // samples)}, or null outside it.
  at(monoUsAt) {
    const boot = this.bootAt(monoUsAt);
    const t = this.track;
    let i = t.findIndex((s) => s.boot > boot);
    if (i <= 0) return null;
    const [a, b] = [t[i - 1], t[i]];
    const k = (boot - a.boot) / (b.boot - a.boot);
    const [na, ea] = this.ne(a.lat, a.lon);
    const [nb, eb] = this.ne(b.lat, b.lon);
    const course = (s) => h.deg(Math.atan2(s.ve, s.vn));
    const near = (dt) => t.reduce((best, s) => (Math.abs(s.boot - boot - dt) < Math.abs(best.boot - boot - dt) ? s : best));
    const [before, after] = [near(-500), near(500)];
    return {
      n: na + k * (nb - na), e: ea + k * (eb - ea), alt: a.alt + k * (b.alt - a.alt),
      vn: a.vn + k * (b.vn - a.vn), ve: a.ve + k * (b.ve - a.ve),
      speed: Math.hypot(a.vn + k * (b.vn - a.vn), a.ve + k * (b.ve - a.ve)),
      rate: h.wrap(course(after) - course(before)) / ((after.boot - before.boot) / 1000),
      gap: b.boot - a.boot,
    };
  }
  // Newest sample: {speed, alt_rel}.
  newest() {
    const s = this.samples().pop();
    return s ? { speed: Math.hypot(s.data.vx, s.data.vy) / 100, altRel: s.data.relativeAlt / 1000, boot: s.data.timeBootMs } : null;
  }
}

function velocityTarget(vn, ve, vd, an, ae, yawDeg) {
  const m = new h.common.SetPositionTargetLocalNed();
  m.timeBootMs = 0; m.targetSystem = 1; m.targetComponent = 1;
  m.coordinateFrame = 1; // MAV_FRAME_LOCAL_NED
  m.typeMask = 1 | 2 | 4 | 2048; // velocity, acceleration and yaw; no position, no yaw rate
  m.x = 0; m.y = 0; m.z = 0;
  m.vx = vn; m.vy = ve; m.vz = vd;
  m.afx = an; m.afy = ae; m.afz = 0;
  m.yaw = h.rad(yawDeg); m.yawRate = 0;
  return m;
}

// A command to 1/1 until its ACK is `result` 0 or `ms` pass; the last ACK's result.
async function commandAccepted(gcs, command, params, ms, every = 1000) {
  const end = Date.now() + ms;
  let last = null;
  while (Date.now() < end) {
    const t0 = Date.now();
    gcs.command(command, params);
    const ack = await until(() => gcs.acks.find((a) => a.t >= t0 && a.command === command), Math.min(every, 2000), 'ACK')
      .catch(() => null);
    if (ack) last = ack.result;
    if (ack && ack.result === 0) return 0;
    await sleep(Math.max(0, every - (Date.now() - t0)));
  }
  return last;
}

// The ground station's own streams: GLOBAL_POSITION_INT at 50 Hz (the
// truth) and GPS_RAW_INT at 5 Hz (the receiver's accuracy), asked until
// they come.
async function askTruth(gcs, truth) {
  for (let i = 0; i < 20; i += 1) {
    gcs.command(MAV_CMD_SET_MESSAGE_INTERVAL, [GLOBAL_POSITION_INT, 20000, 0, 0, 0, 0, 0]);
    gcs.command(MAV_CMD_SET_MESSAGE_INTERVAL, [GPS_RAW_INT, 200000, 0, 0, 0, 0, 0]);
    const t0 = monoUs();
    await sleep(1000);
    const n = truth.samples().filter((r) => r.mono >= t0).length;
    if (n >= 40) return n;
  }
  return 0;
}

function cliPhoto(gportctl, sock) {
  return new Promise((resolve) => {
    execFile(gportctl, ['--socket', sock, '--json', 'photo'], { timeout: 5000 }, (error, stdout, stderr) => {
      let index = null;
      try { index = JSON.parse(stdout.trim().split('\n').pop()).capture.index; } catch (e) { /* below */ }
      resolve({ ok: !error, index, stderr: stderr.trim() });
    });
  });
}

async function allCaptures(sock, since) {
  const out = [];
  for (let from = since, more = true; more;) {
    const page = (await h.rpc(sock, 'captures', { since: from, limit: 1000 })).result;
    out.push(...page.captures);
    [from, more] = [page.next, page.more];
  }
  return out;
}

// As soon as SITL answers (before the gimbal's discovery): the parameters
// and the ground station's streams. ANGLE_MAX 60° (at its default 30° the
// SITL quad holds only about 10 m/s), WPNAV_SPEED 20 m/s (the guided
// velocity's limit), WPNAV_ACCEL 10 m/s² (its acceleration's limit: a
// 30°/s turn at 15 m/s needs 7.9 m/s², the default is 2.5), WPNAV_SPEED_UP
// 5 m/s.
// SITL's EKF uses its GPS about 41 s after the start whatever else is set
// (EK3_GPS_CHECK 0 and EK3_GBIAS_P_NSE changed nothing): that is most of
// the test's time.
async function geotagPrepare(gcs) {
  await until(() => gcs.since(0, 'HEARTBEAT').find((m) => m.header.compid === 1), 20000, "SITL's heartbeat").catch(() => null);
  for (const [name, value, type] of [['ANGLE_MAX', 6000, PARAM_INT16],
    ['WPNAV_SPEED', 2000, PARAM_REAL32], ['WPNAV_ACCEL', 1000, PARAM_REAL32], ['WPNAV_SPEED_UP', 500, PARAM_REAL32]]) {
    const got = await h.setParam(gcs, name, value, type);
    check(got === value, `PARAM_SET ${name} ${value}: reads back ${got}`);
  }
  const rate = await askTruth(gcs, new Truth(gcs));
  check(rate >= 40, `the ground station's GLOBAL_POSITION_INT at 50 Hz (the truth): ${rate} in 1 s`);
}

async function geotagRun({ gcs, sock, gportctl, workRoot, started }) {
  const truth = new Truth(gcs);
  // GUIDED, armed (SITL's EKF needs its GPS first), taking off to ALTITUDE.
  const beat = () => gcs.since(0, 'HEARTBEAT').filter((m) => m.header.compid === 1).pop();
  const armStart = Date.now();
  let armed = false;
  while (!armed && Date.now() - armStart < 60000) {
    const hb = beat();
    if (!hb || hb.data.customMode !== GUIDED) await commandAccepted(gcs, MAV_CMD_DO_SET_MODE, [1, GUIDED, 0, 0, 0, 0, 0], 1000);
    else if (await commandAccepted(gcs, MAV_CMD_COMPONENT_ARM_DISARM, [1, 0, 0, 0, 0, 0, 0], 1000) === 0) armed = true;
  }
  figures.push(`armed in GUIDED ${((Date.now() - started) / 1000).toFixed(1)} s after SITL started` +
    ` (${((Date.now() - armStart) / 1000).toFixed(1)} s of trying)`);
  if (!check(armed, 'SITL armed in GUIDED')) return;
  const tookOff = await commandAccepted(gcs, MAV_CMD_NAV_TAKEOFF, [0, 0, 0, 0, 0, 0, ALTITUDE], 5000);
  check(tookOff === 0, `MAV_CMD_NAV_TAKEOFF ${ALTITUDE} m: ACK ${tookOff}`);
  const t0 = Date.now();
  // Off the ground (4 m): on to 15 m/s north while climbing on to ALTITUDE.
  const up = await until(() => { const n = truth.newest(); return n && n.altRel >= 4; }, 30000, 'the altitude')
    .catch(() => null);
  figures.push(`took off to ${truth.newest().altRel.toFixed(1)} m in ${((Date.now() - t0) / 1000).toFixed(1)} s`);
  if (!check(up !== null, 'took off (4 m)')) return;

  // Velocity targets at 20 Hz: north at 15 m/s, then turning at 30°/s
  // with the centripetal acceleration. In a steady turn ArduCopter's
  // guided velocity flies faster than asked with the acceleration and
  // slower without it (asked 15 m/s: 17.8 m/s and 10.6 m/s, every run;
  // following the speed flown with the speed asked oscillated, 9-18 m/s),
  // so the turn asks TURN_ASKED (12.6 flew 13.3 m/s, 13.5 14.3 m/s, 13.8
  // 14.7 m/s, after 13.2 m/s and 39°/s in the first seconds).
  let turnFrom = null; // monotonic µs
  const target = () => {
    const course = turnFrom === null ? 0 : TURN_RATE * Math.max(0, monoUs() - turnFrom) / 1e6;
    const c = h.rad(course);
    const w = turnFrom === null ? 0 : h.rad(TURN_RATE);
    const n = truth.newest();
    const asked = turnFrom === null ? SPEED : TURN_ASKED;
    const climb = n && n.altRel < ALTITUDE ? -Math.min(4, ALTITUDE - n.altRel) : 0;
    gcs.send(velocityTarget(asked * Math.cos(c), asked * Math.sin(c), climb, -w * asked * Math.sin(c), w * asked * Math.cos(c), course));
  };
  target();
  const targets = setInterval(target, 50);
  try {
    const t1 = Date.now();
    let fastSince = null;
    const fast = await until(() => {
      const n = truth.newest();
      if (n && n.speed >= SPEED - 0.5) fastSince = fastSince || Date.now(); else fastSince = null;
      return fastSince && Date.now() - fastSince >= 500;
    }, 30000, '15 m/s').catch(() => null);
    figures.push(`speed profile (s, m/s): ${profile(truth, t1)}`);
    figures.push(`reached ${truth.newest().speed.toFixed(1)} m/s ${((Date.now() - t1) / 1000).toFixed(1)} s after the first velocity target`);
    if (!check(fast !== null, `SITL holds ${SPEED - 0.5} m/s and more for 0.5 s`)) return;

    let since = 0;
    for (let more = true; more;) ({ next: since, more } = (await h.rpc(sock, 'captures', { since, limit: 1000 })).result);
    const requests = [];
    const take = async (phase, k) => {
      const via = k % 2 === 0 ? 'cli' : 'mavlink';
      const r = { phase, via, at: monoUs(), t: Date.now() };
      requests.push(r);
      if (via === 'cli') Object.assign(r, await cliPhoto(gportctl, sock));
      else gcs.commandTo(MAV_CMD_IMAGE_START_CAPTURE, [0, 0, 1, 0, 0, 0, 0], 100);
    };
    const series = async (phase) => {
      const start = monoUs();
      const pending = [];
      for (let k = 0; k < PHOTOS; k += 1) {
        const wait = (start + k * PERIOD_MS * 1000 - monoUs()) / 1000;
        if (wait > 0) await sleep(wait);
        pending.push(take(phase, k));
      }
      await Promise.all(pending);
    };
    const phases = {};
    phases.straight = { from: monoUs() };
    await series('straight');
    phases.straight.to = monoUs();
    turnFrom = monoUs();
    await sleep(2500); // rolled into the turn, the speed settled
    phases.turn = { from: monoUs() };
    await series('turn');
    phases.turn.to = monoUs();
    await sleep(800); // the last ACK
    clearInterval(targets);
    gcs.send(velocityTarget(0, 0, 0, 0, 0, 0));
    await report({ gcs, sock, truth, requests, phases, since, workRoot });
  } finally {
    clearInterval(targets);
  }
}

// Speed over time since `from` (Date.now()), every 0.5 s.
function profile(truth, from) {
  const out = [];
  let next = from;
  for (const r of truth.samples()) {
    if (r.t >= next) { out.push(`${((r.t - from) / 1000).toFixed(1)}:${(Math.hypot(r.data.vx, r.data.vy) / 100).toFixed(1)}`); next += 500; }
  }
  return out.join(' ');
}

async function report({ gcs, sock, truth, requests, phases, since, workRoot }) {
  truth.freeze();
  fs.writeFileSync(path.join(workRoot, 'truth.jsonl'), truth.track.map((s) => JSON.stringify(s)).join('\n') + '\n');
  const captures = (await allCaptures(sock, since)).filter((c) => c.kind === 'photo');
  // gport-sim's clock: its start on CLOCK_MONOTONIC (µs).
  const simStart = Math.min(...h.trace.filter((e) => typeof e.j.t_ms === 'number').map((e) => perfToMonoUs(e.hr) - e.j.t_ms * 1000));
  const frames = h.trace.filter((e) => e.j.cmd === '0x86' && e.j.action === 'photo')
    .map((e) => simStart + e.j.t_ms * 1000).filter((m) => m >= phases.straight.from);
  const mavlink = requests.filter((r) => r.via === 'mavlink');
  const acks = gcs.received.filter((r) => r.name === 'COMMAND_ACK' && r.header.compid === 100 &&
    r.data.command === MAV_CMD_IMAGE_START_CAPTURE && r.mono >= phases.straight.from);
  const cli = requests.filter((r) => r.via === 'cli');
  check(cli.every((r) => r.ok && r.index !== null), `${cli.length} \`gportctl photo\`: all sent ` +
    `(${cli.filter((r) => !r.ok).map((r) => r.stderr).join(' | ') || 'no error'})`);
  check(acks.length === mavlink.length && acks.every((a) => a.data.result === 0),
    `${mavlink.length} IMAGE_START_CAPTURE to 1/100: ${acks.length} ACKs, results ${[...new Set(acks.map((a) => a.data.result))].join(',')}`);
  check(captures.length === requests.length && frames.length === requests.length,
    `every photo taken: ${requests.length} asked, ${captures.length} in gportd's capture log, ${frames.length} photo frames on gport-sim's trace`);
  const untagged = captures.filter((c) => !(c.vehicle && c.vehicle.tagged));
  check(untagged.length === 0, `every capture tagged by gportd (${untagged.length} not` +
    `${untagged.length ? ': ' + untagged.map((c) => c.vehicle && c.vehicle.why).join(' | ') : ''})`);

  const rows = [];
  for (const c of captures) {
    const shutter = c.shutter_mono_us;
    // The photo frame gport-sim read nearest to gportd's instant.
    const frame = frames.reduce((best, m) => (best === null || Math.abs(m - shutter) < Math.abs(best - shutter) ? m : best), null);
    const instant = frame !== null && Math.abs(frame - shutter) < 50000 ? frame : null;
    const phase = shutter < phases.straight.to + 1e6 ? 'straight' : 'turn';
    const at = instant !== null ? truth.at(instant) : null;
    const atShutter = truth.at(shutter);
    const v = c.vehicle || {};
    const err = (lat, lon, t) => { const [n, e] = truth.ne(lat, lon); return Math.hypot(n - t.n, e - t.e); };
    // Along the track (+: ahead of the truth), in ms of flight; across it, in m.
    const ahead = (lat, lon, t) => { const [n, e] = truth.ne(lat, lon); return ((n - t.n) * t.vn + (e - t.e) * t.ve) / (t.speed * t.speed) * 1000; };
    const across = (lat, lon, t) => { const [n, e] = truth.ne(lat, lon); return Math.abs((e - t.e) * t.vn - (n - t.n) * t.ve) / t.speed; };
    rows.push({
      index: c.index, phase, via: c.meta ? 'mavlink' : 'cli',
      lineMinusSim: instant !== null ? (c.line_mono_us - instant) / 1000 : NaN,
      after: at && v.tagged ? err(v.lat, v.lon, at) : NaN,
      afterShutter: atShutter && v.tagged ? err(v.lat, v.lon, atShutter) : NaN,
      afterV: at && v.tagged ? Math.abs(v.alt_msl_m - at.alt) : NaN,
      before: at && c.meta && typeof c.meta.lat === 'number' ? err(c.meta.lat, c.meta.lon, at) : NaN,
      aheadMs: at && v.tagged ? ahead(v.lat, v.lon, at) : NaN,
      acrossM: at && v.tagged ? across(v.lat, v.lon, at) : NaN,
      beforeAheadMs: at && c.meta && typeof c.meta.lat === 'number' ? ahead(c.meta.lat, c.meta.lon, at) : NaN,
      instant, shutter,
      hAcc: v.h_acc_m, age: v.age_ms, speed: at ? at.speed : NaN, rate: at ? at.rate : NaN, gap: at ? at.gap : NaN,
    });
  }
  fs.writeFileSync(path.join(workRoot, 'geotag.json'), JSON.stringify({ rows, captures, requests }, null, 1));
  // SITL's clock against CLOCK_MONOTONIC. gportd maps the autopilot's
  // clock by the least delayed sample of the last 30 s: with a clock
  // falling behind, that is the oldest, up to drift x 30 s early.
  figures.push(`SITL's clock fell behind CLOCK_MONOTONIC by ${(truth.drift * 1e6).toFixed(0)} ppm ` +
    `(${(truth.drift * 30000).toFixed(1)} ms in 30 s, gportd's window for its clock mapping)`);
  const nan = rows.filter((r) => !Number.isFinite(r.after));
  check(nan.length === 0, `every capture has its truth (the photo frame on the trace, the 50 Hz track around it): ${nan.length} without`);
  const gps = gcs.received.filter((r) => r.name === 'GPS_RAW_INT' && r.mono >= phases.straight.from).map((r) => r.data.hAcc / 1000);
  const gpsAcc = gps.length ? Math.min(...gps) : 0;

  const table = ['horizontal error, m                  n    p50    p95    p99    max'];
  const result = {};
  for (const phase of ['straight', 'turn']) {
    const mine = rows.filter((r) => r.phase === phase);
    const after = stats(mine.map((r) => r.after).filter(Number.isFinite));
    const beforeS = stats(mine.map((r) => r.before).filter(Number.isFinite));
    result[phase] = { after, before: beforeS };
    table.push(row(`${phase}: before (meta, newest sample)`, beforeS));
    table.push(row(`${phase}: after (gportd's stamp)`, after));
    table.push(row(`${phase}: after, MAVLink photos only`, stats(mine.filter((r) => r.via === 'mavlink').map((r) => r.after))));
    table.push(row(`${phase}: after, at shutter_mono_us`, stats(mine.map((r) => r.afterShutter).filter(Number.isFinite))));
    table.push(row(`${phase}: after, vertical`, stats(mine.map((r) => r.afterV).filter(Number.isFinite))));
    const range = (k) => { const v = mine.map((r) => r[k]).filter(Number.isFinite); return `${f2(Math.min(...v))}..${f2(Math.max(...v))}`; };
    figures.push(`${phase}: the stamp ahead of the truth along the track by ${range('aheadMs')} ms of flight ` +
      `(median ${f2(percentile(mine.map((r) => r.aheadMs), 0.5))}), off it by ${range('acrossM')} m; ` +
      `the newest sample ahead by ${range('beforeAheadMs')} ms`);
    figures.push(`${phase}: ${mine.length} photos; speed ${range('speed')} m/s, course rate ${range('rate')} °/s; ` +
      `stamp age ${range('age')} ms, h_acc_m ${range('hAcc')}; line_mono_us - gport-sim's last byte ${range('lineMinusSim')} ms; ` +
      `truth samples ${range('gap')} ms apart`);
    // The stamp's accuracy claims: the part for the carry (h_acc_m - the
    // receiver's own) against the error (the truth is the autopilot's
    // estimate: its GPS error is in neither).
    const over = mine.filter((r) => r.after > r.hAcc - gpsAcc);
    figures.push(`${phase}: ${over.length} of ${mine.length} stamps with an error above their h_acc_m less the receiver's ` +
      `${gpsAcc.toFixed(2)} m${over.length ? ': ' + over.map((r) => `#${r.index} ${r.after.toFixed(2)} > ${r.hAcc} - ${gpsAcc}`).join(', ') : ''}`);
  }
  console.log(table.join('\n'));
  figures.push(...table);
  for (const phase of ['straight', 'turn']) {
    const { after, before } = result[phase];
    check(after.p95 <= 0.6, `${phase}: the stamp's error p95 ${f2(after.p95)} m <= 0.6 m (goal 0.3 m; p99 ${f2(after.p99)}, goal 0.6 m)`);
    check(after.p95 < before.p95, `${phase}: the stamp's p95 ${f2(after.p95)} m below the newest sample's ${f2(before.p95)} m`);
  }
  const speeds = rows.map((r) => r.speed);
  check(Math.min(...speeds) >= SPEED - 2.5 && Math.max(...speeds) <= SPEED + 2.5,
    `flown at ${SPEED} m/s: ${f2(Math.min(...speeds))} to ${f2(Math.max(...speeds))} m/s at the photos`);
  const turnRates = rows.filter((r) => r.phase === 'turn').map((r) => Math.abs(r.rate));
  check(percentile(turnRates, 0.5) >= TURN_RATE * 0.8, `turning at ${TURN_RATE}°/s: median ${f2(percentile(turnRates, 0.5))}°/s at the turn's photos`);
}

module.exports = { geotagPrepare, geotagRun };
