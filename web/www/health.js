// What the page knows of the way to the gimbal, shown as it is (docs/web.md,
// "What the page shows"): this browser -> gport-web (the live socket) ->
// gportd -> the gimbal's link. The badges, the banner while gport-web or
// gportd is not reachable, and the live values marked stale meanwhile.
import { $ } from './api.js';

const clock = (t) => new Date(t).toTimeString().slice(0, 8);

function setBadge(testid, state, text) {
  const el = $(testid);
  el.dataset.state = state;
  el.textContent = text;
}

export class Health {
  constructor(live) {
    this.live = live;
    this.gportd = 'unknown'; // from hello and the `gportd` message: up, down, unknown
    this.reason = '';
    this.link = 'unknown'; // the gimbal's link as gportd last said
    this.linkReason = '';
    this.valuesAt = 0; // when the last live value arrived
    setInterval(() => this.render(), 1000); // the banner's countdown, the values' age
  }

  // The live socket reached gport-web and gportd (values live, controls on).
  get up() { return this.live.open && this.gportd === 'up'; }

  // gport-web cannot be reached: the socket closed and is not open again.
  get webDown() { return !this.live.open && this.live.failures > 0; }

  setGportd(connected, reason) {
    this.gportd = connected ? 'up' : 'down';
    this.reason = reason || '';
    if (!connected) this.link = 'unknown';
    this.render();
  }

  // The socket closed: what gportd and the link do is unknown from here on.
  lostSocket() {
    this.gportd = 'unknown';
    this.link = 'unknown';
    this.render();
  }

  // gportd's word on the gimbal's link ({state, reason}, from `link` and `status`).
  setLink(link) {
    if (!link || typeof link.state !== 'string') return;
    this.link = link.state;
    this.linkReason = link.reason || '';
    this.render();
  }

  noteValues() { this.valuesAt = Date.now(); }

  render() {
    this.badges();
    this.banner();
    this.stale();
  }

  badges() {
    if (this.live.open) setBadge('conn', 'open', 'gport-web');
    else if (this.webDown) setBadge('conn', 'closed', 'gport-web: down');
    else setBadge('conn', 'connecting', 'gport-web…');
    const gportd = this.live.open ? this.gportd : 'unknown';
    setBadge('gportd', gportd, { up: 'gportd', down: 'gportd: down' }[gportd] || 'gportd ?');
    const link = this.up ? this.link : 'unknown';
    setBadge('link', link, link === 'unknown' ? 'link ?' : `link ${link}`);
    $('link-reason').textContent = this.up && link !== 'unknown'
      ? `${link}: ${this.linkReason}` : `unknown: ${this.why() || 'waiting for gportd\'s word'}`;
  }

  // Why the values are not live (empty when they are).
  why() {
    if (this.webDown) return 'gport-web is not reachable';
    if (!this.live.open) return 'connecting to gport-web';
    if (this.gportd === 'down') return `gportd is not reachable (${this.reason})`;
    if (this.gportd !== 'up') return 'waiting for gportd';
    return ['down', 'stale'].includes(this.link) ? `the gimbal's link is ${this.link}` : '';
  }

  since() {
    return this.valuesAt ? `since ${clock(this.valuesAt)}` : 'yet';
  }

  banner() {
    const el = $('banner');
    let text = '';
    if (this.webDown) {
      const wait = Math.max(0, Math.ceil((this.live.nextTry - Date.now()) / 1000));
      const retry = this.live.nextTry ? `trying again in ${wait} s` : 'trying again';
      text = `gport-web is not reachable: ${retry}. The controls are off until it is back.`;
    } else if (this.live.open && this.gportd === 'down') {
      text = `gportd is not reachable (${this.reason}): gport-web tries again every second. ` +
        'The controls are off until it is back.';
    }
    el.dataset.state = this.webDown ? 'gport-web' : text ? 'gportd' : 'none';
    $('banner-text').textContent = text;
    $('retry').hidden = !this.webDown;
    el.hidden = !text;
  }

  stale() {
    const why = this.why();
    for (const card of document.querySelectorAll('[data-live-values]')) {
      card.dataset.stale = why ? 'yes' : 'no';
    }
    const note = $('stale');
    note.hidden = !why;
    note.textContent = why ? `Not live ${this.since()}: ${why}.` : '';
  }
}
