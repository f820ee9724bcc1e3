// The capability panels: each builds a request from the current design and its own fields, posts it to the
// public API and draws the answer. Nothing here computes what the service answers.
import { post, get, del, postFile, describe, leaves } from "./api.js";
import { linePlot, polarPlot, scatterPlot, fmt } from "./plot.js";
import { toModel, drawLinkage, layout } from "./draw.js";
import { h, s, put, table } from "./dom.js";
import { longStep, cancelled } from "./progress.js";

let ctx = null;

const LINKAGE_FIELDS = ["mechanism", "speed_rpm", "crank_acceleration_rad_s2", "samples", "crank_angle_deg", "gravity",
  "loads", "torques", "counterweights"];

/** The design's linkage part, as every mechanism endpoint takes it. */
function linkage() {
  const out = {};
  for (const k of LINKAGE_FIELDS) if (ctx.state.design[k] !== undefined && ctx.state.design[k] !== null) out[k] = structuredClone(ctx.state.design[k]);
  return out;
}

const FAMILY = { fourbar: "four-bar", slider_crank: "slider-crank", slotted_lever: "shaper (slotted lever)", linkage: "linkage" };

const ORDINALS = ["first", "second", "third", "fourth", "fifth", "sixth"];

/** A gear stage as every table and message of the page names it: "First", "Second", … (motor side first). */
export function stageName(k, { capital = true } = {}) {
  const w = ORDINALS[k] || `stage ${k + 1}`;
  return capital ? w.replace(/^./, (c) => c.toUpperCase()) : w;
}

/** What is left of a quantity below a billionth of its unbalanced size is rounding, read as zero. */
export const ZERO_FRACTION = 1e-9;

/** A value read as "0" when it is below ZERO_FRACTION of `scale` (round-off of a balance), else as fmt does. */
export function fmtZero(v, scale) { return Math.abs(v) <= ZERO_FRACTION * Math.abs(scale) ? "0" : fmt(v); }

/** A length [m] in the form's unit, rounded for reading. */
function L(v) { return `${fmt(v / ctx.factor("length"))} ${ctx.unitLabel("length")}`; }

/** One labelled input of a panel, described by the OpenAPI document (model, path); `kind` length or mass turns the
 *  form's units on. */
function field(prefix, { name, label, model, path, kind = "plain", value = "", options = null, choose = {} }) {
  const d = model ? describe(model, path || name, choose) : { text: "", unit: "" };
  const id = `${prefix}-${name}`;
  const unit = ctx.unitLabel(kind, d.unit);
  const shown = value === "" || value === null || value === undefined ? "" : (kind === "plain" ? String(value) : ctx.toDisplay(value, kind));
  let input;
  if (options) {
    input = h("select", { id, name, title: d.text }, options.map(([v, l]) => h("option", { value: v, selected: String(value) === String(v) }, l)));
  } else {
    // the schema's default as the placeholder: what an emptied field stands for
    const placeholder = typeof d.default === "number" ? (kind === "plain" ? String(d.default) : ctx.toDisplay(d.default, kind)) : "";
    input = h("input", { id, name, type: "text", inputmode: "decimal", autocomplete: "off", title: d.text, placeholder, dataset: { kind } });
    input.value = shown;
  }
  // a choice among numbers (a motor speed class) keeps its unit; a choice among names has none
  const numbers = options && model && ["number", "integer"].includes(d.type) && d.unit !== "–";
  return h("div", { class: "row", dataset: { field: name, range: model ? rangeText(d, kind) : "" } }, h("label", { for: id, title: d.text }, label), input,
    h("span", { class: "unit" }, options && !numbers ? "" : unit), h("p", { class: "msg", id: `${id}-msg`, hidden: true }));
}

/** A panel input's value in SI: null when empty, NaN when not a number. */
function read(prefix, name) {
  const el = document.getElementById(`${prefix}-${name}`);
  if (el.tagName === "SELECT") return el.value;
  const raw = el.value.trim().replace(",", ".");
  if (raw === "") return null;
  const v = Number(raw);
  return Number.isFinite(v) ? v * ctx.factor(el.dataset.kind) : NaN;
}

function clearPanel(prefix) {
  document.querySelectorAll(`[id^="${prefix}-"].msg, [id$="-msg"][id^="${prefix}-"]`).forEach((m) => { m.hidden = true; m.textContent = ""; });
  document.querySelectorAll(`[id^="${prefix}-"][aria-invalid]`).forEach((i) => i.removeAttribute("aria-invalid"));
  const p = document.getElementById(`${prefix}-problem`);
  if (p) { p.hidden = true; p.textContent = ""; }
}

/** Show a problem next to the panel field it names (the field's last name part that the panel has), else in the
 *  panel's problem box; a field of the linkage itself goes to the editor's form. */
function panelProblem(prefix, err) {
  clearPanel(prefix);
  ctx.showProblem(err, `${prefix}-problem`, (fieldName, message) => {
    if (!fieldName) return false;
    const parts = fieldName.replace(/\[(\d+)\]/g, ".$1").split(".");
    for (let n = 0; n < parts.length; n++) {
      const id = `${prefix}-${parts.slice(n).join(".")}`;
      const el = document.getElementById(id);
      if (el) {
        const m = document.getElementById(`${id}-msg`);
        m.textContent = message; m.hidden = false; el.setAttribute("aria-invalid", "true");
        const folded = el.closest("details");
        if (folded) folded.open = true;
        (el.closest(".row") || m).scrollIntoView({ block: "nearest", inline: "nearest" });
        return true;
      }
    }
    // a field of the linkage itself: marked in the editor's form too, and said in the panel
    ctx.showMessage(fieldName, message);
    return false;
  });
}

function checkNumbers(prefix, names) {
  let ok = true;
  for (const n of names) {
    const v = read(prefix, n);
    if (Number.isNaN(v)) {
      const m = document.getElementById(`${prefix}-${n}-msg`);
      m.textContent = "enter a number"; m.hidden = false;
      document.getElementById(`${prefix}-${n}`).setAttribute("aria-invalid", "true");
      ok = false;
    }
  }
  return ok;
}

/** Remember the design a panel's answer is for, so that opening the panel later can say when it has changed. */
function answered(panel) {
  const el = document.getElementById(`panel-${panel}`);
  el.dataset.design = JSON.stringify(ctx.state.design);
  el.querySelector(".stale")?.remove();
}

function busy(prefix, text) {
  const s = document.getElementById(`${prefix}-status`);
  if (s) s.textContent = text;
}

function download(blob, name) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob); a.download = name;
  document.body.appendChild(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 5000);
}

function summaryTable(rows, before, after) {
  return table(["", "before", "after"], rows.map(([k, label, unit]) =>
    [label, [`${fmt(before[k])} ${unit}`, { class: "num" }], [after ? `${fmtZero(after[k], before[k])} ${unit}` : "", { class: "num" }]]));
}

/** The buttons and status line under a panel's fields. */
function actions(...children) { return h("div", { class: "actions" }, children); }

const SUMMARY_ROWS = [["rms_shaking_force_N", "RMS shaking force", "N"], ["max_shaking_force_N", "peak shaking force", "N"],
  ["rms_shaking_moment_Nm", "RMS shaking moment", "N·m"], ["rms_driving_torque_Nm", "RMS driving torque", "N·m"],
  ["max_driving_torque_Nm", "peak driving torque", "N·m"], ["max_bearing_force_N", "largest bearing force", "N"]];

// --- balancing ---------------------------------------------------------------------------------------------------
function balancingPanel() {
  const el = document.getElementById("panel-balancing");
  const render = () => {
    const fam = ctx.state.design.mechanism.type;
    const modes = fam === "fourbar" ? [["static", "static: force zero"], ["full", "full: force, moment zero"], ["optimal", "optimal trade-off"]]
      : [["optimal", "optimal trade-off"]];
    const links = fam === "fourbar" ? ["crank", "rocker"] : fam === "slider_crank" ? ["crank"] : ["crank", "rocker"];
    put(el, h("h2", {}, "Balancing with counterweights"), h("div", { class: "controls" },
      field("bal", { name: "mode", label: "Mode", options: modes, value: modes[0][0] }),
      links.map((l) => field("bal", { name: `max_radius_m.${l}`, label: `Largest radius on the ${l}`, model: "BalanceIn", path: "max_radius_m", kind: "length" })),
      field("bal", { name: "mass_budget_kg", label: "Mass budget (optimal)", model: "BalanceIn", path: "mass_budget_kg", kind: "mass" }),
      field("bal", { name: "weights.shaking_force", label: "Weight: shaking force", model: "WeightsIn", path: "shaking_force", value: 1 }),
      field("bal", { name: "weights.shaking_moment", label: "Weight: shaking moment", model: "WeightsIn", path: "shaking_moment", value: 1 }),
      field("bal", { name: "weights.driving_torque", label: "Weight: driving torque", model: "WeightsIn", path: "driving_torque", value: 0 })),
    actions(h("button", { class: "run", id: "bal-run", onclick: run }, "Balance"),
      h("button", { class: "secondary", id: "bal-apply", disabled: true, onclick: apply }, "Put these counterweights on the design"),
      h("span", { id: "bal-status", class: "note" })),
    h("p", { id: "bal-problem", class: "problem", hidden: true }), h("div", { id: "bal-result" }), h("div", { id: "bal-plots", class: "plots" }));
  };
  let answer = null;
  const request = (mode) => {
    const fam = ctx.state.design.mechanism.type;
    const body = { ...linkage() };
    const radii = {};
    for (const l of (fam === "slider_crank" ? ["crank"] : ["crank", "rocker"])) {
      const v = read("bal", `max_radius_m.${l}`);
      if (v !== null) radii[l] = v;
    }
    body.max_radius_m = radii;
    if (mode === "optimal") {
      body.weights = { shaking_force: read("bal", "weights.shaking_force") ?? 0, shaking_moment: read("bal", "weights.shaking_moment") ?? 0,
        driving_torque: read("bal", "weights.driving_torque") ?? 0 };
      const budget = read("bal", "mass_budget_kg");
      if (budget !== null) body.mass_budget_kg = budget;
      // the trade-off curve: from all force to all moment, each point re-analysed by the service
      body.sweep = [0, 0.25, 0.5, 0.75, 1].map((t) => ({ shaking_force: 1 - t, shaking_moment: t }));
    }
    return body;
  };
  async function run() {
    clearPanel("bal");
    const mode = read("bal", "mode");
    if (!checkNumbers("bal", ["mass_budget_kg", "weights.shaking_force", "weights.shaking_moment", "weights.driving_torque"])) return;
    busy("bal", "balancing…");
    try {
      answer = await post(`/v1/balancing/${mode}`, request(mode));
      await show(answer);
      answered("balancing");
      busy("bal", "");
      document.body.dataset.balanced = mode;
    } catch (err) { busy("bal", ""); panelProblem("bal", err); }
  }
  async function show(ans, picked = -1) {
    answer = ans;
    // the balanced linkage analysed again by the service: the before/after curves
    const before = ctx.state.answer;
    const after = await post("/v1/analysis", { ...linkage(), balancing: ans });
    const res = document.getElementById("bal-result");
    const num = (t) => [t, { class: "num" }];
    put(res, h("h3", {}, `${ans.mode} balance: ${ans.counterweights.length} counterweight(s), ${fmt(ans.total_added_mass_kg)} kg added`),
      table(["link", "mass", "radius", "angle"], ans.placements.map((p, n) =>
        [p.link, num(`${fmt(ans.counterweights[n].mass_kg)} kg`), num(L(p.radius_m)), num(`${fmt(p.angle_deg)}°`)])),
      ans.counter_rotors ? h("p", {}, `Counter-rotors: ${ans.counter_rotors.map((r) => `${r.link} ${fmt(r.inertia_kgm2)} kg·m² at −${fmt(r.ratio)}×`).join(", ")}` +
        (ans.coupler_inertia_kgm2 !== null ? `; coupler inertia about its centre ${fmt(ans.coupler_inertia_kgm2)} kg·m²` : "")) : null,
      summaryTable(SUMMARY_ROWS, ans.summary_before, ans.summary_after),
      h("p", { class: "note" }, `Check: residual shaking force ${fmtZero(ans.checks.residual_shaking_force_N, ans.summary_before.max_shaking_force_N)} N, ` +
        `residual shaking moment ${fmtZero(ans.checks.residual_shaking_moment_Nm, ans.summary_before.rms_shaking_moment_Nm)} N·m ` +
        "(the balanced linkage re-analysed by the service)."));
    const box = document.getElementById("bal-plots");
    box.replaceChildren();
    const x = after.crank_angle_deg;
    polarPlot(box, "bal-polar", { title: "Shaking force: before and after", unit: "N",
      series: Object.assign([{ name: "before", points: before.shaking_force_N, colour: "#8a93a3" }, { name: "after", points: after.shaking_force_N, colour: "#1f5fbf" }], { angles: x }) });
    document.getElementById("bal-polar").dataset.afterRadius = Math.max(...after.shaking_force_N.map((p) => Math.hypot(p[0], p[1])));
    document.getElementById("bal-polar").dataset.beforeRadius = Math.max(...before.shaking_force_N.map((p) => Math.hypot(p[0], p[1])));
    linePlot(box, "bal-moment", { title: "Shaking moment: before and after", x, xLabel: "crank angle φ [°]", yLabel: "M [N·m]", unit: "N·m",
      series: [{ name: "before", values: before.shaking_moment_Nm, colour: "#8a93a3" }, { name: "after", values: after.shaking_moment_Nm, colour: "#1f5fbf" }] });
    linePlot(box, "bal-torque", { title: "Driving torque: before and after", x, xLabel: "crank angle φ [°]", yLabel: "T [N·m]", unit: "N·m",
      series: [{ name: "before", values: before.driving_torque_Nm, colour: "#8a93a3" }, { name: "after", values: after.driving_torque_Nm, colour: "#1f5fbf" }] });
    if (ans.tradeoff && ans.tradeoff.length) {
      scatterPlot(box, "bal-tradeoff", { title: "Trade-off sweep (click a point to open its design)", line: true, highlight: [picked],
        xLabel: "RMS shaking force [N]", yLabel: "RMS shaking moment [N·m]",
        points: ans.tradeoff.map((t) => ({ x: t.summary_after.rms_shaking_force_N, y: t.summary_after.rms_shaking_moment_Nm, design: t,
          label: `force weight ${fmt(t.weights.shaking_force)}, moment weight ${fmt(t.weights.shaking_moment)}` })),
        onPick: (p, n) => show({ ...p.design, tradeoff: ans.tradeoff }, n) });
    }
    document.getElementById("bal-apply").disabled = false;
  }
  function apply() {
    if (!answer) return;
    const d = structuredClone(ctx.state.design);
    d.counterweights = [...(d.counterweights || []), ...answer.counterweights];
    if (answer.counter_rotors) d.counter_rotors = [...(d.counter_rotors || []), ...answer.counter_rotors.map((r) => ({ link: r.link, inertia_kgm2: r.inertia_kgm2, ratio: r.ratio }))];
    if (answer.coupler_inertia_kgm2 !== null && answer.coupler_inertia_kgm2 !== undefined) d.coupler_inertia_kgm2 = answer.coupler_inertia_kgm2;
    ctx.setDesign(d);
    ctx.selectTab("mechanism");
  }
  return render;
}

// --- flywheel ----------------------------------------------------------------------------------------------------
// The flywheel request's fields the panel's first rows hold, and the linkage (the editor's: its speed is the mean
// speed, its tables the alternative to a linkage).
const FLYWHEEL_OWN = [...LINKAGE_FIELDS, "tables", "cycle_deg", "mean_speed_rpm", "mean_speed_rad_s", "delta", "machine_type",
  "geometry.shape", "geometry.density_kg_m3", "geometry.max_rim_speed_m_s"];
const FLYWHEEL_LABELS = { "motor.synchronous_speed_rpm": "Motor synchronous speed", "motor.rated_speed_rpm": "Motor rated speed",
  "motor.rated_torque_Nm": "Motor rated torque", "motor.gear_ratio": "Gear ratio (motor over crank)", "motor.rotor_inertia_kgm2": "Rotor inertia",
  "elastic_drive.stiffness_Nm_rad": "Elastic link stiffness at the crank", "elastic_drive.damping_ratio": "Elastic link damping ratio",
  "elastic_drive.flywheel_on": "Flywheel on", "elastic_drive.start": "Simulate the run-up" };

function flywheelPanel() {
  const el = document.getElementById("panel-flywheel");
  let types = [];
  const render = async () => {
    if (!types.length) { try { types = await get("/v1/machine-types"); } catch { types = []; } }
    put(el, h("h2", {}, "Flywheel"), h("div", { class: "controls" },
      field("fly", { name: "delta", label: "Target δ (empty: machine type)", model: "FlywheelIn", path: "delta", value: 0.05 }),
      field("fly", { name: "machine_type", label: "Machine type", options: [["", "–"], ...types.map((t) => [t.machine_type, `${t.label} (δ ≤ ${fmt(t.default_delta, 3)})`])], value: "" }),
      field("fly", { name: "geometry.shape", label: "Shape", options: [["rim", "rim on spokes"], ["disc", "solid disc"]], value: "rim" }),
      field("fly", { name: "geometry.density_kg_m3", label: "Density", model: "GeometryIn", path: "density_kg_m3", value: 7200 }),
      field("fly", { name: "geometry.max_rim_speed_m_s", label: "Largest rim speed", model: "GeometryIn", path: "max_rim_speed_m_s", value: 30 })),
    schemaFields("fly", "FlywheelIn", { skip: FLYWHEEL_OWN, labels: FLYWHEEL_LABELS, folds: { "": "Cycle and inertia on the crank",
      motor: "Motor", geometry: "Flywheel body", elastic_drive: "Elastic drive", friction: "Friction" } }),
    actions(h("button", { class: "run", id: "fly-run", onclick: run }, "Size the flywheel"), h("span", { id: "fly-status", class: "note" })),
    h("p", { id: "fly-problem", class: "problem", hidden: true }), h("div", { id: "fly-result" }), h("div", { id: "fly-plots", class: "plots" }));
  };
  async function run() {
    clearPanel("fly");
    if (!checkNumbers("fly", ["delta", "geometry.density_kg_m3", "geometry.max_rim_speed_m_s"])) return;
    if (!checkSchemaFields("flywheel")) return;
    const body = linkage();
    body.mean_speed_rpm = body.speed_rpm; delete body.speed_rpm;
    const delta = read("fly", "delta"), type = read("fly", "machine_type");
    if (delta !== null) body.delta = delta;
    if (type) body.machine_type = type;
    body.geometry = { shape: read("fly", "geometry.shape"), density_kg_m3: read("fly", "geometry.density_kg_m3"),
      max_rim_speed_m_s: read("fly", "geometry.max_rim_speed_m_s") };
    // the folded fields: sent when filled, else the API's default (no motor, no link)
    collectSchemaFields("flywheel", body);
    busy("fly", "sizing…");
    try {
      const a = await post("/v1/flywheel", body);
      answered("flywheel");
      busy("fly", "");
      show(a);
    } catch (err) { busy("fly", ""); panelProblem("fly", err); }
  }
  function show(a) {
    const g = a.geometry && a.geometry.best;
    const res = document.getElementById("fly-result");
    const num = (t) => [t, { class: "num" }];
    const rpm = (w) => (w * 30) / Math.PI;
    put(res, table(null, [["Flywheel inertia to add", num(`${fmt(a.flywheel_inertia_kgm2)} kg·m²`)],
      ["Target δ / simulated δ (check)", num(`${fmt(a.target_delta)} / ${fmt(a.achieved_delta)}`)],
      ["Crank speed band", num(`${fmt(rpm(a.omega_min_rad_s))} … ${fmt(rpm(a.omega_max_rad_s))} rev/min`)],
      ...(g ? [[`Body (${g.shape}) on the ${g.shaft} shaft`, num(`outer D = ${L(g.outer_diameter_m)} (mean ${L(g.diameter_m)}), ` +
        `b = ${L(g.width_m)}, m = ${fmt(g.mass_kg)} kg, rim speed ${fmt(g.rim_speed_m_s)} m/s`)]] : [])]));
    const box = document.getElementById("fly-plots");
    box.replaceChildren();
    const sp = a.speed;
    linePlot(box, "fly-speed", { title: "Crank speed over the cycle, within its band", x: sp.crank_angle_deg, xLabel: "crank angle φ [°]",
      yLabel: "n [rev/min]", unit: "rev/min", series: [{ name: "n", values: sp.omega_rad_s.map(rpm) }],
      limits: [{ y: rpm(a.mean_speed_rad_s * (1 + a.target_delta / 2)), label: "n_mean(1+δ/2)" }, { y: rpm(a.mean_speed_rad_s * (1 - a.target_delta / 2)), label: "n_mean(1−δ/2)" }] });
    const em = a.energy_mass;
    const plot = scatterPlot(box, "fly-energy-mass", { title: "Energy-mass diagram (Wittenbauer) with its tangents", xLabel: "J_red [kg·m²]", yLabel: "ΔA [J]",
      points: em.reduced_inertia_kgm2.map((j, n) => ({ x: j, y: em.excess_work_J[n], label: `φ = ${fmt(em.crank_angle_deg[n])}°` })).filter((_, n) => n % 4 === 0) });
    const svg = plot.el.querySelector("svg");
    svg.querySelectorAll("circle.pick").forEach((c) => { c.setAttribute("r", 2); c.removeAttribute("tabindex"); });
    const js = em.reduced_inertia_kgm2, x0 = Math.min(...js), x1 = Math.max(...js);
    for (const [k, b, colour] of [[em.tangent_max_slope_J_per_kgm2, em.tangent_max_intercept_J, "#1b7a3a"], [em.tangent_min_slope_J_per_kgm2, em.tangent_min_intercept_J, "#b3261e"]]) {
      const l = document.createElementNS("http://www.w3.org/2000/svg", "line");
      l.setAttribute("x1", plot.X(x0)); l.setAttribute("x2", plot.X(x1)); l.setAttribute("y1", plot.Y(k * x0 + b)); l.setAttribute("y2", plot.Y(k * x1 + b));
      l.setAttribute("stroke", colour); l.setAttribute("stroke-width", "1.2"); l.setAttribute("clip-path", plot.clip);
      svg.appendChild(l);
    }
    if (g) drawBody(box, g);
    if (a.elastic_drive) showElastic(res, box, a.elastic_drive);
  }
  /** The drive through the elastic link with the sized flywheel: its mode, the link's torque against the rigid
   *  model's, and the load harmonics near the mode. */
  function showElastic(res, box, e) {
    const num = (t) => [t, { class: "num" }];
    const near = e.harmonics.filter((x) => x.near_resonance);
    res.appendChild(h("h3", {}, "Elastic drive with this flywheel"));
    res.appendChild(table(null, [["Link stiffness at the crank", num(`${fmt(e.stiffness_Nm_rad)} N·m/rad`)],
      ["J1 (rotor side) / J2 (machine, mean)", num(`${fmt(e.rotor_inertia_kgm2)} / ${fmt(e.machine_inertia_kgm2[0])} kg·m²`)],
      ["Natural frequency (over the cycle)", num(`${fmt(e.natural_frequency_Hz)} Hz (${fmt(e.natural_frequency_range_Hz[0])} … ${fmt(e.natural_frequency_range_Hz[1])})`)],
      ["Peak torque in the link / rigid model", num(`${fmt(e.peak_elastic_torque_Nm)} / ${fmt(e.peak_rigid_torque_Nm)} N·m`)],
      ["Dynamic factor", num(fmt(e.dynamic_factor))],
      ["Load harmonics near resonance", num(near.length ? near.map((x) => `${x.order} (${fmt(x.frequency_Hz)} Hz)`).join(", ") : "none")]], { id: "fly-elastic-table" }));
    if (e.warnings.length) res.appendChild(h("ul", { id: "fly-elastic-warnings", class: "warnings" }, e.warnings.map((w) => h("li", {}, w.message))));
    linePlot(box, "fly-elastic", { title: "Torque in the elastic link over the steady cycle", x: e.crank_angle_deg, xLabel: "crank angle φ [°]",
      yLabel: "T at the crank [N·m]", unit: "N·m", series: [{ name: "rigid model", values: e.rigid_torque_Nm }, { name: "elastic link", values: e.elastic_torque_Nm }] });
    if (e.start) {
      linePlot(box, "fly-elastic-start", { title: "Run-up from rest through the link", x: e.start.time_s, xLabel: "time [s]", yLabel: "n [rev/min]", unit: "rev/min",
        series: [{ name: "rotor (at the crank)", values: e.start.rotor_speed_rpm }, { name: "crank", values: e.start.crank_speed_rpm }] });
    }
  }
  function drawBody(box, g) {
    const R = g.outer_diameter_m / 2, r = g.shape === "rim" ? R - g.rim_thickness_m : 0, b = g.width_m;
    const W = 2 * R + b * 3, H = 2 * R * 1.25, sw = R / 60;
    const ink = { fill: "#dfe7f3", stroke: "#2d3e5c", "stroke-width": sw };
    const spokes = r > 0 ? [0, 60, 120].map((a) => s("line", { x1: -r * Math.cos(a * Math.PI / 180), y1: -r * Math.sin(a * Math.PI / 180),
      x2: r * Math.cos(a * Math.PI / 180), y2: r * Math.sin(a * Math.PI / 180), stroke: "#2d3e5c", "stroke-width": sw * 3 })) : [];
    box.appendChild(h("div", { class: "plot", id: "fly-body" }, h("h4", {}, `The flywheel (${g.shape}): front and section`),
      s("svg", { viewBox: `${-R * 1.1} ${-R * 1.2} ${W} ${H}`, role: "img", "aria-label": "flywheel drawing" },
        s("circle", { cx: 0, cy: 0, r: R, ...ink }),
        r > 0 ? s("circle", { cx: 0, cy: 0, r, ...ink, fill: "#fff" }) : null, spokes,
        s("circle", { cx: 0, cy: 0, r: R * 0.08, ...ink, fill: "#fff" }),
        s("rect", { x: R * 1.3, y: -R, width: b, height: 2 * R, ...ink }),
        r > 0 ? s("rect", { x: R * 1.3 + b * 0.35, y: -r, width: b * 0.3, height: 2 * r, ...ink, fill: "#fff" }) : null,
        s("text", { x: 0, y: R * 1.08, "text-anchor": "middle", style: { fontSize: `${R / 9}px` } }, `D = ${L(g.outer_diameter_m)}`),
        s("text", { x: R * 1.3 + b / 2, y: -R * 1.06, "text-anchor": "middle", style: { fontSize: `${R / 9}px` } }, `b = ${L(b)}`))));
  }
  return render;
}

// --- drive -------------------------------------------------------------------------------------------------------
// The drive request's fields the panel's first rows hold.
const DRIVE_OWN = ["output_power_W", "output_speed_rpm", "stages"];
const DRIVE_LABELS = { "strength.life_h": "Required life", "strength.application_factor": "Application factor K_A",
  "strength.min_safety_contact": "Least S_H", "strength.min_safety_root": "Least S_F", "strength.pinion_material": "Pinion material",
  "strength.gear_material": "Gear material", "strength.helix_angle_deg": "Helix angle", "strength.pinion_teeth": "Pinion teeth",
  "strength.accuracy_grade": "Accuracy grade (ISO 1328)", "strength.oil_viscosity_40C_mm2_s": "Oil viscosity at 40 °C",
  "strength.module_series": "Module series", "strength.objective": "Sized for", "output_speed_rad_s": "Or the crank speed in rad/s" };

/** A stage as the tables name it: "First (21/95)", its tooth pair built. */
function stageLabel(k, teeth) { return teeth ? `${stageName(k)} (${teeth[0]}/${teeth[1]})` : stageName(k); }

/** The drive to build, one row per stage: the split's ratio, the teeth built (the sized pair's when the gears are
 *  sized for strength, else the pair nearest the split) and how far the built ratio lies from the split's. */
function driveTable(split, built, efficiencies) {
  const num = (t) => [t, { class: "num" }];
  return table(["stage", "ratio (split)", "teeth built", "ratio built", "from the split", "efficiency"], split.map((u, k) => {
    const b = built[k];
    return [stageLabel(k, b && b.teeth), num(fmt(u)), num(b ? `${b.teeth[0]} / ${b.teeth[1]}` : "–"), num(b ? fmt(b.ratio, 5) : "–"),
      num(b ? `${b.ratio >= u ? "+" : ""}${fmt(100 * (b.ratio / u - 1), 3)} %` : "–"), num(efficiencies ? fmt(efficiencies[k]) : "–")];
  }), { class: "drive-built" });
}

/** The stages of a drive answer sized for strength: module, width, safety factors, mass (their teeth are the drive
 *  table's). */
function sizedGears(d) {
  const num = (t) => [t, { class: "num" }];
  const pair = (xs) => xs.map((x) => fmt(x, 3)).join(" / ");
  return [h("h3", {}, "Gears sized for strength (ISO 6336)"),
    table(["stage", "module", "face width", "centre distance", "S_H pinion / gear", "S_F pinion / gear", "width set by", "mass"],
      d.gears.map((g, n) => (g === null ? [stageName(n), "not a cylindrical pair", "", "", "", "", "", ""] : [stageLabel(g.stage, [g.pinion_teeth, g.gear_teeth]),
        num(`${fmt(g.module_mm)} mm`), num(`${fmt(g.face_width_mm, 4)} mm`),
        num(`${fmt(g.centre_distance_mm, 5)} mm`), num(pair(g.safety_contact)), num(pair(g.safety_root)),
        g.binding.replace(/_/g, " "), num(`${fmt(g.mass_kg, 4)} kg`)]))),
    h("p", {}, `Wheels' mass ${fmt(d.gear_mass_kg, 4)} kg (solid discs of the reference diameters).`)];
}

function drivePanel() {
  const el = document.getElementById("panel-drive");
  const render = () => {
    const a = ctx.state.answer;
    // The mean power the crank takes, read off the analysis answer as a starting value the user may change.
    const w = (ctx.state.design.speed_rpm * Math.PI) / 30;
    const mean = a ? a.driving_torque_Nm.reduce((s, v) => s + v, 0) / a.driving_torque_Nm.length * w : 1000;
    const folds = schemaFields("drv", "DriveIn", { skip: DRIVE_OWN, labels: DRIVE_LABELS, folds: { "": "Motor, split and inertias", strength: "Gear strength (ISO 6336)" } });
    folds.find((d) => d.id === "drv-more-strength")?.querySelector(".controls")
      .prepend(field("drv", { name: "size_gears", label: "Size the gears for strength", options: [["false", "no"], ["true", "yes"]], value: "false" }));
    put(el, h("h2", {}, "Drive: motor, ratio split, teeth"), h("div", { class: "controls" },
      field("drv", { name: "output_power_W", label: "Power at the crank", model: "DriveIn", path: "output_power_W", value: Math.max(1, Number(mean.toPrecision(4))) }),
      field("drv", { name: "output_speed_rpm", label: "Crank speed", model: "DriveIn", path: "output_speed_rpm", value: ctx.state.design.speed_rpm }),
      field("drv", { name: "stages", label: "Gear stages", options: [["1", "1 helical"], ["2", "2 helical"], ["3", "3 helical"]], value: "2" })),
    folds,
    actions(h("button", { class: "run", id: "drv-run", onclick: run }, "Design the drive"), h("span", { id: "drv-status", class: "note" })),
    h("p", { id: "drv-problem", class: "problem", hidden: true }), h("div", { id: "drv-result" }));
  };
  async function run() {
    clearPanel("drv");
    const sized = read("drv", "size_gears") === "true";
    // the strength block is sent only when the gears are sized: its fields when filled (else the API's defaults)
    const unsized = (path) => !sized && path.startsWith("strength.");
    if (!checkNumbers("drv", ["output_power_W", "output_speed_rpm"]) || !checkSchemaFields("drive", unsized)) return;
    const stages = Array(Number(read("drv", "stages"))).fill("helical");
    const body = { output_power_W: read("drv", "output_power_W"), stages };
    if (read("drv", "output_speed_rpm") !== null) body.output_speed_rpm = read("drv", "output_speed_rpm");
    if (sized) body.strength = {};
    collectSchemaFields("drive", body, unsized);
    busy("drv", "designing…");
    try {
      const d = await post("/v1/gears/drive", body);
      // the teeth built: the sized pairs when the gears are sized for strength; else the pair nearest each stage's
      // share of the split, one search per stage
      let built;
      if (d.gears) {
        built = d.gears.map((g) => (g ? { teeth: [g.pinion_teeth, g.gear_teeth], ratio: g.ratio } : null));
      } else {
        const teeth = await Promise.all(d.stage_ratios.map((r) => post("/v1/gears/teeth", { total_ratio: r, stages: 1 })));
        built = teeth.map((t) => ({ teeth: [t.stages[0].pinion_teeth, t.stages[0].gear_teeth], ratio: t.stages[0].ratio }));
      }
      busy("drv", "");
      answered("drive");
      const res = document.getElementById("drv-result");
      const num = (t) => [t, { class: "num" }];
      const total = built.reduce((p, b, k) => p * (b ? b.ratio : d.stage_ratios[k]), 1);
      put(res, h("h3", {}, `Motor ${d.motor.name}: ${fmt(d.motor.rated_power_W / 1000)} kW at ${fmt(d.motor.rated_rpm)} rev/min; required ${fmt(d.required_power_W / 1000)} kW`),
        h("h3", {}, d.gears ? "The drive to build: the teeth sized for strength" : "The drive to build: the teeth nearest the split"),
        driveTable(d.stage_ratios, built, d.stage_efficiencies),
        h("p", { id: "drv-total" }, `Total ratio built ${fmt(total, 5)}; the split's ${fmt(d.total_ratio, 5)} ` +
          `(${total >= d.total_ratio ? "+" : ""}${fmt(100 * (total / d.total_ratio - 1), 3)} %): the crank turns at ${fmt(d.output_speed_rpm * d.total_ratio / total)} rev/min.`),
        h("h3", {}, "Shafts"),
        table(["shaft", "speed", "torque", "power"], d.shafts.map((sh, n) => [n === 0 ? "motor" : n === d.shafts.length - 1 ? "crank" : `after the ${stageName(n - 1, { capital: false })} stage`,
          num(`${fmt(sh.speed_rpm)} rev/min`), num(`${fmt(sh.torque_Nm)} N·m`), num(`${fmt(sh.power_W)} W`)])),
        h("p", { class: "note" }, `Check: power balance error ${fmt(d.checks.power_balance_error)}; kinetic energy ${fmt(d.checks.kinetic_energy_J)} J = reduced ${fmt(d.checks.reduced_kinetic_energy_J)} J. ` +
          "Shafts at the split's ratios."),
        d.gears ? sizedGears(d) : null,
        (d.warnings || []).map((w) => h("p", { class: "note" }, `⚠ ${w.message}`)));
    } catch (err) { busy("drv", ""); panelProblem("drv", err); }
  }
  return render;
}

// --- the whole machine -------------------------------------------------------------------------------------------
const STAGE_COUNTS = [1, 2, 3, 4, 5, 6];
const STAGE_LABELS = { type: "type", ratio_min: "ratio from", ratio_max: "ratio to", efficiency: "efficiency", ratio: "fixed ratio" };
// The machine request's less common fields, by where they are folded away: path in MachineIn, label.
const MACHINE_MORE = {
  drive: [["drive.motor", "Motor (catalogue name)"], ["drive.reserve_factor", "Power reserve factor"], ["drive.objective", "Ratio split"],
    ["drive.max_teeth", "Largest wheel (teeth)"], ["drive.min_teeth", "Smallest wheel (teeth)"], ["drive.tooth_tolerance", "Ratio tolerance of the teeth"],
    ["drive.pinion_inertia_kgm2", "Pinion inertia"], ["drive.load_inertia_kgm2", "Extra inertia on the crank shaft"]],
  other: [["balancing.mass_budget_kg", "Mass budget (optimal)"], ["flywheel.placement", "Flywheel on"], ["flywheel.geometry.shape", "Flywheel shape"],
    ["flywheel.geometry.density_kg_m3", "Flywheel density"], ["flywheel.geometry.max_rim_speed_m_s", "Largest rim speed"],
    ["flywheel.geometry.max_diameter_m", "Largest flywheel diameter"], ["speed_tolerance", "Mean speed tolerance"]],
  running: [["start_under_load", "Starts under load"], ["max_startup_time_s", "Longest run-up"], ["max_rundown_time_s", "Longest run-down"],
    ["brake_torque_Nm", "Brake torque at the crank"]],
  strength: [["drive.size_gears", "Size the gears for strength"], ["drive.strength.life_h", "Required life"],
    ["drive.strength.application_factor", "Application factor K_A"], ["drive.strength.min_safety_contact", "Least S_H"],
    ["drive.strength.min_safety_root", "Least S_F"], ["drive.strength.pinion_material", "Pinion material"], ["drive.strength.gear_material", "Gear material"],
    ["drive.strength.helix_angle_deg", "Helix angle"], ["drive.strength.pinion_teeth", "Pinion teeth"], ["drive.strength.accuracy_grade", "Accuracy grade (ISO 1328)"],
    ["drive.strength.oil_viscosity_40C_mm2_s", "Oil viscosity at 40 °C"], ["drive.strength.module_series", "Module series"]],
  around: [["elastic_drive.stiffness_Nm_rad", "Elastic link stiffness at the crank"], ["elastic_drive.damping_ratio", "Elastic link damping ratio"],
    ["elastic_drive.max_dynamic_factor", "Largest dynamic factor"], ["regulation.load_step_Nm", "Load step at the crank"],
    ["regulation.max_settling_time_s", "Longest settling after the step"]],
};
// Labels the office reads better than the manual's first clause; every other field of the request is labelled
// from its description.
const MACHINE_LABELS = Object.fromEntries(Object.values(MACHINE_MORE).flat());
const MACHINE_FOLDS = { "": "Machine type, speed, start-up and run-down, name", drive: "Drive: motor, split and teeth",
  balancing: "Balancing", flywheel: "Flywheel", title_block: "Title block of the record", foundation: "Foundation",
  elastic_drive: "Elastic drive", regulation: "Load step and speed regulation", friction: "Friction",
  strength: "Parts sized for strength: links, pins, bearings, crank shaft and keys (any field filled sizes them)" };
// The fields the panel's first rows hold, and the linkage (the editor's).
const MACHINE_OWN = [...LINKAGE_FIELDS, "delta", "balancing.mode", "drive.synchronous_rpm", "drive.stages", "alternatives"];

// Lists the service keeps, offered as choices for fields that name one of their entries.
const CATALOGUES = [[/_material$/, "/v1/gears/materials", (m) => [m.name, `${m.name.replace(/_/g, " ")}: ${m.description}`]],
  [/(^|\.)motor(\.name)?$/, "/v1/gears/motors", (m) => [m.name, `${m.name}: ${fmt(m.rated_power_W / 1000)} kW, ${fmt(m.rated_rpm)} rev/min`]],
  [/(^|\.)machine_type$/, "/v1/machine-types", (t) => [t.machine_type, `${t.label} (δ ≤ ${fmt(t.default_delta, 3)})`]]];
const catalogues = {};

/** Fetch the service's catalogues the panels offer as choices, once. */
async function loadCatalogues() {
  await Promise.all(CATALOGUES.map(async ([, url]) => {
    if (catalogues[url]) return;
    try { catalogues[url] = await get(url); } catch { catalogues[url] = []; }
  }));
}

/** A field's label when the panel gives none: its description's first clause. */
function labelOf(d, path) {
  const first = (d.text || "").split(/(?:\. |; |: | \[|\.$)/)[0].trim();
  const name = path.split(".").pop().replace(/_/g, " ");
  return first && first.length <= 60 ? first : name;
}

/** "at least 1e-06, less than 1" in the field's unit, for the field's tooltip. */
function rangeText(d, kind) {
  const b = d.bounds, show = (v) => (kind === "plain" ? fmt(v) : ctx.toDisplay(v, kind));
  const lo = b.minimum !== undefined ? `≥ ${show(b.minimum)}` : b.exclusiveMinimum !== undefined ? `> ${show(b.exclusiveMinimum)}` : "";
  const hi = b.maximum !== undefined ? `≤ ${show(b.maximum)}` : b.exclusiveMaximum !== undefined ? `< ${show(b.exclusiveMaximum)}` : "";
  return [lo, hi].filter(Boolean).join(", ");
}

/** A field of a request described by the manual, whatever the schema's shape: a choice for an enumeration, a yes/no
 *  or an entry of one of the service's catalogues; a number with its unit (a length or a mass in the form's unit)
 *  and its range; a list of numbers; JSON for a table of objects. Left empty, the API's default stands (shown as
 *  the placeholder). */
function schemaField(prefix, { path, label = null, schema = null, value = "" }) {
  const [model, sp] = schema || ["MachineIn", path];
  const d = describe(model, sp);
  const baseUnit = d.unit === "list" ? "–" : d.unit.replace(/, list$/, "");
  const kind = baseUnit === "m" ? "length" : baseUnit === "kg" ? "mass" : "plain";
  const id = `${prefix}-${path}`;
  const dflt = d.default;
  const range = rangeText(d, kind);
  const shownDefault = dflt === undefined || dflt === null ? "" : typeof dflt === "number" ? (kind === "plain" ? fmt(dflt) : ctx.toDisplay(dflt, kind))
    : typeof dflt === "object" ? JSON.stringify(dflt) : String(dflt);
  const title = [d.text, range && `Range: ${range}.`, shownDefault && `Default: ${shownDefault}.`].filter(Boolean).join(" ");
  const catalogue = d.type === "string" && !d.choices.length ? CATALOGUES.find(([re]) => re.test(sp)) : null;
  const choices = d.choices.length ? d.choices.map((v) => [String(v), typeof v === "boolean" ? (v ? "yes" : "no") : String(v).replace(/_/g, " ")])
    : catalogue ? (catalogues[catalogue[1]] || []).map(catalogue[2]) : [];
  const type = d.type === "array" || d.type === "object" ? (d.unit === "JSON" ? "json" : "list") : d.type;
  let input;
  const data = { path, type, kind, unit: d.unit };
  if (choices.length) {
    input = h("select", { id, name: path, title, dataset: data },
      h("option", { value: "" }, shownDefault ? `default (${shownDefault.replace(/_/g, " ")})` : "default"),
      choices.map(([v, l]) => h("option", { value: v, selected: String(value) === v }, l)));
  } else if (type === "json") {
    input = h("textarea", { id, name: path, title, rows: 2, spellcheck: "false", placeholder: shownDefault, dataset: data });
    if (value !== "") input.value = JSON.stringify(value);
  } else {
    const list = type === "list";
    input = h("input", { id, name: path, type: "text", autocomplete: "off", title, inputmode: type === "string" || list ? "text" : "decimal",
      placeholder: list && Array.isArray(dflt) ? dflt.map((v) => (kind === "plain" ? fmt(v) : ctx.toDisplay(v, kind))).join(", ") : shownDefault,
      dataset: data });
    if (value !== "") input.value = String(value);
  }
  const unit = choices.length ? "" : type === "string" ? "" : type === "json" ? "JSON" : ctx.unitLabel(kind, baseUnit) + (type === "list" ? " (list)" : "");
  return h("div", { class: "row", dataset: { field: path, range } }, h("label", { for: id, title }, label || labelOf(d, sp)), input,
    h("span", { class: "unit" }, unit), h("p", { class: "msg", id: `${id}-msg`, hidden: true }));
}

/** Every field of a request model the panel does not fill another way, folded by the object it belongs to:
 *  `labels` names some, `folds` titles the groups ("" the model's own top-level fields). */
function schemaFields(prefix, model, { skip = [], labels = {}, folds = {}, open = false } = {}) {
  const groups = new Map();
  for (const { path, group } of leaves(model, skip)) {
    if (!groups.has(group)) groups.set(group, []);
    groups.get(group).push(schemaField(prefix, { path, label: labels[path] || null, schema: [model, path] }));
  }
  return [...groups.entries()].map(([group, rows]) => h("details", { class: "more", id: `${prefix}-more-${group || "other"}`, dataset: { group }, open },
    h("summary", {}, folds[group] || (group ? group.replace(/_/g, " ").replace(/^./, (c) => c.toUpperCase()) : "More")),
    h("div", { class: "controls" }, rows)));
}

/** A schema field's value for the request: undefined when left empty, NaN when it cannot be read. */
function readSchemaField(input) {
  const raw = input.value.trim();
  if (raw === "") return undefined;
  const t = input.dataset.type;
  const f = ctx.factor(input.dataset.kind || "plain");
  if (t === "boolean") return raw === "true";
  if (t === "string") return raw;
  if (t === "json") { try { return JSON.parse(raw); } catch { return NaN; } }
  if (t === "list") {
    if (raw.startsWith("[")) { try { return JSON.parse(raw).map((v) => v * f); } catch { return NaN; } }
    const vs = raw.split(/[;,\s]+/).filter(Boolean).map((v) => Number(v.replace(",", ".")));
    return vs.every(Number.isFinite) ? vs.map((v) => v * f) : NaN;
  }
  const v = Number(raw.replace(",", "."));
  if (!Number.isFinite(v)) return NaN;
  return t === "integer" ? Math.round(v) : v * f;
}

function checkSchemaFields(panel, skip = () => false) {
  let ok = true;
  document.querySelectorAll(`#panel-${panel} [data-path]`).forEach((input) => {
    if (skip(input.dataset.path)) return;
    const v = readSchemaField(input);
    if (!(typeof v === "number" && Number.isNaN(v))) return;
    const m = document.getElementById(`${input.id}-msg`);
    const t = input.dataset.type;
    m.textContent = t === "json" ? "enter JSON" : t === "list" ? "enter numbers separated by commas" : "enter a number"; m.hidden = false;
    input.setAttribute("aria-invalid", "true");
    const folded = input.closest("details");
    if (folded) folded.open = true;
    ok = false;
  });
  return ok;
}

/** The panel's schema fields into a request body (`skip` a path to leave out). */
function collectSchemaFields(panel, body, skip = () => false) {
  document.querySelectorAll(`#panel-${panel} [data-path]`).forEach((input) => {
    if (skip(input.dataset.path)) return;
    const v = readSchemaField(input);
    if (v !== undefined) ctx.setPath(body, input.dataset.path, v);
  });
  return body;
}

/** The machine's drive as built, stage by stage: the teeth (the sized pair's module when sized for strength) and
 *  how far the built ratio lies from the split's. */
function machineGears(m) {
  const split = m.drive.stage_ratios;
  const meshes = m.teeth ? m.teeth.stages : [];
  return m.stage_ratios.map((u, k) => {
    const mesh = meshes[k], g = m.gears && m.gears[k];
    const off = 100 * (u / split[k] - 1);
    return `${stageLabel(k, mesh && [mesh.pinion_teeth, mesh.gear_teeth])}: ratio ${fmt(u, 5)}` +
      (Math.abs(off) > 1e-9 ? ` (split ${fmt(split[k], 5)}, ${off > 0 ? "+" : ""}${fmt(off, 3)} %)` : " (the split's)") +
      (g ? `, module ${fmt(g.module_mm)} mm, face ${fmt(g.face_width_mm, 4)} mm` : "");
  }).join("; ");
}

function machinePanel() {
  const el = document.getElementById("panel-machine");
  let last = null;
  const render = () => {
    const fam = ctx.state.design.mechanism.type;
    // the modes the chain takes per family (docs/machine.md)
    const modes = { fourbar: ["none", "static", "full", "optimal"], slider_crank: ["none", "static", "full", "optimal"],
      slotted_lever: ["none", "optimal"] }[fam] || ["none"];
    put(el, h("h2", {}, "The whole machine: linkage, balance, drive, flywheel, simulation"), h("div", { class: "controls" },
      field("mac", { name: "delta", label: "Target δ", model: "MachineIn", path: "delta", value: 0.02 }),
      field("mac", { name: "balancing.mode", label: "Balancing", options: modes.map((m) => [m, m]), value: "static" }),
      field("mac", { name: "drive.synchronous_rpm", label: "Motor speed class", model: "MachineIn", path: "drive.synchronous_rpm", options: [["", "any"], ["750", "750 rev/min"],
        ["1000", "1000 rev/min"], ["1500", "1500 rev/min"], ["3000", "3000 rev/min"]], value: "1500" }),
      field("mac", { name: "stage-count", label: "Gear stages", options: STAGE_COUNTS.map((n) => [String(n), String(n)]), value: "1" }),
      field("mac", { name: "alternatives", label: "Alternatives side by side", options: [["true", "yes"], ["false", "no"]], value: "true" })),
    h("div", { class: "controls", id: "mac-stages" }),
    schemaFields("mac", "MachineIn", { skip: MACHINE_OWN, labels: MACHINE_LABELS, folds: MACHINE_FOLDS }),
    actions(h("button", { class: "run", id: "mac-run", onclick: run }, "Design the machine"),
      h("button", { class: "secondary", id: "mac-pdf", disabled: true, onclick: pdf }, "Download the design record (PDF)"),
      h("span", { id: "mac-status", class: "note" })),
    h("div", { id: "mac-progress-box", hidden: true }),
    h("p", { id: "mac-problem", class: "problem", hidden: true }), h("div", { id: "mac-result" }));
    const stageRows = () => {
      const n = Number(read("mac", "stage-count"));
      put(document.getElementById("mac-stages"), Array.from({ length: n }, (_, k) => leaves("StageIn").map(({ path }) =>
        schemaField("mac", { path: `drive.stages.${k}.${path}`, label: `${stageName(k)} stage: ${STAGE_LABELS[path] || path.replace(/_/g, " ")}`,
          schema: ["StageIn", path], value: path === "type" ? "helical" : "" }))));
    };
    document.getElementById("mac-stage-count").addEventListener("change", stageRows);
    stageRows();
  };
  const request = () => {
    const body = linkage();
    body.samples = Math.min(body.samples || 360, 3600);
    body.delta = read("mac", "delta");
    body.balancing = { mode: read("mac", "balancing.mode") };
    const sync = read("mac", "drive.synchronous_rpm");
    body.drive = { stages: Array.from({ length: Number(read("mac", "stage-count")) }, () => ({})) };
    if (sync) body.drive.synchronous_rpm = Number(sync);
    body.alternatives = read("mac", "alternatives") === "true";
    // every other field: sent when filled, else the API's default
    return collectSchemaFields("machine", body);
  };
  /** The answer shown and the PDF button go together: no answer, no record to download. */
  function forget(note) {
    last = null;
    document.getElementById("mac-pdf").disabled = true;
    const res = document.getElementById("mac-result");
    res.replaceChildren();
    delete res.dataset.passed;
    if (note) res.appendChild(h("p", { class: "note" }, note));
  }
  async function run() {
    clearPanel("mac");
    forget();
    if (!checkNumbers("mac", ["delta"]) || !checkSchemaFields("machine")) return;
    const body = request();
    busy("mac", "designing…");
    try {
      const m = await post("/v1/machines/design", body);
      answered("machine");
      busy("mac", "");
      last = body;
      show(m);
      document.getElementById("mac-pdf").disabled = false;
    } catch (err) {
      busy("mac", "");
      forget("No machine for these inputs: the message says why.");
      panelProblem("mac", err);
    }
    document.body.dataset.machine = String(Number(document.body.dataset.machine || 0) + 1);
  }
  async function pdf() {
    if (!last) return;
    // the same request as the answer shown: the service writes the record from the design it holds
    busy("mac", "");
    const step = longStep(document.getElementById("mac-progress-box"), "mac", "writing the design record…");
    const button = document.getElementById("mac-pdf");
    button.disabled = true;
    try {
      const blob = await postFile("/v1/machines/design?format=pdf", last, { signal: step.signal });
      download(blob, "design-record.pdf");
      busy("mac", "design record downloaded");
      document.body.dataset.record = "downloaded";
    } catch (err) {
      if (cancelled(err)) { busy("mac", "cancelled: no record downloaded"); document.body.dataset.record = "cancelled"; }
      else { busy("mac", ""); panelProblem("mac", err); document.body.dataset.record = "problem"; }
    } finally {
      step.end();
      button.disabled = !last;
    }
  }
  function show(m) {
    const tick = (ok) => (ok ? h("span", { class: "ok" }, "✔") : h("span", { class: "ko" }, "✘"));
    const fw = m.flywheel.geometry && m.flywheel.geometry.best;
    const stages = [
      ["1 linkage", `${FAMILY[ctx.state.design.mechanism.type] || ctx.state.design.mechanism.type.replace(/_/g, " ")}, RMS driving torque ${fmt(m.analysis.summary.rms_driving_torque_Nm)} N·m, RMS shaking force ${fmt(m.analysis.summary.rms_shaking_force_N)} N`],
      ["2 balance", `${m.balancing_mode}: RMS shaking force ${fmtZero(m.summary_after_balancing.rms_shaking_force_N, m.analysis.summary.rms_shaking_force_N)} N, ` +
        `moment ${fmtZero(m.summary_after_balancing.rms_shaking_moment_Nm, m.analysis.summary.rms_shaking_moment_Nm)} N·m`],
      ["3 motor", `${m.motor.motor.name}, ${fmt(m.motor.motor.rated_power_W / 1000)} kW; required ${fmt(m.motor.required_power_W / 1000)} kW`],
      ["4 gears", machineGears(m)],
      ["5 flywheel", fw ? `${fmt(fw.mass_kg)} kg ${fw.shape} on the ${m.flywheel_shaft} shaft, D = ${L(fw.outer_diameter_m)}` : "none needed"],
      ["6 simulation", `δ = ${fmt(m.simulation.achieved_delta)}, mean speed ${fmt(m.simulation.mean_crank_speed_rpm)} rev/min, motor peak ${fmt(m.simulation.motor_peak_torque_Nm)} N·m`],
    ];
    // each check beside the stage whose choice it judges
    const judged = { "3 motor": ["motor_rms_torque", "motor_peak_torque"], "4 gears": ["mean_speed"], "5 flywheel": ["delta"] };
    const verdict = (stage) => (judged[stage] || []).map((n) => m.checks.find((c) => c.name === n)).filter(Boolean)
      .map((c) => [tick(c.passed), ` ${c.label || c.name} `]);
    const res = document.getElementById("mac-result");
    res.dataset.passed = String(m.passed);
    const value = (c) => (c.unit ? `${fmt(c.value)} ${c.unit}` : fmt(c.value));
    const limit = (c) => (c.limit === null || c.limit === undefined ? "–" : `${c.kind === "min" ? "≥" : "≤"} ${fmt(c.limit)}${c.unit ? ` ${c.unit}` : ""}`);
    put(res, h("h3", { id: "mac-verdict" }, tick(m.passed), m.passed ? " every check passed" : ` ${m.checks.filter((c) => !c.passed).length} of ${m.checks.length} checks failed`),
      table(["stage", "result", "checks"], stages.map(([k, v]) => [k, v, h("span", {}, verdict(k))])),
      h("h3", {}, "Checks against the simulated machine"),
      table(["", "check", "value", "limit", ""], m.checks.map((c) => h("tr", { class: ["check", c.passed ? "" : "failed"], dataset: { name: c.name, passed: String(c.passed) } },
        h("td", {}, tick(c.passed)), h("td", {}, c.label || c.name), h("td", { class: "num" }, value(c)), h("td", { class: "num" }, limit(c)),
        h("td", { class: "note" }, c.detail)))),
      m.alternatives.length ? [h("h3", {}, "Alternatives side by side"), table(["balancing", "flywheel", "motor", "δ", "checks"], m.alternatives.map((a) => [a.mode,
        a.available ? (a.flywheel_mass_kg !== null ? `${fmt(a.flywheel_mass_kg)} kg on ${a.flywheel_shaft}` : "none") : (a.reason || ""),
        a.motor || "–", [a.achieved_delta !== null ? fmt(a.achieved_delta) : "–", { class: "num" }], a.passed === null ? "–" : tick(a.passed)]))] : null,
      (m.warnings || []).map((w) => h("p", { class: "note" }, `⚠ ${w.message}`)));
    const box = h("div", { class: "plots" });
    res.appendChild(box);
    const rpm = (w) => (w * 30) / Math.PI;
    linePlot(box, "mac-speed", { title: "Simulated crank speed of the assembled machine", x: m.simulation.crank_angle_deg, xLabel: "crank angle φ [°]",
      yLabel: "n [rev/min]", unit: "rev/min", series: [{ name: "n", values: m.simulation.omega_rad_s.map(rpm) }] });
    linePlot(box, "mac-motor", { title: "Motor torque over the cycle", x: m.simulation.crank_angle_deg, xLabel: "crank angle φ [°]",
      yLabel: "T_motor [N·m]", unit: "N·m", series: [{ name: "motor torque", values: m.simulation.motor_torque_Nm }],
      limits: [{ y: m.motor.rated_torque_Nm, label: "rated" }] });
    res.dispatchEvent(new CustomEvent("machine-answer", { detail: m, bubbles: true }));
  }
  return render;
}

// --- synthesis ---------------------------------------------------------------------------------------------------
// The edges of a pivot region, as the request names them, and how the panel labels them.
const EDGES = [["x_min_m", "left x"], ["x_max_m", "right x"], ["y_min_m", "lower y"], ["y_max_m", "upper y"]];
// Each task's region of its ground pivots (request field), the links the size bound limits, and the fields it takes.
const TASKS = {
  "crank-rocker": { model: "CrankRockerIn", region: "crank_pivot_region_m", links: ["crank", "coupler", "rocker", "ground"],
    fields: ["swing_deg", "time_ratio", "scale_length_m", "max_length_ratio", "max_m"] },
  "slider-crank": { model: "SliderCrankSynthesisIn", region: null, links: ["crank", "rod"], fields: ["stroke_m", "time_ratio", "max_length_ratio", "max_m"] },
  path: { model: "PathIn", region: "pivot_box_m", links: ["crank", "coupler", "rocker", "ground"], fields: ["max_m"] },
};
const REGION_NOTES = { crank_pivot_region_m: "Where the crank pivot may go (the rocker pivot at the origin, the rocker at mid-swing along +x); all four edges, or none",
  pivot_box_m: "Where both ground pivots may go, in the path points' frame; all four edges, or none" };

/** An answer's linkage placed in the frame its task speaks of: `pivot` where its crank pivot O goes, `angle` the
 *  direction of its ground line O->Q [rad]. */
function placed(points, pivot, angle) {
  const c = Math.cos(angle), sn = Math.sin(angle), [ox, oy] = pivot;
  return Object.fromEntries(Object.entries(points).map(([k, p]) => [k, { ...p,
    position_m: p.position_m.map(([x, y]) => [ox + c * x - sn * y, oy + sn * x + c * y]) }]));
}

/** "1 cognate", "2 cognates". */
function count(n, noun) { return `${n} ${noun}${n === 1 ? "" : "s"}`; }

function synthesisPanel() {
  const el = document.getElementById("panel-synthesis");
  let points = [];
  let answer = null;      // the service's answer, with the task it answers
  let shown = null;       // the design drawn: the answer, or one of its fits or cognates
  let motion = null;      // its analysis in the task's frame, the layout and the frame shown
  let timer = null;
  const VIEW = { x0: -0.1, y0: -0.05, w: 0.4, h: 0.3 };
  const task = () => read("syn", "task");
  const render = () => {
    const regionRows = (name) => h("div", { class: "controls region", id: `syn-${name}` }, h("p", { class: "note" }, REGION_NOTES[name]),
      EDGES.map(([edge, label]) => field("syn", { name: `${name}.${edge}`, label, model: name === "pivot_box_m" ? "PathIn" : "CrankRockerIn", path: `${name}.${edge}`, kind: "length" })));
    put(el, h("h2", {}, "Synthesis"), h("div", { class: "controls" },
      field("syn", { name: "task", label: "Task", options: [["crank-rocker", "crank-rocker: swing and time ratio"], ["slider-crank", "slider-crank: stroke and time ratio"], ["path", "four-bar through path points"]], value: "crank-rocker" }),
      field("syn", { name: "swing_deg", label: "Rocker swing", model: "CrankRockerIn", path: "swing_deg", value: 40 }),
      field("syn", { name: "time_ratio", label: "Time ratio", model: "CrankRockerIn", path: "time_ratio", value: 1.2 }),
      field("syn", { name: "scale_length_m", label: "Rocker length", model: "CrankRockerIn", path: "scale_length_m", kind: "length", value: 0.15 }),
      field("syn", { name: "stroke_m", label: "Slider stroke", model: "SliderCrankSynthesisIn", path: "stroke_m", kind: "length", value: 0.1 }),
      field("syn", { name: "max_length_ratio", label: "Longest link, in rocker lengths", model: "CrankRockerIn", path: "max_length_ratio" }),
      field("syn", { name: "max_m", label: "Longest link", model: "RangeIn", path: "max_m", kind: "length" })),
    regionRows("crank_pivot_region_m"), regionRows("pivot_box_m"),
    h("p", { class: "note", id: "syn-path-note" }, "Path points: click on the grid, or type a point's coordinates and add it (at least 3 points, in order along the path)."),
    s("svg", { id: "synth-canvas", viewBox: `${VIEW.x0} ${-(VIEW.y0 + VIEW.h)} ${VIEW.w} ${VIEW.h}`, role: "application", "aria-label": "Click to place path points", tabindex: 0 }),
    h("div", { class: "controls", id: "syn-points" }, field("syn", { name: "px", label: "Point x", kind: "length" }), field("syn", { name: "py", label: "Point y", kind: "length" })),
    actions(h("button", { class: "secondary", id: "syn-add" }, "Add the point"), h("button", { class: "secondary", id: "syn-clear" }, "Clear points"),
      h("button", { class: "run", id: "syn-run" }, "Synthesise"), h("button", { class: "secondary", id: "syn-open", disabled: true }, "Open the answer in the editor"),
      h("span", { id: "syn-status", class: "note" })),
    h("p", { id: "syn-problem", class: "problem", hidden: true }), h("div", { id: "syn-result" }),
    h("div", { id: "syn-view", hidden: true },
      s("svg", { id: "syn-drawing", role: "img", "aria-label": "The synthesised linkage" }),
      actions(h("button", { class: "secondary", id: "syn-play", "aria-pressed": "false" }, "Play"),
        h("label", { for: "syn-angle" }, "Crank angle"), h("input", { id: "syn-angle", type: "range", min: 0, max: 0, value: 0 }))),
    h("div", { id: "syn-fits" }));
    const showTask = () => {
      // another task: the answer of the one before is no answer to it
      if (answer && answer.task !== task()) forget();
      const t = TASKS[task()];
      for (const name of ["swing_deg", "time_ratio", "scale_length_m", "stroke_m", "max_length_ratio", "max_m"]) {
        document.getElementById(`syn-${name}`).closest(".row").hidden = !t.fields.includes(name);
      }
      document.querySelector("label[for='syn-max_length_ratio']").textContent = task() === "slider-crank" ? "Longest link, in strokes" : "Longest link, in rocker lengths";
      for (const name of ["crank_pivot_region_m", "pivot_box_m"]) document.getElementById(`syn-${name}`).hidden = t.region !== name;
      // (an SVG element has no `hidden` property: the attribute itself)
      for (const id of ["syn-path-note", "synth-canvas", "syn-points", "syn-add", "syn-clear"]) document.getElementById(id).toggleAttribute("hidden", task() !== "path");
    };
    el.querySelector("#syn-task").addEventListener("change", showTask);
    showTask();
    const canvas = el.querySelector("#synth-canvas");
    canvas.addEventListener("click", (evt) => {
      if (points.length >= 30) return;
      const p = toModel(canvas, evt);
      points.push([Number(p[0].toFixed(5)), Number(p[1].toFixed(5))]);
      if (task() !== "path") { document.getElementById("syn-task").value = "path"; showTask(); }
      drawCanvas();
    });
    el.querySelector("#syn-clear").addEventListener("click", () => { points = []; drawCanvas(); });
    // the keyboard's way to place a point: its coordinates typed in the form's unit
    el.querySelector("#syn-add").addEventListener("click", () => {
      clearPanel("syn");
      const x = read("syn", "px"), y = read("syn", "py");
      if (!checkNumbers("syn", ["px", "py"]) || x === null || y === null) return;
      points.push([x, y]);
      document.getElementById("syn-task").value = "path";
      showTask();
      drawCanvas();
    });
    // the pivot box follows its fields on the points' grid
    el.querySelector("#syn-pivot_box_m").addEventListener("input", drawCanvas);
    el.addEventListener("units-changed", drawCanvas);
    el.querySelector("#syn-run").addEventListener("click", run);
    el.querySelector("#syn-open").addEventListener("click", open);
    el.querySelector("#syn-play").addEventListener("click", play);
    el.querySelector("#syn-angle").addEventListener("input", (e) => { stop(); if (motion) { motion.i = Number(e.target.value); drawMotion(); } });
    drawCanvas();
  };
  /** A region's four edges [m] as the request takes them; null when none is given, NaN-marked fields when only some. */
  function region(name) {
    const edges = EDGES.map(([edge]) => read("syn", `${name}.${edge}`));
    if (edges.every((v) => v === null)) return null;
    if (!checkNumbers("syn", EDGES.map(([edge]) => `${name}.${edge}`))) return undefined;
    const missing = EDGES.filter((_, k) => edges[k] === null);
    for (const [edge] of missing) {
      const m = document.getElementById(`syn-${name}.${edge}-msg`);
      m.textContent = "give all four edges, or none"; m.hidden = false;
      document.getElementById(`syn-${name}.${edge}`).setAttribute("aria-invalid", "true");
    }
    return missing.length ? undefined : Object.fromEntries(EDGES.map(([edge], k) => [edge, edges[k]]));
  }
  /** A region drawn as a box (SVG y down). */
  function box(r, sw) {
    return s("rect", { class: "region", x: r.x_min_m, y: -r.y_max_m, width: r.x_max_m - r.x_min_m, height: r.y_max_m - r.y_min_m,
      fill: "rgba(31, 95, 191, 0.06)", stroke: "#1f5fbf", "stroke-width": sw, "stroke-dasharray": `${4 * sw} ${2 * sw}`, dataset: { region: JSON.stringify(r) } },
    s("title", {}, "pivot region"));
  }
  function drawCanvas() {
    const canvas = document.getElementById("synth-canvas");
    const f = ctx.factor("length"), u = ctx.unitLabel("length");
    const step = 0.05;
    const nodes = [];
    for (let x = VIEW.x0 + step; x < VIEW.x0 + VIEW.w - 1e-9; x += step) {
      nodes.push(s("line", { x1: x, x2: x, y1: -(VIEW.y0 + VIEW.h), y2: -VIEW.y0, stroke: "#e3e7ee", "stroke-width": 0.001 }),
        s("text", { x: x + 0.002, y: -VIEW.y0 - 0.004, "font-size": 0.011, fill: "#5b6575" }, String(+(x / f).toFixed(3))));
    }
    for (let y = VIEW.y0 + step; y < VIEW.y0 + VIEW.h - 1e-9; y += step) {
      nodes.push(s("line", { y1: -y, y2: -y, x1: VIEW.x0, x2: VIEW.x0 + VIEW.w, stroke: "#e3e7ee", "stroke-width": 0.001 }),
        s("text", { x: VIEW.x0 + 0.002, y: -y - 0.003, "font-size": 0.011, fill: "#5b6575" }, String(+(y / f).toFixed(3))));
    }
    nodes.push(s("text", { x: VIEW.x0 + VIEW.w - 0.004, y: -(VIEW.y0 + VIEW.h) + 0.014, "text-anchor": "end", "font-size": 0.012 }, `[${u}]`));
    const edges = EDGES.map(([edge]) => read("syn", `pivot_box_m.${edge}`));
    if (edges.every((v) => Number.isFinite(v))) nodes.push(box(Object.fromEntries(EDGES.map(([edge], k) => [edge, edges[k]])), 0.001));
    if (points.length > 1) nodes.push(s("polyline", { points: points.map((p) => `${p[0]},${-p[1]}`).join(" "), fill: "none", stroke: "#d0243a", "stroke-width": 0.0008 }));
    points.forEach((p, n) => {
      nodes.push(s("circle", { class: "target", cx: p[0], cy: -p[1], r: 0.004 }), s("text", { x: p[0] + 0.005, y: -p[1] - 0.004, "font-size": 0.012 }, String(n + 1)));
    });
    canvas.replaceChildren(...nodes);
    canvas.dataset.points = JSON.stringify(points);
  }
  function forget() {
    stop();
    answer = null; shown = null; motion = null;
    put(document.getElementById("syn-result"));
    put(document.getElementById("syn-fits"));
    document.getElementById("syn-view").hidden = true;
    document.getElementById("syn-open").disabled = true;
    delete document.body.dataset.synthesised;
    delete document.body.dataset.synDrawn;
  }
  async function run() {
    clearPanel("syn");
    const t = task(), spec = TASKS[t];
    if (!checkNumbers("syn", spec.fields)) return;
    let body;
    if (t === "crank-rocker") {
      body = { swing_deg: read("syn", "swing_deg"), time_ratio: read("syn", "time_ratio"), scale_link: "rocker",
        scale_length_m: read("syn", "scale_length_m"), speed_rpm: ctx.state.design.speed_rpm };
    } else if (t === "slider-crank") {
      body = { stroke_m: read("syn", "stroke_m"), time_ratio: read("syn", "time_ratio"), speed_rpm: ctx.state.design.speed_rpm };
    } else {
      body = { points_m: points, starts: 16, seed: 1 };
    }
    if (spec.fields.includes("max_length_ratio") && read("syn", "max_length_ratio") !== null) body.max_length_ratio = read("syn", "max_length_ratio");
    const longest = read("syn", "max_m");
    if (longest !== null) body.bounds_m = Object.fromEntries(spec.links.map((k) => [k, { max_m: longest }]));
    if (spec.region) {
      const r = region(spec.region);
      if (r === undefined) return;
      if (r) body[spec.region] = r;
    }
    forget();
    busy("syn", "synthesising…");
    try {
      const a = await post(`/v1/synthesis/${t}`, body);
      answer = { task: t, request: body, ...a };
      show();
      await choose(a);
      document.body.dataset.synthesised = t;
      busy("syn", "");
    } catch (err) { busy("syn", ""); panelProblem("syn", err.body && err.body.field === "points_m" ? Object.assign(err, { body: { ...err.body, field: null } }) : err); }
  }
  /** Draw one design of the answer (the answer itself, a fit or a cognate): its analysis over a cycle, placed in
   *  the task's frame among the targets and the region. */
  async function choose(fit, index = 0) {
    stop();
    shown = fit;
    const m = fit.mechanism;
    const req = { mechanism: m, samples: 120, speed_rpm: ctx.state.design.speed_rpm };
    let trace = null;
    if (fit.trace_point) { req.trace_points = [fit.trace_point]; trace = fit.trace_point.name; }
    const an = await post("/v1/analysis", req);
    let pivot = [0, 0], angle = 0;
    if (answer.task === "path") { pivot = fit.crank_pivot_m; angle = (fit.ground_angle_deg * Math.PI) / 180; }
    // the crank-rocker's region frame: the rocker pivot Q at the origin, the crank pivot where the answer says
    if (answer.task === "crank-rocker") { pivot = fit.crank_pivot_m; angle = Math.atan2(-pivot[1], -pivot[0]); }
    const moved = { ...an, points: placed(an.points, pivot, angle) };
    const r = answer.request[TASKS[answer.task].region] || null;
    const extras = { tracePoint: trace, targets: answer.task === "path" ? points : [], unitLength: ctx.state.units.length };
    const lay = layout(moved, { mechanism: m }, { targets: [...extras.targets, ...(r ? [[r.x_min_m, r.y_min_m], [r.x_max_m, r.y_max_m]] : [])] });
    motion = { answer: moved, mechanism: m, lay, extras, region: r, i: 0, n: an.crank_angle_deg.length };
    const slider = document.getElementById("syn-angle");
    slider.max = String(motion.n - 1); slider.value = "0";
    document.getElementById("syn-view").hidden = false;
    document.querySelectorAll("#syn-fits tr[data-fit]").forEach((row) => row.setAttribute("aria-selected", String(row.dataset.fit === String(index))));
    drawMotion();
    document.getElementById("syn-open").disabled = false;
    document.body.dataset.synDrawn = `${answer.task}-${index}`;
  }
  function drawMotion() {
    const svg = document.getElementById("syn-drawing");
    drawLinkage(svg, motion.answer, { mechanism: motion.mechanism }, motion.i, motion.lay, motion.extras);
    if (motion.region) svg.firstChild.prepend(box(motion.region, motion.lay.span / 180));
    svg.dataset.frame = String(motion.i);
  }
  function play() {
    const btn = document.getElementById("syn-play");
    if (timer) { stop(); return; }
    btn.textContent = "Pause"; btn.setAttribute("aria-pressed", "true");
    let last = performance.now();
    const step = (now) => {
      if (motion && now - last > 1000 / 30) {
        motion.i = (motion.i + 1) % motion.n;
        document.getElementById("syn-angle").value = String(motion.i);
        drawMotion();
        last = now;
      }
      timer = requestAnimationFrame(step);
    };
    timer = requestAnimationFrame(step);
  }
  function stop() {
    if (timer) cancelAnimationFrame(timer);
    timer = null;
    const btn = document.getElementById("syn-play");
    if (btn) { btn.textContent = "Play"; btn.setAttribute("aria-pressed", "false"); }
  }
  /** Target points in a fit's own frame (crank pivot at the origin, O->Q along x). */
  function targetsInMechanismFrame(fit) {
    const [ox, oy] = fit.crank_pivot_m, t = (fit.ground_angle_deg * Math.PI) / 180;
    return points.map(([x, y]) => [Math.cos(t) * (x - ox) + Math.sin(t) * (y - oy), -Math.sin(t) * (x - ox) + Math.cos(t) * (y - oy)]);
  }
  function show() {
    const a = answer, m = a.mechanism;
    const res = document.getElementById("syn-result");
    const lengths = Object.entries(m).filter(([k]) => k.endsWith("_length_m") || k === "offset_m").map(([k, v]) => `${k.replace(/_m$/, "")} ${L(v)}`).join(", ");
    let text;
    if (a.task === "path") {
      text = `Coupler point ${L(a.trace_point.position_m[0])}, ${L(a.trace_point.position_m[1])} in the coupler frame; largest distance from a target ` +
        `${L(a.max_residual_m)} (RMS ${L(a.rms_residual_m)}); ${a.check.grashof}, swing ${fmt(a.check.swing_deg)}°, ${a.starts_converged}/${a.starts} starts converged.`;
    } else {
      text = `${a.objective} = ${fmt(a.objective_value)} ${a.objective_unit}; check by the kinematics engine: time ratio ${fmt(a.check.time_ratio)}` +
        (a.check.swing_deg !== undefined ? `, swing ${fmt(a.check.swing_deg)}°` : `, stroke ${L(a.check.stroke_m)}`) +
        `, transmission angle ${fmt(a.check.transmission_angle.min_deg)}° … ${fmt(a.check.transmission_angle.max_deg)}°.`;
    }
    put(res, h("h3", {}, `${FAMILY[m.type] || m.type}: ${lengths}`), h("p", {}, text),
      (a.warnings || []).map((w) => h("p", { class: "note" }, `⚠ ${w.message}`)));
    if (a.task === "path") {
      // every distinct design the starts reached, then the answer's cognates: a row drawn when chosen
      const all = [...a.fits, ...a.cognates];
      const rows = all.map((f, k) => h("tr", { dataset: { fit: String(k) }, tabindex: 0, role: "button", "aria-selected": String(k === 0),
        onclick: () => choose(f, k), onkeydown: (e) => { if (e.key === "Enter") choose(f, k); } },
      h("td", {}, k === 0 ? "the answer" : f.source === "cognate" ? "cognate" : `fit ${k + 1}`),
      h("td", { class: "num" }, L(f.max_residual_m)), h("td", { class: "num" }, L(f.rms_residual_m)), h("td", {}, f.grashof),
      h("td", { class: "num" }, f.transmission_angle ? `${fmt(f.transmission_angle.min_deg)}° … ${fmt(f.transmission_angle.max_deg)}°` : "–"),
      h("td", { class: "num" }, fmt(f.link_ratio)), h("td", { class: "num" }, String(f.starts))));
      put(document.getElementById("syn-fits"), h("h3", {}, `${count(a.fits.length, "distinct fit")} and ${count(a.cognates.length, "cognate")}: click one to draw it`),
        table(["design", "largest residual", "RMS residual", "Grashof class", "transmission angle", "link ratio", "starts"], rows, { id: "syn-fit-table", class: "pick" }));
    }
  }
  function open() {
    if (!answer || !shown) return;
    const d = { mechanism: structuredClone(shown.mechanism), speed_rpm: ctx.state.design.speed_rpm, samples: ctx.state.design.samples || 360 };
    let targets = [];
    if (answer.task === "path") {
      d.trace_points = [structuredClone(shown.trace_point)];
      targets = targetsInMechanismFrame(shown);
    } else if (shown.mechanism.type === "fourbar") {
      const len = shown.mechanism.coupler_length_m;
      d.trace_points = [{ name: "P", link: "coupler", position_m: [len / 2, len * 0.4] }];
    }
    ctx.setDesign(d, { targets });
    ctx.selectTab("mechanism");
  }
  return render;
}

// --- studies -----------------------------------------------------------------------------------------------------
// What a study can send each variant to, and the figures of its answer offered as objectives.
const STUDY_ENDPOINTS = {
  "/v1/analysis": { label: "analysis", metrics: [["summary.rms_shaking_force_N", "RMS shaking force [N]"],
    ["summary.rms_driving_torque_Nm", "RMS driving torque [N·m]"], ["summary.rms_shaking_moment_Nm", "RMS shaking moment [N·m]"],
    ["summary.max_bearing_force_N", "largest bearing force [N]"], ["summary.max_driving_torque_Nm", "peak driving torque [N·m]"]] },
  "/v1/balancing/optimal": { label: "optimal balancing", metrics: [["summary_after.rms_shaking_force_N", "RMS shaking force, balanced [N]"],
    ["total_added_mass_kg", "added mass [kg]"], ["summary_after.rms_shaking_moment_Nm", "RMS shaking moment, balanced [N·m]"],
    ["summary_after.rms_driving_torque_Nm", "RMS driving torque, balanced [N·m]"]] },
};
const ALL_METRICS = Object.values(STUDY_ENDPOINTS).flatMap((e) => e.metrics);

/** A study's default range around a value: ±20 %, rounded to three digits; a zero spans 0 to 1. */
function span(v) {
  if (!v) return [0, 1];
  const r = (x) => Number(x.toPrecision(3));
  return [r(Math.min(v * 0.8, v * 1.2)), r(Math.max(v * 0.8, v * 1.2))];
}

function studiesPanel() {
  const el = document.getElementById("panel-studies");
  let study = null, timer = null, base = null;
  const render = () => {
    const numeric = ctx.state.fields.filter((f) => !f.options && !f.path.startsWith("loads") && f.path !== "samples" && typeof ctx.getPath(ctx.state.design, f.path) === "number");
    if (numeric.length < 2) {
      put(el, h("h2", {}, "Design study over the current design"),
        h("p", { class: "note" }, "A study varies two numbers of the design's form: this design has fewer (a general linkage is edited as JSON or drawn)."));
      return;
    }
    const opts = numeric.map((f) => [f.path, `${f.groupLabel}: ${f.label}`]);
    const cur = (p) => ctx.getPath(ctx.state.design, p);
    const row = (n, path) => {
      const f = numeric.find((x) => x.path === path) || numeric[0];
      const v = cur(f.path);
      const [lo, hi] = span(v);
      return [field("stu", { name: `p${n}.path`, label: `Parameter ${n + 1}`, options: opts, value: f.path }),
        field("stu", { name: `p${n}.from`, label: "from", kind: f.kind, value: lo }),
        field("stu", { name: `p${n}.to`, label: "to", kind: f.kind, value: hi }),
        field("stu", { name: `p${n}.count`, label: "values", value: 5 })];
    };
    put(el, h("h2", {}, "Design study over the current design"), h("div", { class: "controls study" }, row(0, "mechanism.crank_length_m"),
      row(1, numeric.find((f) => f.path.endsWith("mass_kg"))?.path || numeric[1].path)), h("div", { class: "controls" },
      field("stu", { name: "endpoint", label: "Each variant to", options: Object.entries(STUDY_ENDPOINTS).map(([k, v]) => [k, v.label]), value: "/v1/analysis" }),
      field("stu", { name: "x", label: "Objective 1 (min)", options: STUDY_ENDPOINTS["/v1/analysis"].metrics, value: STUDY_ENDPOINTS["/v1/analysis"].metrics[0][0] }),
      field("stu", { name: "y", label: "Objective 2 (min)", options: STUDY_ENDPOINTS["/v1/analysis"].metrics, value: STUDY_ENDPOINTS["/v1/analysis"].metrics[1][0] })),
    actions(h("button", { class: "run", id: "stu-run" }, "Start the study"), h("button", { class: "secondary", id: "stu-cancel", disabled: true }, "Cancel"),
      h("button", { class: "secondary", id: "stu-resume", disabled: true }, "Resume"), h("a", { id: "stu-csv", href: "#", hidden: true, download: "study.csv" }, "Results as CSV"),
      h("span", { id: "stu-status", class: "note" })),
    h("progress", { id: "stu-progress", max: 1, value: 0 }), h("p", { id: "stu-problem", class: "problem", hidden: true }), h("div", { id: "stu-plots", class: "plots" }));
    el.querySelector("#stu-run").addEventListener("click", start);
    el.querySelector("#stu-cancel").addEventListener("click", async () => { if (study) { study = await del(study.links.self); poll(); } });
    el.querySelector("#stu-resume").addEventListener("click", async () => { if (study) { study = await post(`${study.links.self}/resume`, {}); poll(); } });
    document.getElementById("stu-endpoint").addEventListener("change", (e) => {
      const metrics = STUDY_ENDPOINTS[e.target.value].metrics;
      ["x", "y"].forEach((k, n) => {
        const sel = document.getElementById(`stu-${k}`);
        put(sel, metrics.map(([v, l]) => h("option", { value: v }, l)));
        sel.value = metrics[n][0];
      });
    });
    for (const n of [0, 1]) {
      document.getElementById(`stu-p${n}.path`).addEventListener("change", (e) => {
        const v = cur(e.target.value), f = numeric.find((x) => x.path === e.target.value);
        span(v).forEach((s, k) => {
          const inp = document.getElementById(`stu-p${n}.${k ? "to" : "from"}`);
          inp.dataset.kind = f.kind; inp.value = ctx.toDisplay(s, f.kind);
          inp.closest(".row").querySelector(".unit").textContent = ctx.unitLabel(f.kind, describe("AnalysisIn", f.schemaPath || f.path, { type: ctx.state.design.mechanism.type }).unit);
        });
      });
    }
  };
  async function start() {
    clearPanel("stu");
    if (!checkNumbers("stu", ["p0.from", "p0.to", "p0.count", "p1.from", "p1.to", "p1.count"])) return;
    base = structuredClone(ctx.state.design);
    const endpoint = read("stu", "endpoint");
    // an analysis varies the design as it is; a balancing study its linkage, with the panel's default weights
    const request = endpoint === "/v1/analysis" ? base : { ...linkage(), weights: { shaking_force: 1, shaking_moment: 1 } };
    const x = read("stu", "x"), y = read("stu", "y");
    const parameters = [0, 1].map((n) => ({ path: read("stu", `p${n}.path`), range: [read("stu", `p${n}.from`), read("stu", `p${n}.to`)], count: Math.round(read("stu", `p${n}.count`)) }));
    const body = { endpoint, base: request, parameters, sampling: "grid", metrics: [...new Set([x, y])], objectives: { [x]: "min", [y]: "min" }, name: "workbench study" };
    try {
      study = await post("/v1/studies", body);
      document.getElementById("stu-plots").replaceChildren();
      poll();
    } catch (err) { panelProblem("stu", err.body && err.body.field ? Object.assign(err, { body: { ...err.body, field: err.body.field.replace(/^parameters\.(\d)\.range.*/, "p$1.from") } }) : err); }
  }
  async function poll() {
    clearTimeout(timer);
    if (!study) return;
    study = await get(study.links.self);
    const bar = document.getElementById("stu-progress");
    bar.max = study.total; bar.value = study.done;
    const pct = study.total ? Math.round((100 * study.done) / study.total) : 0;
    busy("stu", `${study.state}: ${study.done}/${study.total} variants (${pct} %)` + (study.failed ? `, ${study.failed} failed` : "") +
      (study.eta_s !== null && study.state === "running" ? `, about ${Math.ceil(study.eta_s)} s to go` : "") + (study.message ? ` — ${study.message}` : ""));
    document.getElementById("stu-status").dataset.percent = String(pct);
    document.getElementById("stu-cancel").disabled = !["queued", "running"].includes(study.state);
    document.getElementById("stu-resume").disabled = !["cancelled", "interrupted"].includes(study.state);
    const csv = document.getElementById("stu-csv");
    csv.href = `${study.links.results}?format=csv`; csv.hidden = false;
    if (["queued", "running"].includes(study.state)) { timer = setTimeout(poll, 300); return; }
    if (study.state === "done") await front();
  }
  async function front() {
    const x = read("stu", "x"), y = read("stu", "y");
    // every variant, page by page: a large study is more than one page of results
    const PAGE = 1000;
    const variants = [];
    const pareto = await get(study.links.pareto);
    for (let offset = 0; ; offset += PAGE) {
      const page = await get(`${study.links.results}?offset=${offset}&limit=${PAGE}`);
      variants.push(...page.variants);
      if (page.variants.length < PAGE) break;
    }
    const onFront = new Set(pareto.front.map((v) => v.index));
    // a front point is drawn whatever the pages held
    const have = new Set(variants.map((v) => v.index));
    for (const v of pareto.front) if (!have.has(v.index) && v.metrics) variants.push(v);
    const pts = variants.filter((v) => v.metrics && v.metrics[x] !== null && v.metrics[y] !== null).map((v) => ({
      x: v.metrics[x], y: v.metrics[y], variant: v, colour: onFront.has(v.index) ? "#c25e00" : "#b8c2d3",
      label: `variant ${v.index}${onFront.has(v.index) ? " (Pareto front)" : ""}: ` + Object.entries(v.parameters).map(([k, val]) => `${k} = ${fmt(val)}`).join(", "),
    }));
    // the front drawn last, on top
    pts.sort((a, b) => Number(onFront.has(a.variant.index)) - Number(onFront.has(b.variant.index)));
    const box = document.getElementById("stu-plots");
    const label = (m) => ALL_METRICS.find((k) => k[0] === m)[1];
    const plot = scatterPlot(box, "stu-pareto", { title: `Pareto front: ${pareto.front.length} of ${pareto.candidates} variants (click one to open it)`,
      xLabel: label(x), yLabel: label(y), points: pts, onPick: (p) => openVariant(p.variant) });
    plot.el.querySelectorAll("circle.pick").forEach((c, n) => { c.dataset.variant = pts[n].variant.index; c.dataset.front = String(onFront.has(pts[n].variant.index)); });
    plot.el.dataset.points = String(pts.length);
  }
  function openVariant(v) {
    const d = structuredClone(base);
    for (const [path, value] of Object.entries(v.parameters)) ctx.setPath(d, path, value);
    ctx.setDesign(d);
    ctx.selectTab("mechanism");
    document.body.dataset.openedVariant = String(v.index);
  }
  return render;
}

let installed = null;
/** Resolved once the panels have their context (units, the manual): the modules beside them wait for it. */
export const panelsReady = new Promise((resolve) => { installed = resolve; });

/** The panels' field machinery, for the modules beside them (the optimisation form): fields described by the
 *  manual, read in SI, checked, filled from SI values, and a problem put next to the field it names. */
export const kit = {
  schemaField, schemaFields, readSchemaField, checkSchemaFields, panelProblem, clearPanel, loadCatalogues,
  fill(input, v) { input.value = v === undefined || v === null ? "" : typeof v === "number" && input.dataset.kind !== "plain" ? ctx.toDisplay(v, input.dataset.kind) : String(v); },
};

// The panels whose fields this module makes (the Foundation and Cams panels follow the units their own way).
const UNIT_PANELS = ["balancing", "flywheel", "drive", "machine", "synthesis", "studies", "optimise"].map((p) => `#panel-${p}`).join(", ");

/** The form's units chosen again: every length or mass a panel holds (typed, or its default as placeholder) is
 *  shown in the new unit with its value kept, and its unit beside it says so. */
function followUnits() {
  const factors = { length: ctx.factor("length"), mass: ctx.factor("mass") };
  for (const [id, kind] of [["unit-length", "length"], ["unit-mass", "mass"]]) {
    document.getElementById(id).addEventListener("change", () => {
      const before = factors[kind];
      factors[kind] = ctx.factor(kind);
      if (before === factors[kind]) return;
      const again = (text) => text.split(/\s*,\s*/).map((t) => {
        const v = Number(t.replace(",", "."));
        return t.trim() === "" || !Number.isFinite(v) ? t : ctx.toDisplay(v * before, kind);
      }).join(", ");
      document.querySelectorAll(`:is(${UNIT_PANELS}) [data-kind='${kind}']`).forEach((input) => {
        if (input.value.trim() !== "") input.value = again(input.value.trim());
        if (input.placeholder) input.placeholder = again(input.placeholder);
        const unit = input.closest(".row")?.querySelector(".unit");
        if (unit && unit.textContent) unit.textContent = ctx.unitLabel(kind) + (input.dataset.type === "list" ? " (list)" : "");
      });
      document.getElementById("panel-synthesis").dispatchEvent(new CustomEvent("units-changed"));
    });
  }
}

export function installPanels(c) {
  ctx = c;
  installed();
  followUnits();
  const renders = { balancing: balancingPanel(), flywheel: flywheelPanel(), drive: drivePanel(), machine: machinePanel(),
    synthesis: synthesisPanel(), studies: studiesPanel() };
  const rendered = { designs: {} };
  // A panel's form is built when first opened, from the design as it is then; opening it again keeps its answer.
  document.querySelectorAll("#tabs [role=tab]").forEach((t) => t.addEventListener("click", async () => {
    const name = t.dataset.panel;
    if (!renders[name]) return;
    await loadCatalogues();
    const el = document.getElementById(`panel-${name}`);
    const design = JSON.stringify(ctx.state.design);
    // A new family, or a changed design with no answer shown yet: the panel's fields start again from the design.
    if (rendered[name] !== ctx.state.design.mechanism.type || (!el.dataset.design && rendered.designs[name] !== design)) {
      renders[name]();
      rendered[name] = ctx.state.design.mechanism.type;
      rendered.designs[name] = design;
      delete el.dataset.design;
    } else if (el.dataset.design && el.dataset.design !== design && !el.querySelector(".stale")) {
      const note = document.createElement("p");
      note.className = "stale problem";
      note.textContent = "The design has changed since this answer: run again for the current one.";
      el.querySelector("h2").after(note);
    }
  }));
}
