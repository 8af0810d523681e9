// Canvas helpers: a backing store that follows the element's CSS size and
// the device pixel ratio, colours from the style sheet, and redrawing at
// most once per animation frame and only when something changed.

export function fit(canvas) {
  const ratio = window.devicePixelRatio || 1;
  const width = Math.max(1, Math.round(canvas.clientWidth * ratio));
  const height = Math.max(1, Math.round(canvas.clientHeight * ratio));
  if (canvas.width !== width || canvas.height !== height) {
    canvas.width = width;
    canvas.height = height;
  }
  const ctx = canvas.getContext('2d');
  ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
  return { ctx, w: canvas.clientWidth, h: canvas.clientHeight };
}

export const css = (name) => getComputedStyle(document.documentElement).getPropertyValue(name).trim();

// Returns a function that schedules draw() for the next frame, once, and
// no more often than every minIntervalMs (the plot need not redraw at 50 Hz
// on a phone's battery).
export function scheduler(draw, minIntervalMs = 0) {
  let pending = false;
  let last = 0;
  const frame = (now) => {
    if (now - last < minIntervalMs) {
      requestAnimationFrame(frame);
      return;
    }
    pending = false;
    last = now;
    draw();
  };
  const request = () => {
    if (pending) return;
    pending = true;
    requestAnimationFrame(frame);
  };
  new ResizeObserver(request).observe(document.body);
  return request;
}

// A "nice" step (1, 2 or 5 × 10^n) near span / count.
export function niceStep(span, count) {
  const raw = span / Math.max(1, count);
  const power = 10 ** Math.floor(Math.log10(raw));
  const unit = raw / power;
  return (unit < 1.5 ? 1 : unit < 3.5 ? 2 : unit < 7.5 ? 5 : 10) * power;
}
