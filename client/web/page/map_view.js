// The navigation map from above: bounds, obstacles (and their inflation by the robot's radius),
// the planned path of a navigation, the path the base walked and the robot's pose. A tap asks
// for a navigation to that point.
export class MapView {
  constructor(canvas, map, onGoal) {
    this.canvas = canvas;
    this.map = map ?? { bounds: [-5, 5, -5, 5], robot_radius: 0.35, circles: [], polygons: [] };
    this.walked = [];
    this.planned = [];
    this.pose = null;
    this.goal = null;
    canvas.addEventListener('click', (e) => {
      const r = canvas.getBoundingClientRect();
      const [x, y] = this.toWorld(e.clientX - r.left, e.clientY - r.top);
      this.goal = [x, y];
      onGoal(x, y);
    });
  }

  update(state) {
    const [x, y] = state.position;
    const last = this.walked[this.walked.length - 1];
    if (!last || Math.hypot(x - last[0], y - last[1]) > 0.02) this.walked.push([x, y]);
    if (this.walked.length > 5000) this.walked.shift();
    const p = state.task.call === 'navigate' ? state.task.path : [];
    this.planned = [];
    for (let i = 0; i + 1 < p.length; i += 2) this.planned.push([p[i], p[i + 1]]);
    const [w, qx, qy, qz] = state.orientation;
    this.pose = { x, y, yaw: Math.atan2(2 * (w * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz)) };
  }

  // World metres to canvas pixels and back, with x right and y up.
  layout() {
    const [x0, x1, y0, y1] = this.map.bounds;
    const w = this.canvas.clientWidth, h = this.canvas.clientHeight, pad = 8;
    const scale = Math.min((w - 2 * pad) / (x1 - x0), (h - 2 * pad) / (y1 - y0));
    const ox = (w - scale * (x1 - x0)) / 2, oy = (h - scale * (y1 - y0)) / 2;
    return { x0, y1, scale, ox, oy };
  }
  toCanvas(x, y) {
    const l = this.layout();
    return [l.ox + (x - l.x0) * l.scale, l.oy + (l.y1 - y) * l.scale];
  }
  toWorld(cx, cy) {
    const l = this.layout();
    return [l.x0 + (cx - l.ox) / l.scale, l.y1 - (cy - l.oy) / l.scale];
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
    const s = this.layout().scale, m = this.map;
    const [bx0, by0] = this.toCanvas(m.bounds[0], m.bounds[3]);
    g.fillStyle = '#f8fafc';
    g.strokeStyle = '#94a3b8';
    g.fillRect(bx0, by0, (m.bounds[1] - m.bounds[0]) * s, (m.bounds[3] - m.bounds[2]) * s);
    g.strokeRect(bx0, by0, (m.bounds[1] - m.bounds[0]) * s, (m.bounds[3] - m.bounds[2]) * s);
    for (const inflate of [m.robot_radius, 0]) {
      g.fillStyle = inflate ? '#e2e8f0' : '#64748b';
      for (const circle of m.circles) {
        const [cx, cy] = this.toCanvas(...circle.center);
        g.beginPath();
        g.arc(cx, cy, (circle.radius + inflate) * s, 0, 2 * Math.PI);
        g.fill();
      }
      if (inflate) continue;  // polygons are drawn as they are
      for (const polygon of m.polygons) this.line(g, polygon, true);
    }
    g.lineWidth = 2;
    g.strokeStyle = '#f97316';
    this.line(g, this.walked);
    g.strokeStyle = '#2563eb';
    g.setLineDash([6, 4]);
    this.line(g, this.planned);
    g.setLineDash([]);
    if (this.goal) {
      const [gx, gy] = this.toCanvas(...this.goal);
      g.fillStyle = '#2563eb';
      g.fillRect(gx - 4, gy - 4, 8, 8);
    }
    if (this.pose) {
      const [px, py] = this.toCanvas(this.pose.x, this.pose.y);
      g.save();
      g.translate(px, py);
      g.rotate(-this.pose.yaw);
      g.fillStyle = '#111827';
      g.beginPath();
      g.moveTo(12, 0);
      g.lineTo(-7, 6);
      g.lineTo(-7, -6);
      g.closePath();
      g.fill();
      g.restore();
    }
  }

  line(g, points, fill = false) {
    if (points.length < 2) return;
    g.beginPath();
    points.forEach(([x, y], i) => (i ? g.lineTo(...this.toCanvas(x, y)) : g.moveTo(...this.toCanvas(x, y))));
    if (fill) {
      g.closePath();
      g.fill();
    } else {
      g.stroke();
    }
  }
}
