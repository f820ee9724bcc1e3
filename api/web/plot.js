// Small SVG plots: curves over the crank angle, polar diagrams and scatters, with hover read-outs in units.
import { h, s } from "./dom.js";

const W = 420, H = 220, M = { l: 56, r: 12, t: 20, b: 30 };
const COLOURS = ["#1f5fbf", "#c25e00", "#1b7a3a", "#8a2be2", "#8a93a3", "#b3261e", "#007b83", "#6d4c41"];

export function niceTicks(lo, hi, n = 5) {
  if (!(hi > lo)) { const d = Math.abs(lo) || 1; lo -= d * 0.5; hi += d * 0.5; }
  const raw = (hi - lo) / n, mag = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 2.5, 5, 10].map((s) => s * mag).find((s) => raw <= s) || 10 * mag;
  const ticks = [];
  for (let v = Math.ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step) ticks.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  return { ticks, step };
}

export function fmt(v, digits = 4) {
  if (v === null || v === undefined || Number.isNaN(v)) return "–";
  if (v === 0) return "0";
  const a = Math.abs(v);
  if (a >= 1e5 || a < 1e-3) return v.toExponential(2);
  return Number(v.toPrecision(digits)).toString();
}

const tooltip = () => document.getElementById("tooltip");

function showTip(evt, text) {
  const t = tooltip();
  t.textContent = text;
  t.hidden = false;
  t.style.left = `${evt.clientX + 14}px`;
  t.style.top = `${evt.clientY + 10}px`;
}

function hideTip() { tooltip().hidden = true; }

function extent(arrays, pad = 0.05) {
  let lo = Infinity, hi = -Infinity;
  for (const a of arrays) for (const v of a) { if (v < lo) lo = v; if (v > hi) hi = v; }
  if (!Number.isFinite(lo)) return [0, 1];
  const d = (hi - lo) || Math.abs(hi) || 1;
  return [lo - d * pad, hi + d * pad];
}

/** Tick labels with as many digits as it takes for no two to read the same (a front at solver noise: 4.5, 4.5, …
 *  becomes 4.500000001, 4.500000002, …); ticks closer than a float can tell apart are thinned to one. */
export function tickLabels(ticks) {
  for (let digits = 3; digits <= 15; digits++) {
    const labels = ticks.map((v) => fmt(v, digits));
    if (new Set(labels).size === labels.length) return { ticks, labels };
  }
  const mid = ticks[Math.floor(ticks.length / 2)];
  return { ticks: [mid], labels: [fmt(mid, 15)] };
}

function frame(xs, ys, xt, yt, xLabel, yLabel, top = M.t) {
  const X = (v) => M.l + ((v - xs[0]) / (xs[1] - xs[0])) * (W - M.l - M.r);
  const Y = (v) => H - M.b - ((v - ys[0]) / (ys[1] - ys[0])) * (H - top - M.b);
  const nodes = [];
  const yl = tickLabels(yt), xl = tickLabels(xt);
  yl.ticks.forEach((v, k) => nodes.push(s("line", { class: "grid", x1: M.l, x2: W - M.r, y1: Y(v), y2: Y(v) }),
    s("text", { class: "tick", dataset: { axis: "y" }, x: M.l - 4, y: Y(v) + 4, "text-anchor": "end" }, yl.labels[k])));
  xl.ticks.forEach((v, k) => nodes.push(s("line", { class: "grid", y1: top, y2: H - M.b, x1: X(v), x2: X(v) }),
    s("text", { class: "tick", dataset: { axis: "x" }, x: X(v), y: H - M.b + 13, "text-anchor": "middle" }, xl.labels[k])));
  nodes.push(s("line", { class: "axis", x1: M.l, x2: W - M.r, y1: H - M.b, y2: H - M.b }),
    s("line", { class: "axis", x1: M.l, x2: M.l, y1: top, y2: H - M.b }),
    s("text", { x: (M.l + W - M.r) / 2, y: H - 3, "text-anchor": "middle" }, xLabel),
    s("text", { transform: `translate(11 ${(M.t + H - M.b) / 2}) rotate(-90)`, "text-anchor": "middle" }, yLabel));
  return { X, Y, nodes };
}

function polyline(xv, yv, X, Y) {
  let p = "";
  for (let i = 0; i < xv.length; i++) p += `${X(xv[i]).toFixed(1)},${Y(yv[i]).toFixed(1)} `;
  return p;
}

/** Put `nodes` into `parent` reusing the elements already there: one of the same shape (tag, and its children's)
 *  takes the new one's attributes and text in place, so a diagram redrawn at every step of a drag changes attributes
 *  rather than its tree, which is less to style and lay out. The elements now in `parent`, in order. */
function morph(parent, nodes) {
  const old = [...parent.childNodes];
  const live = nodes.map((n, i) => {
    const o = old[i];
    if (o && sameShape(o, n)) { syncNode(o, n); return o; }
    if (o) parent.replaceChild(n, o); else parent.appendChild(n);
    return n;
  });
  for (const o of old.slice(nodes.length)) o.remove();
  return live;
}

function sameShape(a, b) {
  if (a.nodeType !== b.nodeType || a.nodeName !== b.nodeName || a.childNodes.length !== b.childNodes.length) return false;
  for (let i = 0; i < a.childNodes.length; i++) if (!sameShape(a.childNodes[i], b.childNodes[i])) return false;
  return true;
}

function syncNode(a, b) {
  if (a.nodeType !== Node.ELEMENT_NODE) { if (a.nodeValue !== b.nodeValue) a.nodeValue = b.nodeValue; return; }
  for (const { name } of [...a.attributes]) if (!b.hasAttribute(name)) a.removeAttribute(name);
  for (const { name, value } of b.attributes) if (a.getAttribute(name) !== value) a.setAttribute(name, value);
  for (let i = 0; i < a.childNodes.length; i++) syncNode(a.childNodes[i], b.childNodes[i]);
}

function box(container, id, title) {
  let el = container.querySelector(`#${id}`);
  if (!el) {
    el = h("div", { class: "plot", id }, h("h4"), s("svg", { viewBox: `0 0 ${W} ${H}`, role: "img" }));
    container.appendChild(el);
  }
  el.querySelector("h4").textContent = title;
  const svg = el.querySelector("svg");
  svg.setAttribute("aria-label", title);
  return { el, svg };
}

// The plots' text as the style sheet sets it (11 px of the system font), measured to lay legends out.
const measure = { ctx: null };
function textWidth(text) {
  if (!measure.ctx) {
    measure.ctx = document.createElement("canvas").getContext("2d");
    measure.ctx.font = `11px ${getComputedStyle(document.body).fontFamily || "system-ui, sans-serif"}`;
  }
  return measure.ctx.measureText(text).width;
}

const LEGEND_ROW = 13;

/** The legend's entries laid out by their measured width, left to right, a new row when the next would pass the
 *  plot's right edge; and the top margin that leaves room for its rows. */
function legend(series) {
  if (series.length < 2) return { nodes: [], top: M.t };
  const place = [];
  let x = M.l + 8, row = 0;
  for (const c of series) {
    const w = 20 + textWidth(c.name) + 10;
    if (x + w > W - M.r && x > M.l + 8) { x = M.l + 8; row += 1; }
    place.push([x, row]);
    x += w;
  }
  const top = M.t + row * LEGEND_ROW;
  const nodes = series.map((c, i) => s("g", { class: "legend-entry", transform: `translate(${place[i][0]} ${M.t - 10 + place[i][1] * LEGEND_ROW})` },
    s("line", { x1: 0, x2: 16, y1: 0, y2: 0, stroke: c.colour || COLOURS[i % COLOURS.length], "stroke-width": 2, "stroke-dasharray": c.dash || null }),
    s("text", { x: 20, y: 4 }, c.name)));
  return { nodes, top };
}

/** The note a plot carries when everything it draws is numerically zero. */
function zeroNote(peak, unit, x, y, anchor = "end") {
  return s("text", { class: "zero-note", x, y, "text-anchor": anchor }, `≈ 0 (largest |value| ${fmt(peak, 2)} ${unit})`);
}

/** Curves y(x) over one x axis (the crank angle), with optional horizontal limits, a cursor at one sample and a
 *  hover read-out of every curve at the nearest sample. `zero`: a magnitude below which the curves are read as
 *  zero: the axis then spans ±`zeroSpan` and says "≈ 0", rather than autoscaling onto rounding noise. */
export function linePlot(container, id, { title, x, xLabel, series, yLabel, unit, limits = [], cursor = null, zero = 0, zeroSpan = zero }) {
  const { el, svg } = box(container, id, title);
  const xs = [x[0], x[x.length - 1]];
  if (xs[1] <= xs[0]) xs[1] = xs[0] + 1;
  let peak = 0;
  for (const c of series) for (const v of c.values) peak = Math.max(peak, Math.abs(v));
  const isZero = zero > 0 && peak < zero;
  const ys = isZero ? [-zeroSpan, zeroSpan] : extent([...series.map((c) => c.values), ...limits.map((l) => [l.y])]);
  const xt = niceTicks(xs[0], xs[1], 6).ticks.filter((v) => v >= xs[0] - 1e-9 && v <= xs[1] + 1e-9);
  const yt = niceTicks(ys[0], ys[1], 5).ticks.filter((v) => v >= ys[0] - 1e-12 * (ys[1] - ys[0]) && v <= ys[1] + 1e-12 * (ys[1] - ys[0]));
  const key = legend(series);
  const { X, Y, nodes } = frame(xs, ys, xt, yt, xLabel, yLabel, key.top);
  series.forEach((c, i) => {
    nodes.push(s("polyline", { class: "curve", dataset: { series: c.name }, stroke: c.colour || COLOURS[i % COLOURS.length], "stroke-dasharray": c.dash || null,
      points: polyline(x, c.values, X, Y) }));
  });
  for (const l of limits) {
    if (l.y < ys[0] || l.y > ys[1]) continue;
    nodes.push(s("line", { class: "limit", x1: M.l, x2: W - M.r, y1: Y(l.y), y2: Y(l.y) }),
      s("text", { x: W - M.r - 4, y: Y(l.y) - 4, "text-anchor": "end", fill: "#b3261e" }, l.label));
  }
  if (isZero) nodes.push(zeroNote(peak, unit, W - M.r - 4, key.top + 12));
  nodes.push(...key.nodes);
  let cursorLine = s("line", { class: "cursor", y1: key.top, y2: H - M.b, x1: M.l, x2: M.l });
  let hoverLine = s("line", { class: "hover", y1: key.top, y2: H - M.b, x1: 0, x2: 0, visibility: "hidden" });
  nodes.push(cursorLine, hoverLine);
  const live = morph(svg, nodes);
  [cursorLine, hoverLine] = live.slice(-2);
  const setCursor = (i) => {
    if (i === null || i === undefined || i >= x.length) { cursorLine.setAttribute("visibility", "hidden"); return; }
    cursorLine.setAttribute("visibility", "visible");
    cursorLine.setAttribute("x1", X(x[i])); cursorLine.setAttribute("x2", X(x[i]));
  };
  setCursor(cursor);
  svg.onmousemove = (evt) => {
    const r = svg.getBoundingClientRect();
    const px = ((evt.clientX - r.left) / r.width) * W;
    const xv = xs[0] + ((px - M.l) / (W - M.l - M.r)) * (xs[1] - xs[0]);
    let best = 0;
    for (let i = 1; i < x.length; i++) if (Math.abs(x[i] - xv) < Math.abs(x[best] - xv)) best = i;
    hoverLine.setAttribute("x1", X(x[best])); hoverLine.setAttribute("x2", X(x[best])); hoverLine.setAttribute("visibility", "visible");
    showTip(evt, `${xLabel} = ${fmt(x[best])}\n` + series.map((c) => `${c.name} = ${fmt(c.values[best])} ${unit}`).join("\n"));
  };
  svg.onmouseleave = () => { hideTip(); hoverLine.setAttribute("visibility", "hidden"); };
  el.dataset.ymin = ys[0]; el.dataset.ymax = ys[1];
  el.dataset.zero = String(isZero);
  return { setCursor, el };
}

/** Polar diagram of a planar vector over the cycle (the shaking force as the textbooks draw it): equal scales,
 *  origin marked, one curve per series; `zero` as for linePlot. */
export function polarPlot(container, id, { title, series, unit, labels = ["Fx", "Fy"], cursor = null, zero = 0, zeroSpan = zero }) {
  const { el, svg } = box(container, id, title);
  let peak = 0;
  for (const c of series) for (const [a, b] of c.points) peak = Math.max(peak, Math.hypot(a, b));
  const isZero = zero > 0 && peak < zero;
  const r = isZero ? zeroSpan : peak > 0 ? peak * 1.08 : 1;
  const side = H - M.t - M.b, cx = M.l + (W - M.l - M.r) / 2, cy = M.t + side / 2;
  const k = side / (2 * r);
  const X = (v) => cx + v * k, Y = (v) => cy - v * k;
  const { ticks } = niceTicks(-r, r, 4);
  const nodes = [];
  for (const v of ticks) {
    if (Math.abs(v) > r * (1 + 1e-12)) continue;
    nodes.push(s("line", { class: "grid", x1: X(v), x2: X(v), y1: Y(-r), y2: Y(r) }),
      s("line", { class: "grid", y1: Y(v), y2: Y(v), x1: X(-r), x2: X(r) }),
      s("text", { class: "tick", x: X(v), y: Y(-r) + 12, "text-anchor": "middle" }, fmt(v, 3)));
  }
  nodes.push(s("line", { class: "axis", x1: X(-r), x2: X(r), y1: cy, y2: cy }),
    s("line", { class: "axis", x1: cx, x2: cx, y1: Y(-r), y2: Y(r) }),
    s("text", { x: X(r) + 4, y: cy + 4 }, labels[0]), s("text", { x: cx + 4, y: Y(r) + 10 }, labels[1]),
    s("text", { x: W - M.r, y: H - 4, "text-anchor": "end", class: "tick" }, `[${unit}]`));
  series.forEach((c, i) => {
    const xs = c.points.map((p) => p[0]), ys = c.points.map((p) => p[1]);
    nodes.push(s("polygon", { class: "curve", dataset: { series: c.name }, stroke: c.colour || COLOURS[i % COLOURS.length], "stroke-dasharray": c.dash || null,
      points: polyline(xs, ys, X, Y) }));
  });
  nodes.push(s("circle", { cx, cy, r: 2.5, fill: "#223047" }));
  if (series.length > 1) {
    series.forEach((c, i) => nodes.push(s("g", { transform: `translate(${W - M.r - 110} ${M.t + 8 + i * 14})` },
      s("line", { x1: 0, x2: 16, stroke: c.colour || COLOURS[i % COLOURS.length], "stroke-width": 2, "stroke-dasharray": c.dash || null }),
      s("text", { x: 20, y: 4 }, c.name))));
  }
  if (isZero) nodes.push(zeroNote(peak, unit, M.l - 40, M.t + 4, "start"));
  const [ray, dot] = morph(svg, [...nodes, s("line", { class: "cursor", x1: cx, y1: cy, x2: cx, y2: cy }),
    s("circle", { class: "hover-dot", r: 3.5, cx: 0, cy: 0, fill: "#d0a000", visibility: "hidden" })]).slice(-2);
  const first = series[0];
  const setCursor = (i) => {
    if (i === null || i === undefined || !first || i >= first.points.length) return;
    ray.setAttribute("x2", X(first.points[i][0])); ray.setAttribute("y2", Y(first.points[i][1]));
  };
  setCursor(cursor);
  svg.onmousemove = (evt) => {
    const b = svg.getBoundingClientRect();
    const scale = Math.min(b.width / W, b.height / H);
    const ox = (b.width - W * scale) / 2, oy = (b.height - H * scale) / 2;
    const px = (evt.clientX - b.left - ox) / scale, py = (evt.clientY - b.top - oy) / scale;
    let best = null, bd = Infinity;
    series.forEach((c) => c.points.forEach((p, i) => {
      const d = (X(p[0]) - px) ** 2 + (Y(p[1]) - py) ** 2;
      if (d < bd) { bd = d; best = { c, i, p }; }
    }));
    if (!best) return;
    dot.setAttribute("cx", X(best.p[0])); dot.setAttribute("cy", Y(best.p[1])); dot.setAttribute("visibility", "visible");
    const angle = series.angles ? series.angles[best.i] : best.i;
    showTip(evt, `${best.c.name}, crank ${fmt(angle)}°\n${labels[0]} = ${fmt(best.p[0])} ${unit}\n${labels[1]} = ` +
      `${fmt(best.p[1])} ${unit}\n|F| = ${fmt(Math.hypot(best.p[0], best.p[1]))} ${unit}`);
  };
  svg.onmouseleave = () => { hideTip(); dot.setAttribute("visibility", "hidden"); };
  el.dataset.radius = isZero ? peak : r / 1.08;
  el.dataset.axisRadius = r;
  el.dataset.zero = String(isZero);
  return { setCursor, el };
}

/** Scatter of points with a click handler per point (a Pareto front, a trade-off sweep). */
export function scatterPlot(container, id, { title, points, xLabel, yLabel, onPick, line = false, highlight = [] }) {
  const { el, svg } = box(container, id, title);
  const xs = extent([points.map((p) => p.x)], 0.08), ys = extent([points.map((p) => p.y)], 0.08);
  const xt = niceTicks(xs[0], xs[1], 5).ticks.filter((v) => v >= xs[0] && v <= xs[1]);
  const yt = niceTicks(ys[0], ys[1], 5).ticks.filter((v) => v >= ys[0] && v <= ys[1]);
  const { X, Y, nodes } = frame(xs, ys, xt, yt, xLabel, yLabel);
  nodes.push(s("clipPath", { id: `clip-${id}` }, s("rect", { x: M.l, y: M.t, width: W - M.l - M.r, height: H - M.t - M.b })));
  if (line && points.length > 1) {
    const order = [...points].sort((a, b) => a.x - b.x);
    nodes.push(s("polyline", { class: "curve", stroke: "#8a93a3", points: polyline(order.map((p) => p.x), order.map((p) => p.y), X, Y) }));
  }
  // many points: smaller dots, so the cloud stays readable; a large cloud is not each in the tab order
  const dense = points.length > 100, r0 = dense ? 2.4 : 5, focusable = points.length <= 200;
  points.forEach((p, i) => {
    const hot = highlight.includes(i);
    nodes.push(s("circle", { class: "pick", dataset: { index: i }, cx: X(p.x), cy: Y(p.y), r: hot ? r0 + 2 : r0,
      fill: p.colour || (hot ? "#c25e00" : "#1f5fbf"), stroke: dense ? "none" : "#fff", "stroke-width": 1.2, tabindex: focusable || p.focus ? 0 : null,
      role: "button", "aria-label": p.label || `point ${i}` }));
  });
  svg.replaceChildren(...nodes);
  const tip = (evt) => {
    const c = evt.target.closest && evt.target.closest("circle.pick");
    if (!c) return;
    const p = points[Number(c.dataset.index)];
    showTip(evt, `${p.label || ""}\n${xLabel} = ${fmt(p.x)}\n${yLabel} = ${fmt(p.y)}`);
  };
  const pick = (evt) => {
    const c = evt.target.closest && evt.target.closest("circle.pick");
    if (!c) return;
    hideTip();
    if (onPick) onPick(points[Number(c.dataset.index)], Number(c.dataset.index));
  };
  svg.onmousemove = tip;
  svg.onmouseleave = hideTip;
  svg.onclick = pick;
  svg.onkeydown = (e) => { if (e.key === "Enter" || e.key === " ") { e.preventDefault(); pick(e); } };
  return { el, X, Y, clip: `url(#clip-${id})` };
}
