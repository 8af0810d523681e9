'use strict';
// A second real autopilot: PX4 SITL (../shared/tools/px4-sitl, the SIH
// quadcopter, MNT_MODE_IN 4 / MNT_MODE_OUT 2) against gport-mavlink on
// PX4's Gimbal link (udpin on 127.0.0.1:13280, where PX4's run script
// sends it), gportd and gport-sim; a node-mavlink ground station (255/190)
// on PX4's ground-station port (udp 18570). Checked: discovery through
// PX4's broadcast REQUEST_MESSAGE(283) (GIMBAL_MANAGER_STATUS then names
// device 154); control taken with DO_GIMBAL_MANAGER_CONFIGURE; then
// DO_GIMBAL_MANAGER_PITCHYAW angles (vehicle frame) on gport-sim's trace.
//
//   node px4.js PX4_DIR GPORTD GPORT_SIM GPORT_MAVLINK WORKDIR
//
// Exits 77 (skipped, saying why) when PX4_DIR has no bin/px4 or etc/.
const fs = require('fs');
const path = require('path');
const { spawn } = require('child_process');
const os = require('os');
const h = require('./harness');

const [px4Dir, gportdPath, simPath, bridgePath, workRoot] = process.argv.slice(2);
const { check, figures, sleep, until, Peer, heartbeat, commandLong } = h;
const [GIMBAL_LINK_PORT, GCS_PORT] = [13280, 18570];
const [PITCHYAW, CONFIGURE] = [1000, 1001];

const toPx4 = (command, params) => commandLong(command, { params, targetSystem: 1, targetComponent: 1 });

// Sends `command` every 500 ms until PX4 ACKs it; the ACK, or null.
async function commandUntilAck(gcs, command, params, timeoutMs) {
  const t0 = Date.now();
  for (let t = t0; Date.now() - t0 < timeoutMs; t = Date.now()) {
    gcs.send(toPx4(command, params));
    const ack = await until(() => gcs.since(t, 'COMMAND_ACK').find((a) => a.data.command === command), 500, 'ack')
      .catch(() => null);
    if (ack) return ack;
  }
  return null;
}

// PX4 as its `run` script starts it, in a new folder of our own: that
// script runs the shared folder's bin/px4, whose module links (px4-param
// and the like, symbolic links to px4 in PX4's build) may have been copied
// as 3-byte files holding "px4"; then every module call fails ("px4-param:
// Permission denied") and PX4 finds no airframe. The folder gets its own
// bin/ with those links made again (other files linked as they are).
function startPx4() {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'px4-sitl-'));
  const bin = path.join(dir, 'bin');
  fs.mkdirSync(bin);
  for (const name of fs.readdirSync(path.join(px4Dir, 'bin'))) {
    const source = path.join(px4Dir, 'bin', name);
    const flattened = name.startsWith('px4-') && fs.lstatSync(source).size === 3 &&
      fs.readFileSync(source, 'utf8') === 'px4';
    fs.symlinkSync(flattened ? 'px4' : source, path.join(bin, name));
  }
  fs.symlinkSync(path.join(px4Dir, 'etc'), path.join(dir, 'etc'));
  const log = fs.openSync(path.join(dir, 'px4.log'), 'w');
  const child = spawn(path.join(bin, 'px4'), ['-d'], {
    cwd: dir, stdio: ['ignore', log, log],
    env: { PATH: `${bin}:/usr/bin:/bin`, PX4_SIM_MODEL: 'sihsim_quadx', PX4_SIMULATOR: 'sihsim',
      PX4_SYS_AUTOSTART: '10040', PX4_PARAM_MNT_MODE_IN: '4', PX4_PARAM_MNT_MODE_OUT: '2' },
  });
  return { dir, child };
}

async function px4Checks(gcs, bridge, started) {
  // 1. Discovery: PX4's broadcast REQUEST_MESSAGE(283), then its manager names 154.
  const request = await until(() => bridge.lines.find((l) => /REQUEST_MESSAGE\(283\) from system 1 component 1 to 0\/0/.test(l)),
    40000, 'REQUEST_MESSAGE(283)').catch(() => null);
  check(request !== null, `PX4 broadcast REQUEST_MESSAGE(283) on the Gimbal link: ${request}`);
  const status = await until(() => gcs.since(started, 'GIMBAL_MANAGER_STATUS').find((s) => s.data.gimbalDeviceId === 154),
    20000, 'GIMBAL_MANAGER_STATUS naming 154').catch(() => null);
  figures.push(`discovery ${((Date.now() - started) / 1000).toFixed(1)} s after PX4 started`);
  check(status !== null, `GIMBAL_MANAGER_STATUS names gimbal device ${status && status.data.gimbalDeviceId}`);
  if (!status) return;
  // 2. Control: the ground station as primary.
  const configured = await commandUntilAck(gcs, CONFIGURE, [255, 190, -1, -1, 0, 0, 0], 10000);
  check(configured && configured.data.result === 0, `DO_GIMBAL_MANAGER_CONFIGURE (255/190 primary): ACK ${configured && configured.data.result}`);
  const primary = await until(() => gcs.since(Date.now() - 1500, 'GIMBAL_MANAGER_STATUS')
    .find((s) => s.data.primaryControlSysid === 255 && s.data.primaryControlCompid === 190), 5000, 'primary control').catch(() => null);
  check(primary !== null, 'GIMBAL_MANAGER_STATUS: primary control 255/190');
  // 3. Angles: pitch -30, yaw 20 in the vehicle frame (flags 0).
  const t0 = Date.now();
  const moved = await commandUntilAck(gcs, PITCHYAW, [-30, 20, NaN, NaN, 0, 0, 0], 5000);
  check(moved && moved.data.result === 0, `DO_GIMBAL_MANAGER_PITCHYAW -30/20: ACK ${moved && moved.data.result}`);
  const frame = await until(() => h.angleFrames(t0, [0, -30, 20], 0.6).pop(), 8000, 'the angle frame').catch(() => null);
  check(frame !== null, `PITCHYAW -30/20 -> angle frame ${frame && JSON.stringify(frame.j.angle)} on gport-sim's trace`);
  if (frame) figures.push(`PITCHYAW sent -> angle frame ${frame.t - t0} ms`);
}

async function main() {
  if (!fs.existsSync(path.join(px4Dir, 'bin', 'px4')) || !fs.existsSync(path.join(px4Dir, 'etc'))) {
    console.log(`SKIP: no PX4 SITL in ${px4Dir} (GPORT_PX4_SITL_DIR; see docs/mavlink.md, "Tests")`);
    process.exit(77);
  }
  fs.rmSync(workRoot, { recursive: true, force: true });
  fs.mkdirSync(workRoot, { recursive: true });
  const { sim, gportd, sock } = await h.startGimbal(workRoot, gportdPath, simPath);
  const bridge = h.start(workRoot, 'gport-mavlink', bridgePath,
    ['--socket', sock, '--mavlink', `udpin:127.0.0.1:${GIMBAL_LINK_PORT}`, '--log-level', 'debug']);
  await until(() => bridge.lines.some((l) => /MAVLink on udpin/.test(l)), 10000, 'gport-mavlink to start');
  const started = Date.now();
  const { dir, child: px4 } = startPx4();
  process.on('exit', () => { try { px4.kill('SIGKILL'); } catch (e) { /* gone */ } });
  const gcs = new Peer({ sysid: 255, compid: 190 });
  await gcs.bind(); gcs.target(GCS_PORT);
  const beats = setInterval(() => gcs.send(heartbeat({ type: 6, autopilot: 8 })), 1000);
  try {
    gcs.send(heartbeat({ type: 6, autopilot: 8 }));
    await px4Checks(gcs, bridge, started);
  } finally {
    clearInterval(beats);
    gcs.close();
    try { px4.kill('SIGTERM'); } catch (e) { /* gone */ }
  }
  if (h.failures.length === 0) fs.rmSync(dir, { recursive: true, force: true });
  else console.log(`PX4's folder kept: ${dir}`);
  h.finish(workRoot, [bridge, gportd, sim]);
}

main().catch((error) => {
  console.error('FAIL ' + (error.stack || error.message) + `; logs in ${workRoot}`);
  process.exit(1);
});
