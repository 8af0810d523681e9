// The jog pad: moves at the chosen speed only while a button is held.
//
// While held, {"type":"jog",...} goes out every 100 ms; gport-web turns each
// into a `speed` with a 400 ms lease, so if the messages stop for any
// reason the gimbal stops within the lease. Every way a hold can end
// (release, cancel, leaving the button, the window losing focus, the tab
// hidden, the socket closing) stops the repeats and sends one
// {"type":"stop"} so that the release reaches the wire at once rather than
// when the lease runs out.

const PERIOD_MS = 100;

export class Jog {
  constructor(live, root, speedInput) {
    this.live = live;
    this.speedInput = speedInput;
    this.held = null; // {button, axis, sign, pointerId}
    this.timer = 0;
    this.enabled = false;
    for (const button of root.querySelectorAll('.jog-btn')) this.bind(button);
    window.addEventListener('blur', () => this.release('blur'));
    document.addEventListener('visibilitychange', () => {
      if (document.visibilityState === 'hidden') this.release('hidden');
    });
    // Leaving the page: the socket closes too, but say stop first.
    window.addEventListener('pagehide', () => this.release('pagehide'));
    live.on('closed', () => this.release('socket closed'));
  }

  bind(button) {
    button.addEventListener('pointerdown', (event) => {
      if (event.button !== 0) return;
      event.preventDefault(); // no text selection, no focus-steal scroll on touch
      this.hold(button, event.pointerId);
    });
    for (const type of ['pointerup', 'pointercancel', 'pointerleave']) {
      button.addEventListener(type, (event) => {
        if (this.held && this.held.button === button && this.held.pointerId === event.pointerId) {
          this.release(type);
        }
      });
    }
    // A long press on a phone must not open the context menu (it would cancel the hold).
    button.addEventListener('contextmenu', (event) => event.preventDefault());
    // Keyboard: Space or Enter held down jogs too.
    button.addEventListener('keydown', (event) => {
      if ((event.key === ' ' || event.key === 'Enter') && !event.repeat) {
        event.preventDefault();
        this.hold(button, 'key');
      }
    });
    button.addEventListener('keyup', (event) => {
      if (event.key === ' ' || event.key === 'Enter') this.release('keyup');
    });
    button.addEventListener('blur', () => {
      if (this.held && this.held.button === button) this.release('button blur');
    });
  }

  setEnabled(enabled) {
    this.enabled = enabled;
    if (!enabled) this.release('disabled');
  }

  speed() {
    const value = Number(this.speedInput.value);
    return Number.isFinite(value) && value > 0 ? value : 0;
  }

  hold(button, pointerId) {
    if (!this.enabled || button.disabled) return;
    if (this.held) this.stopRepeats();
    this.held = { button, axis: button.dataset.axis, sign: Number(button.dataset.sign), pointerId };
    button.classList.add('held');
    this.send();
    this.timer = setInterval(() => this.send(), PERIOD_MS);
  }

  send() {
    if (!this.held) return;
    const message = { type: 'jog', pitch: 0, yaw: 0, roll: 0 };
    message[this.held.axis] = this.held.sign * this.speed();
    if (!this.live.send(message)) this.release('socket not open');
  }

  stopRepeats() {
    clearInterval(this.timer);
    this.timer = 0;
    if (this.held) this.held.button.classList.remove('held');
    this.held = null;
  }

  // Ends a hold (if any): no more jog messages, and one stop.
  release(why) {
    if (!this.held) return;
    this.stopRepeats();
    this.live.send({ type: 'stop' });
    this.lastRelease = why;
  }
}
