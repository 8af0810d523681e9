'use strict';
// gport-web's page in a real browser (docs/web.md, "data-testid"):
// Debian's chromium, headless, driven by playwright-core, against the real
// gport-web, gportd and gport-sim (with --trace, which shows what reaches
// the gimbal's UART).
//
//   node web.js GPORTD GPORT_SIM GPORT_WEB WORKDIR
//
// The machine is small and shared: timings are asserted on gport-sim's
// trace timestamps (when a frame reached the wire) against the browser's
// own clock at the event, never on how long this script waited.
const crypto = require('crypto');
const fs = require('fs');
const http = require('http');
const path = require('path');
const { chromium } = require('playwright-core');
const h = require('./harness');

const { check, figure, sleep, until } = h;
const [gportdPath, simPath, webPath, workRoot] = process.argv.slice(2);
const CHROMIUM = process.env.GPORT_CHROMIUM || '/usr/bin/chromium';
const RELEASE_BUDGET_MS = 300;
const id = (testid) => `[data-testid="${testid}"]`;

// The strictest policy the page is written for (docs/web.md, "data-testid"):
// scripts and styles from gport-web only, the login page's one inline
// style allowed by its hash. The test adds it to every document it loads
// (gport-web's own policy stays in force too), so a page that needs more
// fails here (a violation is a console error).
function strictPolicy() {
  const login = fs.readFileSync(path.join(__dirname, '../../../web/www/login.html'), 'utf8');
  const style = /<style>([\s\S]*?)<\/style>/.exec(login)[1];
  const hash = crypto.createHash('sha256').update(style).digest('base64');
  return `default-src 'self'; style-src 'self' 'sha256-${hash}'; connect-src 'self'; ` +
    "base-uri 'none'; form-action 'self'; frame-ancestors 'none'";
}

// GPORT_WEB_WWW=DIR serves the page's files from DIR instead of gport-web's
// built-in copy (with gport-web's own answer's status and headers), to
// work on the page without rebuilding gport-web. The ctest does not set it.
const WWW = process.env.GPORT_WEB_WWW;

function withoutLength(headers) {
  const copy = { ...headers };
  delete copy['content-length'];
  return copy;
}

// A browser context whose documents get the strict policy (and, with
// GPORT_WEB_WWW, the page's files from that folder).
async function newContext(browser, url, options) {
  const context = await browser.newContext(options);
  const policy = strictPolicy();
  // The login's POST and /?token= too: their 303 is then followed by the
  // browser as a new request, which comes here again (a redirect followed
  // inside route.fetch would not).
  const documents = (u) => u.origin === url && (u.pathname === '/' || u.pathname === '/login');
  await context.route(documents, async (route) => {
    const response = await route.fetch({ maxRedirects: 0 });
    // Both gport-web's policy (if it sends one) and the strict one: the
    // browser enforces every policy it is given.
    const own = response.headers()['content-security-policy'];
    const headers = { ...response.headers(), 'content-security-policy': own ? `${own}, ${policy}` : policy };
    if (!WWW || response.status() !== 200) return route.fulfill({ response, headers });
    const login = (await response.text()).includes('data-testid="login-form"');
    const body = fs.readFileSync(path.join(WWW, login ? 'login.html' : 'index.html'));
    return route.fulfill({ response, body, headers: withoutLength(headers) });
  });
  if (WWW) {
    await context.route((u) => u.origin === url && /^\/[a-z]+\.(js|css|svg)$/.test(u.pathname), async (route) => {
      const response = await route.fetch();
      if (response.status() !== 200) return route.fulfill({ response });
      const file = path.join(WWW, new URL(route.request().url()).pathname.slice(1));
      return route.fulfill({ response, body: fs.readFileSync(file), headers: withoutLength(response.headers()) });
    });
  }
  return context;
}

// --no-sandbox: CI runs the tests as root, where chromium's sandbox refuses
// to start. LocalNetworkAccessChecks off: a document that newContext's
// route answers has no IP address space of its own, so chromium would refuse
// its WebSocket to 127.0.0.1 (ERR_BLOCKED_BY_LOCAL_NETWORK_ACCESS_CHECKS); a
// page gport-web serves itself talks to its own address, which those checks
// allow.
const LAUNCH = {
  executablePath: CHROMIUM,
  args: ['--no-sandbox', '--disable-features=LocalNetworkAccessChecks'],
};

// A page logged in (cookie from the login form, or from /?token=).
async function openPage(context, url) {
  const page = await context.newPage();
  page.problems = [];
  // When the page got each event that ends a jog, on the browser's clock
  // (which is this machine's): registered before the page's own listeners.
  await page.addInitScript(() => {
    window.eventAt = {};
    for (const type of ['pointerup', 'pointerleave', 'blur', 'visibilitychange']) {
      const target = type === 'visibilitychange' ? document : window;
      target.addEventListener(type, () => { window.eventAt[type] = Date.now(); }, { capture: true });
    }
  });
  page.on('pageerror', (e) => page.problems.push(`pageerror at ${page.url()}: ${e.message}`));
  page.on('console', (m) => { if (m.type() === 'error') page.problems.push(`console at ${page.url()}: ${m.text()}`); });
  // What the page sends on /api/live: {t, type} of each jog and stop.
  page.sent = [];
  page.on('websocket', (ws) => ws.on('framesent', ({ payload }) => {
    try { page.sent.push({ t: Date.now(), type: JSON.parse(payload).type }); } catch (e) { /* not JSON */ }
  }));
  await page.goto(url);
  return page;
}

const number = async (page, testid) => Number(await page.textContent(id(testid)));
// An element's text or attribute now (null when there is none), without
// waiting for it as page.textContent and page.getAttribute do.
const textOf = (page, testid) => page.evaluate((sel) => document.querySelector(sel)?.textContent ?? null, id(testid))
  .catch(() => null);
const stateOf = (page, testid) => page.evaluate((sel) => document.querySelector(sel)?.dataset.state ?? null, id(testid))
  .catch(() => null);

async function waitLive(page) {
  try {
    await page.waitForSelector(`${id('conn')}[data-state="open"]`, { timeout: 15000 });
    await page.waitForSelector(`${id('link')}[data-state="up"]`, { timeout: 15000 });
    await until(async () => Number.isFinite(await number(page, 'imu-pitch')), 10000, 'imu-pitch');
  } catch (e) {
    throw new Error(`the page at ${page.url()} did not go live: ${e.message}\n${page.problems.join('\n')}`);
  }
}

// ---- 1. login
async function login(browser, url, token) {
  const context = await newContext(browser, url, { viewport: { width: 1280, height: 800 } });
  figure(`Content-Security-Policy enforced on the page: ${strictPolicy()}`);
  const page = await openPage(context, url + '/');
  check(await page.isVisible(id('login-form')), 'the page at / without login shows the login form');
  check(!(await page.isVisible(id('imu-pitch'))), 'and no live value');
  const denied = await context.request.get(url + '/api/status', { failOnStatusCode: false });
  check(denied.status() === 401, `GET /api/status without login: ${denied.status()} (401)`);
  await page.fill(id('login-token'), token);
  await Promise.all([page.waitForNavigation(), page.click(id('login-submit'))]);
  await waitLive(page);
  check(true, 'logged in through the form: live values shown');
  // The browser followed the login's 303 itself, past newContext's route:
  // load the page again under both policies.
  await page.goto(url + '/');
  await waitLive(page);
  await policyInForce(context, url);
  return { context, page };
}

// ---- 1b. a wrong token, and too many: the login form again with a line
// of text (and how long to wait), never gport-web's JSON
// ---- 1b. a page of another site the operator has open (issue 42): six
// <img> logins with wrong tokens and a form that posts a login with a
// valid (view) token, as an attacker's page would. Chromium marks them
// Sec-Fetch-Site: cross-site; gport-web refuses them counting nothing, so
// the operator's next wrong token is still "wrong token", not "too many
// tries", and the browser holds no session the attacker chose.
async function crossSite(browser, url, viewToken) {
  const attack = `<!doctype html><title>another site</title>
    ${[0, 1, 2, 3, 4, 5].map((i) => `<img src="${url}/?token=wrong-token-cross-${i}0123456">`).join('')}
    <form id="f" method="post" action="${url}/login"><input name="token" value="${viewToken}"></form>
    <script>addEventListener('load', () => document.getElementById('f').submit())</script>`;
  const server = http.createServer((req, res) => {
    res.writeHead(200, { 'Content-Type': 'text/html' });
    res.end(attack);
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.2', resolve));
  const other = `http://127.0.0.2:${server.address().port}/`;
  const context = await browser.newContext();
  const page = await context.newPage();
  // The images' answers never reach the page (Chromium's ORB blocks a JSON
  // answer to an <img>), but the requests leave the browser: they count.
  const sent = [];
  let posted = 0;
  page.on('request', (r) => { if (r.url().startsWith(url)) sent.push(r.url()); });
  page.on('response', (r) => { if (r.url() === `${url}/login`) posted = r.status(); });
  await page.goto(other);
  await until(() => posted !== 0, 10000, "the other site's login post answered").catch(() => null);
  const cookies = await context.cookies(url);
  check(sent.length >= 7 && posted === 403,
    `a page of another site (${other}) sent ${sent.length - 1} logins with wrong tokens and a form's post ` +
    `of a valid one: the post refused ${posted}`);
  check(!cookies.some((c) => c.name === 'gport_session'), 'it left no session in the browser');
  const mine = await context.newPage();
  const response = await mine.goto(`${url}/?token=wrong-token-0123456789`);
  const line = (await textOf(mine, 'login-error')) || '';
  check(response.status() === 401 && line === 'wrong token',
    `the operator's next wrong token: ${response.status()} "${line}" (nothing counted for the other site)`);
  await context.close();
  server.close();
}

async function wrongToken(browser, url) {
  const context = await newContext(browser, url, { viewport: { width: 390, height: 844 } });
  const page = await openPage(context, url + '/');
  const shown = async (response) => ({
    status: response ? response.status() : 0,
    form: await page.isVisible(id('login-form')),
    line: (await textOf(page, 'login-error')) || '',
    json: /^\s*[{[]/.test(await page.textContent('body')),
  });
  const wrong = 'wrong-token-0123456789';
  let seen = await shown(await page.goto(`${url}/?token=${wrong}`));
  check(seen.status === 401 && seen.form && seen.line === 'wrong token' && !seen.json,
    `/?token= with a wrong token: ${seen.status}, the login form with "${seen.line}" (no JSON)`);
  await page.fill(id('login-token'), wrong);
  const [posted] = await Promise.all([page.waitForNavigation(), page.click(id('login-submit'))]);
  seen = await shown(posted);
  check(seen.status === 401 && seen.form && seen.line === 'wrong token' && !seen.json,
    `the login form with a wrong token: ${seen.status}, the form again with "${seen.line}"`);
  await page.screenshot({ path: path.join(workRoot, 'web-login-wrong-token.png') });
  // 5 wrong tokens a minute from one address; the 6th waits 1 s and gets 429.
  let response = null;
  for (let i = 0; i < 8 && (!response || response.status() !== 429); i += 1) {
    response = await page.goto(`${url}/?token=${wrong}`);
  }
  seen = await shown(response);
  const wait = Number(response.headers()['retry-after']);
  check(seen.status === 429 && seen.form && seen.line === `too many tries: try again in ${wait} s` && wait > 0,
    `too many wrong tokens: ${seen.status} (Retry-After ${wait}), the form with "${seen.line}"`);
  await page.screenshot({ path: path.join(workRoot, 'web-login-too-many.png') });
  await context.close();
}

// The policy really applies (else the page's clean run under it proves
// nothing): in a second tab, an inline script is refused.
async function policyInForce(context, url) {
  const probe = await context.newPage();
  await probe.goto(url + '/');
  const ran = await probe.evaluate(() => {
    const script = document.createElement('script');
    script.textContent = 'window.inlineRan = true;';
    document.body.append(script);
    return window.inlineRan === true;
  });
  check(!ran, 'the policy is in force: an inline script does not run');
  await probe.close();
}

// ---- 2. live values follow gport-sim
async function liveFollows(page, sock) {
  await h.rpc(sock, 'angle', { pitch: -25, yaw: 40, wait: true });
  await until(async () => Math.abs((await number(page, 'hall-pitch')) + 25) < 1 &&
    Math.abs((await number(page, 'hall-yaw')) - 40) < 1, 10000, 'hall angles -25 / 40 on the page');
  check(Math.abs((await number(page, 'imu-pitch')) + 25) < 1, 'imu-pitch follows the gimbal to -25');
  await h.rpc(sock, 'angle', { pitch: 0, yaw: 0, wait: true });
  await until(async () => Math.abs(await number(page, 'hall-yaw')) < 1, 10000, 'hall-yaw back to 0');
  check(true, 'the live values change as gport-sim moves (hall and IMU, pitch and yaw)');
}

// Holds a jog button with the mouse until the gimbal moves; returns when a
// non-zero speed with the expected sign reached the wire.
async function holdJog(page, testid, axisIndex, sign) {
  const since = Date.now();
  await page.hover(id(testid));
  await page.mouse.down();
  const moving = await until(() => h.speedFrames(since)
    .find((e) => Math.sign(e.j.speed[axisIndex]) === sign), 5000, `a ${testid} speed on the wire`);
  return moving;
}

// ---- 3. release: zero speed on the wire within 300 ms of the release
// Each way a hold ends, as the page gets it; `blur` and `hidden` are the
// window's and the document's events (a headless window neither loses focus
// nor hides on its own).
const RELEASES = {
  pointerup: (page) => page.mouse.up(),
  pointerleave: (page) => page.mouse.move(5, 5),
  blur: (page) => page.evaluate(() => window.dispatchEvent(new FocusEvent('blur'))),
  visibilitychange: (page) => page.evaluate(() => {
    Object.defineProperty(document, 'visibilityState', { value: 'hidden', configurable: true });
    document.dispatchEvent(new Event('visibilitychange'));
    delete document.visibilityState; // the real one again
  }),
};

async function releaseOnce(page, round, how) {
  const up = round % 2 === 0;
  await holdJog(page, up ? 'jog-pitch-up' : 'jog-pitch-down', 1, up ? 1 : -1);
  await sleep(600);
  await page.evaluate((type) => { window.eventAt[type] = 0; }, how);
  await RELEASES[how](page);
  const released = await until(() => page.evaluate((type) => window.eventAt[type], how), 5000, how);
  if (how !== 'pointerup') await page.mouse.up();
  const stop = await until(() => h.speedFrames(released - 50).find(h.isZero), 3000, `zero speed after ${how}`);
  await sleep(500);
  // The page said stop (not the lease running out, which takes 300-400
  // ms), once, and nothing after it. (A jog sent just before the release
  // may be reported after it.)
  const said = page.sent.filter((m) => m.t >= released - 50).map((m) => m.type);
  check(said.filter((type) => type === 'stop').length === 1 && said[said.length - 1] === 'stop',
    `${how} (round ${round + 1}): the page sent one {"type":"stop"}, then nothing (${said.join(', ')})`);
  const after = h.speedFrames(h.wireTime(stop) + 1).filter((e) => !h.isZero(e));
  check(after.length === 0, `${how} (round ${round + 1}): no speed after the zero (${after.length})`);
  return h.wireTime(stop) - released;
}

async function jogRelease(page, rounds) {
  const before = await number(page, 'hall-pitch');
  await holdJog(page, 'jog-pitch-up', 1, 1);
  await sleep(700);
  const moved = await number(page, 'hall-pitch');
  await page.mouse.up();
  check(moved - before > 2, `holding jog-pitch-up moves the gimbal: hall pitch ${before} -> ${moved}`);
  await sleep(300);
  const latencies = { pointerup: [] };
  for (let i = 0; i < rounds; i += 1) latencies.pointerup.push(await releaseOnce(page, i, 'pointerup'));
  for (const how of ['pointerleave', 'blur', 'visibilitychange']) latencies[how] = [await releaseOnce(page, 0, how)];
  for (const [how, list] of Object.entries(latencies)) {
    const worst = Math.max(...list);
    figure(`jog ${how} -> zero speed on the wire (trace time - event), ms: ${list.map((l) => l.toFixed(1)).join(', ')}`);
    check(worst <= RELEASE_BUDGET_MS, `${how}: zero speed on the wire within ${RELEASE_BUDGET_MS} ms (worst ${worst.toFixed(1)} ms)`);
  }
}

// ---- 4. a setting written in the page reads back from the gimbal
async function settingReadsBack(page, sock) {
  await page.waitForFunction(() => document.querySelector('[data-testid="settings-dead-zone"]').value !== '');
  const before = Number(await page.inputValue(id('settings-dead-zone')));
  const wanted = before === 17 ? 18 : 17;
  const since = Date.now();
  let dialog = '';
  page.once('dialog', (d) => { dialog = d.message(); d.accept(); });
  await page.fill(id('settings-dead-zone'), String(wanted));
  await page.click(id('settings-save'));
  await page.waitForFunction((w) => /read back: dead zone (\d+)/.exec(
    document.querySelector('[data-testid="settings-readback"]').textContent)?.[1] === String(w), wanted, { timeout: 10000 });
  check(/dead_zone: \d+ → \d+/.test(dialog), `the page asked to confirm ("${dialog.replace(/\n/g, ' / ')}")`);
  const written = h.trace.find((e) => e.j.cmd === '0x15' && h.wireTime(e) >= since - 50);
  check(written && written.j.dead_zone === wanted, `0x15 on the wire with dead_zone ${wanted}`);
  const gimbal = (await h.rpc(sock, 'get_settings')).result;
  check(gimbal.dead_zone === wanted, `the gimbal holds dead_zone ${gimbal.dead_zone}; the page shows it read back`);
}

// ---- 5. a photo taken in the page appears in the captures table
async function photoInTable(page) {
  const since = Date.now();
  const rowsBefore = await page.locator(id('capture-row')).count();
  await page.click(id('photo'));
  await page.waitForSelector(`${id('capture-row')}[data-kind="photo"]`, { timeout: 10000 });
  const rows = await page.locator(id('capture-row')).count();
  check(rows === rowsBefore + 1, `the photo appears in the captures table (${rowsBefore} -> ${rows} rows)`);
  check(h.cameraFrames(since - 50).some((e) => e.j.action === 'photo'), '0x86 photo on the wire');
}

// ---- 6. captures with a position on the scatter plot, and a pose for the pictures
async function positionsAndPose(page, sock) {
  const rows = await page.locator(id('capture-row')).count();
  const around = [[0, 0], [40, 25], [85, 10], [120, -30], [60, -70]]; // metres east, north
  for (const [east, north] of around) {
    const lat = 47.397742 + north / 111195;
    const lon = 8.545594 + east / (111195 * Math.cos((47.397742 * Math.PI) / 180));
    await h.rpc(sock, 'photo', { meta: { lat, lon, alt_m: 488.5 } });
  }
  await until(async () => (await page.locator(id('capture-row')).count()) === rows + around.length, 10000,
    'the positioned captures in the table');
  await page.waitForFunction(() => /^5 capture/.test(document.querySelector('[data-testid="captures-map-note"]').textContent),
    null, { timeout: 10000 });
  check(true, 'captures with a position appear on the scatter plot (5, from /api/captures.geojson)');
  await h.rpc(sock, 'angle', { roll: 8, pitch: -20, yaw: 35, wait: true });
}

// ---- 6b. captures whose meta is odd (a client's own): shown as they are,
// the table never broken (lat with no numeric lon threw in every browser)
async function oddMetaInTable(page, sock) {
  const rows = await page.locator(id('capture-row')).count();
  const odd = [{ lat: 47.3 }, { lat: 'north', lon: null }, { lon: 8.5, note: 'no lat' }];
  for (const meta of odd) await h.rpc(sock, 'photo', { meta });
  await until(async () => (await page.locator(id('capture-row')).count()) === rows + odd.length, 10000,
    'the captures with an odd meta in the table');
  const cells = await page.locator(id('capture-row')).evaluateAll((trs) => trs.slice(0, 3).map((tr) => tr.cells[5].textContent));
  check(JSON.stringify(cells) === JSON.stringify(['?, 8.500000', '"north", null', '47.300000, ?']),
    `captures with lat and no lon (and other odd metas) shown as they are: ${JSON.stringify(cells)}`);
  check(page.problems.length === 0, `no script error from them (${page.problems.join('; ') || 'none'})`);
}

// ---- 6c. captures gportd stamped with the vehicle (published as
// gport-mavlink does): a tagged one shows the stamp's position and its
// accuracy, not the meta's; an untagged one shows why and no position,
// though its meta has one; the plot gets the tagged one only.
async function stampedInTable(page, sock) {
  const rows = await page.locator(id('capture-row')).count();
  const points = Number((/^(\d+) capture/.exec(await page.textContent(id('captures-map-note'))) || [0, 0])[1]);
  // Standing still, so the position carried to the shutter is the one sent
  // (and its accuracy not grown), whatever the photo's delay.
  const publish = async (bootMs, fix) => (await h.rpc(sock, 'publish_vehicle', {
    position: { boot_ms: bootMs, lat: 47.3978, lon: 8.5456, alt_msl_m: 488.25, velocity_ned: [0, 0, 0],
      heading_deg: 90, fix, h_acc_m: 0.9, v_acc_m: 1.4, satellites: 14 },
    time: { boot_ms: bootMs, utc_us: 1763770000000000 + bootMs * 1000 },
  })).result;
  const meta = { lat: 47.5, lon: 8.7, alt_m: 400 }; // the client's: never shown for a stamped capture
  const tagged = await publish(60000, 3);
  await h.rpc(sock, 'photo', { meta });
  const untagged = await publish(60100, 1);
  await h.rpc(sock, 'photo', { meta });
  check(tagged && tagged.taken && untagged && untagged.taken, 'the vehicle published (publish_vehicle, fix 3 then 1)');
  await until(async () => (await page.locator(id('capture-row')).count()) === rows + 2, 10000,
    'the stamped captures in the table');
  const [last, first] = await page.locator(id('capture-row')).evaluateAll((trs) =>
    trs.slice(0, 2).map((tr) => ({ text: tr.cells[5].textContent, title: tr.cells[5].title, from: tr.cells[5].dataset.position })));
  check(first.from === 'vehicle' && first.text === '47.397800, 8.545600 ±0.9 m' && /altitude 488\.25 m MSL/.test(first.title) &&
    /GPS UTC 2025-11-22T00:07:4\d\.\d{3}Z/.test(first.title) && /stamped by gportd/.test(first.title),
  `a tagged capture shows the vehicle's position and accuracy, not the meta's: "${first.text}" ` +
    `(${JSON.stringify(first.title)})`);
  check(last.from === 'untagged' && last.text === 'untagged: no 3D GPS fix (GPS_FIX_TYPE 1)',
    `an untagged capture shows why and no position, though its meta has one: "${last.text}"`);
  await page.waitForFunction((n) => new RegExp(`^${n} capture`).test(document.querySelector('[data-testid="captures-map-note"]').textContent),
    points + 1, { timeout: 10000 }).catch(() => {});
  const note = await page.textContent(id('captures-map-note'));
  check(note.startsWith(`${points + 1} capture`), `the plot: the tagged capture added, the untagged one not ("${note}")`);
  check(page.problems.length === 0, `no script error from them (${page.problems.join('; ') || 'none'})`);
}

// ---- 6d. a server that lies about the stamps (issue 43): gport-web's own
// answers, rewritten on their way to the page, give the newest captures a
// `vehicle` of every shape gportd never writes, and the plot's GeoJSON
// points it cannot place. The table shows each as untagged or as its meta,
// a reason as text (never markup), and neither the table nor the plot
// throws; then the real answers come back.
const ODD_STAMPS = [
  ['"junk"', 'junk', 'meta'],
  ['an array', [47, 8], 'meta'],
  ['tagged "yes"', { tagged: 'yes', lat: 47, lon: 8 }, 'untagged'],
  ['a string latitude', { tagged: true, lat: '47.1', lon: 8 }, 'untagged'],
  ['a latitude of 91', { tagged: true, lat: 91, lon: 8 }, 'untagged'],
  ['odd members beside a position', { tagged: true, lat: 47.25, lon: 8.5, h_acc_m: 'x', v_acc_m: -1e308,
    utc_us: 1e20, heading_deg: null, age_ms: 'old', alt_msl_m: {} }, 'vehicle'],
  ['a reason that is markup', { tagged: false, why: '<img src=x onerror="window.injected=1">' }, 'untagged'],
  ['a reason that is an object', { tagged: false, why: { text: 'no' }, utc_us: -1e300 }, 'untagged'],
];
const ODD_FEATURES = [
  { type: 'Feature', geometry: { type: 'Point', coordinates: null }, properties: null },
  { type: 'Feature', geometry: { type: 'Point', coordinates: 'x' } },
  { type: 'Feature', geometry: { type: 'Point', coordinates: [1e308, -1e308] } },
  { type: 'Feature', geometry: { type: 'Point', coordinates: [8.5] } },
  { type: 'Feature', geometry: null },
  null,
];
async function lyingStamps(page) {
  const captures = (u) => u.pathname === '/api/captures';
  const geojson = (u) => u.pathname === '/api/captures.geojson';
  let points = 0;
  await page.route(captures, async (route) => {
    const response = await route.fetch();
    const body = await response.json();
    const rows = body.captures.slice(-ODD_STAMPS.length);
    rows.forEach((c, i) => { c.vehicle = ODD_STAMPS[i][1]; });
    body.captures.unshift(null, 'a row', 17); // no row at all: left out
    return route.fulfill({ response, json: body });
  });
  await page.route(geojson, async (route) => {
    const response = await route.fetch();
    const body = await response.json();
    points = body.features.length;
    body.features = [...ODD_FEATURES, ...body.features, ...ODD_FEATURES];
    return route.fulfill({ response, json: body });
  });
  const problems = page.problems.length;
  await h.rpc(page.sock, 'photo', {}); // its notification reloads the table and the plot
  const shown = await until(async () => {
    const cells = await page.locator(id('capture-row')).evaluateAll((trs) =>
      trs.slice(0, 8).reverse().map((tr) => ({ text: tr.cells[5].textContent, from: tr.cells[5].dataset.position,
        title: tr.cells[5].title })));
    return cells.length === ODD_STAMPS.length && cells.every((c, i) => c.from === ODD_STAMPS[i][2]) ? cells : null;
  }, 10000, 'the captures with odd stamps in the table');
  ODD_STAMPS.forEach(([what, , from], i) => check(shown[i].from === from,
    `a stamp that is ${what}: ${from} ("${shown[i].text}")`));
  const odd = shown[5];
  check(odd.text === '47.250000, 8.500000' && !/NaN|undefined|Infinity|\[object|e\+|accuracy|altitude|UTC/.test(odd.title),
    `its odd members left out (no accuracy, altitude or UTC from them): "${odd.text}" (${JSON.stringify(odd.title)})`);
  check(shown[6].text === 'untagged: <img src=x onerror="window.injected=1">' &&
    await page.evaluate(() => window.injected === undefined && !document.querySelector('#captures-table img')),
  'a reason that is markup is shown as its text, never run');
  check(shown[7].text === 'untagged: untagged by gportd', `a reason that is no text: "${shown[7].text}"`);
  await until(async () => new RegExp(`^${points} capture`).test(await page.textContent(id('captures-map-note'))), 10000,
    'the plot with the points it can place');
  check(true, `the plot places the ${points} real points and none of the ${2 * ODD_FEATURES.length} it cannot`);
  const thrown = page.problems.slice(problems);
  check(thrown.length === 0, `no script error from the lies (${thrown.join('; ') || 'none'})`);
  await page.unroute(captures);
  await page.unroute(geojson);
  await page.click(id('captures-latest'));
}

// ---- 7. screenshots
async function screenshots(page) {
  const shots = [];
  // The pictures without the last message (it hides itself after 4 s).
  await page.waitForSelector(id('message'), { state: 'hidden', timeout: 8000 }).catch(() => {});
  for (const [w, hgt] of [[1280, 800], [390, 844]]) {
    await page.setViewportSize({ width: w, height: hgt });
    await page.evaluate(() => window.scrollTo(0, 0));
    await sleep(1500); // a second of the plot and one status
    const file = path.join(workRoot, `web-${w}x${hgt}.png`);
    await page.screenshot({ path: file });
    await page.screenshot({ path: path.join(workRoot, `web-${w}x${hgt}-full.png`), fullPage: true });
    const overflow = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
    check(overflow <= 0, `${w}x${hgt}: no horizontal scrolling (${overflow} px too wide)`);
    shots.push(file);
  }
  figure(`screenshots: ${shots.join(', ')}`);
  await page.setViewportSize({ width: 1280, height: 800 });
}

// ---- 7b. recording on and off (gportd's assumed state; a toggle only when it differs)
async function recordOnOff(page) {
  // 50 ms of slack for a toggle the click made (its wire time is estimated
  // from gport-sim's clock), none where none may be: the toggle before it
  // can reach the wire within 50 ms of the page showing its state.
  const toggles = (since, slack = 50) => h.cameraFrames(since - slack).filter((e) => e.j.action === 'record').length;
  const recorded = (state) => page.waitForSelector(`${id('record-state')}[data-state="${state}"]`, { timeout: 5000 });
  check(await page.getAttribute(id('record-state'), 'data-state') === 'unknown', 'recording: unknown at first');
  let since = Date.now();
  let dialog = '';
  page.once('dialog', (d) => { dialog = d.message(); d.accept(); });
  await page.click(id('record-on'));
  await recorded('on');
  check(/does not know/.test(dialog) && toggles(since) === 1,
    `Start recording while unknown: asked first ("${dialog.slice(0, 60)}…"), one toggle on the wire (${toggles(since)}), on`);
  since = Date.now();
  await page.click(id('record-on'));
  await page.waitForFunction(() => /already on/.test(document.querySelector('[data-testid="message"]').textContent));
  await sleep(300);
  check(toggles(since, 0) === 0, `Start recording while on: nothing sent (${toggles(since, 0)} toggles)`);
  since = Date.now();
  await page.click(id('record-off'));
  await recorded('off');
  await until(() => toggles(since) === 1, 3000, 'the record toggle on the wire');
  check((await h.rpc(page.sock, 'status')).result.recording === 'off', 'Stop recording: one toggle, gportd says off');
}

// ---- 7c. a phone (390x844): the jog pad and the angles and horizon on one
// screen while jogging
async function phoneJog(page) {
  await page.setViewportSize({ width: 390, height: 844 });
  await page.evaluate(() => window.scrollTo(0, 0));
  const before = await number(page, 'hall-pitch');
  await holdJog(page, 'jog-pitch-up', 1, 1); // scrolls the button into view if it has to
  await sleep(600);
  const inView = await page.evaluate((testids) => testids.filter((t) => {
    const r = document.querySelector(`[data-testid="${t}"]`).getBoundingClientRect();
    return r.top < 0 || r.bottom > window.innerHeight || r.height === 0;
  }), ['imu-pitch', 'hall-pitch', 'horizon', 'jog-pitch-up', 'jog-pitch-down', 'stop']);
  const moving = await number(page, 'hall-pitch');
  const file = path.join(workRoot, 'web-390x844-jogging.png');
  await page.screenshot({ path: file });
  await page.mouse.up();
  check(inView.length === 0, `390x844 while jogging: the angles, the horizon and the pad on one screen (outside: ${inView.join(', ') || 'none'})`);
  check(moving - before > 1, `and the angles move meanwhile (hall pitch ${before} -> ${moving})`);
  await page.click('a[href="#control"]');
  await sleep(300);
  const angles = await page.evaluate(() => document.querySelector('[data-testid="imu-pitch"]').getBoundingClientRect().top);
  check(angles >= 0, `the Control tab keeps the angles on screen (imu-pitch at ${angles.toFixed(0)} px)`);
  figure(`phone, jogging: ${file}`);
  await page.setViewportSize({ width: 1280, height: 800 });
}

// ---- 7d. "this browser": its own jog is not "pid N"
async function thisBrowser(page) {
  await holdJog(page, 'jog-yaw-right', 2, 1);
  // This jog's speed (yaw), not a status still showing the jog before it.
  const motion = await page.waitForFunction(() => {
    const text = document.querySelector('[data-testid="motion"]').textContent;
    return /^speed/.test(text) && !/yaw -?0\.00/.test(text) && text;
  }, null, { timeout: 3000 }).then((handle) => handle.jsonValue()).catch(() => 'no speed shown');
  await page.mouse.up();
  check(/^speed by this browser/.test(motion), `while this page jogs, motion says "${motion}"`);
  const controller = await page.textContent(id('controller'));
  check(/^nobody \(no client holds exclusive control\)/.test(controller), `control held by: "${controller}"`);
}

const DISABLED_WHILE_DOWN = ['jog-pitch-up', 'stop', 'center', 'photo', 'record-on', 'angle-go', 'settings-save'];
async function enabledOf(page, testids) {
  const enabled = [];
  for (const t of testids) if (await page.isEnabled(id(t))) enabled.push(t);
  return enabled;
}

// ---- 7e. gportd killed and started again: a banner, the controls off and
// the values marked stale; then live again, the error gone and the captures
// table the new gportd's
async function gportdRestart(page, gimbal) {
  await h.kill(gimbal.gportd);
  await page.waitForSelector(`${id('banner')}[data-state="gportd"]`, { timeout: 5000 });
  const badges = [await stateOf(page, 'conn'), await stateOf(page, 'gportd'), await stateOf(page, 'link')];
  check(badges.join() === 'open,down,unknown', `gportd killed: the banner "${await page.textContent(id('banner-text'))}"; badges ${badges.join(', ')}`);
  const enabled = await enabledOf(page, DISABLED_WHILE_DOWN);
  check(enabled.length === 0, `gportd away: the controls off (enabled: ${enabled.join(', ') || 'none'})`);
  check(await page.getAttribute('#live', 'data-stale') === 'yes' && await page.isVisible(id('stale')),
    `the values marked stale ("${await textOf(page, 'stale')}")`);
  await page.click(id('settings-reload'));
  await page.waitForSelector(`${id('message')}[data-kind="error"]`, { timeout: 5000 });
  const error = await page.textContent(id('message'));
  await page.evaluate(() => window.scrollTo(0, 0));
  await page.screenshot({ path: path.join(workRoot, 'web-gportd-down.png') });
  const again = await h.startGportd(workRoot, gportdPath);
  gimbal.gportd = again.gportd;
  await page.waitForSelector(`${id('banner')}[data-state="none"]`, { state: 'attached', timeout: 10000 });
  await waitLive(page);
  await page.waitForSelector(id('jog-pitch-up') + ':enabled', { timeout: 5000 });
  check(!(await page.isVisible(id('message'))) || (await page.getAttribute(id('message'), 'data-kind')) !== 'error',
    `gportd back: live, the controls on, the error ("${error}") gone`);
  await page.waitForSelector(`${id('captures-page')}:has-text("no captures yet")`, { timeout: 5000 });
  await h.rpc(gimbal.sock, 'photo', {});
  await page.waitForSelector(`${id('capture-row')}[data-index="1"]`, { timeout: 5000 });
  const rows = await page.locator(id('capture-row')).count();
  check(rows === 1, `the captures table reloaded: the new gportd's log (${rows} row, #1), not the old one's`);
  check(await page.getAttribute('#live', 'data-stale') === 'no', 'the values live again (not marked stale)');
}

// ---- 7f. gport-web killed and started again (same address and tokens):
// a banner while it is away, then the page live again or the login form
// (sessions were gport-web's memory), never JSON
async function webRestart(page, web) {
  await h.kill(web.web);
  await page.waitForSelector(`${id('banner')}[data-state="gport-web"]`, { timeout: 5000 });
  const badges = [await stateOf(page, 'conn'), await stateOf(page, 'gportd'), await stateOf(page, 'link')];
  check(badges.join() === 'closed,unknown,unknown',
    `gport-web killed: the banner "${await page.textContent(id('banner-text'))}"; badges ${badges.join(', ')}`);
  const enabled = await enabledOf(page, DISABLED_WHILE_DOWN);
  check(enabled.length === 0, `gport-web away: the controls off (enabled: ${enabled.join(', ') || 'none'})`);
  await page.evaluate(() => window.scrollTo(0, 0));
  await page.screenshot({ path: path.join(workRoot, 'web-gport-web-down.png') });
  const again = await h.startWeb(workRoot, webPath, web.sock, web);
  web.web = again.web;
  const t0 = Date.now();
  const back = await until(async () => ((await page.isVisible(id('login-form')).catch(() => false)) && 'login') ||
    ((await stateOf(page, 'conn').catch(() => null)) === 'open' && 'live'), 15000, 'the page back');
  figure(`gport-web back: the page ${back === 'login' ? 'shows the login form' : 'is live'} ${Date.now() - t0} ms after the start`);
  const body = await page.textContent('body');
  check(!/^\s*[{[]/.test(body), `gport-web back: ${back === 'login' ? 'the login form' : 'live again'}, no JSON`);
  // Sessions outlive a restart (kept beside the token file): still logged in.
  check(back === 'live', `gport-web back: still logged in, live again (${back})`);
  if (back === 'login') {
    const line = await textOf(page, 'login-error');
    check(/session has ended/.test(line), `the login form says why: "${line}"`);
    await page.fill(id('login-token'), web.tokens.control);
    await Promise.all([page.waitForNavigation(), page.click(id('login-submit'))]);
  }
  await waitLive(page);
  check(await page.isHidden(id('banner')), 'and live again after the login, no banner');
}

// ---- 8. a read-only login: controls disabled
async function viewOnly(browser, url, token) {
  const context = await newContext(browser, url);
  const page = await openPage(context, `${url}/?token=${token}`);
  await waitLive(page);
  check(!page.url().includes('token='), `/?token= leaves the address bar without the token (${page.url()})`);
  await page.waitForSelector(`${id('role')}[data-state="view"]`);
  const enabled = [];
  for (const t of ['jog-pitch-up', 'jog-yaw-right', 'center', 'photo', 'record-on', 'record-off', 'settings-save', 'angle-go']) {
    if (await page.isEnabled(id(t))) enabled.push(t);
  }
  check(enabled.length === 0, `a view login has every control disabled (enabled: ${enabled.join(', ') || 'none'})`);
  await context.close();
}

// ---- 8b. the one-time link: what chromium's History keeps logs no one in
// (issue 42): a profile of its own opens gport-web's printed link, closes;
// every address in its History file that carries a code or token is opened
// in a fresh context and gets the login form, not the page.
async function linkInHistory(web) {
  const line = web.web.lines.find((l) => /gport-web: open \S+\?code=/.test(l));
  const link = line && line.match(/open (\S+\?code=\S+)/)[1];
  if (!check(Boolean(link), `gport-web printed a one-time link (${line})`)) return;
  const profile = fs.mkdtempSync(path.join(workRoot, 'profile-'));
  const context = await chromium.launchPersistentContext(profile, LAUNCH);
  const page = await openPage(context, link);
  await waitLive(page);
  check(!page.url().includes('code='), `the link leaves the address bar without its code (${page.url()})`);
  await context.close();
  const history = fs.readFileSync(path.join(profile, 'Default', 'History')).toString('latin1');
  const opened = [...new Set(history.match(/http:\/\/127\.0\.0\.1:\d+\/[\x21-\x7e]*/g) || [])];
  const logins = opened.filter((u) => /[?&](code|token)=/.test(u));
  check(logins.length > 0, `chromium's History holds the link it opened (${logins.length} address(es) with a code)`);
  const browser = await chromium.launch(LAUNCH);
  const fresh = await browser.newContext();
  for (const address of logins) {
    const again = await fresh.newPage();
    await again.goto(address);
    const form = await again.isVisible(id('login-form'));
    const why = form ? await again.textContent(id('login-error')).catch(() => '') : '';
    check(form, `the address from History logs no one in: the login form (${why.trim()})`);
    await again.close();
  }
  await browser.close();
}

// ---- 9. the deadman: closing the page or killing the browser while held
async function deadman(browser, url, token, label, end) {
  const context = await newContext(browser, url);
  const page = await openPage(context, `${url}/?token=${token}`);
  await waitLive(page);
  await holdJog(page, 'jog-yaw-right', 2, 1);
  await sleep(300);
  const t0 = Date.now();
  await end(page);
  const stop = await until(() => h.speedFrames(t0 - 50).find(h.isZero), 5000, `zero speed after ${label}`);
  const ms = h.wireTime(stop) - t0;
  figure(`${label}: zero speed on the wire ${ms.toFixed(1)} ms later`);
  // The lease (400 ms) bounds it even if nobody says stop; allow for a slow machine.
  check(ms < 1500, `${label} stops the gimbal (${ms.toFixed(1)} ms)`);
  await sleep(700);
  const after = h.speedFrames(h.wireTime(stop) + 1).filter((e) => !h.isZero(e));
  check(after.length === 0, `${label}: no speed after the zero (${after.length})`);
  await context.close().catch(() => {});
}

async function killedBrowser(url, token) {
  // launchServer: the browser's own process, to kill with SIGKILL.
  const server = await chromium.launchServer(LAUNCH);
  const browser = await chromium.connect(server.wsEndpoint());
  const proc = server.process();
  await deadman(browser, url, token, 'killing the browser while held', async () => {
    // The whole process group: the network service holds the socket.
    try { process.kill(-proc.pid, 'SIGKILL'); } catch (e) { proc.kill('SIGKILL'); }
  });
  await server.close().catch(() => {});
}

async function main() {
  // The test's own folder in the build tree: last run's logs and sockets go.
  fs.rmSync(workRoot, { recursive: true, force: true });
  fs.mkdirSync(workRoot, { recursive: true });
  const gimbal = await h.startGimbal(workRoot, gportdPath, simPath);
  const { sock } = gimbal;
  const web = { ...(await h.startWeb(workRoot, webPath, sock)), sock };
  const { url, tokens } = web;
  console.log(`gport-web at ${url}; logs in ${workRoot}`);
  const browser = await chromium.launch(LAUNCH);
  try {
    const { page } = await login(browser, url, tokens.control);
    page.sock = sock;
    await crossSite(browser, url, tokens.view);
    await wrongToken(browser, url);
    await liveFollows(page, sock);
    await jogRelease(page, 6);
    await settingReadsBack(page, sock);
    await photoInTable(page);
    await positionsAndPose(page, sock);
    await oddMetaInTable(page, sock);
    await stampedInTable(page, sock);
    await lyingStamps(page);
    await screenshots(page);
    check(page.problems.length === 0, `no script errors in the page (${page.problems.join('; ') || 'none'})`);
    await recordOnOff(page);
    await phoneJog(page);
    await thisBrowser(page);
    check(page.problems.length === 0, `no script errors meanwhile (${page.problems.join('; ') || 'none'})`);
    await gportdRestart(page, gimbal);
    await webRestart(page, web);
    // Refused requests and sockets while they were away are console errors; no exception.
    const thrown = page.problems.filter((p) => p.startsWith('pageerror'));
    check(thrown.length === 0, `no script exception through both restarts (${thrown.join('; ') || 'none'})`);
    await viewOnly(browser, url, tokens.view);
    await linkInHistory(web);
    await deadman(browser, url, tokens.control, 'closing the page while held', (page) => page.close());
  } finally {
    await browser.close().catch(() => {});
  }
  await killedBrowser(url, tokens.control);
}

main().then(async () => {
  await h.stopAll();
  console.log('figures:\n  ' + h.figures.join('\n  '));
  if (h.failures.length) {
    console.error(`${h.failures.length} check(s) failed; logs in ${workRoot}`);
    process.exit(1);
  }
  console.log('all checks passed');
  process.exit(0);
}, (e) => {
  console.error(`error: ${e.stack || e}\nlogs in ${workRoot}`);
  process.exit(1);
});
