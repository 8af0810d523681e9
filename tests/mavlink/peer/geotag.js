'use strict';
// Geotag by default (issue 31 item 4): node-mavlink plays an autopilot
// (system 1 component 1) that streams no GLOBAL_POSITION_INT or ATTITUDE
// until asked with MAV_CMD_SET_MESSAGE_INTERVAL, as ArduPilot on a serial
// port with its default stream rates; a ground station's commands reach
// gport-mavlink through it (one link, as ArduPilot forwards them). Then
// the autopilot stops and ignores requests: the bridge asks a bounded
// number of times and, at the next photo, says once what to set.
//
//   node geotag.js GPORTD GPORT_SIM GPORT_MAVLINK WORKDIR
const fs = require('fs');
const h = require('./harness');

const [gportdPath, simPath, bridgePath, workRoot] = process.argv.slice(2);
const { check, figures, sleep, until, common, Peer, heartbeat, commandLong } = h;
const CAMERA = 100;
const [IMAGE_START, SET_MESSAGE_INTERVAL] = [2000, 511];
const [ATTITUDE_ID, POSITION_ID, GPS_ID, TIME_ID] = [30, 33, 24, 2];
const POSITION = { lat: -353632621, lon: 1491652374, alt: 584070, relativeAlt: 30250 };
// The autopilot's clocks: its boot time, and a UTC 2026-11-29T00:00:00Z at boot.
const booted = Date.now();
const bootMs = () => Date.now() - booted;
const UTC_AT_BOOT_US = 1795910400000000n;

function position() {
  const m = new common.GlobalPositionInt();
  Object.assign(m, { timeBootMs: bootMs(), vx: 0, vy: 0, vz: 0, hdg: 3000 }, POSITION);
  return m;
}
function attitude() {
  const m = new common.Attitude();
  Object.assign(m, { timeBootMs: bootMs(), roll: 0, pitch: 0, yaw: 0.5, rollspeed: 0, pitchspeed: 0, yawspeed: 0 });
  return m;
}
function gps() {
  const m = new common.GpsRawInt();
  Object.assign(m, { timeUsec: BigInt(bootMs()) * 1000n, fixType: 3, lat: POSITION.lat, lon: POSITION.lon,
    alt: POSITION.alt, eph: 80, epv: 120, vel: 0, cog: 0, satellitesVisible: 14, altEllipsoid: 0,
    hAcc: 900, vAcc: 1500, velAcc: 0, hdgAcc: 0, yaw: 0 });
  return m;
}
function systemTime() {
  const m = new common.SystemTime();
  const boot = bootMs();
  Object.assign(m, { timeBootMs: boot, timeUnixUsec: UTC_AT_BOOT_US + BigInt(boot) * 1000n });
  return m;
}
const makers = { [POSITION_ID]: position, [ATTITUDE_ID]: attitude, [GPS_ID]: gps, [TIME_ID]: systemTime };
function commandAck(command, result, target) {
  const m = new common.CommandAck();
  Object.assign(m, { command, result, progress: 0, resultParam2: 0, targetSystem: target.sysid,
    targetComponent: target.compid });
  return m;
}
const cam = (params) => commandLong(IMAGE_START, { params, targetComponent: CAMERA });

async function main() {
  fs.rmSync(workRoot, { recursive: true, force: true });
  fs.mkdirSync(workRoot, { recursive: true });
  const { sock } = await h.startGimbal(workRoot, gportdPath, simPath);
  const port = await h.freeUdpPort();
  const bridge = h.start(workRoot, 'gport-mavlink', bridgePath,
    ['--socket', sock, '--mavlink', `udpin:127.0.0.1:${port}`, '--log-level', 'debug']);
  await until(() => bridge.lines.some((l) => /MAVLink on udpin/.test(l)), 10000, 'gport-mavlink to start');

  const autopilot = new Peer({ sysid: 1, compid: 1 });
  const gcs = new Peer({ sysid: 255, compid: 190 }); // its frames go through the autopilot's link
  await autopilot.bind(); autopilot.target(port);
  // The autopilot: answers SET_MESSAGE_INTERVAL and streams at the asked
  // interval while `obliging`.
  let obliging = true;
  const streams = {};
  const requests = [];
  const serve = setInterval(() => {
    for (const r of autopilot.received.filter((x) => x.name === 'COMMAND_LONG' && !x.seen)) {
      r.seen = true;
      if (r.data.command !== SET_MESSAGE_INTERVAL) continue;
      requests.push({ t: Date.now(), header: r.header, data: r.data });
      if (!obliging) continue;
      autopilot.send(commandAck(SET_MESSAGE_INTERVAL, 0, r.header));
      const id = r.data._param1;
      clearInterval(streams[id]);
      const make = makers[id];
      if (make) streams[id] = setInterval(() => autopilot.send(make()), r.data._param2 / 1000);
    }
  }, 20);
  const beats = setInterval(() => autopilot.send(heartbeat()), 1000);
  const t0 = Date.now();
  autopilot.send(heartbeat());

  // 1. No position and no attitude from the autopilot: the bridge asks for both.
  const asked = (id, since = t0) => requests.filter((r) => r.t >= since && r.data._param1 === id);
  await until(() => asked(POSITION_ID).length && asked(ATTITUDE_ID).length, 10000, 'SET_MESSAGE_INTERVAL').catch(() => null);
  const [pos, att] = [asked(POSITION_ID)[0], asked(ATTITUDE_ID)[0]];
  check(pos && att, `SET_MESSAGE_INTERVAL for GLOBAL_POSITION_INT and ATTITUDE (${requests.length} requests)`);
  if (pos && att) {
    check(pos.header.sysid === 1 && pos.header.compid === 154 && pos.data.targetSystem === 1 &&
      pos.data.targetComponent === 1, `from 1/154 to the autopilot 1/1 (${pos.data.targetSystem}/${pos.data.targetComponent})`);
    check(pos.data._param2 === 200000 && att.data._param2 === 100000,
      `intervals ${pos.data._param2} µs (5 Hz) and ${att.data._param2} µs (10 Hz)`);
    check(pos.t - t0 >= 2500, `asked ${pos.t - t0} ms after the autopilot's first heartbeat (grace 3 s)`);
    figures.push(`first SET_MESSAGE_INTERVAL ${pos.t - t0} ms after the autopilot's first heartbeat`);
  }

  // 2. Streaming now: a photo has the position, in CAMERA_IMAGE_CAPTURED and
  //    in gportd's capture log; no more requests while it streams.
  await sleep(1000);
  let t = Date.now();
  autopilot.sendBytes(gcs.frame(cam([0, 0, 1])));
  const captured = await until(() => autopilot.since(t, 'CAMERA_IMAGE_CAPTURED')[0], 5000, 'CAMERA_IMAGE_CAPTURED').catch(() => null);
  check(captured && captured.data.lat === POSITION.lat && captured.data.lon === POSITION.lon,
    `CAMERA_IMAGE_CAPTURED has the streamed position (${captured && captured.data.lat}/${captured && captured.data.lon})`);
  const listed = await h.rpc(sock, 'captures', { limit: 100 }).catch(() => null);
  const last = listed && listed.result && (listed.result.captures || []).filter((c) => c.kind === 'photo').pop();
  check(last && last.meta && Math.abs(last.meta.lat - POSITION.lat / 1e7) < 1e-6 &&
    Math.abs(last.meta.lon - POSITION.lon / 1e7) < 1e-6, `gportd's capture log meta: ${last && JSON.stringify(last.meta)}`);
  // gport-mavlink published the vehicle: gportd stamped the photo with it,
  // the GPS's accuracy and the autopilot's UTC.
  const v = last && last.vehicle;
  check(v && v.tagged && Math.abs(v.lat - POSITION.lat / 1e7) < 1e-6 && Math.abs(v.h_acc_m - 0.9) < 0.01 &&
    v.fix === 3 && v.satellites === 14, `gportd's capture stamped with the vehicle: ${JSON.stringify(v)}`);
  // The autopilot's UTC at the shutter instant: its UTC at boot plus the
  // boot time then, within the latency of a datagram on this machine.
  const shutterUtcUs = v && Number(UTC_AT_BOOT_US) + (last.utc_us - booted * 1000) +
    (last.shutter_mono_us - last.mono_us);
  check(v && typeof v.utc_us === 'number' && Math.abs(v.utc_us - shutterUtcUs) < 50000,
    `its UTC is the autopilot's at the shutter (${v && v.utc_us}; ${v && ((v.utc_us - shutterUtcUs) / 1000).toFixed(1)} ms from it)`);
  // 2b. A ground station (255/190, on the same link) and a stranger
  //     (system 42) send a position 10 km away, a GPS claiming 1 mm and a
  //     UTC a year off: none of it reaches gportd's stamp (gport-mavlink
  //     takes the vehicle's state from the vehicle's autopilot only).
  const stranger = new Peer({ sysid: 42, compid: 1 });
  const spoofs = () => {
    for (const peer of [gcs, stranger]) {
      const far = position();
      far.lat = POSITION.lat + 900000; // 0.09 degrees: 10 km north
      const sharp = gps();
      sharp.hAcc = 1;
      sharp.lat = far.lat;
      const late = systemTime();
      late.timeUnixUsec += 365n * 86400n * 1000000n;
      for (const m of [far, sharp, late]) autopilot.sendBytes(peer.frame(m));
    }
  };
  const spoofing = setInterval(spoofs, 20);
  await sleep(500);
  t = Date.now();
  autopilot.sendBytes(gcs.frame(cam([0, 0, 1])));
  await until(() => autopilot.since(t, 'CAMERA_IMAGE_CAPTURED')[0], 5000, 'CAMERA_IMAGE_CAPTURED').catch(() => null);
  clearInterval(spoofing);
  const spoofed = await h.rpc(sock, 'captures', { limit: 100 }).catch(() => null);
  const sv = spoofed && spoofed.result && ((spoofed.result.captures || []).filter((c) => c.kind === 'photo').pop() || {}).vehicle;
  check(sv && sv.tagged && Math.abs(sv.lat - POSITION.lat / 1e7) < 1e-6 && Math.abs(sv.h_acc_m - 0.9) < 0.05 &&
    v && Math.abs(sv.utc_us - v.utc_us) < 60 * 1000000,
  `a ground station's and a stranger's position, GPS accuracy and UTC (50 Hz for 0.5 s) ignored: the stamp is the autopilot's (${sv && sv.lat}, ±${sv && sv.h_acc_m} m)`);
  const before = requests.length;
  await sleep(3500);
  check(requests.length === before, `no request while the streams come (${requests.length - before} more)`);

  // 3. The autopilot stops and no longer obliges: 3 requests for each, no more.
  obliging = false;
  Object.values(streams).forEach(clearInterval);
  t = Date.now();
  await sleep(14000);
  check(asked(POSITION_ID, t).length === 3 && asked(ATTITUDE_ID, t).length === 3,
    `a stream lost: ${asked(POSITION_ID, t).length} requests for GLOBAL_POSITION_INT and ` +
    `${asked(ATTITUDE_ID, t).length} for ATTITUDE in 14 s (bounded: 3 each)`);

  // 4. Photos without a position: zeros, and one warning naming what to set.
  t = Date.now();
  autopilot.sendBytes(gcs.frame(cam([0, 0, 1])));
  const bare = await until(() => autopilot.since(t, 'CAMERA_IMAGE_CAPTURED')[0], 5000, 'CAMERA_IMAGE_CAPTURED').catch(() => null);
  await sleep(700);
  autopilot.sendBytes(gcs.frame(cam([0, 0, 1])));
  await until(() => autopilot.since(t, 'CAMERA_IMAGE_CAPTURED').length >= 2, 5000, 'a second photo').catch(() => null);
  await sleep(300);
  const warned = bridge.lines.filter((l) => /has no position/.test(l));
  check(bare && bare.data.captureResult === 1 && bare.data.lat === 0, `a photo without a position: lat ${bare && bare.data.lat}`);
  check(warned.length === 1 && /MAVn_POSITION/.test(warned[0]) && /SRn_POSITION/.test(warned[0]) &&
    /MAV_x_MODE/.test(warned[0]) && /\bwarn/.test(warned[0]), `one warning for two such photos: ${warned[0]}`);

  clearInterval(beats);
  clearInterval(serve);
  autopilot.close();
}

main().catch((e) => { check(false, 'unexpected: ' + (e.stack || e)); }).finally(() => h.finish(workRoot, h.children));
