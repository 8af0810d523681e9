'use strict';
// Cross-checks our MAVLink 2 codec against node-mavlink, an implementation
// we did not write (docs/mavlink.md, "Cross-check").
//
//   node crosscheck.js TOOL WORKDIR
//
// 1. TOOL emits one frame of every message we encode (ours.bin) and the
//    values it put in them (expected.json); node-mavlink splits and checks
//    the frames (its own CRC and CRC_EXTRA table), decodes them, and every
//    field is compared with expected.json.
// 2. node-mavlink encodes the same messages from expected.json (theirs.bin);
//    its frames must equal ours byte for byte, and TOOL must decode them
//    back to expected.json field by field.
// Node 18 (Debian 12) is enough: CommonJS, no newer syntax or API.
const { execFileSync } = require('child_process');
const fs = require('fs');
const path = require('path');
const { Readable } = require('stream');
const mavlink = require('node-mavlink');

const { MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, minimal, common } = mavlink;
const REGISTRY = Object.assign({}, minimal.REGISTRY, common.REGISTRY);

// Fields our codec has (from the current common.xml) that the mavlink-mappings
// node-mavlink pins predate: node cannot check them; when node encodes the
// message they are absent, so ours must decode them as zero (extension rule).
const NOT_IN_NODE = { GIMBAL_DEVICE_INFORMATION: ['cap_flags2'] };

const failures = [];
function fail(message) {
  failures.push(message);
  console.error('FAIL: ' + message);
}

function fromJson(value, type) {
  if (value === 'NaN') return NaN;
  if (value === 'Infinity') return Infinity;
  if (value === '-Infinity') return -Infinity;
  if (type.startsWith('uint64_t') || type.startsWith('int64_t')) return BigInt(value);
  if (Array.isArray(value)) return value.map((v) => fromJson(v, type.replace('[]', '')));
  return value;
}

function sameValue(expected, actual, type) {
  const want = fromJson(expected, type);
  if (Array.isArray(want)) {
    return Array.isArray(actual) && actual.length === want.length &&
      want.every((w, i) => sameValue(expected[i], actual[i], type.replace('[]', '')));
  }
  if (typeof want === 'number' && Number.isNaN(want)) return Number.isNaN(actual);
  if (type === 'char[]') return String(actual).replace(/\0+$/, '') === want;
  return actual === want;
}

function show(v) {
  return JSON.stringify(v, (k, x) => (typeof x === 'bigint' ? x.toString() + 'n' : x));
}

async function packetsOf(buffer) {
  let crcErrors = 0;
  const splitter = new MavLinkPacketSplitter({}, { onCrcError: () => { crcErrors += 1; } });
  const reader = Readable.from([buffer]).pipe(splitter).pipe(new MavLinkPacketParser());
  const packets = [];
  for await (const packet of reader) packets.push(packet);
  return { packets, crcErrors, invalid: splitter.invalidPackages };
}

// Direction 1: node decodes what we encoded.
async function nodeDecodesOurs(tool, work, expected) {
  const ours = path.join(work, 'ours.bin');
  const { packets, crcErrors, invalid } = await packetsOf(fs.readFileSync(ours));
  if (crcErrors !== 0 || invalid !== 0) fail(`node-mavlink rejected ${crcErrors} CRC / ${invalid} invalid frames of ours`);
  if (packets.length !== expected.length) fail(`node-mavlink found ${packets.length} frames in ours.bin, expected ${expected.length}`);
  packets.forEach((packet, i) => {
    const want = expected[i];
    if (!want) return;
    const h = packet.header;
    if (h.msgid !== want.id || h.seq !== want.seq || h.sysid !== want.sysid || h.compid !== want.compid) {
      fail(`${want.name}: header ${show(h)} differs from ${show(want)}`);
    }
    const clazz = REGISTRY[h.msgid];
    const data = packet.protocol.data(packet.payload, clazz);
    const skip = NOT_IN_NODE[want.name] || [];
    const known = new Set(clazz.FIELDS.map((f) => f.source));
    for (const name of Object.keys(want.fields)) {
      if (!known.has(name) && !skip.includes(name)) fail(`${want.name}.${name}: node-mavlink has no such field`);
    }
    for (const f of clazz.FIELDS) {
      if (!(f.source in want.fields)) { fail(`${want.name}.${f.source}: our codec lacks this field`); continue; }
      if (!sameValue(want.fields[f.source], data[f.name], f.type)) {
        fail(`${want.name}.${f.source}: node-mavlink decoded ${show(data[f.name])}, we encoded ${show(want.fields[f.source])}`);
      }
    }
    console.log(`ok   node decodes our ${want.name} (${clazz.FIELDS.length} fields, ${packet.header.payloadLength}-byte payload on the wire)`);
  });
}

// Direction 2: we decode what node encoded; byte equality where the layouts agree.
function oursDecodesNode(tool, work, expected) {
  const ours = fs.readFileSync(path.join(work, 'ours.bin'));
  const frames = [];
  let offset = 0;
  for (const want of expected) {
    const clazz = REGISTRY[want.id];
    const msg = new clazz();
    for (const f of clazz.FIELDS) msg[f.name] = fromJson(want.fields[f.source], f.type);
    const frame = new MavLinkProtocolV2(want.sysid, want.compid).serialize(msg, want.seq);
    const ourLength = 10 + ours.readUInt8(offset + 1) + 2;
    const ourFrame = ours.subarray(offset, offset + ourLength);
    offset += ourLength;
    if (NOT_IN_NODE[want.name]) {
      console.log(`skip byte comparison of ${want.name}: node-mavlink lacks ${NOT_IN_NODE[want.name].join(', ')}`);
    } else if (!frame.equals(ourFrame)) {
      fail(`${want.name}: node-mavlink's frame ${frame.toString('hex')} differs from ours ${ourFrame.toString('hex')}`);
    } else {
      console.log(`ok   ${want.name}: node-mavlink's frame equals ours byte for byte (${frame.length} bytes)`);
    }
    frames.push(frame);
  }
  const theirs = path.join(work, 'theirs.bin');
  fs.writeFileSync(theirs, Buffer.concat(frames));
  const decoded = JSON.parse(execFileSync(tool, ['decode', theirs], { encoding: 'utf8' }));
  if (decoded.messages.length !== expected.length) fail(`we decoded ${decoded.messages.length} of node's ${expected.length} frames (${show(decoded.stats)})`);
  decoded.messages.forEach((got, i) => {
    const want = expected[i];
    for (const key of ['name', 'id', 'seq', 'sysid', 'compid']) {
      if (got[key] !== want[key]) fail(`${want.name}: ${key} ${got[key]} decoded, ${want[key]} sent`);
    }
    const skip = NOT_IN_NODE[want.name] || [];
    for (const [name, value] of Object.entries(want.fields)) {
      const sent = skip.includes(name) ? 0 : value;
      if (JSON.stringify(got.fields[name]) !== JSON.stringify(sent)) {
        fail(`${want.name}.${name}: we decoded ${show(got.fields[name])} from node-mavlink's ${show(sent)}`);
      }
    }
    console.log(`ok   we decode node's ${want.name}`);
  });
}

async function main() {
  const [tool, work] = process.argv.slice(2);
  if (!tool || !work) throw new Error('usage: node crosscheck.js TOOL WORKDIR');
  const ours = path.join(work, 'ours.bin');
  const expectedPath = path.join(work, 'expected.json');
  execFileSync(tool, ['emit', ours, expectedPath], { stdio: 'inherit' });
  const expected = JSON.parse(fs.readFileSync(expectedPath, 'utf8'));
  console.log(`node ${process.version}, node-mavlink ${require('node-mavlink/package.json').version}, ${expected.length} messages`);
  await nodeDecodesOurs(tool, work, expected);
  oursDecodesNode(tool, work, expected);
  if (failures.length > 0) {
    console.error(`${failures.length} difference(s) between our codec and node-mavlink`);
    process.exit(1);
  }
  console.log('cross-check passed: every message and field agrees with node-mavlink');
}

main().catch((e) => { console.error(e); process.exit(1); });
