'use strict';
// gport-mavlink's camera component (compid 100) against the real programs:
// node-mavlink plays the vehicle (system 1: heartbeat, ATTITUDE,
// GLOBAL_POSITION_INT) and a ground station (system 255) against
// gport-mavlink (udpin, defaults) + gportd + gport-sim; a rogue system 99
// is ignored. gport-sim's --trace shows what reaches the gimbal: 0x86
// photo ("0x86 2") and record ("0x86 1") frames.
//
//   node camera.js GPORTD GPORT_SIM GPORT_MAVLINK WORKDIR
//
// Timing checks are loose; the latencies are printed as figures.
const fs = require('fs');
const path = require('path');
const h = require('./harness');

const [gportdPath, simPath, bridgePath, workRoot] = process.argv.slice(2);
const { check, figures, sleep, until, common, Peer, heartbeat, commandLong, toEuler, wrap } = h;
const CAMERA = 100;
const [IMAGE_START, IMAGE_STOP, VIDEO_START, VIDEO_STOP, REQUEST_MESSAGE, DIGICAM] =
  [2000, 2001, 2500, 2501, 512, 203];
const POSITION = { lat: -353632621, lon: 1491652374, alt: 584070, relativeAlt: 30250 };
const VEHICLE_YAW = 30; // degrees, ATTITUDE's

const text = (bytes) => Buffer.from(bytes.filter((b) => b !== 0)).toString();

// The autopilot's boot time: a real one's samples carry increasing times
// (gport-mavlink publishes each new one to gportd, which stamps the photos).
const booted = Date.now();
const bootMs = () => Date.now() - booted;

function position() {
  const m = new common.GlobalPositionInt();
  Object.assign(m, { timeBootMs: bootMs(), vx: 0, vy: 0, vz: 0, hdg: 3000 }, POSITION);
  return m;
}
function attitude() {
  const m = new common.Attitude();
  Object.assign(m, { timeBootMs: bootMs(), roll: 0, pitch: 0, yaw: h.rad(VEHICLE_YAW), rollspeed: 0,
    pitchspeed: 0, yawspeed: 0 });
  return m;
}
const cam = (command, params = []) => commandLong(command, { params, targetComponent: CAMERA });
const fromCamera = (peer, t, name) => peer.since(t, name).filter((r) => r.header.compid === CAMERA);
const ackOf = (peer, t, command) => until(() => fromCamera(peer, t, 'COMMAND_ACK')
  .find((r) => r.data.command === command), 5000, `COMMAND_ACK for ${command}`);
const photos = (t) => h.cameraFrames(t).filter((f) => f.j.action === 'photo');
const records = (t) => h.cameraFrames(t).filter((f) => f.j.action === 'record');

async function requestStatus(gcs) {
  const t = Date.now();
  gcs.send(cam(REQUEST_MESSAGE, [262]));
  return (await until(() => fromCamera(gcs, t, 'CAMERA_CAPTURE_STATUS')[0], 5000, 'CAMERA_CAPTURE_STATUS')).data;
}

async function main() {
  fs.rmSync(workRoot, { recursive: true, force: true });
  fs.mkdirSync(workRoot, { recursive: true });
  const { sock } = await h.startGimbal(workRoot, gportdPath, simPath);
  const port = await h.freeUdpPort();
  const bridge = h.start(workRoot, 'gport-mavlink', bridgePath,
    ['--socket', sock, '--mavlink', `udpin:127.0.0.1:${port}`, '--log-level', 'debug']);
  await until(() => bridge.lines.some((l) => /MAVLink on udpin/.test(l)), 10000, 'gport-mavlink to start');
  check(bridge.lines.some((l) => /camera: compid 100/.test(l)), 'the start line names the camera component');

  const rogue = new Peer({ sysid: 99, compid: 1 });
  const vehicle = new Peer({ sysid: 1, compid: 1 });
  const gcs = new Peer({ sysid: 255, compid: 190 });
  for (const p of [rogue, vehicle, gcs]) { await p.bind(); p.target(port); }

  // 1. A rogue system's camera commands do nothing and get no answer.
  let t0 = Date.now();
  rogue.send(heartbeat());
  for (const m of [cam(IMAGE_START, [0, 0, 1]), cam(VIDEO_START), cam(REQUEST_MESSAGE, [259]),
    commandLong(IMAGE_START, { params: [0, 0, 1], targetComponent: 0 }), cam(DIGICAM, [0, 0, 0, 0, 1])]) {
    rogue.send(m);
  }
  await sleep(1000);
  check(h.cameraFrames(t0).length === 0 && rogue.datagrams === 0,
    `rogue system 99 (photo, video, information, broadcast photo, DIGICAM shot): ${h.cameraFrames(t0).length} ` +
    `camera frames reach the gimbal, ${rogue.datagrams} datagrams answer it`);

  // 2. The vehicle: heartbeat, attitude and position streams; the camera's
  //    heartbeat beside the gimbal's, 1 Hz each.
  const streams = setInterval(() => { vehicle.send(position()); vehicle.send(attitude()); }, 100);
  const beats = setInterval(() => vehicle.send(heartbeat()), 1000);
  vehicle.send(heartbeat());
  t0 = Date.now();
  await sleep(3200);
  const camBeats = fromCamera(vehicle, t0, 'HEARTBEAT');
  const gimbalBeats = vehicle.since(t0, 'HEARTBEAT').filter((r) => r.header.compid === 154);
  check(camBeats.length >= 2 && camBeats.length <= 5 && camBeats.every((b) => b.data.type === 30 &&
    b.data.autopilot === 8 && b.header.sysid === 1),
  `camera HEARTBEAT from 1/100: ${camBeats.length} in 3.2 s, MAV_TYPE_CAMERA (30), MAV_AUTOPILOT_INVALID (8)`);
  check(gimbalBeats.length >= 2, `the gimbal's heartbeat (154) continues beside it (${gimbalBeats.length})`);

  // 3. CAMERA_INFORMATION on request, from the ground station.
  t0 = Date.now();
  gcs.send(cam(REQUEST_MESSAGE, [259]));
  const infoAck = await ackOf(gcs, t0, REQUEST_MESSAGE).catch(() => null);
  const info = await until(() => fromCamera(gcs, t0, 'CAMERA_INFORMATION')[0], 5000, 'CAMERA_INFORMATION').catch(() => null);
  check(infoAck && infoAck.data.result === 0 && infoAck.data.targetSystem === 255,
    `REQUEST_MESSAGE(CAMERA_INFORMATION): ACK ${infoAck && infoAck.data.result} to system ${infoAck && infoAck.data.targetSystem}`);
  check(info && text(info.data.vendorName) === 'HEQUAV' && text(info.data.modelName) === 'G-Port' &&
    info.data.flags === 3 && info.data.gimbalDeviceId === 154 && Number.isNaN(info.data.focalLength) &&
    info.data.resolutionH === 0,
  `CAMERA_INFORMATION: ${info && text(info.data.vendorName)} ${info && text(info.data.modelName)}, flags ` +
    `${info && info.data.flags} (CAPTURE_VIDEO|CAPTURE_IMAGE), gimbal_device_id ${info && info.data.gimbalDeviceId}, focal length NaN`);
  // The legacy request and the storage ("not available").
  t0 = Date.now();
  gcs.send(cam(521, [1]));
  gcs.send(cam(REQUEST_MESSAGE, [261]));
  const legacy = await until(() => fromCamera(gcs, t0, 'CAMERA_INFORMATION')[0], 5000, 'legacy information').catch(() => null);
  const storage = await until(() => fromCamera(gcs, t0, 'STORAGE_INFORMATION')[0], 5000, 'STORAGE_INFORMATION').catch(() => null);
  check(legacy !== null, 'MAV_CMD_REQUEST_CAMERA_INFORMATION (521) answered with CAMERA_INFORMATION');
  check(storage && storage.data.status === 0, `STORAGE_INFORMATION status ${storage && storage.data.status} (not available)`);

  // 4. A still gimbal at pitch -30, yaw 20 (vehicle frame), then one photo.
  vehicle.send(h.setAttitude({ q: h.toQuaternion(0, -30, 20) }));
  let gimbal = null;
  for (let i = 0; i < 100; i += 1) {
    gimbal = (await h.rpc(sock, 'attitude')).result;
    if (Math.abs(gimbal.imu.pitch + 30) < 0.5 && Math.abs(gimbal.hall.yaw - 20) < 0.5) break;
    await sleep(100);
  }
  await sleep(300);
  gimbal = (await h.rpc(sock, 'attitude')).result;
  t0 = Date.now();
  const sentHr = performance.now();
  gcs.send(cam(IMAGE_START, [0, 0, 1, 0]));
  const photoAck = await ackOf(gcs, t0, IMAGE_START).catch(() => null);
  const shot = await until(() => photos(t0)[0], 5000, 'a photo frame').catch(() => null);
  const captured = await until(() => fromCamera(gcs, t0, 'CAMERA_IMAGE_CAPTURED')[0], 5000, 'CAMERA_IMAGE_CAPTURED').catch(() => null);
  check(photoAck && photoAck.data.result === 0, `IMAGE_START_CAPTURE (1 image): ACK ${photoAck && photoAck.data.result} from the camera`);
  check(shot !== null && photos(t0).length === 1, `one 0x86 photo frame on gport-sim's trace (${photos(t0).length})`);
  if (check(captured !== null, 'CAMERA_IMAGE_CAPTURED from 1/100')) {
    const c = captured.data;
    const e = toEuler(c.q);
    check(c.captureResult === 1, `capture_result ${c.captureResult}`);
    check(Math.abs(e.pitch - gimbal.imu.pitch) < 1 && Math.abs(e.roll - gimbal.imu.roll) < 1,
      `q: roll ${e.roll.toFixed(2)}, pitch ${e.pitch.toFixed(2)} match the IMU's ${gimbal.imu.roll}, ${gimbal.imu.pitch} within 1°`);
    check(Math.abs(wrap(e.yaw - (VEHICLE_YAW + gimbal.hall.yaw))) < 1,
      `q: yaw ${e.yaw.toFixed(2)} = the vehicle's ${VEHICLE_YAW} + the hall yaw ${gimbal.hall.yaw} (earth frame)`);
    check(c.lat === POSITION.lat && c.lon === POSITION.lon && c.alt === POSITION.alt &&
      c.relativeAlt === POSITION.relativeAlt,
    `lat/lon/alt/relative_alt ${c.lat}/${c.lon}/${c.alt}/${c.relativeAlt} are the GLOBAL_POSITION_INT sent`);
    check(c.imageIndex >= 0, `image_index ${c.imageIndex}`);
    const utcSkew = Math.abs(Number(c.timeUtc) / 1000 - Date.now());
    check(utcSkew < 10000, `time_utc within 10 s of the clock (${utcSkew.toFixed(0)} ms)`);
    figures.push(`photo: IMAGE_START_CAPTURE sent -> CAMERA_IMAGE_CAPTURED received ${(captured.hr - sentHr).toFixed(2)} ms; ` +
      `0x86 line on gport-sim's trace -> CAMERA_IMAGE_CAPTURED ${shot ? (captured.hr - shot.hr).toFixed(2) : '?'} ms ` +
      '(performance.now() in this process at send and on arrival; trace lines stamped when read from gport-sim\'s stdout)');
  }
  // The capture's meta: in gportd's capture log (gportd and gport-mavlink
  // ship together: the bridge never repeats a call without it).
  const listed = await h.rpc(sock, 'captures', { limit: 100 }).catch(() => null);
  const last = listed && listed.result && Array.isArray(listed.result.captures)
    ? listed.result.captures.filter((c) => c.kind === 'photo').pop() : null;
  check(last && last.meta && Math.abs(last.meta.lat - POSITION.lat / 1e7) < 1e-6 &&
    Math.abs(last.meta.lon - POSITION.lon / 1e7) < 1e-6, `gportd's capture log has the position as meta (${last && JSON.stringify(last.meta)})`);

  // 5. One command, one photo (docs/mavlink.md). ArduPilot (CAMx_TYPE 6)
  //    forwards a ground station's broadcast command to 1/100 and sends its
  //    own IMAGE_START_CAPTURE there 0.3 ms later, on the same link: played
  //    here as one datagram from the vehicle's socket with both frames.
  //    One photo, and both ACCEPTED, each to its sender.
  const broadcast = (command, params) => commandLong(command, { params, targetComponent: 0 });
  const bothAcks = async (t, n) => {
    await until(() => fromCamera(vehicle, t, 'COMMAND_ACK').length >= n, 5000, `${n} ACKs`).catch(() => null);
    await until(() => photos(t).length >= 1, 5000, 'a photo frame').catch(() => null);
    await sleep(300);
    return fromCamera(vehicle, t, 'COMMAND_ACK').map((a) => `${a.data.command}:${a.data.result}->${a.data.targetSystem}`).sort();
  };
  t0 = Date.now();
  vehicle.sendBytes(Buffer.concat([gcs.frame(broadcast(IMAGE_START, [0, 0, 1])), vehicle.frame(cam(IMAGE_START, [0, 0, 1]))]));
  let acks = await bothAcks(t0, 2);
  const captures1 = fromCamera(vehicle, t0, 'CAMERA_IMAGE_CAPTURED');
  check(acks.join() === '2000:0->1,2000:0->255' && photos(t0).length === 1 && captures1.length === 1,
    `forwarded IMAGE_START_CAPTURE + ArduPilot's own in one datagram: ACKs ${acks.join(', ')} ` +
    `(command:result->system), ${photos(t0).length} photo frame, ${captures1.length} CAMERA_IMAGE_CAPTURED`);
  check(bridge.lines.some((l) => /came .* ms after the command of the photo in flight: the same photo/.test(l)),
    'the bridge says the second command is the same photo');
  // DIGICAM_CONTROL forwarded, ArduPilot's IMAGE_START_CAPTURE 10 ms later
  // (a separate datagram: the photo may be done by then).
  await sleep(300);
  t0 = Date.now();
  vehicle.sendBytes(gcs.frame(broadcast(DIGICAM, [0, 0, 0, 0, 1])));
  await sleep(10);
  vehicle.send(cam(IMAGE_START, [0, 0, 1]));
  acks = await bothAcks(t0, 2);
  check(acks.join() === '2000:0->1,203:0->255' && photos(t0).length === 1,
    `forwarded DIGICAM_CONTROL + ArduPilot's IMAGE_START_CAPTURE 10 ms later: ACKs ${acks.join(', ')}, ` +
    `${photos(t0).length} photo frame`);
  // Two separate photos: the autopilot's command 100 ms (> the 50 ms window)
  // after the ground station's was answered.
  await sleep(300);
  t0 = Date.now();
  gcs.send(cam(IMAGE_START, [0, 0, 1]));
  await ackOf(gcs, t0, IMAGE_START).catch(() => null);
  await sleep(100);
  vehicle.send(cam(IMAGE_START, [0, 0, 1]));
  await ackOf(vehicle, t0, IMAGE_START).catch(() => null);
  await sleep(500);
  check(photos(t0).length === 2, `a ground station's photo and the autopilot's 100 ms after its ACK: ${photos(t0).length} photo frames`);
  // One sender's two photos in one datagram are not one command forwarded
  // twice: the second is TEMPORARILY_REJECTED (one camera call in flight).
  t0 = Date.now();
  gcs.sendBytes(Buffer.concat([gcs.frame(cam(IMAGE_START, [0, 0, 1])), gcs.frame(cam(IMAGE_START, [0, 0, 1]))]));
  await until(() => fromCamera(gcs, t0, 'COMMAND_ACK').length >= 2, 5000, 'two ACKs').catch(() => null);
  // The trace is read from gport-sim's output: the photo's line may come
  // after the ACKs on a loaded machine.
  await until(() => photos(t0).length >= 1, 5000, 'the photo frame').catch(() => null);
  const results = fromCamera(gcs, t0, 'COMMAND_ACK').map((a) => a.data.result).sort();
  check(results.join() === '0,1' && photos(t0).length === 1,
    `one ground station's two photos at once: ACKs ${results.join()} (ACCEPTED, TEMPORARILY_REJECTED), ${photos(t0).length} photo`);
  await sleep(500);

  // 6. Interval capture: 3 images, 1 s apart.
  t0 = Date.now();
  gcs.send(cam(IMAGE_START, [0, 1, 3, 0]));
  const intervalAck = await ackOf(gcs, t0, IMAGE_START).catch(() => null);
  const during = await requestStatus(gcs).catch(() => null);
  await until(() => photos(t0).length >= 3, 8000, 'three photos').catch(() => null);
  await sleep(2000);
  const frames = photos(t0);
  const images = vehicle.since(t0, 'CAMERA_IMAGE_CAPTURED').concat(gcs.since(t0, 'CAMERA_IMAGE_CAPTURED'))
    .sort((a, b) => a.t - b.t);
  const gaps = frames.slice(1).map((f, i) => f.t - frames[i].t);
  check(intervalAck && intervalAck.data.result === 0, `IMAGE_START_CAPTURE (interval 1 s, 3 images): ACK ${intervalAck && intervalAck.data.result}`);
  check(during && during.imageStatus >= 2 && during.imageInterval === 1,
    `CAMERA_CAPTURE_STATUS during it: image_status ${during && during.imageStatus}, interval ${during && during.imageInterval}`);
  check(frames.length === 3 && gaps.every((g) => g > 500 && g < 2000),
    `3 photo frames (${frames.length}), ${gaps.join(', ')} ms apart`);
  const indexes = images.map((i) => i.data.imageIndex);
  check(images.length === 3 && indexes.every((v, i) => i === 0 || v === indexes[i - 1] + 1) &&
    images.every((i) => i.data.captureResult === 1 && i.data.lat === POSITION.lat),
  `3 CAMERA_IMAGE_CAPTURED, indexes ${indexes.join(', ')}, each with the position`);
  figures.push(`interval capture: photo frames ${gaps.join(', ')} ms apart (asked 1000); 0x86 -> CAMERA_IMAGE_CAPTURED ` +
    `${frames.map((f, i) => (images[i] ? (images[i].hr - f.hr).toFixed(2) : '?')).join(', ')} ms`);
  // 6b. A missed CAMERA_IMAGE_CAPTURED asked again (REQUEST_MESSAGE 263,
  // param2 the image_index, param3 0: that one; -1: it and all after): the
  // same message as first sent; an index never taken: FAILED; a fraction:
  // DENIED.
  if (images.length === 3) {
    const same = (a, b) => ['imageIndex', 'lat', 'lon', 'alt', 'timeUtc', 'timeBootMs', 'captureResult']
      .every((k) => String(a[k]) === String(b[k])) && a.q.every((v, i) => v === b.q[i]);
    t0 = Date.now();
    gcs.send(cam(REQUEST_MESSAGE, [263, indexes[1], 0]));
    const again = await until(() => fromCamera(gcs, t0, 'CAMERA_IMAGE_CAPTURED')[0], 5000, 'the image again').catch(() => null);
    const againAck = await ackOf(gcs, t0, REQUEST_MESSAGE).catch(() => null);
    check(againAck && againAck.data.result === 0 && again && same(again.data, images[1].data),
      `REQUEST_MESSAGE(263, image ${indexes[1]}): ACK ${againAck && againAck.data.result}, the same CAMERA_IMAGE_CAPTURED as first sent`);
    t0 = Date.now();
    gcs.send(cam(REQUEST_MESSAGE, [263, indexes[0], -1]));
    await ackOf(gcs, t0, REQUEST_MESSAGE).catch(() => null);
    await sleep(300);
    const all = fromCamera(gcs, t0, 'CAMERA_IMAGE_CAPTURED').map((r) => r.data.imageIndex);
    check(all.join() === indexes.join(), `REQUEST_MESSAGE(263, ${indexes[0]}, -1): images ${all.join(', ')} again`);
    const refusal = async (params) => {
      const t = Date.now();
      gcs.send(cam(REQUEST_MESSAGE, params));
      const ack = await ackOf(gcs, t, REQUEST_MESSAGE).catch(() => null);
      return ack && ack.data.result;
    };
    const never = await refusal([263, indexes[2] + 1000, 0]);
    const fraction = await refusal([263, 1.5, 0]);
    check(never === 4 && fraction === 2,
      `REQUEST_MESSAGE(263) for an image never taken: ${never} (FAILED); for image 1.5: ${fraction} (DENIED)`);
    // The attack: 300 requests for every image in one burst. What is sent
    // again stays within the re-send budget (128 a second, a burst of 128),
    // past it TEMPORARILY_REJECTED (gport-mavlink's own command limits may
    // drop some of the burst before the camera sees it: fewer ACKs).
    await sleep(1100); // the budget full again
    t0 = Date.now();
    const burst = [];
    for (let i = 0; i < 300; i += 1) burst.push(gcs.frame(cam(REQUEST_MESSAGE, [263, -1, 0])));
    for (let i = 0; i < burst.length; i += 30) gcs.sendBytes(Buffer.concat(burst.slice(i, i + 30)));
    await sleep(2000);
    const elapsedS = (Date.now() - t0) / 1000;
    const acks = fromCamera(gcs, t0, 'COMMAND_ACK').filter((a) => a.data.command === REQUEST_MESSAGE);
    const resent = fromCamera(gcs, t0, 'CAMERA_IMAGE_CAPTURED').length;
    const rejected = acks.filter((a) => a.data.result === 1).length;
    check(rejected > 0 && resent <= 128 + 128 * elapsedS + 3,
      `300 requests for every image at once: ${acks.length} ACKs, ${rejected} TEMPORARILY_REJECTED, ` +
      `${resent} images sent again in ${elapsedS.toFixed(2)} s (budget 128 + 128/s)`);
  }
  // An unlimited one, stopped.
  t0 = Date.now();
  gcs.send(cam(IMAGE_START, [0, 1, 0, 0]));
  await until(() => photos(t0).length >= 1, 5000, 'an unlimited capture').catch(() => null);
  gcs.send(cam(IMAGE_STOP));
  const stopAck = await ackOf(gcs, t0, IMAGE_STOP).catch(() => null);
  const stoppedAt = Date.now();
  await sleep(2000);
  check(stopAck && stopAck.data.result === 0 && photos(stoppedAt + 200).length === 0,
    `IMAGE_STOP_CAPTURE ends an unlimited capture (${photos(t0).length} photos, none after the stop)`);
  // Refused parameters.
  t0 = Date.now();
  gcs.send(cam(IMAGE_START, [0, 0.1, 5]));
  const tooFast = await ackOf(gcs, t0, IMAGE_START).catch(() => null);
  check(tooFast && tooFast.data.result === 2 && photos(t0).length === 0 &&
    bridge.lines.some((l) => /interval \(param2\) = 0.1 s/.test(l)),
  `an interval of 0.1 s is DENIED (${tooFast && tooFast.data.result}) and logged with what is allowed`);

  // 6b. Positions from a ground station (trusted for commands, not for
  //     vehicle state), a rogue, another component of the vehicle's system
  //     (issue 30: the autopilot, compid 1, alone) and the autopilot's own
  //     out of bounds (INT32_MAX latitude, INT32_MIN altitude) are not used;
  //     the vehicle's valid one, once over 1 s old, is not either: zeros.
  clearInterval(streams);
  await sleep(1300);
  const spoof = position();
  spoof.lat = 100000000; spoof.lon = 200000000;
  const companion = new Peer({ sysid: 1, compid: 191 });
  await companion.bind(); companion.target(port);
  const wild = position();
  wild.lat = 2147483647; wild.alt = -2147483648;
  gcs.send(spoof); rogue.send(spoof); companion.send(spoof); vehicle.send(wild);
  await sleep(100);
  t0 = Date.now();
  gcs.send(cam(IMAGE_START, [0, 0, 1]));
  const stale = await until(() => fromCamera(gcs, t0, 'CAMERA_IMAGE_CAPTURED')[0], 5000, 'CAMERA_IMAGE_CAPTURED').catch(() => null);
  check(stale && stale.data.captureResult === 1 && stale.data.lat === 0 && stale.data.lon === 0 &&
    stale.data.alt === 0, `spoofed positions (ground station, rogue, vehicle component 191, the autopilot's ` +
    `lat 214.7483647 / alt -2147483.648) ignored, the vehicle's 1.4 s old not used: ` +
    `lat/lon/alt ${stale && [stale.data.lat, stale.data.lon, stale.data.alt].join('/')}`);
  const dropped = (re) => bridge.lines.some((l) => /dropped GLOBAL_POSITION_INT/.test(l) && re.test(l));
  check(dropped(/component 191 is not the vehicle's autopilot/) || dropped(/lat 214.7483647 is outside/),
    `a dropped position is logged naming why: ${bridge.lines.find((l) => /dropped GLOBAL_POSITION_INT/.test(l))}`);
  companion.close();

  // 7. Video: start and stop, two record frames, the status says so.
  t0 = Date.now();
  gcs.send(cam(VIDEO_START));
  const startAck = await ackOf(gcs, t0, VIDEO_START).catch(() => null);
  await sleep(1200);
  const recording = await requestStatus(gcs).catch(() => null);
  const t1 = Date.now();
  gcs.send(cam(VIDEO_STOP));
  const stopVideoAck = await ackOf(gcs, t1, VIDEO_STOP).catch(() => null);
  const idle = await requestStatus(gcs).catch(() => null);
  await until(() => records(t0).length >= 2, 5000, 'two record frames').catch(() => null);
  check(startAck && startAck.data.result === 0 && stopVideoAck && stopVideoAck.data.result === 0,
    `VIDEO_START/STOP_CAPTURE: ACKs ${startAck && startAck.data.result}, ${stopVideoAck && stopVideoAck.data.result}`);
  check(records(t0).length === 2, `two 0x86 record frames on the trace (${records(t0).length})`);
  check(recording && recording.videoStatus === 1 && recording.recordingTimeMs >= 1000 &&
    idle && idle.videoStatus === 0 && idle.recordingTimeMs === 0,
  `CAMERA_CAPTURE_STATUS: video_status ${recording && recording.videoStatus} (${recording && recording.recordingTimeMs} ms) ` +
    `then ${idle && idle.videoStatus}`);

  // 8. DIGICAM_CONTROL shot (CAMx_TYPE=5 set-ups), broadcast: one photo,
  //    answered by the camera only.
  t0 = Date.now();
  vehicle.send(commandLong(DIGICAM, { params: [0, 0, 0, 0, 1, 0, 0], targetComponent: 0 }));
  const digicam = await until(() => vehicle.since(t0, 'COMMAND_ACK').filter((a) => a.data.command === DIGICAM).length > 0 &&
    vehicle.since(t0, 'COMMAND_ACK').filter((a) => a.data.command === DIGICAM), 5000, 'the DIGICAM ack').catch(() => []);
  await sleep(500);
  check(digicam.length === 1 && digicam[0].header.compid === CAMERA && digicam[0].data.result === 0 &&
    photos(t0).length === 1, `broadcast DIGICAM_CONTROL shot: ${digicam.length} ACK from component ` +
    `${digicam[0] && digicam[0].header.compid}, ${photos(t0).length} photo frame`);

  // 8b. The gimbal component's image commands take the camera's one path
  //     (issue 33): a bare IMAGE_START_CAPTURE to 1/154 (as gimbal
  //     managers send it: one photo whatever its count) is answered from
  //     154, logged with the position as meta, and reported by the camera
  //     (CAMERA_IMAGE_CAPTURED from 1/100 with the next image_index);
  //     IMAGE_STOP_CAPTURE there is accepted too.
  const GIMBAL = 154;
  const taken = (await requestStatus(gcs).catch(() => ({ imageCount: NaN }))).imageCount;
  vehicle.send(position()); // fresh (under 1 s old) for the meta
  await sleep(100);
  t0 = Date.now();
  gcs.send(commandLong(IMAGE_START, { targetComponent: GIMBAL }));
  const gimbalAck = await until(() => gcs.since(t0, 'COMMAND_ACK').find((a) => a.data.command === IMAGE_START),
    5000, 'the ACK of IMAGE_START_CAPTURE to 154').catch(() => null);
  const viaGimbal = await until(() => fromCamera(gcs, t0, 'CAMERA_IMAGE_CAPTURED')[0], 5000,
    'CAMERA_IMAGE_CAPTURED after a photo at 154').catch(() => null);
  check(gimbalAck && gimbalAck.header.compid === GIMBAL && gimbalAck.data.result === 0 && photos(t0).length === 1,
    `IMAGE_START_CAPTURE to 154: ACK ${gimbalAck && gimbalAck.data.result} from component ` +
    `${gimbalAck && gimbalAck.header.compid}, ${photos(t0).length} photo frame`);
  check(viaGimbal && viaGimbal.data.imageIndex === taken,
    `the camera reports it: image_index ${viaGimbal && viaGimbal.data.imageIndex} after ${taken} images`);
  const logged = await h.rpc(sock, 'captures', { limit: 1000 }).catch(() => null);
  const lastPhoto = logged && logged.result && Array.isArray(logged.result.captures)
    ? logged.result.captures.filter((c) => c.kind === 'photo').pop() : null;
  check(lastPhoto && lastPhoto.meta && Math.abs(lastPhoto.meta.lat - POSITION.lat / 1e7) < 1e-6,
    `its capture has the position as meta (${lastPhoto && JSON.stringify(lastPhoto.meta)})`);
  t0 = Date.now();
  gcs.send(commandLong(IMAGE_STOP, { targetComponent: GIMBAL }));
  const stopAt154 = await until(() => gcs.since(t0, 'COMMAND_ACK').find((a) => a.data.command === IMAGE_STOP),
    5000, 'the ACK of IMAGE_STOP_CAPTURE to 154').catch(() => null);
  check(stopAt154 && stopAt154.header.compid === GIMBAL && stopAt154.data.result === 0,
    `IMAGE_STOP_CAPTURE to 154: ACK ${stopAt154 && stopAt154.data.result}`);

  // 9. --no-camera: a second bridge without the component.
  const port2 = await h.freeUdpPort();
  const quiet = h.start(workRoot, 'gport-mavlink-no-camera', bridgePath,
    ['--socket', sock, '--mavlink', `udpin:127.0.0.1:${port2}`, '--no-camera']);
  await until(() => quiet.lines.some((l) => /MAVLink on udpin/.test(l)), 10000, 'the second gport-mavlink');
  const vehicle2 = new Peer({ sysid: 1, compid: 1 });
  await vehicle2.bind(); vehicle2.target(port2);
  t0 = Date.now();
  vehicle2.send(heartbeat());
  vehicle2.send(cam(IMAGE_START, [0, 0, 1]));
  await sleep(2500);
  check(vehicle2.since(t0, 'HEARTBEAT').some((r) => r.header.compid === 154) &&
    fromCamera(vehicle2, t0).length === 0 && photos(t0).length === 0,
  `--no-camera: gimbal heartbeats, nothing from component 100, no photo (${fromCamera(vehicle2, t0).length} frames)`);
  // Its gimbal component still takes photos: answered from 154, and no
  // CAMERA_IMAGE_CAPTURED from a component that is not announced.
  t0 = Date.now();
  vehicle2.send(commandLong(IMAGE_START, { targetComponent: GIMBAL }));
  const quietAck = await until(() => vehicle2.since(t0, 'COMMAND_ACK').find((a) => a.data.command === IMAGE_START),
    5000, 'the ACK of IMAGE_START_CAPTURE to 154 (--no-camera)').catch(() => null);
  await sleep(500);
  check(quietAck && quietAck.header.compid === GIMBAL && quietAck.data.result === 0 && photos(t0).length === 1 &&
    fromCamera(vehicle2, t0).length === 0,
  `--no-camera: IMAGE_START_CAPTURE to 154 is a photo (${photos(t0).length}), ACK from ` +
    `${quietAck && quietAck.header.compid}, nothing from 100 (${fromCamera(vehicle2, t0).length})`);
  quiet.kill('SIGTERM');

  clearInterval(beats);
  for (const p of [rogue, vehicle, gcs, vehicle2]) p.close();
}

main().catch((e) => { check(false, 'unexpected: ' + (e.stack || e)); }).finally(() => h.finish(workRoot, h.children));
