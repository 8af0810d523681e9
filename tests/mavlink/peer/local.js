'use strict';
// What another local user of the companion computer can do to gport-mavlink
// (docs/mavlink.md, "Security"), performed against the real gport-mavlink +
// gportd + gport-sim. The attacker is a process of another uid (65534,
// through setpriv) when the test runs as root, of the same uid otherwise.
//
//   node local.js GPORTD GPORT_SIM GPORT_MAVLINK WORKDIR
//
// 1. Port squatting: a socket with SO_REUSEADDR on the bridge's udpin
//    address (or the wildcard) cannot be bound while the bridge holds it,
//    and one bound first makes the bridge exit 71 saying so, instead of
//    both sharing the port and the squatter getting every datagram.
// 2. Without a signing key, a local process claiming system 1 is obeyed
//    and becomes the reply peer: what the documentation says remains
//    (every local user is trusted); its takeover is logged.
//    Cycling source ports (20, past the old lifetime cap of 16 logged
//    peers) to take the peer: every change is still named (10 a minute)
//    or counted in the summary.
// 3. udpout's connected socket: the same spoof, sent to the bridge's port
//    from anywhere but the configured peer, is dropped by the kernel.
const fs = require('fs');
const path = require('path');
const h = require('./harness');

const [gportdPath, simPath, bridgePath, workRoot] = process.argv.slice(2);
const { check, figures, sleep, until, toQuaternion, Peer, heartbeat, setAttitude } = h;
const MARKER = [0, -42, 33];

// The stranger: binds ADDRESS:PORT with SO_REUSEADDR (node's reuseAddr),
// prints {"bound": port} or {"error": code}, then sends FRAMES (hex,
// comma-separated) to 127.0.0.1:TARGET every 20 ms for MS and prints
// {"received": datagrams}.
const STRANGER = `
const dgram = require('dgram');
const [address, port, target, frames, ms] = process.argv.slice(1);
const s = dgram.createSocket({ type: 'udp4', reuseAddr: true });
let received = 0;
s.on('message', () => { received += 1; });
s.on('error', (e) => { console.log(JSON.stringify({ uid: process.getuid(), error: e.code })); process.exit(0); });
s.bind(Number(port), address, () => {
  console.log(JSON.stringify({ uid: process.getuid(), bound: s.address().port }));
  const list = frames ? frames.split(',').map((x) => Buffer.from(x, 'hex')) : [];
  let i = 0;
  const timer = setInterval(() => { if (list.length) s.send(list[i++ % list.length], Number(target), '127.0.0.1'); }, 20);
  setTimeout(() => { clearInterval(timer); console.log(JSON.stringify({ received })); process.exit(0); }, Number(ms));
});`;

// The cycler: from COUNT fresh sockets in turn, sends FRAMES to
// 127.0.0.1:TARGET; prints {"ports": [...]}.
const CYCLER = `
const dgram = require('dgram');
const [target, frames, count] = process.argv.slice(1);
const list = frames.split(',').map((x) => Buffer.from(x, 'hex'));
const ports = [];
(async () => {
  for (let i = 0; i < Number(count); i += 1) {
    const s = dgram.createSocket('udp4');
    await new Promise((r) => s.bind(0, '127.0.0.1', r));
    ports.push(s.address().port);
    for (const f of list) await new Promise((r) => s.send(f, Number(target), '127.0.0.1', r));
    await new Promise((r) => setTimeout(r, 30));
    s.close();
  }
  console.log(JSON.stringify({ ports }));
})();`;

const root = process.getuid() === 0;
const who = root ? 'uid 65534' : 'the same uid (not root: no second uid to try)';
let strangers = 0;
function stranger(address, port, { target = 0, frames = [], ms = 1000 } = {}) {
  const wrap = root ? ['setpriv', '--reuid=65534', '--regid=65534', '--clear-groups', '--'] : [];
  const argv = [...wrap, process.execPath, '-e', STRANGER, address, String(port), String(target),
    frames.map((f) => f.toString('hex')).join(','), String(ms)];
  strangers += 1;
  const child = h.start(workRoot, `stranger-${strangers}`, argv[0], argv.slice(1));
  child.report = (key) => until(() => {
    const line = child.lines.map((l) => { try { return JSON.parse(l); } catch (e) { return {}; } })
      .find((j) => key in j || 'error' in j);
    return line;
  }, 5000, `the stranger's ${key}`);
  return child;
}

function startBridge(url, name) {
  return h.start(workRoot, name, bridgePath,
    ['--socket', path.join(workRoot, 'gportd.sock'), '--mavlink', url]);
}

async function moves(degrees, send, ms = 700) {
  const t0 = Date.now();
  for (let i = 0; i < 5; i += 1) { send(); await sleep(20); }
  await sleep(ms);
  return h.angleFrames(t0, degrees).length > 0;
}

async function squatting(port) {
  // 1a. The squatter first: the bridge cannot share the port and says so.
  const first = stranger('127.0.0.1', port, { ms: 3000 });
  const bound = await first.report('bound');
  check(bound.bound === port, `${who} binds 127.0.0.1:${port} first (${JSON.stringify(bound)})`);
  const refused = startBridge(`udpin:127.0.0.1:${port}`, 'gport-mavlink-squatted');
  const exit = await refused.exited;
  const why = refused.lines.find((l) => /cannot bind/.test(l));
  check(exit.code === 71 && why && /[Aa]ddress already in use/.test(why),
    `gport-mavlink exits ${exit.code} (71 expected) on a squatted port: ${why}`);
  first.kill('SIGTERM');
  await first.exited;

  // 1b. The bridge first: nobody can bind beside it, on its address or the wildcard.
  const bridge = startBridge(`udpin:127.0.0.1:${port}`, 'gport-mavlink');
  await until(() => bridge.lines.some((l) => /MAVLink on udpin/.test(l)), 10000, 'gport-mavlink to start');
  for (const address of ['127.0.0.1', '0.0.0.0']) {
    const squatter = stranger(address, port);
    const result = await squatter.report('bound');
    check(result.error === 'EADDRINUSE',
      `${who} cannot bind ${address}:${port} beside gport-mavlink, SO_REUSEADDR or not (${JSON.stringify(result)})`);
    await squatter.exited;
  }
  return bridge;
}

async function spoofing(bridge, port) {
  // 2. The vehicle is the peer; a local process claiming system 1 takes over.
  const vehicle = new Peer({ sysid: 1, compid: 1 });
  await vehicle.bind(); vehicle.target(port);
  vehicle.send(heartbeat());
  check(await moves([0, -20, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -20, 0) }))),
    'the vehicle (system 1) moves the gimbal');
  const beats = setInterval(() => vehicle.send(heartbeat()), 1000);
  const forger = new Peer({ sysid: 1, compid: 1 }); // frames only: the stranger sends them
  const frames = [forger.frame(heartbeat()), forger.frame(setAttitude({ q: toQuaternion(...MARKER) }))];
  const t0 = Date.now();
  const spoofer = stranger('127.0.0.1', 0, { target: port, frames, ms: 2000 });
  const from = (await spoofer.report('bound')).bound;
  const got = (await spoofer.report('received')).received;
  clearInterval(beats);
  const moved = h.angleFrames(t0, MARKER).length > 0;
  const logged = bridge.lines.filter((l) => l.includes(`127.0.0.1:${from}`) && /reply peer|replying to/.test(l));
  figures.push(`without a key, ${who} claiming system 1 from port ${from}: gimbal moved ${moved}, ` +
    `${got} datagrams to it, log: ${logged[0]}`);
  check(moved && got > 0,
    `without a key a local process claiming system 1 is obeyed and answered (documented: every local user is trusted): moved ${moved}, ${got} datagrams`);
  check(logged.length >= 1, `its takeover of the reply peer is logged: ${logged[0]}`);
  // 2b. Cycling 20 source ports, each sending an accepted heartbeat.
  const wrap = root ? ['setpriv', '--reuid=65534', '--regid=65534', '--clear-groups', '--'] : [];
  const argv = [...wrap, process.execPath, '-e', CYCLER, String(port),
    forger.frame(heartbeat()).toString('hex'), '20'];
  const cycler = h.start(workRoot, 'cycler', argv[0], argv.slice(1));
  await cycler.exited;
  const cycled = JSON.parse(cycler.lines.find((l) => l.includes('ports'))).ports;
  check(cycled.length === 20, `${who} sent an accepted heartbeat from 20 ports in turn`);
  vehicle.close();
  forger.close();
}

async function connected() {
  // 3. udpout: the kernel drops datagrams from anyone but the peer.
  const vehicle = new Peer({ sysid: 1, compid: 1 });
  await vehicle.bind();
  const bridge = startBridge(`udpout:127.0.0.1:${vehicle.port()}`, 'gport-mavlink-udpout');
  await until(() => vehicle.to !== null, 10000, "gport-mavlink's first heartbeat over udpout");
  const bridgePort = vehicle.to.port;
  const forger = new Peer({ sysid: 1, compid: 1 });
  const frames = [forger.frame(heartbeat()), forger.frame(setAttitude({ q: toQuaternion(...MARKER) }))];
  const t0 = Date.now();
  const spoofer = stranger('127.0.0.1', 0, { target: bridgePort, frames, ms: 1500 });
  const got = (await spoofer.report('received')).received;
  check(h.angleFrames(t0, MARKER).length === 0 && got === 0,
    `udpout: ${who} claiming system 1 to gport-mavlink's port ${bridgePort} moves nothing and gets ${got} datagrams`);
  check(await moves([0, -25, 0], () => vehicle.send(setAttitude({ q: toQuaternion(0, -25, 0) }))),
    'udpout: the configured peer (the vehicle) still moves the gimbal');
  bridge.kill('SIGTERM');
  await bridge.exited;
  vehicle.close();
  forger.close();
}

async function main() {
  fs.rmSync(workRoot, { recursive: true, force: true });
  fs.mkdirSync(workRoot, { recursive: true });
  const { sim, gportd } = await h.startGimbal(workRoot, gportdPath, simPath);
  const port = await h.freeUdpPort();
  const bridge = await squatting(port);
  await spoofing(bridge, port);
  bridge.kill('SIGTERM');
  const exit = await bridge.exited;
  check(exit.code === 0, `gport-mavlink exits 0 on SIGTERM (${exit.code} ${exit.signal})`);
  // Every peer change named (at most 10 a minute) or counted; nothing lost.
  const named = bridge.lines.filter((l) => /replying to/.test(l)).length;
  const counted = bridge.lines.map((l) => /reply peer changed: (\d+) more/.exec(l)).filter((m) => m)
    .reduce((n, m) => n + Number(m[1]), 0);
  figures.push(`reply peer changes: ${named} named, ${counted} counted`);
  check(named <= 10 && named + counted >= 22,
    `peer changes past the old cap of 16 are still accounted for: ${named} named (10 a minute at most) + ${counted} counted >= 22`);
  await connected();
  h.finish(workRoot, [sim, gportd]);
}

main().catch((error) => {
  console.error('FAIL ' + (error.stack || error.message) + `; logs in ${workRoot}`);
  process.exit(1);
});
