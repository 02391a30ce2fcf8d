// A small SVG line plot for live fitness curves: named series, auto-scaled axes with
// "nice" ticks, a legend, and vertical markers (steering changes). Redraws at most once a frame.

import { fmt } from './dom.js';

const NS = 'http://www.w3.org/2000/svg';
/** Width of one legend entry (swatch, name and last value). */
const LEGEND_W = 175;
const PALETTE = ['#2f6fdf', '#d9480f', '#2b8a3e', '#ae3ec9', '#e8a300', '#0c8599', '#c2255c', '#5c7cfa', '#868e96'];

function svg(tag, attrs = {}, text) {
  const el = document.createElementNS(NS, tag);
  for (const [k, v] of Object.entries(attrs)) el.setAttribute(k, v);
  if (text !== undefined) el.textContent = text;
  return el;
}

/** Ticks at 1/2/5 × 10^k covering [lo, hi], about `count` of them. */
export function niceTicks(lo, hi, count = 5) {
  if (!(hi > lo)) return [lo];
  const raw = (hi - lo) / Math.max(1, count);
  const mag = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= raw) ?? 10 * mag;
  const ticks = [];
  for (let t = Math.ceil(lo / step) * step; t <= hi + step * 1e-9; t += step) ticks.push(Number(t.toPrecision(12)));
  return ticks;
}

/** At most about 2·`width` points of `points`: per pixel column its first, min and max, so
 * long runs stay cheap to draw without hiding spikes. */
function thin(points, width) {
  if (points.length <= 2 * width) return points;
  const x0 = points[0][0];
  const span = points[points.length - 1][0] - x0 || 1;
  const out = [];
  let column = -1;
  let lo = null;
  let hi = null;
  const flush = () => {
    if (lo && hi) out.push(...(lo[0] <= hi[0] ? [lo, hi] : [hi, lo]));
  };
  for (const p of points) {
    const c = Math.floor(((p[0] - x0) / span) * width);
    if (c !== column) {
      flush();
      column = c;
      lo = hi = p;
    } else {
      if (p[1] < lo[1]) lo = p;
      if (p[1] > hi[1]) hi = p;
    }
  }
  flush();
  out.push(points[points.length - 1]);
  return out;
}

/** A live line plot inside `container`. */
export class LinePlot {
  constructor(container, { testid = 'plot', xLabel = 'generation', yLabel = 'fitness', height = 260 } = {}) {
    this.container = container;
    this.xLabel = xLabel;
    this.yLabel = yLabel;
    this.height = height;
    this.series = new Map(); // name → {color, points: [[x, y]], dashed}
    this.markers = []; // {x, label}
    this.root = svg('svg', { class: 'plot', 'data-testid': testid, role: 'img', 'aria-label': `${yLabel} by ${xLabel}` });
    container.append(this.root);
    this.pending = false;
    this.resizeObserver = new ResizeObserver(() => this.render());
    this.resizeObserver.observe(container);
  }

  /** Removes every series and marker. */
  clear() {
    this.series.clear();
    this.markers = [];
    this.render();
  }

  /** Adds a point to series `name` (created on first use, colours assigned in order). */
  push(name, x, y, { dashed = false } = {}) {
    if (!Number.isFinite(y)) return;
    let s = this.series.get(name);
    if (!s) {
      s = { color: PALETTE[this.series.size % PALETTE.length], points: [], dashed };
      this.series.set(name, s);
    }
    const last = s.points[s.points.length - 1];
    if (!last || x > last[0]) s.points.push([x, y]);
    else {
      // Late points (history caught up after a reconnect) go in x order.
      const i = s.points.findIndex((p) => p[0] >= x);
      if (s.points[i][0] === x) s.points[i][1] = y;
      else s.points.splice(i, 0, [x, y]);
    }
    this.schedule();
  }

  /** Adds a vertical marker at `x` (e.g. a steering change). */
  mark(x, label) {
    if (this.markers.some((m) => m.x === x && m.label === label)) return;
    this.markers.push({ x, label });
    this.schedule();
  }

  schedule() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      this.render();
    });
  }

  render() {
    const width = Math.max(240, this.container.clientWidth || 600);
    const height = this.height;
    const pad = { left: 56, right: 12, top: 12, bottom: 36 };
    const legendRows = Math.ceil(this.series.size / Math.max(1, Math.floor((width - pad.left) / LEGEND_W)));
    pad.bottom += legendRows * 16;
    this.root.setAttribute('viewBox', `0 0 ${width} ${height}`);
    this.root.setAttribute('width', width);
    this.root.setAttribute('height', height);
    this.root.replaceChildren();

    const all = [...this.series.values()].flatMap((s) => s.points);
    const plotW = width - pad.left - pad.right;
    const plotH = height - pad.top - pad.bottom;
    this.root.append(svg('rect', { x: pad.left, y: pad.top, width: plotW, height: plotH, class: 'plot-frame' }));
    if (all.length === 0) {
      this.root.append(svg('text', { x: pad.left + plotW / 2, y: pad.top + plotH / 2, class: 'plot-empty', 'text-anchor': 'middle' }, 'no data yet'));
      return;
    }
    let [x0, x1] = [Math.min(...all.map((p) => p[0])), Math.max(...all.map((p) => p[0]))];
    let [y0, y1] = [Math.min(...all.map((p) => p[1])), Math.max(...all.map((p) => p[1]))];
    if (x1 === x0) x1 = x0 + 1;
    if (y1 === y0) {
      y0 -= Math.abs(y0) * 0.1 || 1;
      y1 += Math.abs(y1) * 0.1 || 1;
    }
    const margin = (y1 - y0) * 0.05;
    y0 -= margin;
    y1 += margin;
    const sx = (x) => pad.left + ((x - x0) / (x1 - x0)) * plotW;
    const sy = (y) => pad.top + plotH - ((y - y0) / (y1 - y0)) * plotH;

    for (const t of niceTicks(y0, y1, 5)) {
      this.root.append(svg('line', { x1: pad.left, x2: pad.left + plotW, y1: sy(t), y2: sy(t), class: 'plot-grid' }));
      this.root.append(svg('text', { x: pad.left - 6, y: sy(t) + 4, 'text-anchor': 'end', class: 'plot-tick' }, fmt(t, 3)));
    }
    for (const t of niceTicks(x0, x1, Math.max(2, Math.floor(plotW / 80)))) {
      this.root.append(svg('line', { x1: sx(t), x2: sx(t), y1: pad.top + plotH, y2: pad.top + plotH + 4, class: 'plot-axis' }));
      this.root.append(svg('text', { x: sx(t), y: pad.top + plotH + 16, 'text-anchor': 'middle', class: 'plot-tick' }, fmt(t, 4)));
    }
    this.root.append(svg('text', { x: pad.left + plotW, y: pad.top + plotH + 30, 'text-anchor': 'end', class: 'plot-label' }, this.xLabel));
    this.root.append(svg('text', { x: 12, y: pad.top + plotH / 2, 'text-anchor': 'middle', class: 'plot-label',
      transform: `rotate(-90 12 ${pad.top + plotH / 2})` }, this.yLabel));

    for (const m of this.markers) {
      if (m.x < x0 || m.x > x1) continue;
      const g = svg('g', { class: 'plot-marker' });
      g.append(svg('line', { x1: sx(m.x), x2: sx(m.x), y1: pad.top, y2: pad.top + plotH }));
      g.append(svg('title', {}, m.label));
      this.root.append(g);
    }

    // The first series (the headline curve) is drawn last, on top of the others; each
    // series below is drawn wider than the ones above it, so where curves coincide (the
    // generation's best on the best so far) every colour still shows as a border.
    const layers = [...this.series].reverse();
    layers.forEach(([name, s], layer) => {
      const d = thin(s.points, Math.round(plotW)).map((p, i) => `${i ? 'L' : 'M'}${sx(p[0]).toFixed(1)},${sy(p[1]).toFixed(1)}`).join('');
      const width = (1.8 + 1.2 * (layers.length - 1 - layer)).toFixed(1);
      const path = svg('path', { d, stroke: s.color, class: 'plot-line', style: `stroke-width: ${width}px`, 'data-series': name });
      if (s.dashed) path.setAttribute('stroke-dasharray', '5 3');
      this.root.append(path);
    });

    // Legend under the x axis, wrapping into rows.
    const perRow = Math.max(1, Math.floor(plotW / LEGEND_W));
    [...this.series.entries()].forEach(([name, s], i) => {
      const lx = pad.left + (i % perRow) * LEGEND_W;
      const ly = pad.top + plotH + 46 + Math.floor(i / perRow) * 16;
      this.root.append(svg('line', { x1: lx, x2: lx + 16, y1: ly - 4, y2: ly - 4, stroke: s.color, class: 'plot-line' }));
      const last = s.points[s.points.length - 1];
      this.root.append(svg('text', { x: lx + 20, y: ly, class: 'plot-legend' }, `${name} ${last ? fmt(last[1], 4) : ''}`));
    });
  }
}
