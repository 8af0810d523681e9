'use strict';
// What the peer tests against the real programs share (trust.js,
// signing.js, sitl.js): checks and figures, child processes with their
// output, gport-sim's trace, gportd's socket, the quaternion formulas, and
// MAVLink endpoints played with node-mavlink (an implementation we did not
// write), optionally signing with its signer.
const { spawn } = require('child_process');
const dgram = require('dgram');
const fs = require('fs');
const net = require('net');
const path = require('path');
const readline = require('readline');
const { PassThrough } = require('stream');
const {
  MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, MavLinkPacketSignature,
  minimal, common,
} = require('node-mavlink');

const REGISTRY = Object.assign({}, minimal.REGISTRY, common.REGISTRY);
const SIGNATURE_START = Date.UTC(2015, 0, 1);

// ---- checks and figures
const failures = [];
const figures = [];
function check(ok, message) {
  console.log((ok ? 'ok   ' : 'FAIL ') + message);
  if (!ok) failures.push(message);
  return ok;
}
function finish(workRoot, children) {
  for (const child of children) if (child.exitCode === null) child.kill('SIGTERM');
  console.log('figures:\n  ' + figures.join('\n  '));
  if (failures.length > 0) {
    console.error(`${failures.length} check(s) failed; logs in ${workRoot}`);
    process.exit(1);
  }
  console.log('all checks passed');
  process.exit(0);
}

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
async function until(predicate, timeoutMs, what) {
  const end = Date.now() + timeoutMs;
  while (Date.now() < end) {
    const value = predicate();
    if (value) return value;
    await sleep(20);
  }
  throw new Error('timed out waiting for ' + what);
}

const deg = (r) => (r * 180) / Math.PI;
const rad = (d) => (d * Math.PI) / 180;
// MAVLink's mavlink_euler_to_quaternion and back.
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
// An angle in degrees wrapped into [-180, 180).
const wrap = (d) => ((((d + 180) % 360) + 360) % 360) - 180;

// ---- child processes, their output kept in WORKDIR/NAME.log and in memory
const children = [];
process.on('exit', () => children.forEach((c) => { if (c.exitCode === null) c.kill('SIGKILL'); }));
function start(workRoot, name, cmd, args, { onLine, env } = {}) {
  const child = spawn(cmd, args, { stdio: ['ignore', 'pipe', 'pipe'], env: env || process.env });
  children.push(child);
  child.lines = [];
  const log = fs.createWriteStream(path.join(workRoot, name + '.log'), { flags: 'a' });
  const keep = (prefix) => (l) => { child.lines.push(l); log.write(prefix + l + '\n'); if (onLine) onLine(l); };
  readline.createInterface({ input: child.stdout }).on('line', keep(''));
  readline.createInterface({ input: child.stderr }).on('line', keep('stderr: '));
  child.exited = new Promise((resolve) => child.on('exit', (code, signal) => {
    log.write(`exited: ${code} ${signal}\n`);
    resolve({ code, signal });
  }));
  return child;
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

// gportd's status, or null while its socket refuses connections: the
// socket's file exists from gportd's bind(), connections are accepted from
// its listen(), a moment later.
function statusOnceListening(sock) {
  return rpc(sock, 'status').catch((e) => {
    if (e.code === 'ECONNREFUSED' || e.code === 'ENOENT') return null;
    throw e;
  });
}

// ---- gport-sim (with --trace) and gportd on it
// {t: our clock when read, hr: performance.now(), j: trace JSON, sim: its clock}
const trace = [];
// On a loaded machine a trace line may be read long after gport-sim wrote
// it. Each line carries t_ms, gport-sim's own time since it started; a
// frame's time on our clock is t_ms plus that gport-sim's offset, the
// smallest (read time - t_ms) seen (a line read at once). So a frame that
// is read late is still counted with the command that caused it.
function onTrace(line, sim) {
  let j;
  try { j = JSON.parse(line); } catch (e) { return; /* not JSON */ }
  const t = Date.now();
  if (typeof j.t_ms === 'number') sim.offset = Math.min(sim.offset, t - j.t_ms);
  trace.push({ t, hr: performance.now(), j, sim });
}
const sentAt = (e) => (typeof e.j.t_ms === 'number' ? e.sim.offset + e.j.t_ms : e.t);
const controlFrames = (since) => trace.filter((e) => sentAt(e) >= since && e.j.cmd === '0x85');
const cameraFrames = (since) => trace.filter((e) => sentAt(e) >= since && e.j.cmd === '0x86');
// The trace shows raw values: hundredths of a degree (per second).
const sameAxes = (raw, degrees, tol = 0) => Array.isArray(raw) && raw.length === 3 &&
  raw.every((v, i) => Math.abs(v - Math.round(degrees[i] * 100)) <= tol * 100);
const angleFrames = (since, degrees, tol = 0) => controlFrames(since)
  .filter((f) => f.j.mode === 'angle' && sameAxes(f.j.angle, degrees, tol));

// `simArgs`: more options for gport-sim (sitl.js's geotag mode: `--baud
// 115200`, a line drained as a UART's, so a frame's trace time is its last
// byte's).
async function startGimbal(workRoot, gportdPath, simPath, gportdConfig, simArgs = []) {
  const link = path.join(workRoot, 'gimbal');
  const sock = path.join(workRoot, 'gportd.sock');
  const config = path.join(workRoot, 'gportd.json');
  fs.writeFileSync(config, JSON.stringify(gportdConfig || {
    link: { stale_ms: 300, reconnect_initial_ms: 50, reconnect_max_ms: 200 },
    requests: { timeout_ms: 200, retries: 1 },
    camera: { max_commands_per_s: 1000 },
  }));
  const simClock = { offset: Infinity };
  const sim = start(workRoot, 'gport-sim', simPath, ['--link', link, '--trace', '--form', '24'].concat(simArgs),
    { onLine: (line) => onTrace(line, simClock) });
  await until(() => fs.existsSync(link), 10000, 'the simulator link');
  const gportd = start(workRoot, 'gportd', gportdPath,
    ['--config', config, '--socket', sock, '--device', link, '--log-level', 'info']);
  await until(() => fs.existsSync(sock), 10000, "gportd's socket");
  let up = false;
  for (let i = 0; i < 200 && !up; i += 1) {
    const reply = await statusOnceListening(sock);
    up = reply !== null && reply.result.link.state === 'up';
    if (!up) await sleep(50);
  }
  check(up, "gportd's link to gport-sim is up");
  return { sim, gportd, sock, link };
}

// A free UDP port on 127.0.0.1 (bound and released: good enough for a test).
function freeUdpPort() {
  return new Promise((resolve) => {
    const s = dgram.createSocket('udp4');
    s.bind(0, '127.0.0.1', () => { const { port } = s.address(); s.close(() => resolve(port)); });
  });
}

// The kernel's view of the UDP socket bound to 127.0.0.1:PORT, from
// /proc/net/udp: `queued`, the bytes waiting to be read, and `drops`, the
// datagrams dropped because its receive buffer was full (a receiver slowed
// down, under a sanitizer, say). Zeros when no such socket is found.
function udpSocket(port) {
  const local = `0100007F:${port.toString(16).toUpperCase().padStart(4, '0')}`;
  const rows = fs.readFileSync('/proc/net/udp', 'utf8').split('\n').slice(1);
  const row = rows.map((l) => l.trim().split(/\s+/)).find((f) => f[1] === local);
  if (!row) return { queued: 0, drops: 0 };
  return { queued: parseInt(row[4].split(':')[1], 16), drops: Number(row[row.length - 1]) };
}

// ---- signing with node-mavlink's signer
// `timestamp` in MAVLink's units (10 µs since 2015); defaults to now.
function nowTimestamp() { return (Date.now() - SIGNATURE_START) * 100; }
function signBuffer(unsigned, key, linkId, timestamp) {
  const buffer = Buffer.concat([unsigned, Buffer.alloc(MavLinkPacketSignature.SIGNATURE_LENGTH)]);
  const signer = new MavLinkPacketSignature(buffer);
  signer.linkId = linkId;
  signer.timestamp = timestamp;
  signer.signature = signer.calculate(key);
  return buffer;
}

// ---- a MAVLink endpoint on UDP: sends as (sysid, compid), optionally
// signed, and keeps what it receives (with each frame's signature).
class Peer {
  constructor({ sysid, compid, key = null, linkId = 0 }) {
    Object.assign(this, { sysid, compid, key, linkId, seq: 0, received: [], datagrams: 0, to: null,
      lastStamp: 0 });
    this.plain = new MavLinkProtocolV2(sysid, compid);
    this.flagged = new MavLinkProtocolV2(sysid, compid, MavLinkProtocolV2.IFLAG_SIGNED);
    this.socket = dgram.createSocket('udp4');
    const input = new PassThrough();
    input.pipe(new MavLinkPacketSplitter()).pipe(new MavLinkPacketParser()).on('data', (packet) => {
      const clazz = REGISTRY[packet.header.msgid];
      if (!clazz) return;
      this.received.push({ t: Date.now(), hr: performance.now(), name: clazz.MSG_NAME, header: packet.header,
        signature: packet.signature, buffer: packet.buffer,
        data: packet.protocol.data(packet.payload, clazz) });
    });
    this.socket.on('message', (msg, rinfo) => {
      this.datagrams += 1;
      if (!this.to) this.to = { port: rinfo.port, address: rinfo.address };
      input.write(msg);
    });
  }
  bind(port = 0) { return new Promise((resolve) => this.socket.bind(port, '127.0.0.1', resolve)); }
  port() { return this.socket.address().port; }
  target(port) { this.to = { port, address: '127.0.0.1' }; }
  // The bytes of a message: unsigned, or signed with `key` (ours unless
  // given), `linkId` and `timestamp` (default: the clock, kept increasing
  // frame by frame as the specification wants); `zeroSignature` keeps the
  // block zero.
  frame(message, { signed = this.key !== null, key = this.key, linkId = this.linkId,
    timestamp = null, zeroSignature = false } = {}) {
    const seq = this.seq++ & 255;
    if (!signed) return this.plain.serialize(message, seq);
    const unsigned = this.flagged.serialize(message, seq);
    if (zeroSignature) return Buffer.concat([unsigned, Buffer.alloc(13)]);
    if (timestamp === null) {
      timestamp = Math.max(nowTimestamp(), this.lastStamp + 1);
      this.lastStamp = timestamp;
    }
    return signBuffer(unsigned, key, linkId, timestamp);
  }
  sendBytes(bytes) { this.socket.send(bytes, this.to.port, this.to.address); }
  send(message, options) { const bytes = this.frame(message, options); this.sendBytes(bytes); return bytes; }
  since(t, name) { return this.received.filter((r) => r.t >= t && (!name || r.name === name)); }
  close() { this.socket.close(); }
}

// ---- messages
function heartbeat({ type = 2, autopilot = 3 } = {}) {
  const hb = new minimal.Heartbeat();
  hb.type = type; // 2 quadrotor, 6 GCS
  hb.autopilot = autopilot; // 3 ArduPilot, 8 invalid
  hb.baseMode = 0; hb.customMode = 0; hb.systemStatus = 4; hb.mavlinkVersion = 3;
  return hb;
}
function setAttitude({ q, rates, flags = 32, targetSystem = 1, targetComponent = 154 }) {
  const m = new common.GimbalDeviceSetAttitude();
  m.targetSystem = targetSystem; m.targetComponent = targetComponent; m.flags = flags;
  m.q = q || [NaN, NaN, NaN, NaN];
  const [x, y, z] = rates || [NaN, NaN, NaN];
  m.angularVelocityX = x; m.angularVelocityY = y; m.angularVelocityZ = z;
  return m;
}
function commandLong(command, { params = [], targetSystem = 1, targetComponent = 154 } = {}) {
  const m = new common.CommandLong();
  m.targetSystem = targetSystem; m.targetComponent = targetComponent; m.command = command;
  m.confirmation = 0;
  for (let i = 0; i < 7; i += 1) m[`_param${i + 1}`] = params[i] === undefined ? 0 : params[i];
  return m;
}

// Parameters of the autopilot (1/1): `message` (a PARAM_SET or a
// PARAM_REQUEST_READ) sent until the PARAM_VALUE of `name` comes back, at
// most 10 times 500 ms; its value, or NaN.
async function paramExchange(gcs, message, name) {
  const t0 = Date.now();
  for (let i = 0; i < 10; i += 1) {
    gcs.send(message);
    const v = await until(() => gcs.since(t0, 'PARAM_VALUE').find((p) => p.data.paramId.replace(/\0+$/, '') === name),
      500, name).catch(() => null);
    if (v) return v.data.paramValue;
  }
  return NaN;
}
function readParam(gcs, name) {
  const m = new common.ParamRequestRead();
  m.targetSystem = 1; m.targetComponent = 1; m.paramId = name; m.paramIndex = -1;
  return paramExchange(gcs, m, name);
}
function setParam(gcs, name, value, type) {
  const m = new common.ParamSet();
  m.targetSystem = 1; m.targetComponent = 1; m.paramId = name; m.paramValue = value; m.paramType = type;
  return paramExchange(gcs, m, name);
}

module.exports = {
  REGISTRY, check, failures, figures, finish, sleep, until, deg, rad, toQuaternion, toEuler, wrap, start, children,
  rpc, statusOnceListening, trace, sentAt, controlFrames, cameraFrames, sameAxes, angleFrames, startGimbal, freeUdpPort, udpSocket,
  nowTimestamp, signBuffer, Peer, heartbeat, setAttitude, commandLong, minimal, common,
  MavLinkPacketSignature, readParam, setParam,
};
