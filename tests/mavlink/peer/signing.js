'use strict';
// MAVLink 2 signing against the real gport-mavlink (udpin, --signing-key,
// --state-dir) + gportd + gport-sim, played with node-mavlink and its
// signer: unsigned, wrongly signed, replayed and stale frames move nothing;
// correctly signed ones do; every frame the bridge sends verifies with
// node-mavlink; its outgoing timestamp stays monotonic across restarts;
// a key holder's frame 23 h ahead, a planted timestamp file and a
// world-writable state directory lock nobody out (issue 30).
//
//   node signing.js GPORTD GPORT_SIM GPORT_MAVLINK WORKDIR
const crypto = require('crypto');
const dgram = require('dgram');
const fs = require('fs');
const path = require('path');
const h = require('./harness');

const [gportdPath, simPath, bridgePath, workRoot] = process.argv.slice(2);
const { check, figures, sleep, until, toQuaternion, Peer, heartbeat, setAttitude, commandLong } = h;
const PASSPHRASE = 'gport-mavlink peer test';
const KEY = h.MavLinkPacketSignature.key(PASSPHRASE); // SHA-256, as MAVProxy derives it
const ONE_MINUTE = 6000000;

// Whether the frames sent move the gimbal: an angle frame on gport-sim's
// trace within 3 s (a loaded machine can take over 700 ms; a refused frame
// waits the whole 3 s).
async function moves(peer, degrees, send) {
  const t0 = Date.now();
  for (let i = 0; i < 5; i += 1) { send(); await sleep(20); }
  return until(() => h.angleFrames(t0, degrees).length > 0, 3000, 'an angle frame').then(() => true, () => false);
}

function startBridge(keyFile, stateDir, port, name = 'gport-mavlink') {
  return h.start(workRoot, name, bridgePath, ['--socket', path.join(workRoot, 'gportd.sock'),
    '--mavlink', `udpin:127.0.0.1:${port}`, '--signing-key', keyFile, '--state-dir', stateDir]);
}

// The bridge's frames since t0: all signed, all verifying, link 0, timestamps increasing.
function verifyOutgoing(peer, t0, what) {
  const frames = peer.since(t0);
  const signedOk = frames.every((f) => f.signature && f.signature.matches(KEY) && f.signature.linkId === 0);
  const stamps = frames.map((f) => f.signature && f.signature.timestamp);
  const increasing = stamps.every((s, i) => i === 0 || s > stamps[i - 1]);
  check(frames.length > 0 && signedOk && increasing,
    `${what}: ${frames.length} frames from gport-mavlink, all signed with link 0 and verified by node-mavlink, timestamps increasing`);
  return stamps.length > 0 ? stamps[stamps.length - 1] : 0;
}

// Heartbeats every 200 ms until the (re)started bridge answers: it may not
// have bound its port when the first one goes out.
async function reachBridge(peer, what) {
  const t0 = Date.now();
  for (let i = 0; i < 50 && peer.since(t0).length < 3; i += 1) {
    peer.send(heartbeat());
    await sleep(200);
  }
  await until(() => peer.since(t0).length >= 3, 2000, what);
  return t0;
}

async function refusedKeyFile(keyFile, stateDir, port) {
  fs.chmodSync(keyFile, 0o644);
  const loose = startBridge(keyFile, stateDir, port, 'gport-mavlink-loose-key');
  const exit = await loose.exited;
  fs.chmodSync(keyFile, 0o600);
  check(exit.code === 78 && loose.lines.some((l) => l.includes(keyFile) && /mode 0644/.test(l)),
    `a world-readable key file is refused, exit ${exit.code}: ${loose.lines.find((l) => l.includes(keyFile))}`);
  if (process.getuid() === 0) { // run as root: a 0600 key that another user owns (and may change)
    fs.chownSync(keyFile, 65534, 65534);
    const foreign = startBridge(keyFile, stateDir, port, 'gport-mavlink-foreign-key');
    const foreignExit = await foreign.exited;
    fs.chownSync(keyFile, 0, 0);
    check(foreignExit.code === 78 && foreign.lines.some((l) => l.includes(keyFile) && /owned by uid 65534/.test(l)),
      `a key file owned by uid 65534 is refused, exit ${foreignExit.code}: ${foreign.lines.find((l) => l.includes(keyFile))}`);
  }
}

// 8. Restart growth: starts that end before sending anything (here the port
//    is taken: exit 71, which systemd restarts every 2 s) write back the
//    exact value, never a reservation, so the stored timestamp does not
//    creep ahead (20 s ahead of the clock: within the 30 s trusted).
async function failedStarts(keyFile, stateDir, stampFile, port) {
  const squatter = dgram.createSocket('udp4');
  await new Promise((resolve, reject) => { squatter.once('error', reject); squatter.bind(port, '127.0.0.1', resolve); });
  const farAhead = h.nowTimestamp() + 20 * 100000;
  fs.writeFileSync(stampFile, `${farAhead}\n`);
  const values = [];
  const exits = [];
  for (let i = 0; i < 5; i += 1) {
    const failed = startBridge(keyFile, stateDir, port, `gport-mavlink-squatted-${i}`);
    exits.push((await failed.exited).code);
    values.push(Number(fs.readFileSync(stampFile, 'utf8').trim()));
  }
  squatter.close();
  figures.push(`stored timestamp over 5 failed starts: ${farAhead} -> ${values.join(', ')}`);
  check(exits.every((c) => c === 71), `5 starts on a taken port exit 71: ${exits}`);
  check(values.every((v) => v === farAhead),
    `the stored timestamp does not grow over 5 failed starts (${farAhead} -> ${values[values.length - 1]})`);
}

// Issue 30, item 1: one correctly signed frame stamped 23 h ahead from a key
// holder the bridge does not obey (system 99), then from one it obeys (the
// ground station, 255, its clock 23 h ahead). Neither may lock the vehicle
// out: the bridge's timestamps stay within 30 s of the clock, the vehicle's
// new streams and, after a restart, its usual stream are taken.
async function clockAttacks(vehicle, keyFile, stateDir, stampFile, port) {
  fs.writeFileSync(stampFile, `${h.nowTimestamp()}\n`); // start at the clock (8. left 20 s ahead)
  let bridge = startBridge(keyFile, stateDir, port, 'gport-mavlink-clock');
  let t0 = await reachBridge(vehicle, 'frames before the clock attack');
  const hours23 = 23 * 3600 * 100000;
  const lead = (what) => {
    const stamps = vehicle.since(t0).map((f) => f.signature.timestamp);
    const ahead = (Math.max(...stamps) - h.nowTimestamp()) / 100000;
    figures.push(`${what}: the bridge's newest timestamp ${ahead.toFixed(1)} s ahead of the clock`);
    return ahead;
  };
  const stranger = new Peer({ sysid: 99, compid: 1, key: KEY, linkId: 0 });
  await stranger.bind(); stranger.target(port);
  stranger.send(heartbeat(), { timestamp: h.nowTimestamp() + hours23 });
  await sleep(300);
  t0 = await reachBridge(vehicle, 'frames after the stranger');
  check(lead('after system 99 signed 23 h ahead') < 2, 'a key holder the bridge does not obey (system 99) 23 h ahead moves its clock by nothing');
  check(await moves(vehicle, [0, -20, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -20, 0) }), { linkId: 21 })),
    'the vehicle on a new link is still obeyed');
  const gcs = new Peer({ sysid: 255, compid: 190, key: KEY, linkId: 0 });
  await gcs.bind(); gcs.target(port);
  gcs.send(heartbeat({ type: 6, autopilot: 8 }), { timestamp: h.nowTimestamp() + hours23 });
  await sleep(300);
  t0 = await reachBridge(vehicle, 'frames after the ground station');
  const pulled = lead('after the ground station (obeyed) signed 23 h ahead');
  check(pulled > 20 && pulled < 32, `an obeyed ground station 23 h ahead pulls the bridge's clock ${pulled.toFixed(1)} s ahead (30 s at most)`);
  check(bridge.lines.some((l) => /system 255 component 190 carries timestamp .* ahead of our clock: ours follows it to 30 s ahead at most/.test(l)),
    'the pull is logged naming the sender');
  check(await moves(vehicle, [0, -10, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -10, 0) }), { linkId: 22 })),
    'the vehicle on a new link (its clock right) is still obeyed');
  bridge.kill('SIGTERM');
  await bridge.exited;
  const stored = Number(fs.readFileSync(stampFile, 'utf8').trim());
  check(stored < h.nowTimestamp() + 31 * 100000, `stored after it: ${((stored - h.nowTimestamp()) / 100000).toFixed(1)} s ahead (30 s at most)`);
  bridge = startBridge(keyFile, stateDir, port, 'gport-mavlink-clock-restarted');
  await reachBridge(vehicle, 'frames after the restart');
  check(await moves(vehicle, [0, -30, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -30, 0) }))),
    'after a restart the vehicle\'s usual stream is obeyed');
  bridge.kill('SIGTERM');
  await bridge.exited;
  stranger.close(); gcs.close();
}

// Issue 30, item 2: a timestamp file planted at 2^48 - 1 is not taken (the
// start says so and signs near the clock), and a state directory others
// can write is refused.
async function plantedState(vehicle, keyFile, stateDir, stampFile, port) {
  fs.writeFileSync(stampFile, '281474976710655\n');
  const bridge = startBridge(keyFile, stateDir, port, 'gport-mavlink-planted');
  const t0 = await reachBridge(vehicle, 'frames after a planted timestamp');
  const first = vehicle.since(t0)[0].signature.timestamp;
  check(first < h.nowTimestamp() + 31 * 100000 && bridge.lines.some((l) => /not trusted beyond 30 s ahead/.test(l)),
    `a planted 2^48 - 1 is not taken: the first timestamp is ${((first - h.nowTimestamp()) / 100000).toFixed(1)} s ahead, the start says why`);
  check(await moves(vehicle, [0, -15, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -15, 0) }))),
    'the vehicle is obeyed');
  bridge.kill('SIGTERM');
  await bridge.exited;
  fs.chmodSync(stateDir, 0o777);
  const open = startBridge(keyFile, stateDir, port, 'gport-mavlink-open-state-dir');
  const exit = await open.exited;
  fs.chmodSync(stateDir, 0o700);
  const why = open.lines.find((l) => l.includes(`state directory ${stateDir}`));
  check(exit.code === 78 && why && /world-writable/.test(why),
    `a world-writable state directory is refused, exit ${exit.code}: ${why}`);
}

async function main() {
  fs.rmSync(workRoot, { recursive: true, force: true });
  fs.mkdirSync(workRoot, { recursive: true });
  const keyFile = path.join(workRoot, 'mavlink.key');
  fs.writeFileSync(keyFile, KEY.toString('hex') + '\n', { mode: 0o600 });
  const stateDir = path.join(workRoot, 'state');
  fs.mkdirSync(stateDir, { mode: 0o700 });
  const stampFile = path.join(stateDir, 'signing-timestamp');
  const { sim, gportd } = await h.startGimbal(workRoot, gportdPath, simPath);
  const port = await h.freeUdpPort();
  await refusedKeyFile(keyFile, stateDir, port);

  let bridge = startBridge(keyFile, stateDir, port);
  await until(() => bridge.lines.some((l) => /signing: on/.test(l)), 10000, 'gport-mavlink with signing');
  // 0. A second gport-mavlink on the same --state-dir (another port) is
  //    refused: the two would overwrite each other's timestamp.
  const second = startBridge(keyFile, stateDir, await h.freeUdpPort(), 'gport-mavlink-same-state-dir');
  const secondExit = await second.exited;
  const why = second.lines.find((l) => /in use by another process/.test(l));
  check(secondExit.code === 78 && why && why.includes(stateDir),
    `a second gport-mavlink sharing --state-dir exits ${secondExit.code} (78 expected): ${why}`);
  const vehicle = new Peer({ sysid: 1, compid: 1, key: KEY, linkId: 1 });
  await vehicle.bind(); vehicle.target(port);
  const other = crypto.createHash('sha256').update('not the key').digest();

  // 1. Unsigned frames from the right system id move nothing and get no reply.
  let t0 = Date.now();
  vehicle.send(heartbeat(), { signed: false });
  check(!(await moves(vehicle, [0, -25, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -25, 0) }), { signed: false }))),
    'unsigned SET_ATTITUDE from system 1 moves nothing');
  vehicle.send(commandLong(2000), { signed: false });
  await sleep(500);
  check(vehicle.datagrams === 0 && h.cameraFrames(t0).length === 0,
    `unsigned frames get no reply (${vehicle.datagrams} datagrams) and no photo`);
  // 2. Wrong key, all-zero signature: nothing.
  check(!(await moves(vehicle, [0, -25, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -25, 0) }), { key: other }))),
    'SET_ATTITUDE signed with another key moves nothing');
  check(!(await moves(vehicle, [0, -25, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -25, 0) }), { zeroSignature: true }))),
    'SET_ATTITUDE with an all-zero signature moves nothing');
  // 3. Correctly signed: moves, and the vehicle becomes the peer.
  t0 = Date.now();
  vehicle.send(heartbeat());
  check(await moves(vehicle, [0, -25, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -25, 0) }))),
    'correctly signed SET_ATTITUDE moves the gimbal to pitch -25');
  await until(() => vehicle.since(t0, 'GIMBAL_DEVICE_ATTITUDE_STATUS').length >= 5, 5000, 'status to the vehicle');
  // 4. Replay: a captured frame sent again after a newer one moves nothing.
  const captured = vehicle.frame(setAttitude({ q: toQuaternion(0, -35, 0) }));
  check(await moves(vehicle, [0, -35, 0], () => vehicle.sendBytes(captured)), 'the captured frame (pitch -35) moves the gimbal once');
  check(await moves(vehicle, [0, -15, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -15, 0) }))), 'a newer frame moves it to -15');
  check(!(await moves(vehicle, [0, -35, 0], () => vehicle.sendBytes(captured))), 'the replayed capture moves nothing');
  // 5. A new stream (link 9) two minutes behind: refused; a recent one: taken.
  const stale = h.nowTimestamp() - 2 * ONE_MINUTE;
  check(!(await moves(vehicle, [0, -5, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -5, 0) }), { linkId: 9, timestamp: stale }))),
    'a new stream two minutes old moves nothing');
  check(await moves(vehicle, [0, -5, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -5, 0) }), { linkId: 10 })),
    'a new stream with a current timestamp moves the gimbal');
  const lastBefore = verifyOutgoing(vehicle, 0, 'first run');
  const kinds = [/dropped an unsigned/, /with a wrong signature/, /dropped a replayed/, /more than a minute behind/];
  check(kinds.every((re) => bridge.lines.filter((l) => re.test(l)).length === 1),
    `each kind of drop is logged once: ${kinds.map((re) => bridge.lines.filter((l) => re.test(l)).length)}`);

  // 6. Restart after SIGTERM: the stored timestamp covers everything sent,
  //    and the next frames are newer.
  bridge.kill('SIGTERM');
  await bridge.exited;
  const stored = Number(fs.readFileSync(stampFile, 'utf8').trim());
  check(stored >= lastBefore, `stored timestamp ${stored} >= last sent ${lastBefore}`);
  bridge = startBridge(keyFile, stateDir, port);
  t0 = await reachBridge(vehicle, 'frames after the restart');
  const afterRestart = vehicle.since(t0)[0].signature.timestamp;
  check(afterRestart > lastBefore, `after a restart the first timestamp ${afterRestart} > ${lastBefore}`);
  // 7. After a crash (SIGKILL) the stored reservation is above everything
  //    sent; a stored timestamp ahead of the clock (20 s: within the 30 s
  //    trusted) is where the next start begins, not the clock.
  const lastRun = verifyOutgoing(vehicle, t0, 'second run');
  bridge.kill('SIGKILL');
  await bridge.exited;
  const reserved = Number(fs.readFileSync(stampFile, 'utf8').trim());
  check(reserved > lastRun, `after SIGKILL the stored reservation ${reserved} > last sent ${lastRun}`);
  const ahead = h.nowTimestamp() + 20 * 100000;
  fs.writeFileSync(stampFile, `${ahead}\n`);
  bridge = startBridge(keyFile, stateDir, port);
  t0 = await reachBridge(vehicle, 'frames after the second restart');
  const third = vehicle.since(t0)[0].signature.timestamp;
  check(third > ahead, `with a stored timestamp 20 s ahead of the clock the first one sent is ${third} > ${ahead}`);
  verifyOutgoing(vehicle, t0, 'third run');
  figures.push(`timestamps: first run ended ${lastBefore}, second began ${afterRestart}, third began ${third} (stored ${ahead})`);
  bridge.kill('SIGTERM');
  await bridge.exited;
  await failedStarts(keyFile, stateDir, stampFile, port);
  await clockAttacks(vehicle, keyFile, stateDir, stampFile, port);
  await plantedState(vehicle, keyFile, stateDir, stampFile, port);
  vehicle.close();
  h.finish(workRoot, [sim, gportd]);
}

main().catch((error) => {
  console.error('FAIL ' + (error.stack || error.message) + `; logs in ${workRoot}`);
  process.exit(1);
});
