// An attitude indicator (IMU roll and pitch) above a heading tape (IMU yaw).
import { fit, css, scheduler } from './canvas.js';

const PX_PER_DEG = 1.6; // pitch ladder scale, in CSS pixels of a 180 px disc
const TAPE_H = 34;
const NAMES = { 0: 'N', 90: 'E', 180: 'S', 270: 'W' };
const rad = (deg) => (deg * Math.PI) / 180;

export class Horizon {
  constructor(canvas) {
    this.canvas = canvas;
    this.att = null;
    this.request = scheduler(() => this.draw(), 33);
  }

  set(imu) {
    this.att = imu;
    this.request();
  }

  draw() {
    const { ctx, w, h } = fit(this.canvas);
    ctx.clearRect(0, 0, w, h);
    const r = Math.min(w, h - TAPE_H) / 2 - 4;
    const cx = w / 2;
    const cy = r + 4;
    const { roll = 0, pitch = 0, yaw = 0 } = this.att || {};
    this.disc(ctx, cx, cy, r, roll, pitch);
    this.tape(ctx, { x: 4, y: h - TAPE_H + 4, w: w - 8, h: TAPE_H - 6 }, yaw);
  }

  disc(ctx, cx, cy, r, roll, pitch) {
    const scale = PX_PER_DEG * (r / 90);
    ctx.save();
    ctx.beginPath();
    ctx.arc(cx, cy, r, 0, 2 * Math.PI);
    ctx.clip();
    ctx.translate(cx, cy);
    ctx.rotate(-rad(roll));
    ctx.translate(0, pitch * scale);
    ctx.fillStyle = '#3d8fd6';
    ctx.fillRect(-2 * r, -4 * r, 4 * r, 4 * r);
    ctx.fillStyle = '#8a5a2b';
    ctx.fillRect(-2 * r, 0, 4 * r, 4 * r);
    this.ladder(ctx, scale, r);
    ctx.restore();
    this.reference(ctx, cx, cy, r);
  }

  ladder(ctx, scale, r) {
    ctx.strokeStyle = '#fff';
    ctx.fillStyle = '#fff';
    ctx.lineWidth = 1.5;
    ctx.font = '10px system-ui, sans-serif';
    ctx.textBaseline = 'middle';
    for (let p = -90; p <= 90; p += 10) {
      const y = -p * scale;
      const half = p === 0 ? 2 * r : (p % 30 === 0 ? r * 0.35 : r * 0.18);
      ctx.beginPath();
      ctx.moveTo(-half, y);
      ctx.lineTo(half, y);
      ctx.stroke();
      if (p !== 0 && p % 30 === 0) ctx.fillText(String(p), half + 3, y);
    }
  }

  // The fixed aircraft symbol and the disc's rim.
  reference(ctx, cx, cy, r) {
    ctx.strokeStyle = css('--line');
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.arc(cx, cy, r, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.strokeStyle = '#ffd33d';
    ctx.lineWidth = 3;
    ctx.beginPath();
    ctx.moveTo(cx - r * 0.5, cy);
    ctx.lineTo(cx - r * 0.15, cy);
    ctx.lineTo(cx, cy + r * 0.1);
    ctx.lineTo(cx + r * 0.15, cy);
    ctx.lineTo(cx + r * 0.5, cy);
    ctx.stroke();
  }

  tape(ctx, box, yaw) {
    const heading = ((yaw % 360) + 360) % 360;
    const pxPerDeg = box.w / 120; // 120° visible
    ctx.save();
    ctx.beginPath();
    ctx.rect(box.x, box.y, box.w, box.h);
    ctx.clip();
    ctx.strokeStyle = css('--muted');
    ctx.fillStyle = css('--fg');
    ctx.font = '11px system-ui, sans-serif';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'top';
    const mid = box.x + box.w / 2;
    for (let d = Math.floor((heading - 70) / 10) * 10; d <= heading + 70; d += 10) {
      const x = mid + (d - heading) * pxPerDeg;
      const norm = ((d % 360) + 360) % 360;
      ctx.beginPath();
      ctx.moveTo(x, box.y);
      ctx.lineTo(x, box.y + (norm % 30 === 0 ? 9 : 5));
      ctx.stroke();
      if (norm % 30 === 0) ctx.fillText(NAMES[norm] || String(norm), x, box.y + 11);
    }
    ctx.restore();
    ctx.fillStyle = '#ffd33d';
    ctx.beginPath();
    ctx.moveTo(mid - 5, box.y + box.h);
    ctx.lineTo(mid + 5, box.y + box.h);
    ctx.lineTo(mid, box.y + box.h - 8);
    ctx.fill();
  }
}
