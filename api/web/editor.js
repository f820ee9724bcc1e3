// The drawing editor: a general linkage placed point by point on the canvas, kept as one model (points, links,
// blocks on guides) from which the `linkage` mechanism of the request is written. Every edit is undoable; the JSON
// box of the form is a view of the same mechanism; the structure (mobility, Assur groups) is said as you draw.
import { state, edited, analyse, renderForm, factor, markStale, defaultMechanism } from "./app.js";
import { post, Problem } from "./api.js";
import { h, s, put } from "./dom.js";
import { TEMPLATES } from "./templates.js";

// A drawn link is a steel bar of 10 kg per metre from its first point to each other point, its centre of mass at
// the mean of its points and J = m·mean(r²)/3 about it (m L²/12 for a bar); a block is 5 kg.
const KG_PER_M = 10, BLOCK_KG = 5;
const GRID = { mm: [0.005, 0.01, 0.05], m: [0.01, 0.05, 0.1] };
const TOOLS = [["move", "V", "Move / select"], ["frame", "F", "Frame point"], ["joint", "J", "Joint"],
  ["bar", "B", "Binary link (2 points)"], ["plate", "T", "Ternary link (3 points)"],
  ["slide", "S", "Block on a guide or in a slot: joint, then frame point or link"], ["crank", "C", "Crank"], ["output", "O", "Output"],
  ["point", "P", "Coupler point: click on a link"], ["delete", "X", "Delete"]];
// The coupler point's name in the answer's `points`.
const TRACE = "P";
const GROUP_COLOURS = ["#1b7a3a", "#8a2be2", "#c25e00", "#0a7d8c", "#a0306e"];

export const ed = {
  on: false, model: null, tool: "move", pending: [], selected: null, undo: [], redo: [], view: null,
  grid: 0.005, groups: null, structureKey: "", offset: [0, 0], fit: 0, dragging: null, messages: [], answerOk: false,
  // every press on the canvas handled, and where it landed [m]: a script clicking waits on these
  presses: 0, lastPress: null,
  // a drag sends its next position as soon as an answer arrives, before drawing it; `early` false is the drag as it
  // was before (the next position sent once the answer is drawn, the canvas drawn before the request goes), which
  // bench/workbench_drag.py compares against
  early: true,
};

const clone = (m) => JSON.parse(JSON.stringify(m));
// What a design says about its links and pairs by name, beside the mechanism: kept through every edit, each entry
// dropped with the link or pair it names (and back with an undo).
const BY_NAME = ["counterweights", "counter_rotors", "torques", "trace_points", "friction", "coupler_inertia_kgm2", "loads"];
const jointKey = (kind, links) => `${kind}|${[...links].sort().join("|")}`;

/** The model and the design's parts named after its links, as one undo step. */
function snapshot() {
  const d = state.design || {};
  return JSON.stringify({ model: ed.model, byName: Object.fromEntries(BY_NAME.filter((k) => k in d).map((k) => [k, d[k]])) });
}

function restore(text) {
  const snap = JSON.parse(text);
  ed.model = snap.model;
  for (const k of BY_NAME) delete state.design[k];
  Object.assign(state.design, snap.byName);
}

/** The design's entries that name a link or pair no longer drawn go with it. */
function prune(d, mech) {
  const links = new Set(["frame", ...mech.links.map((l) => l.name)]), joints = new Set(mech.joints.map((j) => j.name));
  for (const k of ["counterweights", "counter_rotors", "torques", "trace_points"]) {
    if (!Array.isArray(d[k])) continue;
    d[k] = d[k].filter((e) => links.has(e.link));
    if (!d[k].length) delete d[k];
  }
  if (d.friction) {
    d.friction = Object.fromEntries(Object.entries(d.friction).filter(([name]) => joints.has(name)));
    if (!Object.keys(d.friction).length) delete d.friction;
  }
  if (d.coupler_inertia_kgm2 !== undefined && !links.has("coupler")) delete d.coupler_inertia_kgm2;
  // a process load is on the output: a torque on one that turns, a force on one that slides (or of fixed direction)
  const out = mech.links.find((l) => l.name === mech.output);
  if (Array.isArray(d.loads) && out) {
    const slides = out.joints.length === 1;
    d.loads = d.loads.filter((l) => {
      const want = !slides && l.direction !== "frame" ? "torque_Nm" : "force_N", other = want === "force_N" ? "torque_Nm" : "force_N";
      return l[want] !== undefined && l[want] !== null && (l[other] === undefined || l[other] === null);
    });
    if (!d.loads.length) delete d.loads;
  }
}

/** A link's mass properties: as the design gave them (they stay with the link by name), or the bar rule. */
const PROPS = ["mass_kg", "com_m", "inertia_kgm2"];
function propsOf(link) {
  if (!link) return undefined;
  return Object.fromEntries(PROPS.filter((k) => link[k] !== undefined).map((k) => [k, clone(link[k])]));
}
// a family's link left out of its `links` is massless
const famProps = (link) => propsOf(link) || {};
const pt = (name) => ed.model.points.find((p) => p.name === name);
const bodiesAt = (m, name) => [...m.links.filter((l) => l.points.includes(name)).map((l) => l.name),
  ...m.blocks.filter((b) => b.point === name).map((b) => b.name)];

// --- model -> request ------------------------------------------------------------------------------------------------
function crankOf(m) {
  const onFrame = (l) => l.points.some((n) => (m.points.find((p) => p.name === n) || {}).ground);
  const c = m.links.find((l) => l.name === m.crank && onFrame(l)) || m.links.find(onFrame);
  return c || null;
}

function outputOf(m, crank) {
  if (m.output && (m.links.some((l) => l.name === m.output) || m.blocks.some((b) => b.name === m.output))) return m.output;
  const grounded = [...m.links.filter((l) => l.points.some((n) => (m.points.find((p) => p.name === n) || {}).ground)).map((l) => l.name),
    ...m.blocks.map((b) => b.name)].filter((n) => !crank || n !== crank.name);
  return grounded.pop() || null;
}

/** The linkage of the request from the drawing: the crank pivot moved to the origin, each link's frame on its
 *  first two points, masses by the bar rule above. */
export function toMechanism(m) {
  const crank = crankOf(m);
  const P = Object.fromEntries(m.points.map((p) => [p.name, p]));
  let pivot = m.points.find((p) => p.ground) || { x: 0, y: 0 };
  if (crank) pivot = P[crank.points.find((n) => P[n].ground)];
  const off = [pivot.x, pivot.y];
  const rel = (n) => [P[n].x - off[0], P[n].y - off[1]];
  const frame = {};
  for (const p of m.points) if (p.ground) frame[p.name] = rel(p.name);
  const links = m.links.map((l) => {
    let names = [...l.points];
    if (crank && l.name === crank.name) names = [names.find((n) => P[n].ground), ...names.filter((n) => n !== names.find((q) => P[q].ground))];
    const [p0, p1] = names.map(rel);
    const L = Math.hypot(p1[0] - p0[0], p1[1] - p0[1]), th = Math.atan2(p1[1] - p0[1], p1[0] - p0[0]);
    const local = names.map((n) => {
      const d = [rel(n)[0] - p0[0], rel(n)[1] - p0[1]];
      return [Math.cos(th) * d[0] + Math.sin(th) * d[1], -Math.sin(th) * d[0] + Math.cos(th) * d[1]];
    });
    local[0] = [0, 0]; local[1] = [L, 0];
    const out = { name: l.name, joints: names.slice(0, 2), length_m: L };
    if (names.length > 2) out.points_m = Object.fromEntries(names.slice(2).map((n, k) => [n, local[k + 2]]));
    if (l.props) return Object.assign(out, clone(l.props));
    const com = [local.reduce((t, q) => t + q[0], 0) / local.length, local.reduce((t, q) => t + q[1], 0) / local.length];
    const mass = KG_PER_M * local.slice(1).reduce((t, q) => t + Math.hypot(q[0], q[1]), 0);
    const r2 = local.reduce((t, q) => t + (q[0] - com[0]) ** 2 + (q[1] - com[1]) ** 2, 0) / local.length;
    return Object.assign(out, { mass_kg: mass, com_m: com, inertia_kgm2: (mass * r2) / 3 });
  });
  for (const b of m.blocks) links.push({ name: b.name, joints: [b.point], ...(b.props ? clone(b.props) : { mass_kg: BLOCK_KG }) });
  // a pair keeps the name the design gave it (friction and branches are keyed by it), else its point's
  const names = m.jointNames || {}, used = new Set();
  const named = (kind, links, fallback) => {
    const want = names[jointKey(kind, links)];
    const name = want && !used.has(want) ? want : fallback;
    used.add(name);
    return name;
  };
  const joints = [];
  for (const p of m.points) {
    const bodies = [...(p.ground ? ["frame"] : []), ...bodiesAt(m, p.name)];
    for (let k = 0; k + 1 < bodies.length; k++) {
      const pair = [bodies[k], bodies[k + 1]];
      const j = { name: named("revolute", pair, k ? `${p.name}_${k + 1}` : p.name), kind: "revolute", links: pair };
      if (j.name !== p.name) j.point = p.name;
      joints.push(j);
    }
  }
  for (const b of m.blocks) {
    // a block in a slot of a moving link: the slot through that link's origin at axis_deg in its frame
    if (b.slot) joints.push({ name: named("prismatic", [b.slot, b.name], `${b.name}_slot`), kind: "prismatic", links: [b.slot, b.name], axis_link: b.slot, axis_deg: b.axis_deg });
    else joints.push({ name: named("prismatic", ["frame", b.name], `${b.name}_guide`), kind: "prismatic", links: ["frame", b.name], through: b.through, axis_deg: b.axis_deg });
  }
  const mech = { type: "linkage", frame_points_m: frame, links, joints };
  if (crank) mech.crank = crank.name;
  const output = outputOf(m, crank);
  if (output) mech.output = output;
  const branches = Object.fromEntries(Object.entries(m.branches || {}).filter(([k]) => joints.some((j) => j.name === k)));
  if (Object.keys(branches).length) mech.branches = branches;
  return { mech, offset: off, crank };
}

/** W = 3n − 2p and what is wrong with the chain, each said at its place. */
export function check(m) {
  const { mech, crank, offset } = toMechanism(m);
  const n = mech.links.length, p = mech.joints.length, W = 3 * n - 2 * p;
  const out = [];
  for (const q of m.points) {
    if (!q.ground && !bodiesAt(m, q.name).length) out.push({ at: q.name, text: `joint ${q.name} is on no link` });
  }
  for (const l of m.links) {
    const shared = l.points.some((name) => pt(name).ground || bodiesAt(m, name).length > 1);
    if (!shared) out.push({ at: l.points[0], link: l.name, text: `link ${l.name} is joined to nothing` });
  }
  if (n && !crank) out.push({ at: null, text: "no link turns about a frame point: nothing can be the crank" });
  if (n && W > 1) out.push({ at: null, text: `W = 3·${n} − 2·${p} = ${W}: the chain has ${W} degrees of freedom; one crank cannot drive it (add a link, or join a joint to the frame)` });
  // A chain the formula counts as a structure may still move when a link is passive (a double parallelogram): the
  // service judges it from its geometry, so this is said but the analysis is still asked for.
  if (n && W < 1) out.push({ at: null, soft: true, text: `W = 3·${n} − 2·${p} = ${W} by the formula: the chain moves only if a link is passive (its constraints repeat others'); the service judges it from the geometry` });
  return { W, n, p, problems: out, mech, offset };
}

// --- the editor's model from a mechanism the service answered for -----------------------------------------------------
/** Any answered design as an editable drawing: its points at the shown crank angle, its links through them. */
export function fromAnswer(design, answer, i) {
  const mech = design.mechanism, at = (n) => answer.points[n] && answer.points[n].position_m[i];
  const points = [], seen = new Set();
  const add = (name, ground) => {
    if (seen.has(name) || !at(name)) return;
    seen.add(name);
    points.push({ name, x: at(name)[0], y: at(name)[1], ground });
  };
  if (mech.type === "linkage") {
    for (const n of Object.keys(mech.frame_points_m || {})) add(n, true);
    const links = [], blocks = [];
    for (const l of mech.links) {
      const names = [...(l.joints || []), ...Object.keys(l.points_m || {})];
      names.forEach((n) => add(n, false));
      if (names.length === 1) {
        const g = (mech.joints || []).find((j) => j.kind === "prismatic" && j.links.includes(l.name) && j.links.includes("frame"));
        const slot = !g && (mech.joints || []).find((j) => j.kind === "prismatic" && j.links.includes(l.name) && (j.axis_link || j.links[0]) !== l.name);
        if (g) blocks.push({ name: l.name, point: names[0], through: g.through, axis_deg: g.axis_deg || 0, props: propsOf(l) });
        else if (slot) blocks.push({ name: l.name, point: names[0], slot: slot.axis_link || slot.links[0], axis_deg: slot.axis_deg || 0, props: propsOf(l) });
      } else links.push({ name: l.name, points: names, props: propsOf(l) });
    }
    const jointNames = Object.fromEntries((mech.joints || []).map((j) => [jointKey(j.kind, j.links), j.name]));
    return { points, links, blocks, crank: mech.crank, output: mech.output, branches: { ...(mech.branches || {}) }, jointNames };
  }
  const famLinks = mech.links || {};
  const fam = mech.type;
  if (fam === "fourbar") {
    ["O", "Q"].forEach((n) => add(n, true)); ["A", "B"].forEach((n) => add(n, false));
    // the family's link frames are the drawing's (origin at the first point, x toward the second): masses carry over
    return { points, links: [{ name: "crank", points: ["O", "A"], props: famProps(famLinks.crank) }, { name: "coupler", points: ["A", "B"], props: famProps(famLinks.coupler) },
      { name: "rocker", points: ["Q", "B"], props: famProps(famLinks.rocker) }],
    blocks: [], crank: "crank", output: "rocker", branches: {} };
  }
  if (fam === "slider_crank") {
    add("O", true); add("A", false); add("B", false);
    points.push({ name: "G", x: at("B")[0], y: at("B")[1], ground: true });
    return { points, links: [{ name: "crank", points: ["O", "A"], props: famProps(famLinks.crank) }, { name: "rod", points: ["A", "B"], props: famProps(famLinks.rod) }],
      blocks: [{ name: "slider", point: "B", through: "G", axis_deg: 0, props: famProps(famLinks.slider) }], crank: "crank", output: "slider",
      branches: {}, jointNames: { [jointKey("prismatic", ["frame", "slider"])]: "guide" } };
  }
  if (fam === "slotted_lever") {
    // the shaper as its engine writes it: blocks in the lever's slot and across the ram, the ram guide through G
    add("O", true); add("O1", true); ["A", "B", "R"].forEach((n) => add(n, false));
    points.push({ name: "G", x: 0, y: -mech.ground_length_m + mech.ram_height_m, ground: true });
    return { points, links: [{ name: "crank", points: ["O", "A"], props: famProps(famLinks.crank) }, { name: "rocker", points: ["O1", "B"], props: famProps(famLinks.rocker) }],
      blocks: [{ name: "slider", point: "A", slot: "rocker", axis_deg: 0, props: famProps(famLinks.slider) },
        { name: "ram", point: "R", through: "G", axis_deg: 0, props: famProps(famLinks.ram) },
        { name: "ram_slider", point: "B", slot: "ram", axis_deg: 90, props: famProps(famLinks.ram_slider) }],
      crank: "crank", output: "ram", branches: {},
      jointNames: { [jointKey("prismatic", ["rocker", "slider"])]: "A_slot", [jointKey("prismatic", ["ram", "ram_slider"])]: "B_slot", [jointKey("prismatic", ["frame", "ram"])]: "R" } };
  }
  return null;
}

// --- edits -------------------------------------------------------------------------------------------------------------
function snap(v) { return Math.round(v / ed.grid) * ed.grid; }
function snapXY([x, y], free) {
  if (free) return [x, y];
  // to the grid in the chosen unit, exact in it (300 mm is 0.3 m, not 0.30000000000000004)
  const per = Math.round(1 / factor("length")) * 1e6;
  const r = (v) => Math.round(snap(v) * per) / per;
  return [r(x), r(y)];
}

/** A joint placed as the far end of a binary link: the link's length a whole number of grid steps (exact in the
 *  chosen unit), its direction as clicked. */
function snapLength(from, xy) {
  const dx = xy[0] - from.x, dy = xy[1] - from.y, L = Math.hypot(dx, dy);
  if (L < 1e-12) return xy;
  const per = Math.round(1 / factor("length")) * 1e6;
  const want = Math.round(Math.max(1, Math.round(L / ed.grid)) * ed.grid * per) / per;
  if (Math.abs(want - L) < 1e-9) return xy;  // the grid point is already at a round length: keep it exact
  return [from.x + (dx * want) / L, from.y + (dy * want) / L];
}

function nextName(ground) {
  const used = new Set([...ed.model.points.map((p) => p.name)]);
  const order = ground ? ["O", "Q", "G", "H", "K", "M", "N", "R", "U", "W"] : "ABCDEFIJLPSTVXYZ".split("");
  const free = order.find((n) => !used.has(n));
  if (free) return free;
  for (let k = 1; ; k++) if (!used.has(`${ground ? "G" : "P"}${k}`)) return `${ground ? "G" : "P"}${k}`;
}

function nextLinkName(prefix) {
  const used = new Set([...ed.model.links.map((l) => l.name), ...ed.model.blocks.map((b) => b.name)]);
  for (let k = 1; ; k++) if (!used.has(`${prefix}${k}`)) return `${prefix}${k}`;
}

/** Apply an edit: the model before it goes on the undo stack (a drag pushes once, at its start). */
function change(fn, { push = true, topology = true } = {}) {
  if (push) { ed.undo.push(snapshot()); ed.redo = []; if (ed.undo.length > 500) ed.undo.shift(); }
  fn(ed.model);
  if (topology) ed.fit = 4;
  commit();
}

function undo() {
  if (!ed.undo.length) return;
  ed.redo.push(snapshot());
  restore(ed.undo.pop());
  ed.fit = 4; ed.pending = [];
  commit();
}

function redo() {
  if (!ed.redo.length) return;
  ed.undo.push(snapshot());
  restore(ed.redo.pop());
  ed.fit = 4; ed.pending = [];
  commit();
}

/** Blocks whose slot was in a link no longer there go with it (and the blocks in theirs). */
function dropSlots(m) {
  for (let n = -1; n !== m.blocks.length;) {
    n = m.blocks.length;
    const bodies = new Set([...m.links.map((l) => l.name), ...m.blocks.map((b) => b.name)]);
    m.blocks = m.blocks.filter((b) => !b.slot || bodies.has(b.slot));
  }
}

/** The world angle [deg] of a block's slide: its guide's, or its slot's in the slotted link as drawn. */
function slideAngle(m, b, depth = 0) {
  if (!b.slot) return b.axis_deg;
  const l = m.links.find((q) => q.name === b.slot);
  if (l) {
    const [a, c] = l.points.map((n) => m.points.find((p) => p.name === n));
    return (Math.atan2(c.y - a.y, c.x - a.x) * 180) / Math.PI + b.axis_deg;
  }
  const host = m.blocks.find((q) => q.name === b.slot);
  return (host && depth < 8 ? slideAngle(m, host, depth + 1) : 0) + b.axis_deg;
}

function deletePoint(name) {
  change((m) => {
    m.points = m.points.filter((p) => p.name !== name);
    m.links = m.links.filter((l) => !l.points.includes(name));
    m.blocks = m.blocks.filter((b) => b.point !== name && b.through !== name);
    dropSlots(m);
  });
}

function deleteLink(name) {
  change((m) => { m.links = m.links.filter((l) => l.name !== name); m.blocks = m.blocks.filter((b) => b.name !== name); dropSlots(m); });
}

// --- the model into the design, the drawing, the table ----------------------------------------------------------------
let lastChecked = null;
function commit(t0 = performance.now(), { draw = true } = {}) {
  const c = check(ed.model);
  lastChecked = c;
  ed.messages = c.problems;
  ed.offset = c.offset;
  const d = state.design;
  const wasLinkage = d.mechanism.type === "linkage";
  d.mechanism = c.mech;
  ed.committed = JSON.stringify(c.mech);
  prune(d, c.mech);
  // the JSON box follows at the end of a drag, not at every step of it
  if (!ed.dragging) { syncJson(wasLinkage); render(); }
  document.body.dataset.mobility = String(c.W);
  const blocking = c.problems.filter((q) => !q.soft);
  if (blocking.length || !c.mech.links.length) {
    if (ed.dragging) render();
    // nothing the service could analyse: an answer still on its way is for a chain no longer drawn
    if (state.pending) { state.pending.abort(); state.pending = null; }
    state.seq += 1;
    ed.answerOk = false;
    markStale(blocking.length ? blocking[0].text : "nothing drawn yet");
    document.body.dataset.drawProblem = c.problems.map((p) => p.text).join(" | ");
    if (!ed.dragging) history.replaceState(null, "", `#design=${encodeURIComponent(JSON.stringify(state.design))}`);
    return null;
  }
  document.body.dataset.drawProblem = c.problems.map((p) => p.text).join(" | ");
  refreshStructure(c.mech);
  if (!ed.dragging) return edited(t0);
  // a dragged joint: the request on its way first, then the drawing from the points as they are; the address bar
  // (the whole design, encoded) follows at the end of the drag: writing it costs as much as drawing
  if (!ed.early) { render(); return analyse(t0); }
  const sent = analyse(t0);
  if (draw) render();
  return sent;
}

function syncJson(wasLinkage) {
  const box = document.getElementById("f-mechanism");
  if (!wasLinkage || !box) { renderForm(); return; }
  if (document.activeElement === box) return;
  box.value = JSON.stringify(state.design.mechanism, null, 1);
}

async function refreshStructure(mech) {
  const key = JSON.stringify([mech.crank, mech.joints.map((j) => [j.kind, ...j.links])]);
  if (key === ed.structureKey) return;
  ed.structureKey = key;
  ed.groups = null;
  try {
    const st = await post("/v1/structure", { links: ["frame", ...mech.links.map((l) => l.name)],
      pairs: mech.joints.map((j) => ({ name: j.name, links: j.links, kind: j.kind })), input_links: mech.crank ? [mech.crank] : null });
    if (key !== ed.structureKey) return;
    ed.groups = st.assur_groups || [];
    ed.structureNote = st.note;
    if (ed.answerOk && state.answer && state.pending === null) settle(state.answer); else render();
  } catch { ed.groups = null; }
}

// --- the assembly branches, read off the drawing ------------------------------------------------------------------------
/** The service places each dyad on one of its two branches: compare the answer at the drawn crank angle with the
 *  drawing and turn round the first group whose points land elsewhere, until the answer is the drawing. */
function fitBranches(answer) {
  if (!ed.fit || !ed.groups || ed.dragging) return false;
  ed.fit -= 1;
  const m = ed.model, mech = state.design.mechanism, crank = crankOf(m);
  if (!crank) { ed.fit = 0; return false; }
  const lk = mech.links.find((l) => l.name === crank.name);
  const a = pt(lk.joints[0]), b = pt(lk.joints[1]);
  const phi = ((Math.atan2(b.y - a.y, b.x - a.x) * 180) / Math.PI + 360) % 360;
  const angles = answer.crank_angle_deg;
  let k = 0;
  angles.forEach((v, j) => { if (Math.abs(((v - phi + 540) % 360) - 180) < Math.abs(((angles[k] - phi + 540) % 360) - 180)) k = j; });
  const span = Math.max(...m.points.map((p) => p.x)) - Math.min(...m.points.map((p) => p.x)) + 1e-9;
  const tol = 0.03 * span + Math.hypot(b.x - a.x, b.y - a.y) * 0.05;
  for (const g of ed.groups) {
    if (g.links.length !== 2) { ed.fit = 0; return false; }
    const names = g.links.flatMap((l) => { const L = m.links.find((q) => q.name === l); return L ? L.points : m.blocks.filter((q) => q.name === l).map((q) => q.point); });
    const off = names.some((n) => {
      const r = answer.points[n] && answer.points[n].position_m[k];
      return r && Math.hypot(r[0] + ed.offset[0] - pt(n).x, r[1] + ed.offset[1] - pt(n).y) > tol;
    });
    if (!off) continue;
    const inner = mech.joints.find((j) => j.links.includes(g.links[0]) && j.links.includes(g.links[1]));
    if (!inner) { ed.fit = 0; return false; }
    m.branches = { ...(m.branches || {}), [inner.name]: -((m.branches || {})[inner.name] || 1) };
    commit();
    return true;
  }
  ed.fit = 0;
  return false;
}

// --- drawing ------------------------------------------------------------------------------------------------------------
function viewFor(m) {
  const xs = m.points.map((p) => p.x), ys = m.points.map((p) => p.y);
  if (state.answer && ed.answerOk) for (const p of Object.values(state.answer.points)) for (const [x, y] of p.position_m) { xs.push(x + ed.offset[0]); ys.push(y + ed.offset[1]); }
  if (!xs.length) return { x0: -0.2, y0: -0.2, w: 1.2, h: 0.6 };
  let x0 = Math.min(...xs), x1 = Math.max(...xs), y0 = Math.min(...ys), y1 = Math.max(...ys);
  const span = Math.max(x1 - x0, y1 - y0, 0.2), pad = span * 0.2;
  x0 -= pad; x1 += pad; y0 -= pad; y1 += pad;
  // the canvas's own proportions, so a click lands where it is drawn
  const box = document.getElementById("draw-canvas").getBoundingClientRect();
  const aspect = box.width / Math.max(box.height, 1) || 2.5;
  let w = x1 - x0, hh = y1 - y0;
  if (w / hh < aspect) { const nw = hh * aspect; x0 -= (nw - w) / 2; w = nw; } else { const nh = w / aspect; y0 -= (nh - hh) / 2; hh = nh; }
  return { x0, y0, w, h: hh };
}

function render() {
  if (!ed.on) return;
  drawCanvas();
  // while a point is dragged only the numbers change: the table keeps its nodes
  if (ed.dragging) updateSide(); else renderSide();
}

function updateSide() {
  for (const p of ed.model.points) {
    const x = document.getElementById(`dp-${p.name}-x`), y = document.getElementById(`dp-${p.name}-y`);
    if (x) x.value = num(p.x);
    if (y) y.value = num(p.y);
  }
  for (const l of ed.model.links) {
    const el = document.getElementById(`dl-${l.name}`), [a, b] = l.points.map(pt);
    if (el) el.value = num(Math.hypot(b.x - a.x, b.y - a.y));
  }
}

let gridCache = null;
function drawCanvas() {
  const svg = document.getElementById("draw-canvas"), m = ed.model, v = ed.view;
  svg.setAttribute("viewBox", `${v.x0} ${-(v.y0 + v.h)} ${v.w} ${v.h}`);
  const sw = v.w / 600, g = s("g", { "stroke-width": sw });
  const Y = (y) => -y;
  // the grid: one line per step, every tenth darker
  // a line every grid step, or every 2, 5, 10… steps when the view is wide for it
  const step = ed.grid * [1, 2, 5, 10, 20, 50, 100].find((k) => v.w / (ed.grid * k) <= 120);
  if (Number.isFinite(step)) {
    // the same view and step (all through a drag): the grid stays in the canvas as it is, only the drawing over it
    // is replaced (a grid put back would be styled and laid out again, line by line)
    const key = `${v.x0} ${v.y0} ${v.w} ${v.h} ${step}`;
    if (!gridCache || gridCache.key !== key || gridCache.grid.parentNode !== svg) {
      const grid = s("g", { class: "draw-grid", "stroke-width": sw });
      for (let x = Math.ceil(v.x0 / step) * step; x <= v.x0 + v.w; x += step) grid.appendChild(s("line", { x1: x, x2: x, y1: Y(v.y0), y2: Y(v.y0 + v.h), "stroke-width": sw * 0.5 }));
      for (let y = Math.ceil(v.y0 / step) * step; y <= v.y0 + v.h; y += step) grid.appendChild(s("line", { y1: Y(y), y2: Y(y), x1: v.x0, x2: v.x0 + v.w, "stroke-width": sw * 0.5 }));
      gridCache = { key, grid };
    }
  } else gridCache = null;
  const colour = {};
  const crank = crankOf(m);
  if (crank) colour[crank.name] = "#1f5fbf";
  (ed.groups || []).forEach((gr, k) => gr.links.forEach((l) => { colour[l] = GROUP_COLOURS[k % GROUP_COLOURS.length]; }));
  // the paths every joint sweeps in the last answer
  if (state.answer && ed.answerOk) {
    for (const [name, p] of Object.entries(state.answer.points)) {
      if (name.startsWith("S_") || name.startsWith("cw") || (pt(name) && pt(name).ground)) continue;
      g.appendChild(s("polyline", { class: "draw-path", points: p.position_m.map((q) => `${q[0] + ed.offset[0]},${-(q[1] + ed.offset[1])}`).join(" "), "stroke-width": sw }));
    }
  }
  for (const b of m.blocks) {
    const jp = pt(b.point), host = b.slot && (m.links.find((l) => l.name === b.slot) || m.blocks.find((q) => q.name === b.slot));
    const gp = b.slot ? host && pt(host.points ? host.points[0] : host.point) : pt(b.through);
    if (!gp || !jp) continue;
    const deg = slideAngle(m, b), a = (deg * Math.PI) / 180;
    // a frame guide runs across the view; a slot is drawn along its link, a little past the block either way
    const L = b.slot ? Math.hypot(jp.x - gp.x, jp.y - gp.y) + 40 * sw : v.w;
    g.appendChild(s("line", { class: b.slot ? "slot" : "guide", x1: gp.x - Math.cos(a) * (b.slot ? 0 : L), y1: Y(gp.y - Math.sin(a) * (b.slot ? 0 : L)), x2: gp.x + Math.cos(a) * L, y2: Y(gp.y + Math.sin(a) * L),
      "stroke-width": b.slot ? 12 * sw : sw, "stroke-dasharray": b.slot ? null : `${8 * sw} ${3 * sw}` }));
    if (b.slot) {
      // the slot's own run the other way, for a block between the link's origin and its far side
      g.appendChild(s("line", { class: "slot", x1: gp.x, y1: Y(gp.y), x2: gp.x - Math.cos(a) * 40 * sw, y2: Y(gp.y - Math.sin(a) * 40 * sw), "stroke-width": 12 * sw }));
    }
    g.appendChild(s("rect", { class: "slider", dataset: { link: b.name }, x: jp.x - 16 * sw, y: Y(jp.y) - 9 * sw, width: 32 * sw, height: 18 * sw, "stroke-width": 2 * sw,
      transform: `rotate(${-deg} ${jp.x} ${Y(jp.y)})`, stroke: colour[b.name] || "#2d3e5c" }, s("title", {}, b.name)));
  }
  for (const l of m.links) {
    const ps = l.points.map(pt).filter(Boolean);
    const stroke = colour[l.name] || "#5b6575";
    const attrs = { class: ["draw-link", ed.selected === `link:${l.name}` && "selected"], dataset: { link: l.name }, stroke };
    if (ps.length === 2) g.appendChild(s("line", { ...attrs, x1: ps[0].x, y1: Y(ps[0].y), x2: ps[1].x, y2: Y(ps[1].y), "stroke-width": 6 * sw }, s("title", {}, l.name)));
    else g.appendChild(s("polygon", { ...attrs, points: ps.map((p) => `${p.x},${Y(p.y)}`).join(" "), "stroke-width": 5 * sw }, s("title", {}, l.name)));
  }
  // counterweights where they sit on their links, the disc's area as their mass
  const mechLinks = Object.fromEntries(((state.design && state.design.mechanism.links) || []).map((l) => [l.name, l]));
  const cws = (state.design && state.design.counterweights) || [];
  const heaviest = Math.max(1e-9, ...cws.map((cw) => cw.mass_kg));
  for (const cw of cws) {
    const l = mechLinks[cw.link], p0 = l && pt(l.joints[0]), p1 = l && l.joints[1] && pt(l.joints[1]);
    if (!p0) continue;
    const th = p1 ? Math.atan2(p1.y - p0.y, p1.x - p0.x) : 0, [u, w] = cw.position_m;
    const x = p0.x + Math.cos(th) * u - Math.sin(th) * w, y = p0.y + Math.sin(th) * u + Math.cos(th) * w;
    g.appendChild(s("line", { class: "draw-cw-arm", x1: p0.x, y1: Y(p0.y), x2: x, y2: Y(y), "stroke-width": 3 * sw }));
    g.appendChild(s("circle", { class: "draw-cw", cx: x, cy: Y(y), r: (6 + 8 * Math.sqrt(cw.mass_kg / heaviest)) * sw, "stroke-width": sw },
      s("title", {}, `counterweight ${cw.mass_kg.toPrecision(3)} kg on the ${cw.link}`)));
  }
  for (const p of m.points) {
    if (p.ground) g.appendChild(s("path", { class: "ground", d: `M${p.x},${Y(p.y)} l${-7 * sw},${12 * sw} h${14 * sw} z` }));
    const sel = ed.selected === `point:${p.name}` || ed.pending.includes(p.name);
    g.appendChild(s("circle", { class: ["draw-point", p.ground && "frame", sel && "selected"], dataset: { point: p.name }, cx: p.x, cy: Y(p.y), r: 5 * sw, "stroke-width": 2 * sw },
      s("title", {}, p.name)));
  }
  const tpos = tracePosition(m);
  if (tpos) {
    g.appendChild(s("path", { class: "draw-trace", d: `M${tpos[0]},${Y(tpos[1]) - 6 * sw} l${6 * sw},${6 * sw} l${-6 * sw},${6 * sw} l${-6 * sw},${-6 * sw} z`,
      fill: "#c25e00", "stroke-width": sw }, s("title", {}, `coupler point ${TRACE}`)));
  }
  ed.labels = placeLabels(m, crank, v, sw);
  for (const l of ed.labels) {
    g.appendChild(s("text", { class: l.cls, x: (l.box.x0 + l.box.x1) / 2, y: (l.box.y0 + l.box.y1) / 2, "text-anchor": "middle",
      "dominant-baseline": "central", "font-size": l.px * sw, dataset: { label: l.of } }, l.text));
  }
  // what is wrong, said at its place, in lines that stay on the canvas
  let row = 0;
  const right = v.x0 + v.w - 6 * sw, lineH = 10 * sw;
  for (const msg of ed.messages) {
    const p = msg.at && pt(msg.at);
    let x = p ? p.x + 10 * sw : v.x0 + 10 * sw;
    // beside its joint if a line of 40 characters or so fits there, else from the canvas's left edge
    if (right - x < 220 * sw) x = v.x0 + 10 * sw;
    const lines = wrapText(msg.text, 8, 600, (right - x) / sw);
    const y = p ? Y(p.y) + 18 * sw : Y(v.y0 + v.h) + 16 * sw + row * lineH;
    if (!p) row += lines.length + 0.5;
    g.appendChild(s("text", { class: ["draw-msg", msg.soft && "soft"], x, y, "font-size": 8 * sw },
      lines.map((ln, k) => s("tspan", { x, dy: k ? lineH : 0 }, ln))));
  }
  const grid = gridCache && gridCache.grid;
  if (grid && svg.firstChild === grid && svg.childNodes.length === 2) svg.replaceChild(g, svg.lastChild);
  else svg.replaceChildren(...(grid ? [grid] : []), g);
}

// --- labels ----------------------------------------------------------------------------------------------------------
// Each name goes where it covers no other name, no joint and no block and stays on the canvas: a joint's name in one of
// eight places round it, a link's off its middle on the side with room (or further along it), a plate's inside it or
// off one of its edges; of the places that cover nothing, the one crossing fewest other links. All in the canvas's
// own units (y down), the sizes in screen pixels times `sw`.
const measure = { ctx: null, family: "", widths: new Map() };
function textWidthPx(text, px, weight) {
  if (!measure.ctx) {
    measure.ctx = document.createElement("canvas").getContext("2d");
    measure.family = getComputedStyle(document.getElementById("draw-canvas")).fontFamily;
  }
  const font = `${weight} ${px}px ${measure.family}`, key = `${font}|${text}`;
  let w = measure.widths.get(key);
  if (w === undefined) { measure.ctx.font = font; w = measure.ctx.measureText(text).width; measure.widths.set(key, w); }
  return w;
}

/** A text broken at spaces into lines no wider than `maxPx` at `px` (a word wider than that on a line of its own). */
function wrapText(text, px, weight, maxPx) {
  const lines = [];
  let line = "";
  for (const word of String(text).split(" ")) {
    const next = line ? `${line} ${word}` : word;
    if (line && textWidthPx(next, px, weight) > maxPx) { lines.push(line); line = word; } else line = next;
  }
  if (line) lines.push(line);
  return lines;
}

const LINE_EM = 1.25;  // a text's box is about 1.2 em high (ascent and descent of the font)
const meets = (a, b) => a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
const grow = (b, d) => ({ x0: b.x0 - d, y0: b.y0 - d, x1: b.x1 + d, y1: b.y1 + d });

/** Whether the segment crosses the box (Liang–Barsky clipping). */
function cuts(box, [x1, y1, x2, y2]) {
  let t0 = 0, t1 = 1;
  const dx = x2 - x1, dy = y2 - y1;
  for (const [p, q] of [[-dx, x1 - box.x0], [dx, box.x1 - x1], [-dy, y1 - box.y0], [dy, box.y1 - y1]]) {
    if (p === 0) { if (q < 0) return false; continue; }
    const r = q / p;
    if (p < 0) { if (r > t1) return false; if (r > t0) t0 = r; } else { if (r < t0) return false; if (r < t1) t1 = r; }
  }
  return true;
}

function segDist([px, py], [x1, y1, x2, y2]) {
  const dx = x2 - x1, dy = y2 - y1, L2 = dx * dx + dy * dy;
  const t = L2 ? Math.max(0, Math.min(1, ((px - x1) * dx + (py - y1) * dy) / L2)) : 0;
  return Math.hypot(px - x1 - t * dx, py - y1 - t * dy);
}

/** Distance from a point to a link drawn through `ps`: zero inside a plate. */
function linkDist(q, ps) {
  if (ps.length > 2) {
    let inside = false;
    for (let i = 0, j = ps.length - 1; i < ps.length; j = i++) {
      if ((ps[i][1] > q[1]) !== (ps[j][1] > q[1]) && q[0] < ps[i][0] + ((q[1] - ps[i][1]) * (ps[j][0] - ps[i][0])) / (ps[j][1] - ps[i][1])) inside = !inside;
    }
    if (inside) return 0;
  }
  const ring = ps.length > 2 ? [...ps, ps[0]] : ps;
  let d = Infinity;
  for (let k = 0; k + 1 < ring.length; k++) d = Math.min(d, segDist(q, [...ring[k], ...ring[k + 1]]));
  return d;
}

function placeLabels(m, crank, v, sw) {
  const P = Object.fromEntries(m.points.map((p) => [p.name, [p.x, -p.y]]));
  const hard = [], segments = [];
  for (const p of m.points) {
    const [x, y] = P[p.name];
    hard.push({ x0: x - 7 * sw, y0: y - 7 * sw, x1: x + 7 * sw, y1: y + 7 * sw });
    if (p.ground) hard.push({ x0: x - 7 * sw, y0: y, x1: x + 7 * sw, y1: y + 12 * sw });
  }
  const blockBox = {};
  for (const b of m.blocks) {
    if (!P[b.point]) continue;
    const [x, y] = P[b.point], a = (slideAngle(m, b) * Math.PI) / 180, c = Math.abs(Math.cos(a)), sn = Math.abs(Math.sin(a));
    const hx = (16 * c + 9 * sn + 1) * sw, hy = (16 * sn + 9 * c + 1) * sw;
    blockBox[b.name] = { x0: x - hx, y0: y - hy, x1: x + hx, y1: y + hy };
    hard.push(blockBox[b.name]);
    // a frame guide runs across the canvas: a name is better off it
    const g = !b.slot && P[b.through];
    if (g) segments.push({ link: b.name, xy: [g[0] - Math.cos(a) * v.w, g[1] + Math.sin(a) * v.w, g[0] + Math.cos(a) * v.w, g[1] - Math.sin(a) * v.w] });
  }
  for (const l of m.links) {
    const ps = l.points.map((n) => P[n]).filter(Boolean);
    const ring = ps.length > 2 ? [...ps, ps[0]] : ps;
    for (let k = 0; k + 1 < ring.length; k++) segments.push({ link: l.name, xy: [...ring[k], ...ring[k + 1]] });
  }
  const inside = grow({ x0: v.x0, y0: -(v.y0 + v.h), x1: v.x0 + v.w, y1: -v.y0 }, -2 * sw);
  const mid = m.points.length ? [m.points.reduce((t, p) => t + p.x, 0) / m.points.length, -m.points.reduce((t, p) => t + p.y, 0) / m.points.length] : [0, 0];
  const placed = [];
  // a name nearer another joint (or link) than its own would be read as that one's
  const linkPts = m.links.map((l) => [l.name, l.points.map((n) => P[n]).filter(Boolean)]).filter(([, ps]) => ps.length > 1);
  const misread = (of, q) => {
    if (P[of] && m.points.some((p) => p.name === of)) {
      const own = Math.hypot(q[0] - P[of][0], q[1] - P[of][1]);
      return m.points.some((p) => p.name !== of && Math.hypot(q[0] - P[p.name][0], q[1] - P[p.name][1]) < own);
    }
    const mine = linkPts.find(([n]) => n === of);
    if (!mine) return false;
    const own = linkDist(q, mine[1]);
    return linkPts.some(([n, ps]) => n !== of && linkDist(q, ps) < own);
  };
  // how far a name sits from what it names: of two free places, the nearer
  const nearness = (of, q) => {
    const mine = linkPts.find(([n]) => n === of);
    return mine ? linkDist(q, mine[1]) : 0;
  };
  const put1 = (of, text, cls, px, weight, centres) => {
    const w = textWidthPx(text, px, weight) * sw, hh = px * LINE_EM * sw;
    let best = null;
    centres(w, hh).forEach(([cx, cy], k) => {
      const box = { x0: cx - w / 2, y0: cy - hh / 2, x1: cx + w / 2, y1: cy + hh / 2 };
      const out = box.x0 < inside.x0 || box.x1 > inside.x1 || box.y0 < inside.y0 || box.y1 > inside.y1;
      const covers = hard.reduce((t, o) => t + (meets(box, o) ? 1 : 0), 0);
      // a link is drawn 6 units wide: the box grown by half of that meets its edge
      const wide = grow(box, 3 * sw);
      const crossed = segments.reduce((t, sg) => t + (cuts(wide, sg.xy) ? 1 : 0), 0);
      let cost = (out ? 1e6 : 0) + covers * 1e4 + crossed * 10 + k * 1e-3;
      if (best && cost >= best.cost) return;  // the rest only adds
      cost += nearness(of, [cx, cy]) / sw / 20;
      if (best && cost >= best.cost) return;
      if (misread(of, [cx, cy])) cost += 30;
      if (!best || cost < best.cost) best = { cost, box };
    });
    if (!best) return;
    hard.push(grow(best.box, 2 * sw));
    placed.push({ of, text, cls, px, box: best.box });
  };
  // a joint's name: NE first (as it always was), then round the joint
  const DIRS = [[1, -1], [-1, -1], [1, 1], [-1, 1], [1, 0], [-1, 0], [0, -1], [0, 1]];
  for (const p of m.points) {
    const [x, y] = P[p.name], r = 8 * sw;
    put1(p.name, p.name, "draw-point-name", 13, 600, (w, hh) => DIRS.map(([dx, dy]) => [x + dx * (r + w / 2), y + dy * (r + hh / 2)]));
  }
  // a link's name off its middle, then a third and a fifth of the way from either end, first on the side away from
  // the linkage's middle, then further off
  const ALONG = [0.5, 0.35, 0.65, 0.2, 0.8];
  const off = (a, b, away, w, hh) => {
    const L = Math.hypot(b[0] - a[0], b[1] - a[1]) || 1, n = [-(b[1] - a[1]) / L, (b[0] - a[0]) / L];
    const c = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
    const side = (c[0] - away[0]) * n[0] + (c[1] - away[1]) * n[1] >= 0 ? 1 : -1;
    const ext = (w / 2) * Math.abs(n[0]) + (hh / 2) * Math.abs(n[1]) + 6 * sw;
    const out = [];
    for (const gap of [0, 10 * sw, 24 * sw, 44 * sw]) for (const t of ALONG) for (const sd of [side, -side]) {
      out.push([a[0] + t * (b[0] - a[0]) + sd * n[0] * (ext + gap), a[1] + t * (b[1] - a[1]) + sd * n[1] * (ext + gap)]);
    }
    return out;
  };
  const output = outputOf(m, crank);
  for (const l of m.links) {
    const ps = l.points.map((n) => P[n]).filter(Boolean);
    if (ps.length < 2) continue;
    const role = l.name === (crank && crank.name) ? " (crank)" : l.name === output ? " (output)" : "";
    const c = [ps.reduce((t, p) => t + p[0], 0) / ps.length, ps.reduce((t, p) => t + p[1], 0) / ps.length];
    // and if none of those is free (a short link hemmed in by its neighbours or the canvas's edge): anywhere round
    // its middle, nearer first
    const round = (w, hh) => [1, 1.6, 2.4, 3.4].flatMap((f) => [...Array(16).keys()].map((k) => {
      const a = (k * Math.PI) / 8;
      return [c[0] + Math.cos(a) * f * (w / 2 + 8 * sw), c[1] + Math.sin(a) * f * (hh / 2 + 8 * sw)];
    }));
    put1(l.name, l.name + role, "draw-link-name", 11, 400, (w, hh) => [...(ps.length === 2 ? off(ps[0], ps[1], mid, w, hh)
      : [c, ...ps.map((p) => [(c[0] + p[0]) / 2, (c[1] + p[1]) / 2]),
        ...ps.flatMap((p, k) => off(p, ps[(k + 1) % ps.length], c, w, hh).filter((_, j) => j % 2 === 0))]), ...round(w, hh)]);
  }
  for (const b of m.blocks) {
    const bb = blockBox[b.name];
    if (!bb || b.name !== output) continue;
    const cy = (bb.y0 + bb.y1) / 2, cx = (bb.x0 + bb.x1) / 2, gap = 4 * sw;
    put1(b.name, `${b.name} (output)`, "draw-link-name", 11, 400, (w, hh) => [[bb.x1 + gap + w / 2, cy], [bb.x0 - gap - w / 2, cy],
      [cx, bb.y0 - gap - hh / 2], [cx, bb.y1 + gap + hh / 2], [bb.x1 + gap + w / 2, bb.y0 - hh / 2], [bb.x1 + gap + w / 2, bb.y1 + hh / 2],
      [bb.x0 - gap - w / 2, bb.y0 - hh / 2], [bb.x0 - gap - w / 2, bb.y1 + hh / 2]]);
  }
  return placed;
}

/** Where each name on the canvas was placed, in screen pixels: for tests that check no two cover each other. */
export function labelBoxes() {
  const svg = document.getElementById("draw-canvas"), M = svg.getScreenCTM();
  const at = (x, y) => { const p = svg.createSVGPoint(); p.x = x; p.y = y; const q = p.matrixTransform(M); return [q.x, q.y]; };
  return (ed.labels || []).map((l) => {
    const [x0, y0] = at(l.box.x0, l.box.y0), [x1, y1] = at(l.box.x1, l.box.y1);
    return { of: l.of, text: l.text, left: x0, top: y0, right: x1, bottom: y1 };
  });
}

function num(v) { return String(Number((v / factor("length")).toPrecision(8))); }

function renderSide() {
  const side = document.getElementById("draw-side");
  const m = ed.model, c = lastChecked || check(m), u = state.units.length;
  const focused = document.activeElement && side.contains(document.activeElement) ? document.activeElement.id : null;
  const W = h("p", { id: "draw-mobility", class: ["mobility", c.W > 1 && "bad", c.W < 1 && "soft"] }, `W = 3n − 2p = 3·${c.n} − 2·${c.p} = ${c.W}`);
  const groups = ed.groups ? h("p", { class: "groups" }, ed.groups.length ? `Assur groups: ${ed.groups.map((g2) => `${g2.group_class} (${g2.links.join(", ")})`).join("; ")}` : "") : null;
  const msgs = h("ul", { id: "draw-messages", class: "draw-messages", role: "alert" }, ed.messages.map((p) => h("li", { class: p.soft ? "soft" : null }, p.text)));
  const pointRows = m.points.map((p) => h("tr", { class: ed.selected === `point:${p.name}` ? "selected" : null },
    h("td", {}, p.name), h("td", {}, p.ground ? "frame" : "joint"),
    h("td", {}, h("input", { id: `dp-${p.name}-x`, "aria-label": `${p.name} x [${u}]`, value: num(p.x), dataset: { point: p.name, axis: "x" }, inputmode: "decimal" })),
    h("td", {}, h("input", { id: `dp-${p.name}-y`, "aria-label": `${p.name} y [${u}]`, value: num(p.y), dataset: { point: p.name, axis: "y" }, inputmode: "decimal" }))));
  const linkRows = m.links.map((l) => {
    const [a, b] = l.points.map(pt);
    const L = Math.hypot(b.x - a.x, b.y - a.y);
    return h("tr", {}, h("td", {}, l.name), h("td", {}, l.points.join("-")),
      h("td", {}, h("input", { id: `dl-${l.name}`, "aria-label": `${l.name} length ${l.points[0]}-${l.points[1]} [${u}]`, value: num(L), dataset: { link: l.name } })));
  });
  const blockRows = m.blocks.map((b) => h("tr", {}, h("td", {}, b.name), h("td", {}, b.slot ? `${b.point} in ${b.slot}` : `${b.point} on ${b.through}`),
    h("td", {}, h("input", { id: `db-${b.name}`, "aria-label": b.slot ? `${b.name} slot axis in ${b.slot}'s frame [°]` : `${b.name} guide axis [°]`, value: String(b.axis_deg), dataset: { block: b.name } }), "°")));
  put(side,
    h("div", { class: "draw-tools", role: "radiogroup", "aria-label": "Drawing tool" }, TOOLS.map(([id, key, label]) =>
      h("button", { type: "button", role: "radio", "aria-checked": String(ed.tool === id), dataset: { tool: id }, title: `${label} (${key})`, id: `tool-${id}` }, `${label.split(" ")[0]} ${key}`))),
    h("div", { class: "draw-actions" },
      h("button", { type: "button", id: "draw-undo", disabled: !ed.undo.length, title: "Undo (Ctrl+Z)" }, "Undo"),
      h("button", { type: "button", id: "draw-redo", disabled: !ed.redo.length, title: "Redo (Ctrl+Y)" }, "Redo"),
      h("button", { type: "button", id: "draw-zoom-in", title: "Zoom in (+; the wheel zooms about the pointer)" }, "+"),
      h("button", { type: "button", id: "draw-zoom-out", title: "Zoom out (−)" }, "−"),
      h("button", { type: "button", id: "draw-fit", title: "Zoom to fit the linkage and its paths (0); drag the empty canvas to pan" }, "Fit"),
      h("button", { type: "button", id: "draw-invert", disabled: !(ed.selected || "").startsWith("link:"),
        title: "Kinematic inversion: the selected link becomes the frame, the frame a link" }, "Make it the frame"),
      h("label", {}, "Grid ", h("select", { id: "draw-grid" }, GRID[u].map((g2) => h("option", { value: String(g2), selected: Math.abs(g2 - ed.grid) < 1e-12 }, `${num(g2)} ${u}`)))),
      h("label", {}, "Template ", h("select", { id: "draw-template" }, h("option", { value: "" }, "—"), Object.entries(TEMPLATES).map(([k, t]) => h("option", { value: k }, t.label))))),
    W, groups, msgs,
    h("table", { class: "draw-table", id: "draw-points" }, h("tr", {}, h("th", {}, "Point"), h("th", {}, ""), h("th", {}, `x [${u}]`), h("th", {}, `y [${u}]`)), pointRows),
    h("table", { class: "draw-table", id: "draw-links" }, h("tr", {}, h("th", {}, "Link"), h("th", {}, "points"), h("th", {}, `length [${u}]`)), linkRows, blockRows));
  if (focused && document.getElementById(focused)) document.getElementById(focused).focus();
}

// --- input --------------------------------------------------------------------------------------------------------------
function toModel(svg, evt) {
  const p = svg.createSVGPoint();
  p.x = evt.clientX; p.y = evt.clientY;
  const q = p.matrixTransform(svg.getScreenCTM().inverse());
  return [q.x, -q.y];
}

function hitPoint(svg, evt) {
  const name = evt.target.dataset && evt.target.dataset.point;
  if (name) return name;
  const [x, y] = toModel(svg, evt), r = (ed.view.w / 600) * 9;
  const near = ed.model.points.map((p) => [Math.hypot(p.x - x, p.y - y), p.name]).sort((a, b) => a[0] - b[0])[0];
  return near && near[0] < r ? near[1] : null;
}

function place(xy, ground) {
  const name = nextName(ground);
  change((m) => { m.points.push({ name, x: xy[0], y: xy[1], ground }); }, { topology: true });
  return name;
}

// --- the view: zoom to fit, zoom about a point, pan ----------------------------------------------------------------------
/** The whole linkage and the paths of its joints in view. */
export function fitView() {
  ed.view = viewFor(ed.model);
  ed.userView = false;
  render();
}

/** Zoom by `k` (below 1: in) about a model point [m] that stays where it is on the screen (default: the middle). */
export function zoom(k, about = null) {
  const v = ed.view, [cx, cy] = about || [v.x0 + v.w / 2, v.y0 + v.h / 2];
  ed.view = { x0: cx - (cx - v.x0) * k, y0: cy - (cy - v.y0) * k, w: v.w * k, h: v.h * k };
  ed.userView = true;
  render();
}

function onWheel(e) {
  if (!ed.on || !ed.view) return;
  e.preventDefault();
  zoom(e.deltaY > 0 ? 1.2 : 1 / 1.2, toModel(e.currentTarget, e));
}

/** The link frame of a drawn link as the request writes it: origin at its first point (a crank's on the frame), x
 *  toward its second. */
function frameOf(m, l) {
  let names = [...l.points];
  const crank = crankOf(m);
  if (crank && l.name === crank.name) {
    const g = names.find((n) => pt(n).ground);
    names = [g, ...names.filter((n) => n !== g)];
  }
  const a = pt(names[0]), b = pt(names[1]);
  return { origin: [a.x, a.y], angle: Math.atan2(b.y - a.y, b.x - a.x) };
}

/** Where the coupler point sits on the drawing [m], from its link's points as drawn. */
function tracePosition(m) {
  const tp = ((state.design && state.design.trace_points) || []).find((q) => q.name === TRACE);
  const l = tp && m.links.find((q) => q.name === tp.link);
  if (!l) return null;
  const { origin: [x, y], angle } = frameOf(m, l), [u, w] = tp.position_m;
  return [x + Math.cos(angle) * u - Math.sin(angle) * w, y + Math.sin(angle) * u + Math.cos(angle) * w];
}

/** Put the coupler point on a drawn link where the pointer is (one coupler point: a new one replaces it). */
function placeTrace(linkName, [x, y]) {
  const l = ed.model.links.find((q) => q.name === linkName);
  if (!l) return;
  const { origin: [ox, oy], angle } = frameOf(ed.model, l), dx = x - ox, dy = y - oy;
  const local = [Math.cos(angle) * dx + Math.sin(angle) * dy, -Math.sin(angle) * dx + Math.cos(angle) * dy];
  change(() => { state.design.trace_points = [{ name: TRACE, link: linkName, position_m: local.map((c) => Number(c.toPrecision(12))) }]; }, { topology: false });
}

/** The nearest drawn link to a model point within a few pixels, by name. */
function nearestLink(xy) {
  const r = (ed.view.w / 600) * 8;
  let best = null;
  for (const l of ed.model.links) {
    const d = linkDist(xy, l.points.map((n) => [pt(n).x, pt(n).y]));
    if (d <= r && (!best || d < best[0])) best = [d, l.name];
  }
  return best && best[1];
}

/** Kinematic inversion: the link `name` becomes the frame and the frame a link (its points one body). */
export function invert(name) {
  const m = ed.model, L = m.links.find((l) => l.name === name);
  const ground = m.points.filter((p) => p.ground).map((p) => p.name);
  let why = null;
  if (!L) why = "select a drawn link (Move, click on it) to make it the frame";
  else if (m.blocks.length) why = "an inversion here takes pin-jointed links only: this drawing has blocks";
  else if (ground.length < 2) why = "the frame has fewer than two points: it cannot become a link";
  if (why) { ed.messages = [...ed.messages, { text: why }]; render(); return false; }
  change((mm) => {
    for (const p of mm.points) p.ground = L.points.includes(p.name);
    mm.links = mm.links.filter((l) => l.name !== name);
    mm.links.push({ name: nextLinkName("L"), points: ground });
    // the crank and output are chosen again among the links on the new frame; the branches read off the drawing
    mm.crank = null; mm.output = null; mm.branches = {};
  });
  ed.selected = null;
  return true;
}

function onPointerDown(e) {
  const svg = e.currentTarget;
  svg.focus();
  const hit = hitPoint(svg, e), link = e.target.dataset && e.target.dataset.link;
  const xy = snapXY(toModel(svg, e), e.altKey);
  ed.lastPress = toModel(svg, e);
  ed.presses += 1;
  svg.dataset.presses = String(ed.presses);
  // the middle button, or the Move tool on empty canvas: the view is dragged
  if (e.button === 1 || (ed.tool === "move" && !hit && !link)) {
    ed.panning = { x: e.clientX, y: e.clientY, view: { ...ed.view }, scale: ed.view.w / svg.getBoundingClientRect().width };
    if (ed.selected) { ed.selected = null; render(); }
    svg.setPointerCapture(e.pointerId);
    e.preventDefault();
    return;
  }
  const t = ed.tool;
  if (t === "move") {
    if (hit) {
      ed.selected = `point:${hit}`;
      ed.undo.push(snapshot()); ed.redo = [];
      ed.dragging = { name: hit, moved: false };
      svg.setPointerCapture(e.pointerId);
      render();
    } else if (link) { ed.selected = `link:${link}`; render(); }
  } else if (t === "frame" || t === "joint") {
    if (hit) { ed.selected = `point:${hit}`; render(); } else place(xy, t === "frame");
  } else if (t === "bar" || t === "plate") {
    // Shift: the point on the grid, its link any length; Alt: anywhere
    const from = t === "bar" && ed.pending.length ? pt(ed.pending[0]) : null;
    const name = hit || place(from && !e.shiftKey && !e.altKey ? snapLength(from, xy) : xy, false);
    if (!ed.pending.includes(name)) ed.pending.push(name);
    if (ed.pending.length === (t === "bar" ? 2 : 3)) {
      const points = ed.pending; ed.pending = [];
      change((m) => { m.links.push({ name: nextLinkName("L"), points }); });
    } else render();
  } else if (t === "slide") {
    if (!hit && link && ed.pending.length === 1 && !pt(ed.pending[0]).ground && !bodiesAt(ed.model, ed.pending[0]).includes(link)) {
      // a joint, then a moving link: a block at the joint in a slot of that link, along it (a block's: across it)
      const j = ed.pending[0], host = ed.model.blocks.find((b) => b.name === link);
      ed.pending = []; ed.problem = null;
      change((m) => { m.blocks.push({ name: nextLinkName("block"), point: j, slot: link, axis_deg: host ? 90 : 0 }); });
      e.preventDefault();
      return;
    }
    if (!hit) return;
    ed.pending.push(hit);
    if (ed.pending.length === 2) {
      const [j, gname] = ed.pending; ed.pending = [];
      const jp = pt(j), gp = pt(gname);
      if (jp.ground || !gp.ground) { ed.problem = "a block: click its joint first, then the frame point its guide runs through or the link its slot is in"; render(); return; }
      ed.problem = null;
      const d = Math.hypot(jp.x - gp.x, jp.y - gp.y);
      const axis = d > 1e-12 ? Math.round(((Math.atan2(jp.y - gp.y, jp.x - gp.x) * 180) / Math.PI) / 15) * 15 : 0;
      change((m) => { m.blocks.push({ name: nextLinkName("block"), point: j, through: gname, axis_deg: ((axis % 360) + 360) % 360 }); });
    } else render();
  } else if (t === "point") {
    const on = (link && ed.model.links.some((l) => l.name === link) && link) || nearestLink(toModel(svg, e));
    if (on) placeTrace(on, toModel(svg, e));
  } else if (t === "crank" || t === "output") {
    const name = link || (hit && bodiesAt(ed.model, hit)[0]);
    if (name) change((m) => { m[t] = name; });
  } else if (t === "delete") {
    if (hit) deletePoint(hit); else if (link) deleteLink(link);
  }
  e.preventDefault();
}

// A drag keeps at most one analysis in flight: the joint follows the pointer at once, and the position it has when
// the answer comes is the next one sent, before that answer is drawn (the moves in between are never asked for, so
// none is thrown away: aborting a request in flight for a newer move leaves the service computing it all the same).
function onPointerMove(e) {
  if (ed.panning) {
    const p = ed.panning, v = p.view;
    ed.view = { ...v, x0: v.x0 - (e.clientX - p.x) * p.scale, y0: v.y0 + (e.clientY - p.y) * p.scale };
    ed.userView = true;
    drawCanvas();
    return;
  }
  if (!ed.dragging) return;
  const t0 = performance.now();
  const d = ed.dragging, [x, y] = snapXY(toModel(e.currentTarget, e), e.altKey);
  const p = pt(d.name);
  if (p.x === x && p.y === y) return;
  p.x = x; p.y = y; d.moved = true;
  state.dragging = true;
  if (d.since === undefined) d.since = t0;  // the oldest move not yet analysed: the latency is counted from it
  if (state.pending) { d.queued = true; drawCanvas(); updateSide(); return; }
  sendDrag();
}

function sendDrag(draw = true) {
  const d = ed.dragging;
  if (!d || d.since === undefined) return;
  const t0 = d.since;
  d.since = undefined; d.queued = false;
  commit(t0, { draw });
}

function onPointerUp() {
  if (ed.panning) { ed.panning = null; render(); return; }
  if (!ed.dragging) return;
  const moved = ed.dragging.moved;
  ed.dragging = null;
  state.dragging = false;
  if (!moved) { ed.undo.pop(); return; }
  ed.fit = 4;
  // the view follows the linkage, unless the user has zoomed or panned it
  if (!ed.userView) ed.view = viewFor(ed.model);
  commit();
}

function onKey(e) {
  if (!ed.on) return;
  const inField = ["INPUT", "TEXTAREA", "SELECT"].includes(e.target.tagName);
  const mod = e.ctrlKey || e.metaKey;
  if (mod && !inField && (e.key === "z" || e.key === "Z") && !e.shiftKey) { undo(); e.preventDefault(); return; }
  if (mod && !inField && (e.key === "y" || ((e.key === "z" || e.key === "Z") && e.shiftKey))) { redo(); e.preventDefault(); return; }
  if (inField || mod || e.altKey) return;
  const tool = TOOLS.find(([, k]) => k === e.key.toUpperCase());
  if (tool) { setTool(tool[0]); e.preventDefault(); return; }
  if (e.key === "Escape") { ed.pending = []; ed.selected = null; render(); return; }
  if (e.key === "+" || e.key === "=") { zoom(1 / 1.25); e.preventDefault(); return; }
  if (e.key === "-") { zoom(1.25); e.preventDefault(); return; }
  if (e.key === "0") { fitView(); e.preventDefault(); return; }
  if ((e.key === "Delete" || e.key === "Backspace") && ed.selected) {
    const [kind, name] = ed.selected.split(":");
    ed.selected = null;
    if (kind === "point") deletePoint(name); else deleteLink(name);
    e.preventDefault();
    return;
  }
  const arrows = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, 1], ArrowDown: [0, -1] };
  if (arrows[e.key] && ed.selected && ed.selected.startsWith("point:")) {
    const name = ed.selected.slice(6), [dx, dy] = arrows[e.key];
    change((m) => { const p = m.points.find((q) => q.name === name); [p.x, p.y] = snapXY([p.x + dx * ed.grid, p.y + dy * ed.grid]); });
    e.preventDefault();
  }
}

function setTool(id) { ed.tool = id; ed.pending = []; render(); }

function onSideChange(e) {
  const el = e.target;
  if (el.id === "draw-grid") { ed.grid = Number(el.value); render(); return; }
  if (el.id === "draw-template") { if (el.value) openTemplate(el.value); return; }
  const v = Number(el.value.trim().replace(",", "."));
  if (!Number.isFinite(v)) { el.setAttribute("aria-invalid", "true"); return; }
  el.removeAttribute("aria-invalid");
  if (el.dataset.point) change((m) => { m.points.find((p) => p.name === el.dataset.point)[el.dataset.axis] = v * factor("length"); });
  else if (el.dataset.link) {
    // a length typed: the link's second point moves along the link (its first, if the second is on the frame)
    change((m) => {
      const l = m.links.find((q) => q.name === el.dataset.link);
      let [a, b] = l.points.map((n) => m.points.find((p) => p.name === n));
      if (b.ground) [a, b] = [b, a];
      const L = Math.hypot(b.x - a.x, b.y - a.y) || 1, want = v * factor("length");
      b.x = a.x + ((b.x - a.x) * want) / L; b.y = a.y + ((b.y - a.y) * want) / L;
    });
  } else if (el.dataset.block) change((m) => { m.blocks.find((b) => b.name === el.dataset.block).axis_deg = v; });
}

function onSideClick(e) {
  const b = e.target.closest("button");
  if (!b) return;
  if (b.dataset.tool) setTool(b.dataset.tool);
  else if (b.id === "draw-undo") undo();
  else if (b.id === "draw-redo") redo();
  else if (b.id === "draw-zoom-in") zoom(1 / 1.25);
  else if (b.id === "draw-zoom-out") zoom(1.25);
  else if (b.id === "draw-fit") fitView();
  else if (b.id === "draw-invert") invert((ed.selected || "").slice(5));
}

export function openTemplate(key) {
  const t = TEMPLATES[key];
  ed.undo.push(snapshot()); ed.redo = [];
  ed.model = clone(t.model);
  ed.fit = 4;
  ed.view = null;
  ed.structureKey = "";
  if (t.loads) state.design.loads = clone(t.loads); else delete state.design.loads;
  // the last answer is of another linkage: its paths are no part of this one's view, until its own answer comes
  ed.answerOk = false;
  ed.view = viewFor(ed.model);
  ed.refit = true;
  return commit();
}

// --- on and off ----------------------------------------------------------------------------------------------------------
function emptyModel() { return { points: [], links: [], blocks: [], crank: null, output: null, branches: {} }; }

export function setEditing(on) {
  ed.on = on;
  document.body.dataset.drawing = on ? "1" : "";
  document.getElementById("draw-toggle").setAttribute("aria-pressed", String(on));
  // SVG elements have no `hidden` property: the attribute itself
  document.getElementById("draw-canvas").toggleAttribute("hidden", !on);
  document.getElementById("drawing").toggleAttribute("hidden", on);
  document.getElementById("draw-side").hidden = !on;
  if (!on) return;
  const imported = state.answer && fromAnswer(state.design, state.answer, state.index);
  ed.model = imported || emptyModel();
  ed.undo = []; ed.redo = []; ed.pending = []; ed.structureKey = "";
  ed.answerOk = Boolean(imported) && state.design.mechanism.type === "linkage";
  // a family's assembly branch becomes the drawing's: read off the points as they were drawn
  if (imported && state.design.mechanism.type !== "linkage") ed.fit = 4;
  ed.offset = [0, 0];
  ed.view = viewFor(ed.model);
  ed.refit = true;
  if (imported) commit(); else render();
}

/** Start over with an empty canvas (the chain drawn from nothing). */
export function clearDrawing() {
  ed.undo.push(snapshot()); ed.redo = [];
  ed.model = emptyModel();
  // a new linkage: the loads, counterweights and the rest of the one before are not its own (an undo keeps them);
  // nor are the paths its joints swept
  for (const k of BY_NAME) delete state.design[k];
  ed.answerOk = false;
  // drawn from nothing: the canvas stays where it is while the points go down (Fit zooms to them on demand)
  ed.refit = false;
  // room for a linkage a metre across, in the canvas's proportions
  const b = document.getElementById("draw-canvas").getBoundingClientRect(), aspect = b.width / Math.max(b.height, 1) || 2.4;
  const w = Math.max(1.6, 1.5 * aspect);
  ed.view = { x0: -0.25, y0: -0.3, w, h: w / aspect };
  ed.groups = null; ed.structureKey = "";
  return commit();
}

/** Screen position of a model point [m], for tests and the bench that click the canvas. */
export function toScreen(x, y) {
  const svg = document.getElementById("draw-canvas");
  const p = svg.createSVGPoint();
  p.x = x; p.y = -y;
  const q = p.matrixTransform(svg.getScreenCTM());
  return [q.x, q.y];
}

function install() {
  const fig = document.getElementById("drawing-box");
  const canvas = s("svg", { id: "draw-canvas", tabindex: "0", role: "application", "aria-label": "Drawing canvas: tools by letter (V move, F frame point, J joint, B binary link, T ternary link, S block, C crank, O output, X delete), a link's far end snaps to a length in whole grid steps (Shift: any length, Alt: off the grid), arrows move the selected point, Ctrl+Z undo, Ctrl+Y redo", hidden: true });
  fig.insertBefore(canvas, document.getElementById("drawing").nextSibling);
  const side = h("section", { id: "draw-side", class: "draw-side", "aria-label": "Drawing: points and links", hidden: true });
  const aside = document.getElementById("editor");
  aside.insertBefore(side, aside.querySelector(".units").nextSibling);
  const toggle = h("button", { id: "draw-toggle", type: "button", "aria-pressed": "false", title: "Draw and edit the linkage on the canvas" }, "Draw");
  const clear = h("button", { id: "draw-new", type: "button", title: "An empty canvas to draw a linkage from nothing" }, "New drawing");
  const cap = fig.querySelector("figcaption");
  cap.insertBefore(clear, cap.firstChild);
  cap.insertBefore(toggle, cap.firstChild);
  toggle.addEventListener("click", () => setEditing(!ed.on));
  clear.addEventListener("click", () => { if (!ed.on) setEditing(true); clearDrawing(); });
  canvas.addEventListener("pointerdown", onPointerDown);
  canvas.addEventListener("pointermove", onPointerMove);
  canvas.addEventListener("pointerup", onPointerUp);
  canvas.addEventListener("pointercancel", onPointerUp);
  canvas.addEventListener("wheel", onWheel, { passive: false });
  document.addEventListener("keydown", onKey);
  side.addEventListener("change", onSideChange);
  side.addEventListener("click", onSideClick);
  // the answer's own drawing first (the rest of analyse runs before a microtask), then the drag's latest position
  // an answer arrived: the drag's latest position is sent before the answer is drawn (its drawing redraws the canvas)
  state.hooks.received.push(() => { if (ed.early && ed.dragging && ed.dragging.queued) sendDrag(false); });
  const sendQueued = () => { if (ed.dragging && ed.dragging.queued) queueMicrotask(sendDrag); };
  state.hooks.answer.push(sendQueued);
  state.hooks.problem.push(sendQueued);
  state.hooks.answer.push((answer) => {
    if (!ed.on) return;
    ed.problem = null;
    // the drawing's own linkage (a dragged joint may have moved on since it was sent)
    const mine = JSON.stringify(state.design.mechanism) === ed.committed;
    if (!mine) {
      // the JSON box or a panel changed the linkage: the drawing follows it
      const m = fromAnswer(state.design, answer, state.index);
      if (m) { ed.model = m; ed.offset = [0, 0]; ed.view = viewFor(m); }
    }
    ed.answerOk = true;
    // a drawing opened, a template or a new drawing: zoomed to fit once its first answer (and the paths its joints
    // sweep) is in
    if (ed.refit && !ed.dragging) { ed.refit = false; ed.userView = false; ed.view = viewFor(ed.model); }
    settle(answer);
  });
  state.hooks.problem.push((err) => {
    if (!ed.on) return;
    const body = err instanceof Problem ? err.body : { detail: String(err.message || err) };
    ed.answerOk = false;
    ed.problem = body.not_assemblable_ranges_deg
      ? `${body.detail || "a dyad cannot close"}: no assembly for crank angles ${body.not_assemblable_ranges_deg.map(([a, b]) => `${Number(a).toFixed(1)}°–${Number(b).toFixed(1)}°`).join(", ")}`
      : body.detail || body.title;
    ed.messages = [...(lastChecked ? lastChecked.problems : []), { at: placeOf(body), text: ed.problem }];
    // the note above the canvas says what the service said, not that the form holds an error
    markStale(ed.problem);
    render();
  });
  window.workbench.editor = { ed, setEditing, openTemplate, toScreen, labelBoxes, clearDrawing, toMechanism, undo, redo, familyExample: defaultMechanism,
    fitView, zoom, invert };
  document.body.dataset.editorReady = "1";
}

/** After an answer (and the structure it needs): fit the branches, or say the drawing is settled. */
function settle(answer) {
  if (ed.fit && !ed.groups && !ed.dragging) return;  // the structure's answer calls again
  if (fitBranches(answer)) return;
  if (!ed.dragging && !ed.fit) document.body.dataset.editorFit = String(state.seq);
  render();
}

/** The point a problem of the service is about, from the link or joint its field or text names. */
function placeOf(body) {
  const f = String(body.field || "") + " " + String(body.detail || "");
  for (const l of ed.model.links) if (f.includes(`'${l.name}'`) || f.includes(`links.${l.name}`)) return l.points[l.points.length - 1];
  for (const b of ed.model.blocks) if (f.includes(`'${b.name}'`) || f.includes(`links.${b.name}`)) return b.point;
  return null;
}

function whenReady() {
  if (document.body.dataset.ready === "1" && window.workbench) install();
  else setTimeout(whenReady, 50);
}
whenReady();
