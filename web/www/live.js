// The live WebSocket /api/live (docs/web.md): one socket, reconnected with
// exponential backoff and jitter, messages dispatched by method.

const BACKOFF_MIN_MS = 500;
// At most this long between tries: gport-web back is live again within it.
const BACKOFF_MAX_MS = 5000;

export class Live extends EventTarget {
  constructor(path = '/api/live') {
    super();
    const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
    this.url = `${scheme}://${location.host}${path}`;
    this.socket = null;
    this.backoff = BACKOFF_MIN_MS;
    this.timer = 0;
    this.failures = 0; // closes (or failed tries) since the socket was last open
    this.nextTry = 0; // when the next try starts (Date.now()), 0 while none is due
  }

  get open() { return this.socket !== null && this.socket.readyState === WebSocket.OPEN; }

  start() {
    clearTimeout(this.timer);
    this.nextTry = 0;
    const socket = new WebSocket(this.url);
    this.socket = socket;
    let opened = false;
    this.emit('state', 'connecting');
    socket.addEventListener('open', () => {
      opened = true;
      this.backoff = BACKOFF_MIN_MS;
      this.failures = 0;
      this.emit('state', 'open');
    });
    socket.addEventListener('message', (event) => this.dispatch(event.data));
    socket.addEventListener('close', () => {
      if (this.socket !== socket) return;
      this.socket = null;
      this.failures += 1;
      this.retry();
      this.emit('state', 'closed');
      this.emit('closed', { opened });
    });
  }

  retry() {
    // Jitter, so that browsers that lost gport-web together do not return together.
    const delay = this.backoff * (0.75 + Math.random() * 0.5);
    this.backoff = Math.min(this.backoff * 2, BACKOFF_MAX_MS);
    this.nextTry = Date.now() + delay;
    this.timer = setTimeout(() => this.start(), delay);
  }

  // Tries again now (the banner's "retry now") unless a socket is open or opening.
  retryNow() {
    if (this.socket === null) this.start();
  }

  dispatch(text) {
    let message;
    try {
      message = JSON.parse(text);
    } catch {
      return;
    }
    if (message && typeof message.method === 'string') this.emit(message.method, message.params);
  }

  // Sends one JSON message; false when the socket is not open.
  send(message) {
    if (!this.open) return false;
    this.socket.send(JSON.stringify(message));
    return true;
  }

  emit(type, detail) { this.dispatchEvent(new CustomEvent(type, { detail })); }

  on(type, handler) { this.addEventListener(type, (event) => handler(event.detail)); }
}
