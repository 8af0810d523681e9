'use strict';
// Issue 22, item 4: how many lines gport-mavlink writes under two floods
// (a figure, not a ctest; docs/mavlink.md, "Security").
//
//   NODE_PATH=<build>/tests/mavlink/peer/mavlink-peer/node_modules \
//     node tests/mavlink/peer/log_flood.js GPORTD GPORT_SIM GPORT_MAVLINK WORKDIR [ARGS...]
//
// ARGS go to gport-mavlink (e.g. --sysid 1 for a build that adopts the
// system id). It listens on udpin:127.0.0.1:<free port>.
//   (a) 1,000 GIMBAL_DEVICE_SET_ATTITUDE with an infinite quaternion from
//       system 1, its other components different each time (a value in the
//       text made the old "once per distinct message" write every one): warning lines, counted until gport-mavlink has exited
//       (SIGTERM), so that a summary written at exit counts too;
//   (b) 5,000 one-byte datagrams, alternating between two source ports,
//       after one valid heartbeat from system 1: lines about the peer.
const fs = require('fs');
const path = require('path');
const h = require('./harness');

const [gportdPath, simPath, bridgePath, workRoot, ...extra] = process.argv.slice(2);
const { sleep, until, Peer, heartbeat, setAttitude } = h;

async function run(name, flood, countRe) {
  const port = await h.freeUdpPort();
  const bridge = h.start(workRoot, name, bridgePath,
    ['--socket', path.join(workRoot, 'gportd.sock'), '--mavlink', `udpin:127.0.0.1:${port}`, ...extra]);
  await until(() => bridge.lines.some((l) => /MAVLink on/.test(l)), 10000, 'gport-mavlink to start');
  const peers = [new Peer({ sysid: 1, compid: 1 }), new Peer({ sysid: 1, compid: 1 })];
  for (const p of peers) { await p.bind(); p.target(port); }
  peers[0].send(heartbeat());
  await sleep(300);
  const before = bridge.lines.length;
  await flood(peers);
  await sleep(1000);
  bridge.kill('SIGTERM');
  await bridge.exited;
  for (const p of peers) p.close();
  const lines = bridge.lines.slice(before).filter((l) => countRe.test(l));
  console.log(`${name}: ${lines.length} lines (of ${bridge.lines.length - before} written during and after the flood)`);
  for (const l of lines.slice(0, 3)) console.log(`    ${l.slice(0, 160)}`);
  return lines.length;
}

async function main() {
  fs.rmSync(workRoot, { recursive: true, force: true });
  fs.mkdirSync(workRoot, { recursive: true });
  const { sim, gportd } = await h.startGimbal(workRoot, gportdPath, simPath);
  const a = await run('(a) 1,000 infinite quaternions', async ([p]) => {
    for (let i = 0; i < 1000; i += 1) {
      p.send(setAttitude({ q: [Infinity, i / 1000, 0, 0] }));
      if (i % 50 === 49) await sleep(5);
    }
  }, /warn/);
  const b = await run('(b) 5,000 one-byte datagrams from two ports', async (peers) => {
    for (let i = 0; i < 5000; i += 1) {
      peers[i % 2].sendBytes(Buffer.from([i & 0xff]));
      if (i % 100 === 99) await sleep(2);
    }
  }, /mavlink: peer |replying to/);
  console.log(`figures: (a) ${a} warning lines, (b) ${b} peer lines`);
  for (const child of [gportd, sim]) child.kill('SIGTERM');
  process.exit(0);
}

main().catch((error) => {
  console.error('FAIL ' + (error.stack || error.message));
  process.exit(1);
});
