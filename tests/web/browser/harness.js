'use strict';
// What web.js needs around the browser: checks and figures, child
// processes with their output kept in WORKDIR/NAME.log, gport-sim's trace
// on our clock, gportd's socket, and gport-web started with a token file.
const { spawn } = require('child_process');
const crypto = require('crypto');
const fs = require('fs');
const net = require('net');
const path = require('path');
const readline = require('readline');

// ---- checks and figures
const failures = [];
const figures = [];
function check(ok, message) {
  console.log((ok ? 'ok   ' : 'FAIL ') + message);
  if (!ok) failures.push(message);
  return ok;
}
function figure(text) {
  console.log('     ' + text);
  figures.push(text);
}
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
async function until(predicate, timeoutMs, what) {
  const end = Date.now() + timeoutMs;
  for (;;) {
    const value = await predicate();
    if (value) return value;
    if (Date.now() > end) throw new Error('timed out waiting for ' + what);
    await sleep(20);
  }
}

// ---- child processes
const children = [];
process.on('exit', () => children.forEach((c) => { if (c.exitCode === null) c.kill('SIGKILL'); }));
function start(workRoot, name, cmd, args, onLine) {
  // A .js "program" (a stand-in for a server under development) runs under this node.
  const [file, argv] = cmd.endsWith('.js') ? [process.execPath, [cmd, ...args]] : [cmd, args];
  const child = spawn(file, argv, { stdio: ['ignore', 'pipe', 'pipe'] });
  children.push(child);
  child.lines = [];
  const log = fs.createWriteStream(path.join(workRoot, name + '.log'), { flags: 'a' });
  const keep = (prefix) => (line) => {
    child.lines.push(line);
    log.write(prefix + line + '\n');
    if (onLine) onLine(line);
  };
  readline.createInterface({ input: child.stdout }).on('line', keep(''));
  readline.createInterface({ input: child.stderr }).on('line', keep('stderr: '));
  child.exited = new Promise((resolve) => child.on('exit', (code, signal) => {
    log.write(`exited: ${code} ${signal}\n`);
    resolve({ code, signal });
  }));
  return child;
}

// ---- gport-sim's trace
// Each line carries t_ms, gport-sim's own clock. A frame's time on our
// clock (Date.now(), which the browser shares on this machine) is t_ms
// plus the smallest (read time - t_ms) seen: a line read late on a loaded
// machine still gets the time it reached the wire, and the estimate can only
// err late (a latency measured with it is never too small).
const trace = [];
const simClock = { offset: Infinity };
function onTrace(line) {
  let j;
  try { j = JSON.parse(line); } catch (e) { return; }
  const t = Date.now();
  if (typeof j.t_ms === 'number') simClock.offset = Math.min(simClock.offset, t - j.t_ms);
  trace.push({ t, j });
}
const wireTime = (e) => (typeof e.j.t_ms === 'number' ? simClock.offset + e.j.t_ms : e.t);
const speedFrames = (since) =>
  trace.filter((e) => e.j.cmd === '0x85' && e.j.mode === 'speed' && wireTime(e) >= since);
const isZero = (e) => e.j.speed.every((v) => v === 0);
const cameraFrames = (since) => trace.filter((e) => e.j.cmd === '0x86' && wireTime(e) >= since);

// ---- gportd's socket: one JSON-RPC call per connection
function rpc(socketPath, method, params) {
  return new Promise((resolve, reject) => {
    const c = net.createConnection(socketPath);
    let buffer = '';
    c.on('error', reject);
    c.on('connect', () => c.write(JSON.stringify({ id: 1, method, params: params || {} }) + '\n'));
    c.on('data', (d) => {
      buffer += d.toString();
      for (let nl = buffer.indexOf('\n'); nl >= 0; nl = buffer.indexOf('\n')) {
        const message = JSON.parse(buffer.slice(0, nl));
        buffer = buffer.slice(nl + 1);
        if (message.id === 1) { c.end(); resolve(message); return; }
      }
    });
  });
}

// ---- the programs
// gport-sim, then gportd on its link. Resolves once gportd says the link is up.
async function startGimbal(workRoot, gportdPath, simPath) {
  const link = path.join(workRoot, 'gimbal');
  const config = path.join(workRoot, 'gportd.json');
  fs.writeFileSync(config, JSON.stringify({
    link: { stale_ms: 300, reconnect_initial_ms: 50, reconnect_max_ms: 200 },
    requests: { timeout_ms: 500, retries: 2 },
    // A published position is kept 10 s (default 1 s): a slow machine
    // leaves no capture of section 6c untagged by its age.
    camera: { max_commands_per_s: 1000, max_position_age_ms: 10000 },
  }));
  const sim = start(workRoot, 'gport-sim', simPath, ['--link', link, '--trace'], onTrace);
  await until(() => fs.existsSync(link), 10000, 'the simulator link');
  const { gportd, sock } = await startGportd(workRoot, gportdPath);
  return { sim, gportd, sock };
}

// gportd on gport-sim's link (again, after startGimbal: a new gportd on the
// same socket path, configuration and link; a stale socket file it removes).
async function startGportd(workRoot, gportdPath) {
  const sock = path.join(workRoot, 'gportd.sock');
  const gportd = start(workRoot, 'gportd', gportdPath, ['--config', path.join(workRoot, 'gportd.json'),
    '--socket', sock, '--device', path.join(workRoot, 'gimbal'), '--log-level', 'info']);
  const up = async () => {
    try { return (await rpc(sock, 'status')).result.link.state === 'up'; } catch (e) { return false; }
  };
  await until(up, 10000, 'gportd answering with the link up');
  return { gportd, sock };
}

// gport-web with a token file of one control and one view token (mode 0600,
// as gport-web demands). Resolves with the URL it prints. With `again`
// (a previous start's {url, tokens}): the same address and token file.
async function startWeb(workRoot, webPath, sock, again) {
  const tokenFile = path.join(workRoot, 'token');
  let tokens = again && again.tokens;
  if (!tokens) {
    tokens = { control: crypto.randomBytes(16).toString('hex'), view: crypto.randomBytes(16).toString('hex') };
    fs.rmSync(tokenFile, { force: true });
    fs.writeFileSync(tokenFile, `control:${tokens.control}\nview:${tokens.view}\n`, { mode: 0o600 });
  }
  const listen = again ? new URL(again.url).host : '127.0.0.1:0';
  const web = start(workRoot, 'gport-web', webPath,
    ['--socket', sock, '--listen', listen, '--token-file', tokenFile]);
  const line = await until(() => web.lines.find((l) => /serving https?:\/\/\S+/.test(l)) ||
    (web.exitCode !== null && 'exited'), 20000, 'gport-web: serving ...');
  if (line === 'exited') throw new Error('gport-web exited: ' + web.lines.join('\n'));
  const url = line.match(/serving (https?:\/\/\S+?)\/?$/)[1];
  return { web, url, tokens };
}

// SIGKILL to one child; resolves once it is gone.
async function kill(child) {
  child.kill('SIGKILL');
  await child.exited;
}

// SIGTERM to every child still running (gport-web, gportd, gport-sim, in
// reverse order of start), SIGKILL after 5 s.
async function stopAll() {
  for (const child of children.slice().reverse()) {
    if (child.exitCode !== null || child.signalCode !== null) continue;
    child.kill('SIGTERM');
    const timer = setTimeout(() => child.kill('SIGKILL'), 5000);
    await child.exited;
    clearTimeout(timer);
  }
}

module.exports = {
  check, figure, failures, figures, sleep, until, start, trace, wireTime, speedFrames, isZero,
  cameraFrames, rpc, startGimbal, startGportd, startWeb, kill, stopAll,
};
