'use strict';
// MAVLink 2 signing against the real gport-mavlink (udpin, --signing-key,
// --state-dir) + gportd + gport-sim, played with node-mavlink and its
// signer: unsigned, wrongly signed, replayed and stale frames move nothing;
// correctly signed ones do; every frame the bridge sends verifies with
// node-mavlink; its outgoing timestamp stays monotonic across restarts.
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

async function moves(peer, degrees, send) {
  const t0 = Date.now();
  for (let i = 0; i < 5; i += 1) { send(); await sleep(20); }
  await sleep(700);
  return h.angleFrames(t0, degrees).length > 0;
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
//    creep ahead; one more than 60 s ahead of the clock is warned about.
async function failedStarts(keyFile, stateDir, stampFile, port) {
  const squatter = dgram.createSocket('udp4');
  await new Promise((resolve, reject) => { squatter.once('error', reject); squatter.bind(port, '127.0.0.1', resolve); });
  const farAhead = h.nowTimestamp() + 120 * 100000;
  fs.writeFileSync(stampFile, `${farAhead}\n`);
  const values = [];
  let warned = 0;
  const exits = [];
  for (let i = 0; i < 5; i += 1) {
    const failed = startBridge(keyFile, stateDir, port, `gport-mavlink-squatted-${i}`);
    exits.push((await failed.exited).code);
    values.push(Number(fs.readFileSync(stampFile, 'utf8').trim()));
    warned += failed.lines.some((l) => /ahead of this machine's clock/.test(l)) ? 1 : 0;
  }
  squatter.close();
  figures.push(`stored timestamp over 5 failed starts: ${farAhead} -> ${values.join(', ')}`);
  check(exits.every((c) => c === 71), `5 starts on a taken port exit 71: ${exits}`);
  check(values.every((v) => v === farAhead),
    `the stored timestamp does not grow over 5 failed starts (${farAhead} -> ${values[values.length - 1]})`);
  check(warned === 5, `each start warns that the stored timestamp is 120 s ahead of the clock (${warned} of 5)`);
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
  //    sent; a stored timestamp ahead of the clock (50 s: within the minute
  //    peers accept) is where the next start begins, not the clock.
  const lastRun = verifyOutgoing(vehicle, t0, 'second run');
  bridge.kill('SIGKILL');
  await bridge.exited;
  const reserved = Number(fs.readFileSync(stampFile, 'utf8').trim());
  check(reserved > lastRun, `after SIGKILL the stored reservation ${reserved} > last sent ${lastRun}`);
  const ahead = h.nowTimestamp() + 50 * 100000;
  fs.writeFileSync(stampFile, `${ahead}\n`);
  bridge = startBridge(keyFile, stateDir, port);
  t0 = await reachBridge(vehicle, 'frames after the second restart');
  const third = vehicle.since(t0)[0].signature.timestamp;
  check(third > ahead, `with a stored timestamp 50 s ahead of the clock the first one sent is ${third} > ${ahead}`);
  verifyOutgoing(vehicle, t0, 'third run');
  figures.push(`timestamps: first run ended ${lastBefore}, second began ${afterRestart}, third began ${third} (stored ${ahead})`);
  bridge.kill('SIGTERM');
  await bridge.exited;
  await failedStarts(keyFile, stateDir, stampFile, port);
  vehicle.close();
  h.finish(workRoot, [sim, gportd]);
}

main().catch((error) => {
  console.error('FAIL ' + (error.stack || error.message) + `; logs in ${workRoot}`);
  process.exit(1);
});
