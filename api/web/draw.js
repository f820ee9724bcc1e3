// The linkage drawn to scale from an analysis answer: every position comes from the answer's `points`; the page
// only chooses where to put the ink.
import { s, append } from "./dom.js";

const LINKS = {
  fourbar: [["crank", "O", "A"], ["coupler", "A", "B"], ["rocker", "Q", "B"]],
  slider_crank: [["crank", "O", "A"], ["rod", "A", "B"]],
  slotted_lever: [["crank", "O", "A"], ["rocker", "O1", "B"], ["ram_link", "B", "R"]],
};
const PIVOTS = { fourbar: ["O", "Q"], slider_crank: ["O"], slotted_lever: ["O", "O1"] };

/** Everything about a drawing that stays while the crank turns: scale, view box, static ink. */
export function layout(answer, design, extras) {
  const pts = answer.points;
  let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
  const grow = (x, y) => { if (x < x0) x0 = x; if (x > x1) x1 = x; if (y < y0) y0 = y; if (y > y1) y1 = y; };
  for (const p of Object.values(pts)) for (const [x, y] of p.position_m) grow(x, y);
  for (const [x, y] of extras.targets || []) grow(x, y);
  const span = Math.max(x1 - x0, y1 - y0, 1e-6);
  const pad = span * 0.12;
  // below the linkage: room for the ground symbols and names under the lowest pivot, then a strip for the scale
  // bar of its own, so neither is cut at the edge nor written over
  return { x0: x0 - pad, x1: x1 + pad, y0: y0 - pad - span * 0.1, y1: y1 + pad, span, family: design.mechanism.type };
}

function scaleBar(span) {
  const raw = span / 4, mag = 10 ** Math.floor(Math.log10(raw));
  const len = [1, 2, 5, 10].map((s) => s * mag).filter((s) => s <= raw).pop() || mag;
  return len;
}

function label(len, unitLength) {
  return unitLength === "mm" ? `${+(len * 1000).toPrecision(3)} mm` : `${+len.toPrecision(3)} m`;
}

/** Draw the linkage at sample `i` into `svg`. `extras`: counterweight trace names, coupler point name, target
 *  points, units, vectors (per point name: [vx, vy] drawn as an arrow, `vectorScale` metres per unit). Every name
 *  from the design or the answer goes in as text. */
export function drawLinkage(svg, answer, design, i, lay, extras) {
  const pts = answer.points, fam = lay.family;
  const at = (name) => pts[name] && pts[name].position_m[i];
  const w = lay.x1 - lay.x0, h = lay.y1 - lay.y0;
  svg.setAttribute("viewBox", `${lay.x0} ${-lay.y1} ${w} ${h}`);
  const sw = lay.span / 180;   // stroke unit: the drawing keeps its look whatever the size of the linkage
  const P = (p) => `${p[0]},${-p[1]}`;
  const g = s("g", { "stroke-width": sw, "font-size": sw * 11 });
  const add = (...nodes) => append(g, nodes);
  const title = (t) => s("title", {}, t);
  const dashGuide = `${8 * sw} ${3 * sw} ${2 * sw} ${3 * sw}`;
  // crank circle, guides, curves: what the cycle sweeps
  const O = at("O"), A = at("A");
  if (O && A) {
    const rc = Math.hypot(A[0] - O[0], A[1] - O[1]);
    add(s("circle", { class: "crank-circle", cx: O[0], cy: -O[1], r: rc, "stroke-width": sw, "stroke-dasharray": `${3 * sw} ${3 * sw}` }));
  }
  const general = fam === "linkage" ? design.mechanism : null;
  if (general) {
    // a general linkage drawn from its own description: each link through its points, each frame point grounded,
    // each slide on the frame a guide through its point along its axis
    for (const j of general.joints || []) {
      if (j.kind !== "prismatic" || !(j.links || []).includes("frame") || !j.through || !at(j.through)) continue;
      const gp = at(j.through), a = ((Number(j.axis_deg) || 0) * Math.PI) / 180, L = lay.span * 0.6;
      add(s("line", { class: "guide", x1: gp[0] - Math.cos(a) * L, y1: -(gp[1] - Math.sin(a) * L), x2: gp[0] + Math.cos(a) * L,
        y2: -(gp[1] + Math.sin(a) * L), "stroke-width": sw, "stroke-dasharray": dashGuide }));
    }
    for (const name of Object.keys(general.frame_points_m || {})) {
      const p = at(name);
      if (p) add(s("path", { class: "ground", d: `M${p[0]},${-p[1]} l${-6 * sw},${10 * sw} h${12 * sw} z` }));
    }
    (general.links || []).forEach((link) => {
      const names = [...(link.joints || []), ...Object.keys(link.points_m || {})].filter((n, k, all) => at(n) && all.indexOf(n) === k);
      if (names.length === 1) {
        const p = at(names[0]);
        add(s("rect", { class: "slider", x: p[0] - 14 * sw, y: -p[1] - 8 * sw, width: 28 * sw, height: 16 * sw, "stroke-width": 2 * sw }, title(link.name)));
      } else if (names.length === 2) {
        const [p, q] = names.map(at);
        add(s("line", { class: ["link", link.name === general.crank && "crank"], x1: p[0], y1: -p[1], x2: q[0], y2: -q[1], "stroke-width": 5 * sw }, title(link.name)));
      } else if (names.length > 2) {
        add(s("polygon", { points: names.map((n) => P(at(n))).join(" "), fill: "#dfe7f3", stroke: "#2d3e5c", "stroke-width": 4 * sw,
          "stroke-linejoin": "round" }, title(link.name)));
      }
    });
  } else if (!LINKS[fam]) {
    // a family without a drawing of its own: every joint's path over the cycle
    for (const [name, p] of Object.entries(pts)) {
      if (name.startsWith("S_") || name.startsWith("cw")) continue;
      add(s("polyline", { points: p.position_m.map(P).join(" "), fill: "none", stroke: "#9fb4d9", "stroke-width": sw }));
    }
  }
  if (fam === "slider_crank") {
    const ys = pts.B.position_m.map((p) => p[1]), xs = pts.B.position_m.map((p) => p[0]);
    const gx0 = Math.min(...xs) - lay.span * 0.08, gx1 = Math.max(...xs) + lay.span * 0.08;
    add(s("line", { class: "guide", x1: gx0, x2: gx1, y1: -ys[0], y2: -ys[0], "stroke-width": sw, "stroke-dasharray": dashGuide }));
  }
  if (fam === "slotted_lever") {
    const xs = pts.R.position_m.map((p) => p[0]), y = pts.R.position_m[0][1];
    add(s("line", { class: "guide", x1: Math.min(...xs) - lay.span * 0.08, x2: Math.max(...xs) + lay.span * 0.08, y1: -y, y2: -y,
      "stroke-width": sw, "stroke-dasharray": dashGuide }));
  }
  if (extras.tracePoint && pts[extras.tracePoint]) {
    add(s("polygon", { class: "path-curve", points: pts[extras.tracePoint].position_m.map(P).join(" "), "stroke-width": sw,
      "stroke-dasharray": `${4 * sw} ${2 * sw}` }));
  }
  for (const [x, y] of extras.targets || []) add(s("circle", { class: "target", cx: x, cy: -y, r: 3.5 * sw, "stroke-width": sw }));
  // ground pivots
  for (const name of PIVOTS[fam] || []) {
    const p = at(name);
    if (!p) continue;
    add(s("path", { class: "ground", d: `M${p[0]},${-p[1]} l${-6 * sw},${10 * sw} h${12 * sw} z` }),
      s("line", { x1: p[0] - 9 * sw, x2: p[0] + 9 * sw, y1: -p[1] + 10 * sw, y2: -p[1] + 10 * sw, stroke: "#8a93a3", "stroke-width": 1.5 * sw }));
  }
  // coupler plate with its coupler point
  if (extras.tracePoint && at(extras.tracePoint) && (fam === "fourbar" || fam === "slider_crank")) {
    add(s("polygon", { points: `${P(at("A"))} ${P(at(extras.tracePoint))} ${P(at("B"))}`, fill: "#dfe7f3", stroke: "#2d3e5c", "stroke-width": 1.5 * sw }));
  }
  for (const [name, a, b] of LINKS[fam] || []) {
    const p = at(a), q = at(b);
    add(s("line", { class: ["link", name], x1: p[0], y1: -p[1], x2: q[0], y2: -q[1], "stroke-width": 5 * sw }));
  }
  if (fam === "slider_crank") {
    const B = at("B");
    add(s("rect", { class: "slider", x: B[0] - 14 * sw, y: -B[1] - 8 * sw, width: 28 * sw, height: 16 * sw, "stroke-width": 2 * sw }));
  }
  if (fam === "slotted_lever") {
    const R = at("R"), A2 = at("A");
    add(s("rect", { class: "slider", x: A2[0] - 7 * sw, y: -A2[1] - 5 * sw, width: 14 * sw, height: 10 * sw, "stroke-width": 1.5 * sw }),
      s("rect", { class: "slider", x: R[0] - 40 * sw, y: -R[1] - 7 * sw, width: 80 * sw, height: 14 * sw, "stroke-width": 2 * sw }));
  }
  // counter-rotors: a geared disc about the pivot of the link it counters
  for (const cr of extras.counterRotors || []) {
    const pivot = at({ crank: "O", rocker: fam === "fourbar" ? "Q" : "O1" }[cr.link] || "O");
    if (!pivot) continue;
    add(s("circle", { cx: pivot[0], cy: -pivot[1], r: 14 * sw, fill: "none", stroke: "#c25e00", "stroke-width": 2 * sw,
      "stroke-dasharray": `${5 * sw} ${2 * sw}` }, title(`counter-rotor ${Number(cr.inertia_kgm2).toPrecision(3)} kg·m² at −${cr.ratio}× the ${cr.link}`)));
  }
  // counterweights and centres of mass
  for (const cw of extras.counterweights || []) {
    const p = at(cw.trace);
    if (!p) continue;
    const r = Math.max(4, Math.min(16, 5 * Math.cbrt(Math.max(Number(cw.mass_kg) || 0, 1e-3)))) * sw;
    add(s("circle", { class: "cw", cx: p[0], cy: -p[1], r, "stroke-width": sw }, title(`counterweight ${Number(cw.mass_kg).toPrecision(3)} kg on ${cw.link}`)));
  }
  for (const [name, p] of Object.entries(pts)) {
    if (!name.startsWith("S_")) continue;
    const q = p.position_m[i];
    add(s("circle", { class: "com", cx: q[0], cy: -q[1], r: 2.2 * sw }, title(`centre of mass of ${name.slice(2)}`)));
  }
  // velocity, acceleration or force arrows at points (the vectors overlay)
  for (const v of extras.vectors || []) {
    const p = at(v.point);
    if (!p || !v.value) continue;
    const dx = v.value[0] * v.scale, dy = v.value[1] * v.scale, len = Math.hypot(dx, dy);
    if (!(len > 0)) continue;
    const ux = dx / len, uy = dy / len, head = Math.min(len * 0.4, 7 * sw), tip = [p[0] + dx, p[1] + dy];
    const l = [tip[0] - head * (ux - 0.45 * uy), tip[1] - head * (uy + 0.45 * ux)], r = [tip[0] - head * (ux + 0.45 * uy), tip[1] - head * (uy - 0.45 * ux)];
    add(s("g", { class: ["vector", v.kind], dataset: { point: v.point, kind: v.kind } },
      s("line", { x1: p[0], y1: -p[1], x2: tip[0], y2: -tip[1], "stroke-width": 1.6 * sw }),
      s("polygon", { points: `${P(tip)} ${P(l)} ${P(r)}` }),
      title(v.label)));
  }
  // joints and their names
  const JOINTS = { fourbar: ["O", "A", "B", "Q"], slider_crank: ["O", "A", "B"], slotted_lever: ["O", "A", "O1", "B", "R"] };
  const joints = (JOINTS[fam] || Object.keys(pts).filter((n) => !n.startsWith("S_") && !n.startsWith("cw") && n !== extras.tracePoint &&
    !(general && (general.joints || []).some((j) => j.kind === "prismatic" && j.through === n && !(general.links || []).some((l) => (l.joints || []).includes(n))))))
    .filter((n) => at(n));
  // each name set outwards from the joints' centre, so it stays clear of the links
  const cx = joints.reduce((t, j) => t + at(j)[0], 0) / (joints.length || 1), cy = joints.reduce((t, j) => t + at(j)[1], 0) / (joints.length || 1);
  for (const j of joints) {
    const p = at(j);
    const dx = p[0] - cx, dy = p[1] - cy, d = Math.hypot(dx, dy) || 1;
    const lx = p[0] + (dx / d) * 11 * sw, ly = p[1] + (dy / d) * 11 * sw;
    add(s("circle", { class: "joint", dataset: { joint: j }, cx: p[0], cy: -p[1], r: 3.6 * sw, "stroke-width": 1.8 * sw }),
      s("text", { class: "joint-name", x: lx, y: -ly + 4 * sw, "text-anchor": "middle", "font-size": 12 * sw, "font-weight": 600 }, j));
  }
  if (extras.tracePoint && at(extras.tracePoint)) {
    const p = at(extras.tracePoint);
    add(s("circle", { cx: p[0], cy: -p[1], r: 3 * sw, fill: "#c25e00" }),
      s("text", { x: p[0] + 6 * sw, y: -p[1] - 6 * sw, "font-size": 12 * sw }, extras.tracePoint));
  }
  // scale bar, bottom left
  const len = scaleBar(lay.span);
  const bx = lay.x0 + lay.span * 0.03, by = -lay.y0 - lay.span * 0.03;
  add(s("line", { class: "scale-bar", x1: bx, x2: bx + len, y1: by, y2: by, stroke: "#223047", "stroke-width": 2 * sw }),
    s("text", { class: "scale-label", x: bx, y: by - 4 * sw, "font-size": 11 * sw }, label(len, extras.unitLength)));
  svg.replaceChildren(g);
}

/** Screen position of the event in drawing coordinates [m] (y up). */
export function toModel(svg, evt) {
  const pt = svg.createSVGPoint();
  pt.x = evt.clientX; pt.y = evt.clientY;
  const p = pt.matrixTransform(svg.getScreenCTM().inverse());
  return [p.x, -p.y];
}
