'use strict';
// The autopilot as gimbal manager, played with node-mavlink (an
// implementation we did not write) against gport-mavlink + gportd +
// gport-sim over UDP on localhost (docs/mavlink.md, "Peer test").
//
//   node gimbal_manager.js GPORTD GPORT_SIM GPORT_MAVLINK WORKDIR
//
// gport-sim's --trace shows the 0x85/0x86 frames that reach the gimbal's
// UART. Timing checks are loose (the CI machine is small and shared); the
// measured figures are printed.
const { spawn } = require('child_process');
const dgram = require('dgram');
const fs = require('fs');
const net = require('net');
const path = require('path');
const readline = require('readline');
const { PassThrough } = require('stream');
const { MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, minimal, common } =
  require('node-mavlink');
// The one helper shared with the other peer tests (harness.js).
const { statusOnceListening } = require('./harness');

const REGISTRY = Object.assign({}, minimal.REGISTRY, common.REGISTRY);
const [gportdPath, simPath, bridgePath, workRoot] = process.argv.slice(2);
const ATTITUDE_RATE = 10;
const LEASE_MS = 500;
const SYSID = 1; // the autopilot's
const COMPID = 154; // gport-mavlink's default

const failures = [];
const figures = [];
function check(ok, message) {
  console.log((ok ? 'ok   ' : 'FAIL ') + message);
  if (!ok) failures.push(message);
  return ok;
}
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
const deg = (r) => (r * 180) / Math.PI;
const rad = (d) => (d * Math.PI) / 180;

// ---- MAVLink's quaternion formulas (mavlink_euler_to_quaternion and back)
function toQuaternion(rollDeg, pitchDeg, yawDeg) {
  const [cr, sr] = [Math.cos(rad(rollDeg) / 2), Math.sin(rad(rollDeg) / 2)];
  const [cp, sp] = [Math.cos(rad(pitchDeg) / 2), Math.sin(rad(pitchDeg) / 2)];
  const [cy, sy] = [Math.cos(rad(yawDeg) / 2), Math.sin(rad(yawDeg) / 2)];
  return [cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
    cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy];
}
function toEuler([w, x, y, z]) {
  return {
    roll: deg(Math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))),
    pitch: deg(Math.asin(Math.max(-1, Math.min(1, 2 * (w * y - z * x))))),
    yaw: deg(Math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))),
  };
}

// ---- child processes with their output lines
const children = [];
process.on('exit', () => children.forEach((c) => c.kill('SIGKILL')));
function start(name, cmd, args, onLine) {
  const child = spawn(cmd, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  children.push(child);
  const log = fs.createWriteStream(path.join(workRoot, name + '.log'));
  readline.createInterface({ input: child.stdout }).on('line', (l) => { log.write(l + '\n'); if (onLine) onLine(l); });
  readline.createInterface({ input: child.stderr }).on('line', (l) => log.write('stderr: ' + l + '\n'));
  child.on('exit', (code, signal) => log.write(`exited: ${code} ${signal}\n`));
  return child;
}

async function until(predicate, timeoutMs, what) {
  const end = Date.now() + timeoutMs;
  while (Date.now() < end) {
    const value = predicate();
    if (value) return value;
    await sleep(20);
  }
  throw new Error('timed out waiting for ' + what);
}

// ---- gportd's socket: one JSON-RPC call per connection
function rpc(socketPath, method, params) {
  return new Promise((resolve, reject) => {
    const c = net.createConnection(socketPath);
    let buffer = '';
    c.on('error', reject);
    c.on('connect', () => c.write(JSON.stringify({ id: 1, method, params: params || {} }) + '\n'));
    c.on('data', (d) => {
      buffer += d.toString();
      const nl = buffer.indexOf('\n');
      if (nl >= 0) { c.end(); resolve(JSON.parse(buffer.slice(0, nl))); }
    });
  });
}

// ---- the simulated gimbal's trace
const trace = []; // {t: our clock, j: trace JSON}
function onTrace(line) {
  try { trace.push({ t: Date.now(), j: JSON.parse(line) }); } catch (e) { /* the slave path */ }
}
const controlFrames = (since) => trace.filter((e) => e.t >= since && e.j.cmd === '0x85');
const near = (a, b, tol) => Math.abs(a - b) <= tol;
// The trace shows the frame's raw values: hundredths of a degree (per second).
const sameAxes = (raw, degrees) => raw.length === 3 && raw.every((v, i) => v === Math.round(degrees[i] * 100));

// ---- the manager's UDP endpoint
const received = []; // {t, name, header, data}
let bridgeAddress = null;
const splitter = new MavLinkPacketSplitter();
const input = new PassThrough();
input.pipe(splitter).pipe(new MavLinkPacketParser()).on('data', (packet) => {
  const clazz = REGISTRY[packet.header.msgid];
  if (!clazz) return;
  received.push({ t: Date.now(), name: clazz.MSG_NAME, header: packet.header,
    data: packet.protocol.data(packet.payload, clazz) });
});
const udp = dgram.createSocket('udp4');
udp.on('message', (msg, rinfo) => { bridgeAddress = rinfo; input.write(msg); });
const protocol = new MavLinkProtocolV2(SYSID, 1);
let seq = 0;
function send(message) {
  if (!bridgeAddress) return;
  udp.send(protocol.serialize(message, seq++ & 255), bridgeAddress.port, bridgeAddress.address);
}
const since = (t, name) => received.filter((r) => r.t >= t && r.name === name);

function heartbeat() {
  const hb = new minimal.Heartbeat();
  hb.type = 2; // quadrotor
  hb.autopilot = 3; // ArduPilot
  hb.baseMode = 0; hb.customMode = 0; hb.systemStatus = 4; hb.mavlinkVersion = 3;
  send(hb);
}
function setAttitude({ q, rates, flags }) {
  const m = new common.GimbalDeviceSetAttitude();
  m.targetSystem = SYSID; m.targetComponent = COMPID;
  m.flags = flags === undefined ? 32 : flags; // YAW_IN_VEHICLE_FRAME
  m.q = q || [NaN, NaN, NaN, NaN];
  const [x, y, z] = rates || [NaN, NaN, NaN];
  m.angularVelocityX = x; m.angularVelocityY = y; m.angularVelocityZ = z;
  send(m);
}
function commandLong(command, param1 = 0) {
  const m = new common.CommandLong();
  m.targetSystem = SYSID; m.targetComponent = COMPID; m.command = command; m.confirmation = 0;
  m._param1 = param1; m._param2 = 0; m._param3 = 0; m._param4 = 0; m._param5 = 0; m._param6 = 0; m._param7 = 0;
  send(m);
}
async function ackOf(command, t0) {
  return until(() => since(t0, 'COMMAND_ACK').find((r) => r.data.command === command), 5000,
    `COMMAND_ACK of ${command}`);
}
async function stream(hz, ms, make) {
  const end = Date.now() + ms;
  let n = 0;
  while (Date.now() < end) { make(); n += 1; await sleep(1000 / hz); }
  return n;
}

async function main() {
  fs.rmSync(workRoot, { recursive: true, force: true });
  fs.mkdirSync(workRoot, { recursive: true });
  const link = path.join(workRoot, 'gimbal');
  const sock = path.join(workRoot, 'gportd.sock');
  const config = path.join(workRoot, 'gportd.json');
  fs.writeFileSync(config, JSON.stringify({
    link: { stale_ms: 300, reconnect_initial_ms: 50, reconnect_max_ms: 200 },
    requests: { timeout_ms: 200, retries: 1 },
    limits: { pitch: { min: -90, max: 30 } }, // reported in GIMBAL_DEVICE_INFORMATION
  }));
  const sim = start('gport-sim', simPath, ['--link', link, '--trace', '--form', '24'], onTrace);
  await until(() => fs.existsSync(link), 10000, 'the simulator link');
  const gportd = start('gportd', gportdPath, ['--config', config, '--socket', sock, '--device', link, '--log-level', 'info']);
  await until(() => fs.existsSync(sock), 10000, "gportd's socket");
  let up = false;
  for (let i = 0; i < 200 && !up; i += 1) {
    const reply = await statusOnceListening(sock);
    up = reply !== null && reply.result.link.state === 'up';
    if (!up) await sleep(50);
  }
  check(up, "gportd's link to gport-sim is up");

  await new Promise((resolve) => udp.bind(0, '127.0.0.1', resolve));
  const port = udp.address().port;
  let bridge = start('gport-mavlink', bridgePath, ['--socket', sock, '--mavlink', `udpout:127.0.0.1:${port}`,
    '--attitude-rate', String(ATTITUDE_RATE), '--lease-ms', String(LEASE_MS), '--log-level', 'debug']);
  const beats = setInterval(heartbeat, 1000);

  // Heartbeat: after ours, an active gimbal in our system.
  await until(() => bridgeAddress, 10000, "gport-mavlink's first datagram");
  heartbeat();
  const hb = await until(() => received.find((r) => r.name === 'HEARTBEAT' && r.data.systemStatus === 4), 10000,
    'an active HEARTBEAT');
  check(hb.header.sysid === SYSID && hb.header.compid === COMPID, `heartbeat from ${hb.header.sysid}/${hb.header.compid}`);
  check(hb.data.type === 26 && hb.data.autopilot === 8 && hb.data.mavlinkVersion === 3,
    `heartbeat type ${hb.data.type} (26), autopilot ${hb.data.autopilot} (8), status ${hb.data.systemStatus} (4)`);

  // GIMBAL_DEVICE_INFORMATION on request, with the ACK.
  let t0 = Date.now();
  commandLong(512, 283);
  const ack = await ackOf(512, t0);
  check(ack.data.result === 0 && ack.data.targetSystem === SYSID && ack.data.targetComponent === 1,
    `REQUEST_MESSAGE acknowledged: result ${ack.data.result}`);
  const info = await until(() => since(t0, 'GIMBAL_DEVICE_INFORMATION')[0], 5000, 'GIMBAL_DEVICE_INFORMATION');
  check(info.data.vendorName.replace(/\0+$/, '') === 'HEQUAV' && info.data.modelName.replace(/\0+$/, '') === 'G-Port',
    `information: vendor ${info.data.vendorName}, model ${info.data.modelName}, cap_flags ${info.data.capFlags}`);
  check(near(info.data.pitchMin, rad(-90), 1e-6) && near(info.data.pitchMax, rad(30), 1e-6) &&
    near(info.data.rollMin, rad(-45), 1e-6) && near(info.data.yawMax, rad(170), 1e-6),
  `information limits from gportd's config: pitch ${info.data.pitchMin}..${info.data.pitchMax} rad; roll/yaw without a soft limit: the G-Port's range (roll min ${info.data.rollMin}, yaw max ${info.data.yawMax} rad)`);

  // Attitude status at the configured rate.
  t0 = Date.now();
  await sleep(3000);
  const statuses = since(t0, 'GIMBAL_DEVICE_ATTITUDE_STATUS');
  const rate = statuses.length / 3;
  figures.push(`attitude status rate: ${rate.toFixed(1)} Hz (configured ${ATTITUDE_RATE})`);
  check(rate >= ATTITUDE_RATE * 0.7 && rate <= ATTITUDE_RATE * 1.3, `attitude status at ${rate.toFixed(1)} Hz`);
  const last = statuses[statuses.length - 1];
  check(last && (last.data.flags & 32) !== 0 && last.data.failureFlags === 0,
    `status flags ${last && last.data.flags} (YAW_IN_VEHICLE_FRAME), failure flags ${last && last.data.failureFlags}`);

  // A quaternion for pitch -30, yaw 45 streamed at 50 Hz: ONE 0x85 angle frame.
  t0 = Date.now();
  const sent = await stream(50, 2000, () => setAttitude({ q: toQuaternion(0, -30, 45) }));
  await sleep(300);
  const angles = controlFrames(t0).filter((e) => e.j.mode === 'angle');
  check(angles.length === 1 && sameAxes(angles[0].j.angle, [0, -30, 45]),
    `${sent} set-attitude messages -> ${angles.length} angle frame(s) ${angles.map((a) => JSON.stringify(a.j.angle))}`);

  // The attitude status matches the simulated gimbal's attitude (once still).
  await sleep(1500);
  const gimbal = (await rpc(sock, 'attitude')).result;
  await sleep(2 * 1000 / ATTITUDE_RATE);
  const s = since(Date.now() - 1000 / ATTITUDE_RATE, 'GIMBAL_DEVICE_ATTITUDE_STATUS').pop();
  const e = toEuler(s.data.q);
  const diffs = [e.roll - gimbal.imu.roll, e.pitch - gimbal.imu.pitch, e.yaw - gimbal.hall.yaw];
  figures.push(`status vs gimbal: ${diffs.map((d) => d.toFixed(4)).join(', ')} deg`);
  check(diffs.every((d) => Math.abs(d) <= 0.05),
    `status ${[e.roll, e.pitch, e.yaw].map((v) => v.toFixed(3))} matches IMU roll/pitch ${gimbal.imu.roll}/${gimbal.imu.pitch}, hall yaw ${gimbal.hall.yaw} within 0.05`);

  // 30 deg/s of yaw rate: speed frames of 30.00, then zero within the lease.
  t0 = Date.now();
  await stream(50, 1000, () => setAttitude({ rates: [NaN, 0, rad(30)] }));
  const lastSent = Date.now();
  const zero = await until(() => controlFrames(lastSent).find((f) => f.j.mode === 'speed' && sameAxes(f.j.speed, [0, 0, 0])),
    5000, 'a zero speed after the stream').catch(() => null);
  const speeds = controlFrames(t0).filter((f) => f.t < lastSent && f.j.mode === 'speed');
  check(speeds.length > 0 && speeds.every((f) => sameAxes(f.j.speed, [0, 0, 30])),
    `${speeds.length} speed frames during the stream, all [0,0,30]: ${[...new Set(speeds.map((f) => JSON.stringify(f.j.speed)))]}`);
  if (check(zero !== null, 'a zero speed after the stream ended')) {
    figures.push(`zero speed ${zero.t - lastSent} ms after the last rate message (lease ${LEASE_MS} ms)`);
    check(zero.t - lastSent <= LEASE_MS + 1500, `zero speed after ${zero.t - lastSent} ms (lease ${LEASE_MS}; loose bound ${LEASE_MS + 1500})`);
  }

  // NEUTRAL -> centre.
  t0 = Date.now();
  setAttitude({ flags: 2 });
  const centre = await until(() => controlFrames(t0).find((f) => f.j.mode === 'center'), 5000, 'a centre frame').catch(() => null);
  check(centre !== null, 'NEUTRAL -> a centre frame');

  // Camera commands, each acknowledged, each a 0x86 frame.
  for (const [command, action, name] of [[2000, 'photo', 'IMAGE_START_CAPTURE'], [2500, 'record', 'VIDEO_START_CAPTURE'],
    [2501, 'record', 'VIDEO_STOP_CAPTURE']]) {
    t0 = Date.now();
    commandLong(command);
    const a = await ackOf(command, t0).catch(() => null);
    const frame = await until(() => trace.find((f) => f.t >= t0 && f.j.cmd === '0x86'), 5000, 'a camera frame').catch(() => null);
    check(a && a.data.result === 0 && frame && frame.j.action === action,
      `${name}: ACK ${a && a.data.result}, camera frame ${frame && frame.j.action}`);
  }

  // Killing gport-mavlink mid-rate stops the gimbal (gportd's deadman).
  t0 = Date.now();
  const streaming = stream(50, 1500, () => setAttitude({ rates: [NaN, 0, rad(20)] }));
  await until(() => controlFrames(t0).find((f) => f.j.mode === 'speed' && sameAxes(f.j.speed, [0, 0, 20])), 5000,
    'a 20 deg/s speed frame');
  bridge.kill('SIGKILL');
  const killed = Date.now();
  await streaming;
  const stop = await until(() => controlFrames(killed).find((f) => f.j.mode === 'speed' && sameAxes(f.j.speed, [0, 0, 0])),
    5000, 'a zero speed after the kill').catch(() => null);
  if (check(stop !== null, 'killing gport-mavlink mid-rate stops the gimbal')) {
    figures.push(`zero speed ${stop.t - killed} ms after SIGKILL`);
  }

  clearInterval(beats);
  udp.close();
  for (const child of [bridge, gportd, sim]) child.kill('SIGTERM');
  console.log('figures:\n  ' + figures.join('\n  '));
  if (failures.length > 0) {
    console.error(`${failures.length} check(s) failed; logs in ${workRoot}`);
    process.exit(1);
  }
  console.log('all checks passed');
  process.exit(0);
}

main().catch((error) => {
  console.error('FAIL ' + error.message + `; logs in ${workRoot}`);
  process.exit(1);
});
