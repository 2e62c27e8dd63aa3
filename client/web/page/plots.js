// Rolling line plots of the last seconds on a canvas: one series per value, a zero line and the
// range of what is shown.
export class RollingPlot {
  constructor(canvas, { seconds = 10, colors, legend = [] }) {
    this.canvas = canvas;
    this.seconds = seconds;
    this.colors = colors;
    this.legend = legend;  // [label, colour] pairs
    this.samples = [];  // [time, values]
  }

  add(time, values) {
    if (this.samples.length && time < this.samples[this.samples.length - 1][0]) this.samples = [];  // restarted
    this.samples.push([time, values]);
    while (this.samples.length && this.samples[0][0] < time - this.seconds) this.samples.shift();
  }

  draw() {
    const c = this.canvas, dpr = window.devicePixelRatio || 1;
    const w = c.clientWidth, h = c.clientHeight;
    if (c.width !== Math.round(w * dpr) || c.height !== Math.round(h * dpr)) {
      c.width = Math.round(w * dpr);
      c.height = Math.round(h * dpr);
    }
    const g = c.getContext('2d');
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    g.clearRect(0, 0, w, h);
    if (this.samples.length < 2) return;
    let lo = -0.1, hi = 0.1;
    for (const [, v] of this.samples) for (const x of v) { lo = Math.min(lo, x); hi = Math.max(hi, x); }
    const pad = 4, t1 = this.samples[this.samples.length - 1][0], t0 = t1 - this.seconds;
    const px = (t) => pad + ((t - t0) / this.seconds) * (w - 2 * pad);
    const py = (x) => h - pad - ((x - lo) / (hi - lo)) * (h - 2 * pad);
    g.strokeStyle = '#cbd5e1';
    g.beginPath();
    g.moveTo(pad, py(0));
    g.lineTo(w - pad, py(0));
    g.stroke();
    g.lineWidth = 1.5;
    this.colors.forEach((color, i) => {
      g.strokeStyle = color;
      g.beginPath();
      this.samples.forEach(([t, v], j) => (j ? g.lineTo(px(t), py(v[i])) : g.moveTo(px(t), py(v[i]))));
      g.stroke();
    });
    g.fillStyle = '#6b7280';
    g.font = '11px system-ui';
    g.fillText(hi.toFixed(2), pad, 12);
    g.fillText(lo.toFixed(2), pad, h - pad - 2);
    const n = this.legend.length;
    g.fillStyle = '#ffffffd0';
    if (n) g.fillRect(w - pad - 28 * n - 4, 0, 28 * n + 4, 16);
    this.legend.forEach(([label, color], i) => {
      g.fillStyle = color;
      g.fillText(label, w - pad - 28 * (n - i), 12);
    });
  }
}
