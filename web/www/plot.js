// A rolling 30-second plot of roll, pitch and yaw: IMU solid, hall dashed.
import { fit, css, scheduler, niceStep } from './canvas.js';

const WINDOW_S = 30;
const AXES = ['roll', 'pitch', 'yaw'];
const MAX_SAMPLES = 50 * WINDOW_S * 2; // 50 Hz with room; older ones go

export class Plot {
  constructor(canvas) {
    this.canvas = canvas;
    this.samples = [];
    this.request = scheduler(() => this.draw(), 66);
  }

  // sample: gportd's attitude params ({t, imu, hall}).
  add(sample) {
    if (!sample || !sample.imu || !sample.hall || typeof sample.t !== 'number') return;
    this.samples.push({ t: sample.t, imu: sample.imu, hall: sample.hall });
    const oldest = sample.t - WINDOW_S;
    let drop = 0;
    while (drop < this.samples.length && this.samples[drop].t < oldest) drop += 1;
    drop = Math.max(drop, this.samples.length - MAX_SAMPLES);
    if (drop > 0) this.samples.splice(0, drop);
    this.request();
  }

  range() {
    let lo = -10;
    let hi = 10;
    for (const s of this.samples) {
      for (const axis of AXES) {
        lo = Math.min(lo, s.imu[axis], s.hall[axis]);
        hi = Math.max(hi, s.imu[axis], s.hall[axis]);
      }
    }
    const step = niceStep(hi - lo, 4);
    return { lo: Math.floor(lo / step) * step, hi: Math.ceil(hi / step) * step, step };
  }

  draw() {
    const { ctx, w, h } = fit(this.canvas);
    ctx.clearRect(0, 0, w, h);
    const pad = { l: 38, r: 8, t: 8, b: 18 };
    const { lo, hi, step } = this.range();
    const now = this.samples.length ? this.samples[this.samples.length - 1].t : 0;
    const x = (t) => pad.l + (w - pad.l - pad.r) * (1 - (now - t) / WINDOW_S);
    const y = (v) => pad.t + (h - pad.t - pad.b) * (hi - v) / (hi - lo);
    this.grid(ctx, { w, h, pad, lo, hi, step, x, y });
    for (const axis of AXES) {
      ctx.strokeStyle = css(`--${axis}`);
      this.line(ctx, axis, 'imu', [], x, y);
      this.line(ctx, axis, 'hall', [5, 4], x, y);
    }
  }

  grid(ctx, { w, h, pad, lo, hi, step, x, y }) {
    ctx.strokeStyle = css('--line');
    ctx.fillStyle = css('--muted');
    ctx.lineWidth = 1;
    ctx.font = '11px system-ui, sans-serif';
    ctx.textAlign = 'right';
    ctx.textBaseline = 'middle';
    for (let v = lo; v <= hi + step / 2; v += step) {
      ctx.beginPath();
      ctx.moveTo(pad.l, y(v));
      ctx.lineTo(w - pad.r, y(v));
      ctx.stroke();
      ctx.fillText(`${Math.round(v)}°`, pad.l - 4, y(v));
    }
    ctx.textAlign = 'center';
    ctx.textBaseline = 'bottom';
    for (let s = 0; s <= WINDOW_S; s += 10) {
      const label = s === 0 ? 'now' : `-${s} s`;
      const now = this.samples.length ? this.samples[this.samples.length - 1].t : 0;
      ctx.fillText(label, Math.min(Math.max(x(now - s), pad.l + 12), w - pad.r - 12), h);
    }
  }

  line(ctx, axis, source, dash, x, y) {
    ctx.setLineDash(dash);
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    let previous = null;
    for (const s of this.samples) {
      const v = s[source][axis];
      // Yaw wraps at ±180: do not draw a line across the whole plot.
      const jump = previous !== null && Math.abs(v - previous) > 180;
      if (previous === null || jump) ctx.moveTo(x(s.t), y(v));
      else ctx.lineTo(x(s.t), y(v));
      previous = v;
    }
    ctx.stroke();
    ctx.setLineDash([]);
  }
}
