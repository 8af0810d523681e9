'use strict';
// gport-mavlink trusts only its vehicle: the attacks of issue 22 performed
// with node-mavlink against the real gport-mavlink (udpin, its defaults:
// vehicle system 1, ground station 255, no signing) + gportd + gport-sim.
//
//   node trust.js GPORTD GPORT_SIM GPORT_MAVLINK WORKDIR
//
// gport-sim's --trace shows what reaches the gimbal: 0x85 motion, 0x86
// camera. Timing checks are loose; figures are printed.
const fs = require('fs');
const path = require('path');
const h = require('./harness');

const [gportdPath, simPath, bridgePath, workRoot] = process.argv.slice(2);
const { check, figures, sleep, until, toQuaternion, Peer, heartbeat, setAttitude, commandLong } = h;
const PHOTO = 2000;

const linesMatching = (child, re) => child.lines.filter((l) => re.test(l));

async function flood(peer, hz, ms, make) {
  const end = Date.now() + ms;
  let n = 0;
  while (Date.now() < end) { peer.send(make()); n += 1; await sleep(1000 / hz); }
  return n;
}

async function main() {
  fs.rmSync(workRoot, { recursive: true, force: true });
  fs.mkdirSync(workRoot, { recursive: true });
  const { sim, gportd } = await h.startGimbal(workRoot, gportdPath, simPath);
  const sock = path.join(workRoot, 'gportd.sock');
  const port = await h.freeUdpPort();
  const bridge = h.start(workRoot, 'gport-mavlink', bridgePath,
    ['--socket', sock, '--mavlink', `udpin:127.0.0.1:${port}`, '--attitude-rate', '10']);
  await until(() => bridge.lines.some((l) => /MAVLink on udpin/.test(l)), 10000, 'gport-mavlink to start');

  const rogue = new Peer({ sysid: 99, compid: 1 });
  const vehicle = new Peer({ sysid: 1, compid: 1 });
  const gcs = new Peer({ sysid: 255, compid: 190 });
  const extras = [0, 1, 2, 3].map(() => new Peer({ sysid: 99, compid: 1 }));
  for (const p of [rogue, vehicle, gcs, ...extras]) { await p.bind(); p.target(port); }

  // 1. A rogue autopilot heartbeat first, then broadcast-targeted commands
  //    from system 99: nothing moves, no photo, and nothing is sent to it.
  let t0 = Date.now();
  for (let i = 0; i < 3; i += 1) { rogue.send(heartbeat()); await sleep(100); }
  const rogueTarget = toQuaternion(0, -45, 60);
  const sent = await flood(rogue, 50, 1500, () => setAttitude({ q: rogueTarget, targetSystem: 0, targetComponent: 0 }));
  rogue.send(commandLong(PHOTO, { targetSystem: 0, targetComponent: 0 }));
  rogue.send(setAttitude({ flags: 2, targetSystem: 0, targetComponent: 0 })); // NEUTRAL
  rogue.send(setAttitude({ rates: [0, 0, h.rad(30)], targetSystem: 0, targetComponent: 0 }));
  await sleep(800);
  check(h.controlFrames(t0).length === 0 && h.cameraFrames(t0).length === 0,
    `rogue system 99 (heartbeat first, ${sent} broadcast SET_ATTITUDE, photo, neutral, rate): ` +
    `${h.controlFrames(t0).length} motion and ${h.cameraFrames(t0).length} camera frames reach the gimbal`);
  check(rogue.datagrams === 0, `the rogue got ${rogue.datagrams} datagrams from gport-mavlink (udpin sends nothing before an accepted frame)`);
  check(linesMatching(bridge, /ignoring system 99 component 1/).length === 1,
    `one log line for the rogue sender (${linesMatching(bridge, /ignoring system 99/).length})`);
  check(!bridge.lines.some((l) => /adopted system/.test(l)), 'the rogue heartbeat was not adopted');

  // 2. The real vehicle (system 1) still works, and becomes the reply peer.
  t0 = Date.now();
  vehicle.send(heartbeat());
  await flood(vehicle, 50, 600, () => setAttitude({ q: toQuaternion(0, -20, 10) }));
  const moved = await until(() => h.angleFrames(t0, [0, -20, 10]).length > 0, 5000, 'the vehicle\'s angle').catch(() => false);
  check(moved, 'the vehicle (system 1) moves the gimbal to pitch -20, yaw 10');
  const status = await until(() => vehicle.since(t0, 'GIMBAL_DEVICE_ATTITUDE_STATUS').length > 0, 5000,
    'attitude status to the vehicle').catch(() => false);
  check(status, 'attitude status goes to the vehicle, the sender of an accepted frame');

  // 3. Rogue datagrams (one byte, garbage, rogue frames) from several ports
  //    do not steal the reply peer.
  t0 = Date.now();
  const beats = setInterval(() => vehicle.send(heartbeat()), 1000);
  let datagrams = 0;
  const end = Date.now() + 2000;
  while (Date.now() < end) {
    for (const p of extras) {
      p.sendBytes(Buffer.from([0xfd]));
      p.sendBytes(Buffer.from([datagrams & 255]));
      p.send(setAttitude({ q: rogueTarget, targetSystem: 0, targetComponent: 0 }));
      datagrams += 3;
    }
    await sleep(10);
  }
  const during = vehicle.since(t0, 'GIMBAL_DEVICE_ATTITUDE_STATUS').length;
  const stolen = extras.reduce((n, p) => n + p.datagrams, 0) + rogue.datagrams;
  figures.push(`${datagrams} rogue datagrams from ${extras.length} ports in 2 s: vehicle got ${during} status messages, rogues ${stolen} datagrams`);
  check(stolen === 0 && during >= 10, `the reply peer stays the vehicle (${during} status messages in 2 s; rogues got ${stolen})`);
  check(h.angleFrames(t0, [0, -45, 60], 0.5).length === 0, "the rogue's target never reaches the gimbal");
  const peerLines = linesMatching(bridge, /replying to/);
  check(peerLines.length === 1, `peer lines: ${peerLines.length} (the vehicle only)`);

  // 4. A ground station (255) may command: a photo, acknowledged.
  t0 = Date.now();
  gcs.send(heartbeat({ type: 6, autopilot: 8 }));
  gcs.send(commandLong(PHOTO));
  const ack = await until(() => gcs.since(t0, 'COMMAND_ACK').find((r) => r.data.command === PHOTO), 5000, 'the photo ACK').catch(() => null);
  const photo = await until(() => h.cameraFrames(t0).find((f) => f.j.action === 'photo'), 5000, 'a photo frame').catch(() => null);
  check(ack && ack.data.result === 0 && photo, `ground station 255: photo ACK ${ack && ack.data.result}, camera frame ${photo && photo.j.action}`);

  // 4b. A camera-command flood (100 photos at once, from a trusted sender or,
  //     without a key, anyone claiming 255): one call in flight at gportd,
  //     the others answered TEMPORARILY_REJECTED (1); the vehicle's angles
  //     still get through (gportd's request budget is not used up).
  t0 = Date.now();
  for (let i = 0; i < 100; i += 1) {
    gcs.send(commandLong(PHOTO));
    if (i % 25 === 24) await sleep(5);
  }
  await until(() => gcs.since(t0, 'COMMAND_ACK').filter((r) => r.data.command === PHOTO).length >= 100, 10000,
    '100 photo ACKs').catch(() => null);
  const acks = gcs.since(t0, 'COMMAND_ACK').filter((r) => r.data.command === PHOTO);
  const accepted = acks.filter((r) => r.data.result === 0).length;
  const busy = acks.filter((r) => r.data.result === 1).length;
  await sleep(500);
  const photos = h.cameraFrames(t0).filter((f) => f.j.action === 'photo').length;
  figures.push(`100 photo commands at once: ${acks.length} ACKs, ${accepted} accepted, ${busy} temporarily rejected, ${photos} photos at the gimbal`);
  check(acks.length === 100 && accepted + busy === 100 && busy >= 20 && accepted >= 1,
    `a flood of 100 photo commands: every one answered (${acks.length}), ${accepted} accepted, ${busy} TEMPORARILY_REJECTED`);
  check(photos === accepted, `only the accepted ones reach the gimbal: ${photos} photos for ${accepted} accepted`);
  check(linesMatching(bridge, /answered TEMPORARILY_REJECTED/).length === 1, 'the rejections are logged once (then counted)');
  t0 = Date.now();
  await flood(vehicle, 50, 400, () => setAttitude({ q: toQuaternion(0, -30, 0) }));
  check(await until(() => h.angleFrames(t0, [0, -30, 0]).length > 0, 5000, 'the angle after the flood').catch(() => false),
    "after the flood the vehicle's angle still reaches the gimbal");

  // 4c. The vehicle is the gimbal manager (docs/mavlink.md, "Who moves the
  //     gimbal, and the stop"): a ground station streaming angles at 200/s
  //     is overruled while the vehicle commands; each of the vehicle's rates
  //     and each of its stops reaches the gimbal, the station's target never.
  //     Five seconds after the vehicle's last message the station moves it.
  t0 = Date.now();
  const gcsTarget = [0, 25, -40];
  let streaming = true;
  const gcsStream = (async () => {
    while (streaming) { gcs.send(setAttitude({ q: toQuaternion(...gcsTarget) })); await sleep(5); }
  })();
  const stopsSent = [];
  for (let i = 0; i < 5; i += 1) {
    await flood(vehicle, 50, 200, () => setAttitude({ rates: [0, 0, h.rad(10)] }));
    stopsSent.push(Date.now());
    vehicle.send(setAttitude({ rates: [0, 0, 0] }));
    await sleep(150);
  }
  streaming = false;
  await gcsStream;
  await sleep(300);
  const speeds = h.controlFrames(t0).filter((f) => f.j.mode === 'speed');
  const zeroAfter = (t) => speeds.some((f) => h.sameAxes(f.j.speed, [0, 0, 0]) && h.sentAt(f) >= t - 5 &&
    h.sentAt(f) < t + 150);
  const stopsSeen = stopsSent.filter(zeroAfter).length;
  const overruled = h.angleFrames(stopsSent[0] - 200, gcsTarget, 0.5).length;
  figures.push(`ground station streaming angles at 200/s while the vehicle sends 5 rates and 5 stops: ` +
    `${stopsSeen} stops and ${overruled} of the station's angles at the gimbal`);
  check(stopsSeen === 5 && overruled === 0,
    `the vehicle's stops all reach the gimbal (${stopsSeen} of 5) and the station's angles none (${overruled})`);
  check(linesMatching(bridge, /is the gimbal manager and commands it/).length === 1,
    'the overruled station is logged once (then counted)');
  await sleep(5200);
  t0 = Date.now();
  await flood(gcs, 50, 400, () => setAttitude({ q: toQuaternion(...gcsTarget) }));
  check(await until(() => h.angleFrames(t0, gcsTarget, 0.5).length > 0, 5000, "the station's angle").catch(() => false),
    '5 s after the vehicle\'s last command the ground station moves the gimbal again');

  // 5. Bounded logs: 40 rogue system ids make no new line (one a minute,
  //    then a count; section 1 wrote this minute's), 1,000
  //    bad quaternions from the vehicle make one warning.
  const before = bridge.lines.length;
  const dropsBefore = h.udpSocket(port).drops;
  for (let id = 100; id < 140; id += 1) {
    const p = new Peer({ sysid: id, compid: 1 });
    p.socket = rogue.socket; // one socket, many claimed ids
    p.to = rogue.to;
    p.send(setAttitude({ q: rogueTarget, targetSystem: 0, targetComponent: 0 }));
  }
  for (let i = 0; i < 1000; i += 1) {
    vehicle.send(setAttitude({ q: [Infinity, 0, 0, 0] }));
    if (i % 50 === 0) await sleep(5);
  }
  await sleep(800);
  await until(() => h.udpSocket(port).queued === 0, 10000, 'gport-mavlink to read every datagram').catch(() => null);
  const dropped = h.udpSocket(port).drops - dropsBefore;
  const stranger = bridge.lines.slice(before).filter((l) => /ignoring system|untrusted senders/.test(l));
  const quaternion = bridge.lines.slice(before).filter((l) => /bad quaternion/.test(l));
  figures.push(`40 more rogue system ids -> ${stranger.length} lines; 1,000 infinite quaternions -> ${quaternion.length} line(s); ` +
    `${dropped} datagram(s) dropped by the kernel (gport-mavlink's receive buffer full)`);
  check(stranger.length <= 1, `rogue sender lines bounded: ${stranger.length} (one a minute, then a count)`);
  check(quaternion.length === 1, `1,000 bad quaternions -> ${quaternion.length} warning line`);

  // 6. Exit: the counters, and the pending summary of the quaternions.
  clearInterval(beats);
  bridge.kill('SIGTERM');
  const exit = await bridge.exited;
  check(exit.code === 0, `gport-mavlink exits 0 on SIGTERM (${exit.code} ${exit.signal})`);
  // Every quaternion that reached gport-mavlink is counted: 999 more, less
  // those the kernel dropped before it could read them (a slow receiver's
  // full socket buffer, under ASan on a busy machine; the drops counted
  // include any of the 40 rogue frames, so the lower bound is loose by at
  // most 40).
  const summary = bridge.lines.map((l) => /bad quaternion: (\d+) more/.exec(l)).find((m) => m);
  const more = summary ? Number(summary[1]) : -1;
  check(more <= 999 && more >= 999 - dropped,
    `the summary counts the other bad quaternions: ${more} more (999 sent, ${dropped} dropped by the kernel)`);
  const refused = bridge.lines.map((l) => /(\d+) refused by the trust rules/.exec(l)).find((m) => m);
  check(refused && Number(refused[1]) >= 40, `the exit line counts the untrusted frames (${refused && refused[1]})`);
  const counted = bridge.lines.map((l) => /untrusted frames ignored: (\d+) more/.exec(l)).find((m) => m);
  check(counted && Number(counted[1]) >= 40, `the untrusted frames not written are counted (${counted && counted[1]} more)`);
  figures.push(`gport-mavlink wrote ${bridge.lines.length} lines in all`);
  check(!bridge.lines.some((l) => /^warning: /.test(l)), 'no "warning: " text-only priority prefix');
  for (const p of [rogue, vehicle, gcs, ...extras]) p.close();
  h.finish(workRoot, [sim, gportd]);
}

main().catch((error) => {
  console.error('FAIL ' + (error.stack || error.message) + `; logs in ${workRoot}`);
  process.exit(1);
});
