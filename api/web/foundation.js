// The Foundation panel: the current linkage's frame on isolators (POST /v1/machines/isolation), or isolators chosen
// for a force limit (POST /v1/machines/isolation/design); the force the foundation feels over the cycle, its
// spectrum and the natural modes drawn on the frame. And, in the Machine panel, the figures of its elastic-drive and
// regulation blocks when the answer holds them. A client of the public API only: every number drawn is the answer's.

import { post, get, Problem } from "./api.js";
import { h, s, put, table } from "./dom.js";
import { linePlot, fmt } from "./plot.js";
import { state } from "./app.js";
import { admitted } from "./signin.js";

const panel = document.getElementById("panel-foundation");
const LINKAGE = ["mechanism", "speed_rpm", "gravity", "loads", "torques", "counterweights"];
const ISOLATOR_FIELDS = [["position_m.0", "x", "m"], ["position_m.1", "y", "m"], ["kx_N_m", "k_x", "N/m"],
  ["ky_N_m", "k_y", "N/m"], ["damping_ratio", "ζ", "–"]];
const FRAME_FIELDS = [["frame.mass_kg", "Frame mass (the whole machine)", "kg"], ["frame.inertia_kgm2", "Inertia about its centre", "kg·m²"],
  ["frame.centre_m.0", "Centre x (linkage's coordinates)", "m"], ["frame.centre_m.1", "Centre y", "m"]];
const DESIGN_FIELDS = [["max_force_N", "Peak force limit (design)", "N", 600], ["max_static_deflection_m", "Static deflection limit", "m", 0.02],
  ["max_block_mass_kg", "Largest inertia block", "kg", 0]];
let seq = 0;
let isolators = [];
// Lengths and masses in the form's units (the editor's choice at the top), SI on the wire.
const KIND = { m: "length", kg: "mass" };
const SCALE = { length: { mm: 1e-3, m: 1 }, mass: { g: 1e-3, kg: 1 } };
const shown = { length: "mm", mass: "kg" };
const scale = (kind) => (kind ? SCALE[kind][shown[kind]] : 1);
const unitOf = (unit) => (KIND[unit] ? shown[KIND[unit]] : unit);
// a value in SI as typed or answered, unrounded; in mm or g to 12 digits (the conversion's last-digit noise off)
const display = (v, kind) => (v === undefined || v === null ? "" : kind ? String(Number((v / scale(kind)).toPrecision(12))) : String(v));

function done(kind) {
  seq += 1;
  document.body.dataset.foundation = `${kind}-${seq}`;
}

function numberRow(id, label, value, unit) {
  const kind = KIND[unit] || "";
  const input = h("input", { id, type: "text", inputmode: "decimal", autocomplete: "off", dataset: { kind } });
  input.value = display(value, kind);
  return h("div", { class: "row" }, h("label", { for: id }, label), input, h("span", { class: "unit", dataset: { kind } }, unitOf(unit)),
    h("p", { class: "msg", id: `${id}-msg`, hidden: true }));
}

function readNumber(id) {
  const el = document.getElementById(id);
  const raw = el.value.trim().replace(",", ".");
  if (raw === "") return undefined;
  const v = Number(raw);
  return Number.isFinite(v) ? v * scale(el.dataset.kind) : NaN;
}

function clear() {
  panel.querySelectorAll(".msg").forEach((m) => { m.hidden = true; m.textContent = ""; });
  panel.querySelectorAll("[aria-invalid]").forEach((i) => i.removeAttribute("aria-invalid"));
  const p = document.getElementById("fnd-problem");
  p.hidden = true; p.textContent = "";
}

function mark(id, message) {
  const el = document.getElementById(id);
  const m = document.getElementById(`${id}-msg`);
  if (!el || !m) return false;
  m.textContent = message; m.hidden = false; el.setAttribute("aria-invalid", "true");
  return true;
}

/** A problem beside the field it names (the frame's or an isolator's), else in the panel's problem box. */
function showProblem(err) {
  const body = err instanceof Problem ? err.body : { detail: String(err.message || err) };
  const list = body.errors && body.errors.length ? body.errors : [{ field: body.field, message: body.detail }];
  const placed = list.map((e) => {
    if (!e.field) return false;
    const field = e.field.replace(/\[(\d+)\]/g, ".$1").replace(/^foundation\./, "");
    return mark(`fnd-${field}`, e.message);
  });
  if (placed.length && placed.every(Boolean)) return;
  const p = document.getElementById("fnd-problem");
  const where = body.field ? ` (field ${body.field})` : body.constraint ? ` (constraint ${body.constraint})` : "";
  put(p, `${body.detail || body.title || "the service refused the request"}${where}`);
  p.hidden = false;
}

function isolatorTable() {
  const rows = isolators.map((iso, i) => h("tr", { dataset: { isolator: String(i) } },
    h("td", {}, String(i + 1)),
    ISOLATOR_FIELDS.map(([path]) => {
      const id = `fnd-isolators.${i}.${path}`;
      const parts = path.split(".");
      const v = parts.length === 2 ? iso[parts[0]][Number(parts[1])] : iso[path];
      const kind = KIND[ISOLATOR_FIELDS.find(([p2]) => p2 === path)[2]] || "";
      const input = h("input", { id, type: "text", inputmode: "decimal", autocomplete: "off", size: 9, "aria-label": `isolator ${i + 1} ${path}`, dataset: { kind } });
      input.value = display(v, kind);
      input.addEventListener("change", () => { const x = readNumber(id); setValue(iso, path, x); });
      return h("td", {}, input, h("p", { class: "msg", id: `${id}-msg`, hidden: true }));
    }),
    h("td", {}, h("button", { class: "secondary", onclick: () => { isolators.splice(i, 1); drawTable(); } }, "remove"))));
  return table(["", ...ISOLATOR_FIELDS.map(([, l, u]) => `${l} [${unitOf(u)}]`), ""], rows, { id: "fnd-isolators" });
}

function setValue(iso, path, v) {
  const parts = path.split(".");
  if (parts.length === 2) iso[parts[0]][Number(parts[1])] = v;
  else if (v === undefined) delete iso[path];
  else iso[path] = v;
}

function drawTable() { put(document.getElementById("fnd-table"), isolatorTable()); }

function readIsolators() {
  // the table's inputs as they stand (a value typed but not yet committed counts)
  return isolators.map((iso, i) => {
    const out = { position_m: [0, 0] };
    for (const [path] of ISOLATOR_FIELDS) {
      const v = readNumber(`fnd-isolators.${i}.${path}`);
      if (v !== undefined) setValue(out, path, v);
    }
    return out;
  });
}

function request() {
  const body = {};
  for (const k of LINKAGE) if (state.design[k] !== undefined && state.design[k] !== null) body[k] = structuredClone(state.design[k]);
  body.samples = 360;
  body.frame = { centre_m: [0, 0] };
  for (const [path] of FRAME_FIELDS) {
    const v = readNumber(`fnd-${path}`);
    const parts = path.split(".");
    if (parts.length === 3) body.frame.centre_m[Number(parts[2])] = v === undefined ? 0 : v;
    else if (v !== undefined) body.frame[parts[1]] = v;
  }
  body.isolators = readIsolators();
  return body;
}

function badNumbers() {
  let bad = false;
  panel.querySelectorAll("input[type=text]").forEach((el) => {
    if (Number.isNaN(readNumber(el.id))) { mark(el.id, "enter a number"); bad = true; }
  });
  return bad;
}

// --- drawings of the answer --------------------------------------------------------------------------------------

/** Bars of each harmonic's amplitude, the shaking force's beside the foundation's, on a log scale. */
function spectrum(container, harmonics) {
  const W = 420, H = 220, M = { l: 56, r: 12, t: 22, b: 30 };
  const kept = harmonics.filter((k) => k.shaking_force_N > 0).slice(0, 12);
  const values = kept.flatMap((k) => [k.shaking_force_N, k.transmitted_force_N]).filter((v) => v > 0);
  const top = Math.ceil(Math.log10(Math.max(...values, 1e-12)));
  const bottom = Math.max(top - 6, Math.floor(Math.log10(Math.min(...values, 10 ** top))));
  const Y = (v) => H - M.b - ((Math.log10(Math.max(v, 10 ** bottom)) - bottom) / (top - bottom || 1)) * (H - M.t - M.b);
  const slot = (W - M.l - M.r) / Math.max(kept.length, 1);
  const nodes = [];
  for (let e = bottom; e <= top; e++) {
    nodes.push(s("line", { class: "grid", x1: M.l, x2: W - M.r, y1: Y(10 ** e), y2: Y(10 ** e) }),
      s("text", { class: "tick", x: M.l - 4, y: Y(10 ** e) + 4, "text-anchor": "end" }, `1e${e}`));
  }
  kept.forEach((k, i) => {
    const x = M.l + i * slot;
    for (const [j, v, colour, name] of [[0, k.shaking_force_N, "#1f5fbf", "shaking"], [1, k.transmitted_force_N, "#c25e00", "to the foundation"]]) {
      const y = Y(v);
      nodes.push(s("rect", { x: x + slot * (0.12 + 0.38 * j), y, width: slot * 0.36, height: Math.max(H - M.b - y, 0), fill: colour,
        dataset: { order: String(k.order), series: name } }, s("title", {}, `harmonic ${k.order}, ${name}: ${fmt(v)} N`)));
    }
    nodes.push(s("text", { class: "tick", x: x + slot / 2, y: H - M.b + 13, "text-anchor": "middle" }, String(k.order)));
  });
  nodes.push(s("line", { class: "axis", x1: M.l, x2: W - M.r, y1: H - M.b, y2: H - M.b }),
    s("text", { x: (M.l + W - M.r) / 2, y: H - 3, "text-anchor": "middle" }, "harmonic order"),
    s("text", { transform: `translate(11 ${(M.t + H - M.b) / 2}) rotate(-90)`, "text-anchor": "middle" }, "amplitude [N]"),
    s("rect", { x: M.l + 8, y: M.t - 16, width: 10, height: 8, fill: "#1f5fbf" }), s("text", { x: M.l + 22, y: M.t - 8 }, "shaking force"),
    s("rect", { x: M.l + 128, y: M.t - 16, width: 10, height: 8, fill: "#c25e00" }), s("text", { x: M.l + 142, y: M.t - 8 }, "to the foundation"));
  container.appendChild(h("div", { class: "plot", id: "fnd-spectrum" }, h("h4", {}, "Spectrum of the force: each harmonic, shaking and passed on"),
    s("svg", { viewBox: `0 0 ${W} ${H}`, role: "img", "aria-label": "Spectrum of the force" }, nodes)));
}

/** Each mode drawn on the frame: the rectangle around the centre, the isolators and O at rest (grey), moved along the
 *  mode's shape (x, y, θ of the centre), magnified so its largest point moves a fifth of the frame's size. */
function modeShapes(container, out, body) {
  const pts = [...body.isolators.map((i) => i.position_m), body.frame.centre_m, [0, 0]];
  const xs = pts.map((p) => p[0]), ys = pts.map((p) => p[1]);
  const size = Math.max(Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys), 0.1);
  const pad = 0.08 * size;
  const lo = [Math.min(...xs) - pad, Math.min(...ys) - pad], hi = [Math.max(...xs) + pad, Math.max(...ys) + pad];
  const outline = [[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]];
  const c = body.frame.centre_m;
  const moved = (p, q, k) => {
    const [x, y, t] = q.map((v) => v * k);
    const rx = p[0] - c[0], ry = p[1] - c[1];
    return [c[0] + Math.cos(t) * rx - Math.sin(t) * ry + x, c[1] + Math.sin(t) * rx + Math.cos(t) * ry + y];
  };
  const span = Math.max(hi[0] - lo[0], hi[1] - lo[1]) * 1.45;
  const mid = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2];
  const view = `${mid[0] - span / 2} ${-(mid[1] + span / 2)} ${span} ${span}`;
  const P = (p) => `${p[0]},${-p[1]}`;
  const colours = ["#1f5fbf", "#c25e00", "#b3261e"];
  const row = h("div", { class: "plots", id: "fnd-modes" });
  out.modes.forEach((m, j) => {
    const q = [m.shape_x_m, m.shape_y_m, m.shape_theta_rad];
    const unit = Math.max(...outline.map((p) => Math.hypot(...moved(p, q, 1).map((v, i) => v - p[i]))), 1e-300);
    const k = (0.2 * size) / unit;
    const lw = span / 250;
    const nodes = [s("polygon", { points: outline.map(P).join(" "), fill: "none", stroke: "#8a93a3", "stroke-width": lw }),
      s("polygon", { points: outline.map((p) => P(moved(p, q, k))).join(" "), fill: "none", stroke: colours[j], "stroke-width": 2 * lw, class: "mode-shape" })];
    for (const iso of body.isolators) {
      const p = iso.position_m, r = span / 60;
      nodes.push(s("polygon", { points: `${p[0]},${-p[1] + r} ${p[0] - r},${-p[1] + 2.2 * r} ${p[0] + r},${-p[1] + 2.2 * r}`, fill: "#444" }),
        s("line", { x1: p[0], y1: -p[1], x2: moved(p, q, k)[0], y2: -moved(p, q, k)[1], stroke: colours[j], "stroke-width": lw, "stroke-dasharray": `${2 * lw}` }));
    }
    nodes.push(s("circle", { cx: 0, cy: 0, r: span / 120, fill: "#000" }), s("circle", { cx: c[0], cy: -c[1], r: span / 160, fill: "none", stroke: "#000", "stroke-width": lw }));
    row.appendChild(h("div", { class: "plot" }, h("h4", {}, `Mode ${j + 1}: ${fmt(m.frequency_Hz)} Hz, ζ ${fmt(m.damping_ratio, 3)}`),
      s("svg", { viewBox: view, role: "img", "aria-label": `Mode ${j + 1} drawn on the frame` }, nodes)));
  });
  container.appendChild(row);
}

/** A mode shape's component: below 1e-9 of the shape's unit scale it is rounding, read as 0. */
function tiny(v) { return Math.abs(v) < 1e-9 ? "0" : fmt(v, 3); }

function showIsolation(out, body, designed) {
  const res = document.getElementById("fnd-result");
  const lines = [];
  if (designed) {
    lines.push(h("p", { id: "fnd-designed" }, `Isolators chosen: k_y ${fmt(designed.ky_N_m)} N/m, k_x ${fmt(designed.kx_N_m)} N/m, ζ ${fmt(designed.damping_ratio, 3)}, `
      + `inertia block ${fmt(designed.block_mass_kg)} kg; static deflection ${fmt(designed.static_deflection_m * 1000)} mm (${designed.method}).`));
  }
  lines.push(h("h3", {}, "Natural modes of the frame"),
    table(["mode", "frequency [Hz]", "x [m]", "y [m]", "θ [rad]", "damping ratio"], out.modes.map((m, j) => [String(j + 1),
      [fmt(m.frequency_Hz), { class: "num freq" }], tiny(m.shape_x_m), tiny(m.shape_y_m), tiny(m.shape_theta_rad), fmt(m.damping_ratio, 3)]), { id: "fnd-mode-table" }),
    h("p", { id: "fnd-peaks" }, `Peak force to the foundation ${fmt(out.peak_force_N)} N against a shaking force of ${fmt(out.peak_shaking_force_N)} N `
      + `(ratio ${fmt(out.force_ratio, 3)}); frame amplitude ${fmt(out.peak_displacement_m * 1000)} mm, ${fmt(out.peak_rotation_rad * 1000)} mrad.`),
    h("p", { class: "note", id: "fnd-check" }, `Check: a time integration of the same equations agrees within ${out.checks.relative_diff.toExponential(1)} of the peaks (${out.checks.method}).`));
  put(res, lines);
  const box = h("div", { class: "plots" });
  res.appendChild(box);
  const mag = (v) => v.map((f) => Math.hypot(f[0], f[1]));
  linePlot(box, "fnd-force", { title: "Force the foundation feels over the cycle", x: out.crank_angle_deg, xLabel: "crank angle φ [°]",
    yLabel: "F [N]", unit: "N", series: [{ name: "shaking", values: mag(out.shaking_force_N) }, { name: "foundation", values: mag(out.force_N) },
      { name: "F_x", values: out.force_N.map((f) => f[0]), dash: "4 3" }, { name: "F_y", values: out.force_N.map((f) => f[1]), dash: "4 3" }] });
  spectrum(box, out.harmonics);
  modeShapes(res, out, body);
}

async function run(kind) {
  clear();
  if (badNumbers()) return done("problem");
  const body = request();
  const status = document.getElementById("fnd-status");
  status.textContent = kind === "design" ? "choosing the isolators…" : "solving…";
  try {
    if (kind === "design") {
      const spec = { ...body, positions_m: body.isolators.map((i) => i.position_m), objective: "amplitude" };
      delete spec.isolators;
      for (const [name] of DESIGN_FIELDS) {
        const v = readNumber(`fnd-${name}`);
        if (v !== undefined) spec[name] = v;
      }
      const d = await post("/v1/machines/isolation/design", spec);
      // the chosen isolators become the table's, so the next run starts from them
      isolators = body.isolators.map((i) => ({ position_m: [...i.position_m], kx_N_m: d.kx_N_m, ky_N_m: d.ky_N_m, damping_ratio: d.damping_ratio }));
      drawTable();
      showIsolation(d.isolation, body, d);
    } else {
      showIsolation(await post("/v1/machines/isolation", body), body, null);
    }
    status.textContent = "";
    done(kind === "design" ? "designed" : "isolated");
  } catch (err) {
    status.textContent = "";
    put(document.getElementById("fnd-result"));
    showProblem(err);
    done("problem");
  }
}

async function example() {
  try {
    const api = await get("/openapi.json");
    return api.components.schemas.IsolationIn.examples[0];
  } catch {
    return null;
  }
}

/** The form's units changed: every length and mass shown again in them, the values unchanged. */
function unitsChanged() {
  const si = [...panel.querySelectorAll("input[data-kind]")].filter((el) => el.dataset.kind).map((el) => [el, readNumber(el.id)]);
  isolators = readIsolators();
  Object.assign(shown, state.units);
  for (const [el, v] of si) if (!Number.isNaN(v)) el.value = display(v, el.dataset.kind);
  panel.querySelectorAll(".unit[data-kind]").forEach((u) => { if (u.dataset.kind) u.textContent = shown[u.dataset.kind]; });
  drawTable();
}

async function build() {
  Object.assign(shown, state.units);
  for (const id of ["unit-length", "unit-mass"]) document.getElementById(id).addEventListener("change", unitsChanged);
  const ex = await example();
  const frame = (ex && ex.frame) || { mass_kg: 400, inertia_kgm2: 60, centre_m: [0, -0.25] };
  isolators = structuredClone((ex && ex.isolators) || []);
  const useExample = h("button", { class: "secondary", id: "fnd-example", onclick: () => {
    // the manual's compressor becomes the design, so every panel works on it
    const d = { mechanism: structuredClone(ex.mechanism), speed_rpm: ex.speed_rpm, samples: ex.samples };
    window.workbench.setDesign(d);
  } }, "Use the manual's compressor");
  put(panel, h("h2", {}, "The machine on its foundation: frame, isolators, the force the foundation feels"),
    h("p", { class: "note" }, "The current linkage at its speed drives the frame with its shaking force and moment. "
      + "The frame is the whole machine as one rigid body; positions in the linkage's coordinates (crank pivot O at the origin, y up), "
      + "lengths and masses in the form's units. "
      + "Forces are as the foundation feels them."),
    h("div", { class: "controls" }, FRAME_FIELDS.map(([path, label, unit]) => {
      const parts = path.split(".");
      const v = parts.length === 3 ? frame.centre_m[Number(parts[2])] : frame[parts[1]];
      return numberRow(`fnd-${path}`, label, v, unit);
    })),
    h("h3", {}, "Isolators"), h("div", { id: "fnd-table" }),
    h("div", { class: "actions" }, h("button", { class: "secondary", id: "fnd-add", onclick: () => {
      isolators = readIsolators();
      isolators.push({ position_m: [0, -0.5], kx_N_m: 5e4, ky_N_m: 1e5, damping_ratio: 0.08 });
      drawTable();
    } }, "Add an isolator"), ex ? useExample : null),
    h("details", { class: "more" }, h("summary", {}, "Design the isolators: limits"),
      h("div", { class: "controls" }, DESIGN_FIELDS.map(([name, label, unit, v]) => numberRow(`fnd-${name}`, label, v, unit)))),
    h("div", { class: "actions" }, h("button", { class: "run", id: "fnd-run", onclick: () => run("isolate") }, "Put it on the isolators"),
      h("button", { class: "run", id: "fnd-design", onclick: () => run("design") }, "Design the isolators"),
      h("span", { id: "fnd-status", class: "note" })),
    h("p", { id: "fnd-problem", class: "problem", role: "alert", hidden: true }), h("div", { id: "fnd-result", "aria-live": "polite" }));
  drawTable();
  document.body.dataset.foundationReady = "1";
}

// --- the Machine panel's elastic-drive and regulation blocks ------------------------------------------------------

function machineBlocks(res, m) {
  if (!m.elastic_drive && !m.regulation && !m.foundation) return;
  const box = h("div", { class: "plots", id: "mac-around" });
  res.appendChild(h("h3", {}, "The machine around its linkage"));
  const notes = [];
  if (m.foundation) notes.push(`Foundation: modes ${m.foundation.modes.map((x) => fmt(x.frequency_Hz)).join(", ")} Hz, peak force ${fmt(m.foundation.peak_force_N)} N.`);
  if (m.elastic_drive) {
    const e = m.elastic_drive;
    notes.push(`Elastic drive: ${fmt(e.natural_frequency_Hz)} Hz, dynamic factor ${fmt(e.dynamic_factor)}; the gears are sized for the ${e.gear_torque_basis} torque.`);
  }
  if (m.regulation) {
    const g = m.regulation;
    notes.push(`After the load step: speed drop ${fmt(g.drop_rpm)} rev/min, settled ${g.settling_time_s === null ? "not within the run" : `after ${fmt(g.settling_time_s)} s`}.`);
  }
  res.appendChild(h("p", { id: "mac-around-notes" }, notes.join(" ")));
  res.appendChild(box);
  if (m.elastic_drive) {
    const e = m.elastic_drive;
    linePlot(box, "mac-elastic", { title: "Torque in the elastic link over the steady cycle", x: e.crank_angle_deg, xLabel: "crank angle φ [°]",
      yLabel: "T at the crank [N·m]", unit: "N·m", series: [{ name: "rigid model", values: e.rigid_torque_Nm }, { name: "elastic link", values: e.elastic_torque_Nm }] });
  }
  if (m.regulation) {
    const g = m.regulation;
    linePlot(box, "mac-regulation-speed", { title: "Speed after the load step", x: g.time_s, xLabel: "time [s]", yLabel: "n [rev/min]", unit: "rev/min",
      series: [{ name: "crank speed", values: g.crank_speed_rpm, colour: "#8a93a3" }, { name: "without the cycle's ripple", values: g.smoothed_speed_rpm }] });
    linePlot(box, "mac-regulation-torque", { title: "Torques after the load step", x: g.time_s, xLabel: "time [s]", yLabel: "T at the crank [N·m]", unit: "N·m",
      series: [{ name: "motor", values: g.motor_torque_Nm }, { name: "load (resisting)", values: g.load_torque_Nm.map((v) => -v) }] });
  }
}

document.addEventListener("machine-answer", (evt) => machineBlocks(evt.target, evt.detail));

admitted.then((ok) => { if (ok && panel) build(); });
