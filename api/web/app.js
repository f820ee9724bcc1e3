// The workbench: the mechanism editor, its drawing and its diagrams; the other panels live in panels.js.
import { loadOpenApi, describe, post, Problem } from "./api.js";
import { linePlot, polarPlot, fmt } from "./plot.js";
import { layout, drawLinkage, toModel } from "./draw.js";
import { installPanels } from "./panels.js";
import { h } from "./dom.js";
import { installExports, vectorsAt } from "./exports.js";
import { admitted } from "./signin.js";

const UNITS = { length: { mm: 1e-3, m: 1 }, mass: { g: 1e-3, kg: 1 } };
const LINK_LABELS = {
  fourbar: { crank: "Crank O-A", coupler: "Coupler A-B", rocker: "Rocker Q-B" },
  slider_crank: { crank: "Crank O-A", rod: "Rod A-B", slider: "Slider B" },
  slotted_lever: { crank: "Crank O-A", slider: "Block A", rocker: "Lever O1-B", ram_slider: "Block B", ram: "Ram R" },
};
const GEOMETRY = {
  fourbar: [["ground_length_m", "Frame O-Q"], ["crank_length_m", "Crank O-A"], ["coupler_length_m", "Coupler A-B"],
    ["rocker_length_m", "Rocker Q-B"], ["branch", "Assembly branch"]],
  slider_crank: [["crank_length_m", "Crank O-A"], ["rod_length_m", "Rod A-B"], ["offset_m", "Slider offset"],
    ["branch", "Assembly branch"]],
  slotted_lever: [["crank_length_m", "Crank O-A"], ["ground_length_m", "Pivots O-O1"], ["rocker_length_m", "Lever O1-B"],
    ["ram_height_m", "Ram guide above O1"]],
};
// The link a coupler point rides on, per family; the shaper has none.
const COUPLER = { fourbar: "coupler", slider_crank: "rod" };
const TRACE = "P";

export const state = {
  design: null, units: { length: "mm", mass: "kg" }, answer: null, layout: null, index: 0, fields: [],
  timings: [], seq: 0, pending: null, plots: [], targets: [], openapi: null,
  // other modules' reactions to each answer and each refusal (the drawing editor)
  hooks: { answer: [], problem: [], received: [] },
};

// --- paths into the request --------------------------------------------------------------------------------------
export function getPath(obj, path) {
  return path.split(".").reduce((o, k) => (o === undefined || o === null ? undefined : o[k]), obj);
}

export function setPath(obj, path, value) {
  const parts = path.split(".");
  let o = obj;
  parts.slice(0, -1).forEach((k, n) => {
    if (o[k] === undefined || o[k] === null) o[k] = /^\d+$/.test(parts[n + 1]) ? [] : {};
    o = o[k];
  });
  const last = parts[parts.length - 1];
  if (value === undefined) { if (Array.isArray(o)) o.splice(Number(last), 1); else delete o[last]; } else o[last] = value;
}

function kindOf(path) {
  if (/_m(\.\d)?$/.test(path) || /position_m\.\d$|com_m\.\d$/.test(path)) return "length";
  if (/_kg$/.test(path)) return "mass";
  return "plain";
}

export function factor(kind) {
  if (kind === "length") return UNITS.length[state.units.length];
  if (kind === "mass") return UNITS.mass[state.units.mass];
  return 1;
}

export function unitLabel(kind, si) {
  if (kind === "length") return state.units.length;
  if (kind === "mass") return state.units.mass;
  return si;
}

export function toDisplay(v, kind) {
  if (v === undefined || v === null || v === "") return "";
  return String(Number((v / factor(kind)).toPrecision(10)));
}

// --- the form ----------------------------------------------------------------------------------------------------
function fieldSpecs(design) {
  const fam = design.mechanism.type;
  const specs = [{ group: "Geometry" }];
  if (!GEOMETRY[fam]) {
    // a family the form has no layout for (the engine grows): its mechanism as JSON, described by the manual
    specs.push({ path: "mechanism", label: `${fam} (JSON)`, json: true });
    specs.push({ group: "Operation" });
    specs.push({ path: "speed_rpm", label: "Crank speed" });
    specs.push({ path: "samples", label: "Samples per cycle" });
    specs.push({ path: "gravity.g_m_s2", label: "Gravity (empty: off)", optional: true });
    return specs;
  }
  for (const [name, label] of GEOMETRY[fam]) {
    specs.push(name === "branch"
      ? { path: "mechanism.branch", label, options: [["1", "+1"], ["-1", "-1"]] }
      : { path: `mechanism.${name}`, label });
  }
  for (const [link, label] of Object.entries(LINK_LABELS[fam])) {
    specs.push({ group: label });
    const base = `mechanism.links.${link}`;
    specs.push({ path: `${base}.mass_kg`, label: "Mass" });
    specs.push({ path: `${base}.com_m.0`, label: "Centre of mass x", schemaPath: `${base}.com_m` });
    specs.push({ path: `${base}.com_m.1`, label: "Centre of mass y", schemaPath: `${base}.com_m` });
    specs.push({ path: `${base}.inertia_kgm2`, label: "Inertia about centre" });
  }
  if (COUPLER[fam]) {
    specs.push({ group: `Coupler point ${TRACE} on the ${COUPLER[fam]}` });
    specs.push({ path: "trace_points.0.position_m.0", label: "x in link frame", schemaPath: "trace_points.0.position_m" });
    specs.push({ path: "trace_points.0.position_m.1", label: "y in link frame", schemaPath: "trace_points.0.position_m" });
  }
  specs.push({ group: "Operation" });
  specs.push({ path: "speed_rpm", label: "Crank speed" });
  specs.push({ path: "samples", label: "Samples per cycle" });
  specs.push({ path: "gravity.g_m_s2", label: "Gravity (empty: off)", optional: true });
  const loadKey = fam === "fourbar" ? "torque_Nm" : "force_N";
  specs.push({ group: `Process load on the output (${fam === "fourbar" ? "torque" : "force"})` });
  specs.push({ path: `loads.0.${loadKey}`, label: fam === "fourbar" ? "Torque (empty: none)" : "Force (empty: none)",
    optional: true, schema: ["WindowLoadIn", loadKey] });
  specs.push({ path: "loads.0.start_deg", label: "From crank angle", schema: ["WindowLoadIn", "start_deg"] });
  specs.push({ path: "loads.0.end_deg", label: "To crank angle", schema: ["WindowLoadIn", "end_deg"] });
  specs.push({ path: "loads.0.stroke", label: "While the output moves", schema: ["WindowLoadIn", "stroke"],
    options: [["0", "either way"], ["1", "in +"], ["-1", "in −"]] });
  (design.counterweights || []).forEach((cw, n) => {
    specs.push({ group: `Counterweight ${n + 1} on the ${cw.link}`, remove: n });
    specs.push({ path: `counterweights.${n}.mass_kg`, label: "Mass" });
    specs.push({ path: `counterweights.${n}.position_m.0`, label: "x in link frame", schemaPath: `counterweights.${n}.position_m` });
    specs.push({ path: `counterweights.${n}.position_m.1`, label: "y in link frame", schemaPath: `counterweights.${n}.position_m` });
  });
  return specs;
}

function describeSpec(spec, fam) {
  if (spec.schema) {
    const d = describe(spec.schema[0], spec.schema[1]);
    return d;
  }
  return describe("AnalysisIn", spec.schemaPath || spec.path, { type: fam });
}

export function renderForm() {
  const form = document.getElementById("design-form");
  const fam = state.design.mechanism.type;
  document.getElementById("family").value = fam;
  const specs = fieldSpecs(state.design);
  state.fields = specs.filter((s) => s.path);
  const nodes = [];
  let set = null, group = "";
  for (const spec of specs) {
    spec.groupLabel = group;
    if (spec.group) {
      group = spec.group;
      set = h("fieldset", {}, h("legend", {}, spec.group));
      if (spec.remove !== undefined) {
        const n = spec.remove;
        set.appendChild(h("button", { type: "button", class: "remove-cw", dataset: { index: n }, onclick: () => {
          state.design.counterweights.splice(n, 1);
          if (!state.design.counterweights.length) { delete state.design.counterweights; delete state.design.counter_rotors; delete state.design.coupler_inertia_kgm2; }
          renderForm();
          edited();
        } }, "Remove"));
      }
      nodes.push(set);
      continue;
    }
    const d = describeSpec(spec, fam);
    const kind = kindOf(spec.path);
    spec.kind = kind;
    const id = `f-${spec.path}`;
    const value = getPath(state.design, spec.path);
    // a choice among names (the assembly branch) has no unit to show
    const unit = d.unit === "choice" ? "" : unitLabel(kind, d.unit);
    const title = `${d.text}`.trim();
    const common = { id, name: spec.path, title, "aria-describedby": `m-${spec.path}` };
    let input;
    if (spec.json) {
      // one line per entry, short lists of numbers or names kept on one line
      const text = JSON.stringify(value, null, 1).replace(/\[\s+([^[\]{}]*?)\s+\]/g, (_, inner) => `[${inner.replace(/\s+/g, " ")}]`);
      input = h("textarea", { ...common, rows: 18, spellcheck: "false" });
      input.value = text;
    } else if (spec.options) {
      input = h("select", common, spec.options.map(([v, l]) => h("option", { value: v, selected: String(value ?? spec.options[0][0]) === v }, l)));
    } else {
      // a field left out takes the schema's default: shown greyed as the placeholder
      let dflt = d.default;
      if (Array.isArray(dflt)) dflt = dflt[Number(spec.path.split(".").pop())];
      const placeholder = typeof dflt === "number" ? toDisplay(dflt, kind) : "";
      input = h("input", { ...common, type: "text", inputmode: "decimal", autocomplete: "off", placeholder });
      input.value = toDisplay(value, kind);
    }
    const row = h("div", { class: "row", dataset: { path: spec.path } }, h("label", { for: id, title }, spec.label), input,
      h("span", { class: "unit" }, unit), h("p", { class: "msg", id: `m-${spec.path}`, hidden: true }));
    if (set) set.appendChild(row); else nodes.push(row);
  }
  form.replaceChildren(...nodes);
}

function clearMessages() {
  document.querySelectorAll("#design-form .msg, #m-mechanism").forEach((m) => { m.hidden = true; m.textContent = ""; m.className = "msg"; });
  document.querySelectorAll("#design-form [aria-invalid]").forEach((i) => i.removeAttribute("aria-invalid"));
  const p = document.getElementById("form-problem");
  p.hidden = true; p.textContent = "";
  document.getElementById("form-warnings").replaceChildren();
}

/** The form row a field name of the API belongs to: `mechanism.fourbar.crank_length_m` (a validation error names
 *  the union member) is the row `mechanism.crank_length_m`. */
function rowFor(field) {
  if (!field) return null;
  const fam = state.design.mechanism.type;
  const clean = field.split(".").filter((p, n) => !(n === 1 && p === fam)).join(".");
  const paths = state.fields.map((s) => s.path);
  const hit = paths.find((p) => p === clean) || paths.find((p) => p.startsWith(`${clean}.`)) ||
    paths.find((p) => clean.startsWith(`${p}.`)) || paths.find((p) => p.replace(/\.0\./, ".") === clean);
  return hit || null;
}

const RELATIONS = { "greater than or equal to": "at least", "greater than": "more than", "less than or equal to": "at most",
  "less than": "less than" };

/** A bound the service states in SI ("greater than or equal to 1e-06"), said in the form's unit of the field. */
export function inFormUnits(path, text) {
  const spec = state.fields.find((f) => f.path === path);
  if (!spec || !spec.kind || spec.kind === "plain") return text;
  const f = factor(spec.kind), u = unitLabel(spec.kind);
  return text.replace(/\b(greater than or equal to|greater than|less than or equal to|less than) (-?\d+(?:\.\d+)?(?:e[-+]?\d+)?)/,
    (_, rel, num) => `${RELATIONS[rel]} ${fmt(Number(num) / f)} ${u}`);
}

/** Bring a message into view next to its field, in the scrolled editor or panel. */
export function reveal(el) {
  if (el && el.scrollIntoView) el.scrollIntoView({ block: "nearest", inline: "nearest" });
}

export function showMessage(field, text, warn = false) {
  // the linkage as a whole (cannot assemble, a weak transmission angle): said under the family
  const path = field === "mechanism" ? "mechanism" : rowFor(field);
  if (!path) return false;
  const m = document.getElementById(`m-${path}`);
  m.textContent = path === "mechanism" ? text : inFormUnits(path, text);
  m.hidden = false;
  m.className = warn ? "msg warn" : "msg";
  if (path !== "mechanism" && !warn) document.getElementById(`f-${path}`).setAttribute("aria-invalid", "true");
  if (!warn) reveal(document.querySelector(`.row[data-path="${CSS.escape(path)}"]`) || m);
  return true;
}

/** Crank-angle gaps as a reader writes them: "76.4°–283.6°". */
function gaps(ranges) {
  return ranges.map(([a, b]) => `${Number(a).toFixed(1)}°–${Number(b).toFixed(1)}°`).join(", ");
}

/** The drawing and the diagrams are of the last design the service answered for: while the form holds an error
 *  they are greyed and say so. */
export function markStale(reason) {
  for (const id of ["drawing-box", "plots"]) document.getElementById(id).classList.toggle("stale-view", Boolean(reason));
  const note = document.getElementById("stale-note");
  note.hidden = !reason;
  note.textContent = reason ? `Drawn for the last design that analysed: ${reason}` : "";
  document.body.dataset.stale = reason ? "1" : "";
}

export function showProblem(err, where = "form-problem", fieldMapper = showMessage) {
  const box = document.getElementById(where);
  const body = err instanceof Problem ? err.body : { detail: String(err.message || err) };
  // a linkage that cannot be assembled is a property of the linkage as a whole
  const field = body.field || (body.not_assemblable_ranges_deg ? "mechanism" : undefined);
  const detail = body.not_assemblable_ranges_deg
    ? `The linkage cannot be assembled for crank angles ${gaps(body.not_assemblable_ranges_deg)} (${body.failing_samples ?? "some"} of the samples): change the lengths.`
    : body.detail;
  const list = body.errors && body.errors.length ? body.errors : [{ field, message: detail }];
  const placed = list.map((e) => fieldMapper(e.field, e.message));
  if (placed.every(Boolean)) return;
  box.hidden = false;
  let text = detail || body.title || "the service refused the request";
  if (body.field) text += ` (field ${body.field})`;
  box.textContent = text;
  reveal(box);
}

function readInput(el) {
  const spec = state.fields.find((s) => s.path === el.name);
  if (spec.json) {
    try { return { ok: true, value: JSON.parse(el.value) }; } catch (err) { return { ok: false, message: `not JSON: ${err.message}` }; }
  }
  const raw = el.value.trim().replace(",", ".");
  if (el.tagName === "SELECT") return { ok: true, value: Number(raw) };
  if (raw === "") {
    if (spec.optional || spec.path.startsWith("loads.0.") || spec.path.startsWith("trace_points")) return { ok: true, value: undefined };
    return { ok: false, message: "enter a number" };
  }
  const v = Number(raw);
  if (!Number.isFinite(v)) return { ok: false, message: `"${raw}" is not a number` };
  return { ok: true, value: spec.path === "samples" ? Math.round(v) : v * factor(spec.kind) };
}

function applyInput(el) {
  const { ok, value, message } = readInput(el);
  if (!ok) return message;
  const path = el.name;
  const fam = state.design.mechanism.type;
  if (path === "gravity.g_m_s2") {
    state.design.gravity = value === undefined ? null : { ...(state.design.gravity || {}), g_m_s2: value };
    if (value === undefined) delete state.design.gravity;
  } else if (path.startsWith("loads.0.")) {
    const key = path.split(".")[2];
    const load = (state.design.loads && state.design.loads[0]) || { type: "window", start_deg: 0, end_deg: 360 };
    if (value === undefined) delete load[key]; else load[key] = value;
    const magnitude = fam === "fourbar" ? "torque_Nm" : "force_N";
    state.design.loads = load[magnitude] === undefined ? [] : [load];
  } else if (path.startsWith("trace_points.0.")) {
    const tp = (state.design.trace_points && state.design.trace_points[0]) ||
      { name: TRACE, link: COUPLER[fam], position_m: [0, 0] };
    tp.position_m[Number(path.split(".")[3])] = value ?? 0;
    state.design.trace_points = [tp];
  } else if (path === "mechanism") {
    state.design.mechanism = { ...value, type: fam };
  } else {
    setPath(state.design, path, value);
  }
  return null;
}

// --- the analysis ------------------------------------------------------------------------------------------------
/** The request sent to /v1/analysis: the design, plus a trace point at every counterweight so the answer says
 *  where each one is. */
function analysisRequest() {
  const body = structuredClone(state.design);
  const cws = body.counterweights || [];
  body.trace_points = [...(body.trace_points || []), ...cws.map((cw, n) => ({ name: `cw${n + 1}`, link: cw.link, position_m: cw.position_m }))];
  return body;
}

export async function analyse(t0 = performance.now()) {
  if (state.pending) state.pending.abort();
  const ctl = new AbortController();
  state.pending = ctl;
  const seq = ++state.seq;
  setStatus("analysing…");
  try {
    const answer = await post("/v1/analysis", analysisRequest(), { signal: ctl.signal });
    if (seq !== state.seq) return;
    const tAnswer = performance.now();
    // before this answer is drawn: a dragged joint's next position can be on its way meanwhile
    for (const f of state.hooks.received) f(answer);
    clearMessages();
    markStale(null);
    state.answer = answer;
    state.index = Math.min(state.index, answer.crank_angle_deg.length - 1);
    const slider = document.getElementById("angle");
    slider.max = answer.crank_angle_deg.length - 1;
    slider.value = state.index;
    // while a joint is dragged the scale stays put, so the joint stays under the pointer
    if (!state.dragging || !state.layout) state.layout = layout(answer, state.design, { targets: state.targets });
    drawAll();
    for (const f of state.hooks.answer) f(answer);
    for (const w of answer.warnings || []) {
      const text = w.message;
      if (!showMessage(w.field, text, true)) {
        const li = document.createElement("li");
        li.textContent = text;
        li.dataset.code = w.code;
        document.getElementById("form-warnings").appendChild(li);
      }
    }
    // a speed no crank of a machine turns at: most likely rad/s or a typing slip
    if (state.design.speed_rpm > 20000) {
      showMessage("speed_rpm", `${fmt(state.design.speed_rpm)} rev/min is beyond any machine crank: is the speed in rev/min?`, true);
    }
    const dt = performance.now() - t0;
    // edit-to-redraw time, and the part of it spent waiting for the service (bench/workbench.py reads these)
    state.timings.push({ total: dt, service: tAnswer - t0, t0 });
    setStatus(`${answer.crank_angle_deg.length} samples · ${dt.toFixed(0)} ms`);
    document.body.dataset.analysed = String(seq);
  } catch (err) {
    if (err.name === "AbortError") return;
    if (seq !== state.seq) return;
    clearMessages();
    showProblem(err);
    markStale("the form holds an error");
    setStatus("not analysed: see the message in the form");
    for (const f of state.hooks.problem) f(err);
    document.body.dataset.problem = String(seq);
  } finally {
    if (state.pending === ctl) state.pending = null;
  }
}

function setStatus(text) { document.getElementById("status").textContent = text; }

function counterweightExtras() {
  return (state.design.counterweights || []).map((cw, n) => ({ ...cw, trace: `cw${n + 1}` }));
}

export function drawAll() {
  const a = state.answer;
  if (!a) return;
  drawFrame();
  const box = document.getElementById("plots");
  const x = a.crank_angle_deg, i = state.index, fam = state.design.mechanism.type;
  const xl = "crank angle φ [°]";
  // The linkage's own force scale, Σm·ω²·size: a shaking force below a billionth of it is rounding (a full
  // balance leaves 1e-13 N), read as zero on an axis a thousandth of it wide.
  const w = ((state.design.speed_rpm || 0) * Math.PI) / 30;
  const masses = [...Object.values(state.design.mechanism.links || {}), ...(state.design.counterweights || [])]
    .reduce((t, l) => t + (Number(l && l.mass_kg) || 0), 0);
  const fScale = masses * w * w * (state.layout ? state.layout.span : 1), mScale = fScale * (state.layout ? state.layout.span : 1);
  const zeroF = { zero: 1e-9 * fScale, zeroSpan: 1e-3 * fScale }, zeroM = { zero: 1e-9 * mScale, zeroSpan: 1e-3 * mScale };
  state.plots = [
    linePlot(box, "plot-torque", { title: "Driving torque on the crank", x, xLabel: xl, yLabel: "T [N·m]", unit: "N·m", cursor: i,
      series: [{ name: "kinetostatic", values: a.driving_torque_Nm }, { name: "virtual power", values: a.virtual_power_torque_Nm, dash: "4 3", colour: "#c25e00" }] }),
    polarPlot(box, "plot-polar", { title: "Shaking force on the frame (polar diagram)", unit: "N", cursor: i, ...zeroF,
      series: Object.assign([{ name: "shaking force", points: a.shaking_force_N }], { angles: x }) }),
    linePlot(box, "plot-moment", { title: "Shaking moment about O", x, xLabel: xl, yLabel: "M [N·m]", unit: "N·m", cursor: i, ...zeroM,
      series: [{ name: "shaking moment", values: a.shaking_moment_Nm }] }),
  ];
  if (a.transmission_angle_deg) {
    state.plots.push(linePlot(box, "plot-transmission", { title: "Transmission angle", x, xLabel: xl, yLabel: "μ [°]", unit: "°", cursor: i,
      series: [{ name: "μ", values: a.transmission_angle_deg }], limits: [{ y: 40, label: "40° limit" }, { y: 140, label: "140°" }] }));
  } else document.getElementById("plot-transmission")?.remove();
  // each joint's reaction over the cycle (its vector at this angle: "joint reactions" under the drawing)
  const reactions = Object.entries(a.joint_reactions_N || {});
  if (reactions.length) {
    state.plots.push(linePlot(box, "plot-reactions", { title: "Joint reactions |R|", x, xLabel: xl, yLabel: "|R| [N]", unit: "N", cursor: i,
      series: reactions.map(([name, f]) => ({ name, values: f.map((v) => Math.hypot(v[0], v[1])) })) }));
  }
  const out = outputMotion(a, fam);
  state.plots.push(
    linePlot(box, "plot-output-s", { title: `Output ${out.name}: displacement`, x, xLabel: xl, yLabel: `${out.s.label}`, unit: out.s.unit, cursor: i, series: [{ name: out.s.sym, values: out.s.values }] }),
    linePlot(box, "plot-output-v", { title: `Output ${out.name}: velocity`, x, xLabel: xl, yLabel: out.v.label, unit: out.v.unit, cursor: i, series: [{ name: out.v.sym, values: out.v.values }] }),
    linePlot(box, "plot-output-a", { title: `Output ${out.name}: acceleration`, x, xLabel: xl, yLabel: out.a.label, unit: out.a.unit, cursor: i, series: [{ name: out.a.sym, values: out.a.values }] }),
    linePlot(box, "plot-jred", { title: "Reduced inertia on the crank", x, xLabel: xl, yLabel: "J_red [kg·m²]", unit: "kg·m²", cursor: i,
      series: [{ name: "J_red", values: a.reduced_inertia_kgm2 }] }),
  );
}

function outputMotion(a, fam) {
  const mech = state.design.mechanism;
  if (fam === "linkage") {
    // the working member: a slider's point along its guide, or a turning link's angle
    const out = mech.output || mech.links[mech.links.length - 1].name;
    const link = mech.links.find((l) => l.name === out);
    const slide = (mech.joints || []).find((j) => j.kind === "prismatic" && j.links.includes(out) && j.links.includes("frame"));
    if (link && slide && link.joints && a.points[link.joints[0]]) {
      const p = a.points[link.joints[0]], t = ((slide.axis_deg || 0) * Math.PI) / 180, c = Math.cos(t), s = Math.sin(t);
      const along = (q) => q[0] * c + q[1] * s, f = factor("length"), u = state.units.length;
      return { name: `${out} (along its guide)`, s: { label: `s [${u}]`, unit: u, sym: "s", values: p.position_m.map((q) => along(q) / f) },
        v: { label: "v [m/s]", unit: "m/s", sym: "v", values: p.velocity_m_s.map(along) },
        a: { label: "a [m/s²]", unit: "m/s²", sym: "a", values: p.acceleration_m_s2.map(along) } };
    }
  }
  if (!GEOMETRY[fam]) {
    const name = Object.keys(a.links).pop(), r = a.links[name];
    return { name, s: { label: "angle [°]", unit: "°", sym: "θ", values: r.angle_deg },
      v: { label: "ω [rad/s]", unit: "rad/s", sym: "ω", values: r.angular_velocity_rad_s },
      a: { label: "ε [rad/s²]", unit: "rad/s²", sym: "ε", values: r.angular_acceleration_rad_s2 } };
  }
  if (fam === "fourbar") {
    const r = a.links.rocker;
    return { name: "rocker Q-B", s: { label: "ψ [°]", unit: "°", sym: "ψ", values: r.angle_deg },
      v: { label: "ω [rad/s]", unit: "rad/s", sym: "ω", values: r.angular_velocity_rad_s },
      a: { label: "ε [rad/s²]", unit: "rad/s²", sym: "ε", values: r.angular_acceleration_rad_s2 } };
  }
  const p = a.points[fam === "slider_crank" ? "B" : "R"];
  const f = factor("length"), u = state.units.length;
  return { name: fam === "slider_crank" ? "slider B" : "ram R",
    s: { label: `x [${u}]`, unit: u, sym: "x", values: p.position_m.map((q) => q[0] / f) },
    v: { label: "v [m/s]", unit: "m/s", sym: "v", values: p.velocity_m_s.map((q) => q[0]) },
    a: { label: "a [m/s²]", unit: "m/s²", sym: "a", values: p.acceleration_m_s2.map((q) => q[0]) } };
}

/** What the drawing shows besides the linkage at sample `i`: coupler point, counterweights, targets, arrows. */
function extrasAt(i) {
  const a = state.answer;
  return { tracePoint: a.points[TRACE] ? TRACE : null, counterweights: counterweightExtras(), targets: state.targets,
    counterRotors: state.design.counter_rotors || [], unitLength: state.units.length,
    vectors: vectorsAt(a, state.vectors, i, state.layout.span) };
}

export function drawFrame() {
  const a = state.answer;
  if (!a) return;
  const i = state.index;
  drawLinkage(document.getElementById("drawing"), a, state.design, i, state.layout, extrasAt(i));
  document.getElementById("angle-out").textContent = `φ = ${a.crank_angle_deg[i].toFixed(1)}°`;
  for (const p of state.plots) p.setCursor(i);
}

// --- dragging a joint changes a length: A the crank's, B a four-bar's rocker's (the distance to its pivot) ------
const DRAG = { fourbar: { A: ["O", "mechanism.crank_length_m"], B: ["Q", "mechanism.rocker_length_m"] },
  slider_crank: { A: ["O", "mechanism.crank_length_m"] }, slotted_lever: { A: ["O", "mechanism.crank_length_m"] } };

function installDragging() {
  const svg = document.getElementById("drawing");
  let drag = null;
  svg.addEventListener("pointerdown", (e) => {
    const joint = e.target.dataset && e.target.dataset.joint;
    const rule = joint && DRAG[state.design.mechanism.type][joint];
    if (!rule || !state.answer) return;
    drag = { pivot: state.answer.points[rule[0]].position_m[state.index], path: rule[1] };
    state.dragging = true;
    svg.setPointerCapture(e.pointerId);
    e.preventDefault();
  });
  svg.addEventListener("pointermove", (e) => {
    if (!drag) return;
    const t0 = performance.now();
    const [x, y] = toModel(svg, e);
    const length = Math.hypot(x - drag.pivot[0], y - drag.pivot[1]);
    if (!(length > 0)) return;
    setPath(state.design, drag.path, Number(length.toPrecision(4)));
    document.getElementById(`f-${drag.path}`).value = toDisplay(getPath(state.design, drag.path), "length");
    edited(t0);
  });
  const end = () => {
    if (!drag) return;
    drag = null;
    state.dragging = false;
    if (state.answer) { state.layout = layout(state.answer, state.design, { targets: state.targets }); drawAll(); }
  };
  svg.addEventListener("pointerup", end);
  svg.addEventListener("pointercancel", end);
}

// --- the design as a file and a link -------------------------------------------------------------------------------
function writeUrl() {
  const hash = `#design=${encodeURIComponent(JSON.stringify(state.design))}&units=${state.units.length},${state.units.mass}`;
  history.replaceState(null, "", hash);
}

function readUrl() {
  const params = new URLSearchParams(location.hash.slice(1));
  const units = (params.get("units") || "").split(",");
  if (UNITS.length[units[0]]) state.units.length = units[0];
  if (UNITS.mass[units[1]]) state.units.mass = units[1];
  const d = params.get("design");
  if (!d) return null;
  try { return JSON.parse(d); } catch { return null; }
}

export function defaultMechanism(fam) {
  const schemas = state.openapi.components.schemas;
  // the manual's own examples: every request example whose mechanism is of this family
  const all = Object.values(schemas).flatMap((s) => s.examples || []).filter((e) => e && e.mechanism).map((e) => e.mechanism);
  const found = all.find((m) => m.type === fam);
  return structuredClone(found || { type: fam });
}

function defaultDesign() {
  const ex = state.openapi.components.schemas.AnalysisIn.examples[0];
  const design = structuredClone(ex);
  // The flywheel example's process load on the same four-bar: a design that does work, so every panel has a case.
  const loaded = state.openapi.components.schemas.FlywheelIn.examples.find((e) => e.mechanism && e.loads);
  if (loaded) design.loads = structuredClone(loaded.loads);
  design.trace_points = [{ name: TRACE, link: "coupler", position_m: [design.mechanism.coupler_length_m * 0.5, design.mechanism.coupler_length_m * 0.4] }];
  return design;
}

/** Replace the design (a loaded file, a synthesis answer, a study's variant) and analyse it. */
export function setDesign(design, { targets = [] } = {}) {
  state.design = design;
  state.targets = targets;
  renderForm();
  writeUrl();
  return analyse();
}

export function edited(t0 = performance.now()) {
  writeUrl();
  return analyse(t0);
}

function selectTab(name) {
  document.querySelectorAll("#tabs [role=tab]").forEach((t) => {
    const on = t.dataset.panel === name;
    t.setAttribute("aria-selected", String(on));
    t.tabIndex = 0;
  });
  document.querySelectorAll(".panel").forEach((p) => { p.hidden = p.id !== `panel-${name}`; });
  document.body.dataset.panel = name;
}

async function main() {
  // an office server that asks who you are: nothing is asked of it before the sign-in
  if (!(await admitted)) return;
  state.openapi = await loadOpenApi();
  const familySelect = document.getElementById("family");
  const mapping = state.openapi.components.schemas.AnalysisIn.properties.mechanism.discriminator?.mapping || {};
  for (const fam of Object.keys(mapping)) {
    const label = { linkage: "general linkage (JSON)" }[fam] || fam.replace(/_/g, " ");
    if (![...familySelect.options].some((o) => o.value === fam)) familySelect.add(new Option(label, fam));
  }
  const fromUrl = readUrl();
  document.getElementById("unit-length").value = state.units.length;
  document.getElementById("unit-mass").value = state.units.mass;
  state.design = fromUrl && fromUrl.mechanism ? fromUrl : defaultDesign();
  renderForm();
  writeUrl();   // the address bar holds the design from the start, so a link to the page as opened reopens it
  const form = document.getElementById("design-form");
  form.addEventListener("input", (evt) => {
    const t0 = performance.now();
    const el = evt.target;
    const msg = applyInput(el);
    const m = document.getElementById(`m-${el.name}`);
    if (msg) {
      m.textContent = msg; m.hidden = false; el.setAttribute("aria-invalid", "true");
      markStale("the form holds an error");
      return;
    }
    m.hidden = true; el.removeAttribute("aria-invalid");
    state.edited = true;
    edited(t0);
  });
  form.addEventListener("submit", (e) => e.preventDefault());
  document.getElementById("family").addEventListener("change", (e) => {
    const fam = e.target.value;
    // another family starts from the manual's example: an edited design is kept unless the user lets it go
    if (state.edited && !window.confirm("Switch to another family? The design in the form is replaced (Save JSON keeps it).")) {
      e.target.value = state.design.mechanism.type;
      return;
    }
    state.edited = false;
    const mech = defaultMechanism(fam);
    const d = { mechanism: mech, speed_rpm: state.design.speed_rpm, samples: state.design.samples };
    if (!GEOMETRY[fam]) { setDesign(d); return; }
    if (COUPLER[fam]) {
      const len = mech.coupler_length_m || mech.rod_length_m;
      d.trace_points = [{ name: TRACE, link: COUPLER[fam], position_m: [len * 0.5, len * 0.4] }];
    }
    setDesign(d);
  });
  for (const [id, kind] of [["unit-length", "length"], ["unit-mass", "mass"]]) {
    document.getElementById(id).addEventListener("change", (e) => {
      state.units[kind] = e.target.value;
      renderForm(); writeUrl(); drawAll();
    });
  }
  installDragging();
  installExports({ state, request: analysisRequest, redraw: drawFrame, setStatus, extrasAt });
  document.getElementById("angle").addEventListener("input", (e) => { state.index = Number(e.target.value); drawFrame(); });
  let timer = null;
  document.getElementById("play").addEventListener("click", (e) => {
    const btn = e.currentTarget;
    if (timer) { cancelAnimationFrame(timer); timer = null; btn.textContent = "Play"; btn.setAttribute("aria-pressed", "false"); return; }
    btn.textContent = "Pause"; btn.setAttribute("aria-pressed", "true");
    let last = performance.now();
    const step = (now) => {
      if (state.answer && now - last > 1000 / 30) {
        const n = state.answer.crank_angle_deg.length;
        state.index = (state.index + Math.max(1, Math.round(n / 120))) % n;
        document.getElementById("angle").value = state.index;
        drawFrame();
        last = now;
      }
      timer = requestAnimationFrame(step);
    };
    timer = requestAnimationFrame(step);
  });
  document.querySelectorAll("#tabs [role=tab]").forEach((t) => t.addEventListener("click", () => selectTab(t.dataset.panel)));
  document.getElementById("save-json").addEventListener("click", () => {
    const blob = new Blob([JSON.stringify(state.design, null, 2)], { type: "application/json" });
    const a = document.createElement("a");
    a.href = URL.createObjectURL(blob); a.download = "design.json"; a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  });
  document.getElementById("load-json").addEventListener("change", async (e) => {
    const file = e.target.files[0];
    if (!file) return;
    let d = null;
    try { d = JSON.parse(await file.text()); } catch {
      d = undefined;
    }
    if (!d || typeof d !== "object" || !d.mechanism || typeof d.mechanism !== "object") {
      clearMessages();
      showProblem(new Error(d === undefined
        ? `${file.name} is not a design: it is not JSON text. Open a file saved with Save JSON, or an /v1/analysis request.`
        : `${file.name} holds no mechanism: open a file saved with Save JSON, or an /v1/analysis request.`));
      document.body.dataset.problem = String(++state.seq);
    } else setDesign(d);
    e.target.value = "";
  });
  document.getElementById("copy-link").addEventListener("click", async () => {
    try { await navigator.clipboard.writeText(location.href); setStatus("link copied"); } catch { setStatus("copy the address bar: it holds the design"); }
  });
  selectTab("mechanism");
  installPanels({ state, showMessage, setDesign, toDisplay, factor, unitLabel, showProblem, describe, getPath, setPath, selectTab, defaultMechanism });
  window.workbench = { state, setDesign, analyse, selectTab };
  await analyse();
  state.firstRender = performance.now();
  document.body.dataset.ready = "1";
}

main();
