// The Machine panel's optimisation: the machine's function in (the request of POST /v1/machines/optimise as a form
// described by the manual: units, defaults, choices), the optimised machine out, its gains, its certificate, and the
// Pareto scatter of every member designed; a point opens that member's design (POST /v1/machines/design with the
// optimisation's machine around it). It lives beside the Machine panel and shows with it. Like the rest of the page,
// a client of the public API.

import { post, get, Problem } from "./api.js";
import { h, s, put, table } from "./dom.js";
import { admitted } from "./signin.js";
import { setPath } from "./app.js";
import { kit, panelsReady } from "./panels.js";
import { longStep, cancelled } from "./progress.js";

const MACHINE_FIELDS = ["loads", "speed_rpm", "samples", "delta", "machine_type", "drive", "balancing", "flywheel",
  "speed_tolerance", "friction", "brake_torque_Nm", "start_under_load", "max_startup_time_s", "max_rundown_time_s"];
// The objectives as the office says them, and their units (the cost in the prices' currency).
const OBJECTIVES = { motor_power: "motor power", added_mass: "added mass", rms_shaking_force: "RMS shaking force",
  machine_mass: "machine mass", cost: "cost" };
const UNITS = { motor_power: "W", added_mass: "kg", rms_shaking_force: "N", machine_mass: "kg", cost: "currency" };
const KEYS = { motor_power: "motor_power_W", added_mass: "added_mass_kg", rms_shaking_force: "rms_shaking_force_N",
  machine_mass: "machine_mass_kg", cost: "cost" };
const FUNCTIONS = { crank_rocker: ["CrankRockerFunctionIn", "crank-rocker: rocker swing, time ratio and one length"],
  slider_crank: ["SliderCrankFunctionIn", "slider-crank: slider stroke and time ratio"] };
// What the form fills its own way (the function, the load, the objective, the stages), and the tables of objects
// it leaves to the API's defaults (the manual describes them; a client sends them as JSON).
const OWN = ["function", "loads", "objective", "weights", "pareto", "search_cells", "drive.stages", "friction",
  "drive.motor_catalogue", "balancing.counterweight_links", "balancing.max_radius_m", "balancing.rotor_ratios", "prices.motors"];
const LABELS = { speed_rpm: "Working crank speed", samples: "Crank angles per revolution", delta: "Target δ",
  machine_type: "Machine type (instead of δ)", speed_tolerance: "Mean speed tolerance", brake_torque_Nm: "Brake torque at the crank",
  start_under_load: "Starts under load", max_startup_time_s: "Longest run-up", max_rundown_time_s: "Longest run-down",
  max_rms_shaking_force_N: "Largest RMS shaking force", max_rms_shaking_moment_Nm: "Largest RMS shaking moment",
  scan_members: "Members scanned", "drive.motor": "Motor (catalogue name)", "drive.synchronous_rpm": "Motor speed class",
  "drive.reserve_factor": "Power reserve factor", "drive.objective": "Ratio split", "drive.size_gears": "Size the gears for strength",
  "balancing.mode": "Balancing", "balancing.mass_budget_kg": "Mass budget (optimal)", "flywheel.placement": "Flywheel on",
  "flywheel.geometry.shape": "Flywheel shape", "drive.pinion_inertia_kgm2": "Inertia of every pinion",
  "drive.load_inertia_kgm2": "Extra inertia on the crank shaft", "drive.shaft_inertias_kgm2": "Inertia on each shaft",
  "drive.max_teeth": "Largest wheel (teeth)", "drive.min_teeth": "Smallest wheel (teeth)", "drive.tooth_tolerance": "Ratio tolerance of the teeth",
  "drive.strength.application_factor": "Application factor K_A", "drive.strength.min_safety_contact": "Least pitting safety S_H",
  "drive.strength.min_safety_root": "Least root safety S_F", "drive.strength.pitting_permitted": "Limited pitting permitted",
  "drive.strength.pinion_material": "Pinion material", "drive.strength.gear_material": "Wheel material",
  "drive.strength.helix_angle_deg": "Helix angle", "drive.strength.pinion_teeth": "Pinion teeth",
  "drive.strength.accuracy_grade": "Accuracy grade (ISO 1328-1)", "drive.strength.module_series": "Module series (ISO 54)",
  "drive.strength.objective": "Gears sized for least", "balancing.weights.shaking_force": "Weight: shaking force",
  "balancing.weights.shaking_moment": "Weight: shaking moment", "balancing.weights.driving_torque": "Weight: driving torque",
  "balancing.weights.bearing_forces": "Weight: joint reactions", "balancing.weights.peak_shaking_force": "Weight: peak shaking force",
  "balancing.weights.peak_shaking_moment": "Weight: peak shaking moment", "balancing.weights.added_mass": "Weight: added mass",
  "flywheel.geometry.density_kg_m3": "Flywheel density", "flywheel.geometry.max_rim_speed_m_s": "Largest rim speed",
  "flywheel.geometry.allowable_stress_Pa": "Allowable stress", "flywheel.geometry.max_diameter_m": "Largest flywheel diameter",
  "flywheel.geometry.thickness_ratio": "Rim thickness over mean diameter", "flywheel.geometry.width_ratio": "Width over diameter",
  "prices.counterweight_per_kg": "Counterweights", "prices.balancer_per_kg": "Balancer masses", "prices.flywheel_per_kg": "Flywheel body",
  "prices.gears_per_kg": "Gear wheels", "prices.motor_per_kg": "Motor (without its own price)" };
// The function's length ranges, link by link.
const BOUNDS = Object.fromEntries(["crank", "coupler", "rocker", "ground", "rod", "offset"].flatMap((k) => [[`bounds_m.${k}.min_m`, `Shortest ${k}`],
  [`bounds_m.${k}.max_m`, `Longest ${k}`]]));
const FOLDS = { "": "Speed, target, constraints and search", drive: "Drive: motor and gears", balancing: "Balancing",
  flywheel: "Flywheel", prices: "Prices of the parts (for the cost)" };
const STAGE_TYPES = ["spur", "helical"];

let seq = 0;
let lastRequest = null;

function fmt(x, digits = 5) { return x === null || x === undefined ? "–" : Number(x).toPrecision(digits); }

function done(kind) {
  seq += 1;
  document.body.dataset.optimise = `${kind}-${seq}`;
}

function showProblem(el, err) {
  const body = err instanceof Problem ? err.body : {};
  const where = body.field ? ` (field ${body.field})` : "";
  put(el, `${err.message}${where}`);
  el.hidden = false;
}

function scatter(answer, onOpen) {
  const [a, b] = answer.pareto_objectives;
  const pts = answer.members.filter((m) => m.feasible && m[KEYS[a]] !== null && m[KEYS[b]] !== null);
  const W = 560, H = 320, L = 70, B = 40, T = 14, R = 14;
  const xs = pts.map((m) => m[KEYS[a]]), ys = pts.map((m) => m[KEYS[b]]);
  const span = (v) => { const lo = Math.min(...v), hi = Math.max(...v); const d = hi - lo || Math.abs(hi) || 1; return [lo - 0.05 * d, hi + 0.05 * d]; };
  const [x0, x1] = span(xs), [y0, y1] = span(ys);
  const X = (v) => L + (v - x0) / (x1 - x0) * (W - L - R), Y = (v) => H - B - (v - y0) / (y1 - y0) * (H - B - T);
  const front = new Set(answer.pareto.map((m) => m.parameter));
  const svg = s("svg", { id: "opt-scatter", viewBox: `0 0 ${W} ${H}`, width: W, height: H, role: "img",
    "aria-label": `Every feasible member designed: ${OBJECTIVES[a]} against ${OBJECTIVES[b]}` },
  s("rect", { x: L, y: T, width: W - L - R, height: H - B - T, fill: "none", stroke: "#999" }),
  s("text", { x: (L + W - R) / 2, y: H - 8, "text-anchor": "middle", "font-size": 12 }, `${OBJECTIVES[a]} [${UNITS[a]}]`),
  s("text", { x: 14, y: (T + H - B) / 2, "text-anchor": "middle", "font-size": 12, transform: `rotate(-90 14 ${(T + H - B) / 2})` }, `${OBJECTIVES[b]} [${UNITS[b]}]`),
  [x0, x1].map((v, i) => s("text", { x: i ? W - R : L, y: H - B + 14, "text-anchor": i ? "end" : "start", "font-size": 10 }, fmt(v, 4))),
  [y0, y1].map((v, i) => s("text", { x: L - 4, y: i ? T + 10 : H - B, "text-anchor": "end", "font-size": 10 }, fmt(v, 4))),
  pts.map((m) => {
    const chosen = m.parameter === answer.parameter, onFront = front.has(m.parameter);
    return s("circle", { cx: X(m[KEYS[a]]), cy: Y(m[KEYS[b]]), r: chosen ? 7 : 4.5, class: "opt-point",
      fill: onFront ? "#1f6fb2" : "#bbb", stroke: chosen ? "#c0392b" : "#555", "stroke-width": chosen ? 2.5 : 0.8,
      tabindex: 0, role: "button", dataset: { parameter: String(m.parameter), stage: m.stage },
      onclick: () => onOpen(m), onkeydown: (e) => { if (e.key === "Enter") onOpen(m); } },
    s("title", {}, `u = ${fmt(m.parameter)} (${m.stage}): ${OBJECTIVES[a]} ${fmt(m[KEYS[a]])} ${UNITS[a]}, ${OBJECTIVES[b]} ${fmt(m[KEYS[b]])} ${UNITS[b]}`));
  }));
  return svg;
}

function designSummary(d, member) {
  const body = d.flywheel_body;
  return h("div", { id: "opt-member-design", dataset: { parameter: String(member.parameter) } },
    h("h4", {}, `Member u = ${fmt(member.parameter)} (${member.stage}), designed by /v1/machines/design`),
    table(["passed", "motor", "achieved δ", "flywheel", "RMS shaking force after balancing"], [[
      d.passed ? "yes" : "no", d.drive.motor.name, fmt(d.simulation.achieved_delta, 4),
      body ? `${fmt(body.mass_kg, 4)} kg on the ${body.shaft} shaft` : "none",
      `${fmt(d.summary_after_balancing.rms_shaking_force_N, 4)} N`]]));
}

function cells(c) {
  const left = c.cells_unsearched
    ? `; to search every cell that could still beat the best, give "search_cells": "all"` : "";
  return h("p", { id: "opt-cells" }, `${c.cells_found} cells between scanned members: ${c.cells_searched} searched, `
    + `${c.cells_pruned} pruned (they cannot beat the best found), ${c.cells_unsearched} left unsearched${left}.`);
}

/** The example's value at a path of the request, as the form shows it. */
function at(obj, path) { return path.split(".").reduce((o, k) => (o === undefined || o === null ? undefined : o[k]), obj); }

function build(api) {
  const machine = document.getElementById("panel-machine");
  // not a .panel: the tabs show one .panel at a time, and this box shows with the Machine panel
  const box = h("div", { id: "panel-optimise", role: "region", "aria-label": "Optimise the machine" });
  machine.after(box);
  const follow = () => { box.hidden = machine.hidden; };
  new MutationObserver(follow).observe(machine, { attributes: true, attributeFilter: ["hidden"] });
  follow();
  // the manual's slider-crank press, its Pareto set between the added mass and the shaking force: members that
  // differ in both, so the scatter spreads
  const ex = api.components.schemas.MachineOptimiseIn.examples || [];
  const start = { ...(ex[1] || ex[0] || {}), pareto: ["added_mass", "rms_shaking_force"] };
  function selectRow(name, label, options, value, schema) {
    const row = kit.schemaField("opt", { path: name, label, schema: schema || ["MachineOptimiseIn", name] });
    const sel = h("select", { id: `opt-${name}`, name, title: row.querySelector("label").title },
      options.map(([v, l]) => h("option", { value: v, selected: String(value) === String(v) }, l)));
    row.querySelector("input, select, textarea").replaceWith(sel);
    row.querySelector(".unit").textContent = "";
    return row;
  }
  const objective = start.objective || (start.weights ? "weights" : "motor_power");
  const stages = at(start, "drive.stages");
  const fnType = at(start, "function.type") || "crank_rocker";
  const fnBox = h("div", { class: "controls", id: "opt-function" });
  const loadBox = h("div", { class: "controls", id: "opt-load" });
  const weightsBox = h("div", { class: "controls", id: "opt-weights" });
  const main = kit.schemaFields("opt", "MachineOptimiseIn", { skip: OWN, labels: LABELS, folds: FOLDS, open: false });
  main.find((d) => d.dataset.group === "").open = true;
  const status = h("span", { id: "opt-status", class: "note" });
  const progress = h("div", { id: "opt-progress-box", hidden: true });
  const problem = h("p", { id: "opt-problem", class: "problem", hidden: true });
  const result = h("div", { id: "opt-result" });
  const member = h("div", { id: "opt-member" });
  put(box, h("h2", {}, "Optimise the machine as a whole, from its function"),
    h("p", { class: "note" }, "The function (swing or stroke and time ratio), the load, the speed, the drive and what to "
      + "minimise: the service chooses the linkage's member with its counterweights, flywheel, motor and ratio. "
      + "Each point of the scatter is a member designed; click one to open its design. A field left empty takes the "
      + "manual's default (shown greyed)."),
    h("h3", {}, "What the linkage must do"),
    h("div", { class: "controls" }, selectRow("function.type", "Linkage", Object.entries(FUNCTIONS).map(([k, v]) => [k, v[1]]), fnType,
      ["MachineOptimiseIn", "function.type"])),
    fnBox,
    h("h3", {}, "Process load on the output (one window)"), loadBox,
    h("h3", {}, "What to minimise"),
    h("div", { class: "controls" },
      selectRow("objective", "Objective", [...Object.entries(OBJECTIVES).map(([k, v]) => [k, `${v} [${UNITS[k]}]`]), ["weights", "weighted sum of the objectives"]], objective),
      selectRow("pareto.0", "Pareto set: first objective", Object.entries(OBJECTIVES).map(([k, v]) => [k, `${v} [${UNITS[k]}]`]), start.pareto[0], ["MachineOptimiseIn", "pareto"]),
      selectRow("pareto.1", "Pareto set: second objective", Object.entries(OBJECTIVES).map(([k, v]) => [k, `${v} [${UNITS[k]}]`]), start.pareto[1], ["MachineOptimiseIn", "pareto"]),
      selectRow("search_cells", "Cells searched", [["", "default (2)"], ...[0, 1, 2, 4, 8, 16].map((n) => [String(n), String(n)]), ["all", "every cell that could beat the best"]],
        start.search_cells === undefined ? "" : start.search_cells),
      selectRow("drive.stages.count", "Gear stages", [1, 2, 3, 4, 5, 6].map((n) => [String(n), String(n)]), Array.isArray(stages) ? stages.length : (stages || 2),
        ["MachineOptimiseIn", "drive.stages"]),
      selectRow("drive.stages.type", "Stage type", STAGE_TYPES.map((t) => [t, t]), Array.isArray(stages) && typeof stages[0] === "string" ? stages[0] : "spur",
        ["MachineOptimiseIn", "drive.stages"])),
    weightsBox,
    main,
    h("div", { class: "actions" }, h("button", { class: "run", id: "opt-run", onclick: () => run() }, "Optimise"), " ", status),
    progress, problem, result, member);
  const fnFields = () => {
    const type = document.getElementById("opt-function.type").value;
    const model = FUNCTIONS[type][0];
    const same = type === (at(start, "function.type") || "crank_rocker");
    put(fnBox, kit.schemaFields("opt", model, { skip: ["type"], labels: { swing_deg: "Rocker swing", time_ratio: "Time ratio", scale_link: "Link of the given length",
      scale_length_m: "Its length", stroke_m: "Slider stroke", slider_mass_kg: "Slider mass", min_transmission_angle_deg: "Least transmission angle",
      max_length_ratio: type === "slider_crank" ? "Longest rod, in strokes" : "Longest link, in rocker lengths", slow_stroke: "Slow stroke", ...BOUNDS }, folds: { "": "The function", bounds_m: "Length ranges of the links",
      linear_density_kg_m: "Mass per metre of each link" }, open: true }).map((d) => { d.id = `opt-function-${d.dataset.group || "own"}`; d.querySelectorAll("[data-path]").forEach((i) => { i.dataset.path = `function.${i.dataset.path}`; i.id = `opt-${i.dataset.path}`; i.closest(".row").dataset.field = i.dataset.path; }); return d; }));
    fnBox.querySelectorAll("label[for]").forEach((l) => { l.htmlFor = `opt-function.${l.htmlFor.replace(/^opt-/, "")}`; });
    fnBox.querySelectorAll(".msg").forEach((m) => { m.id = `opt-function.${m.id.replace(/^opt-/, "")}`; });
    if (same) fnBox.querySelectorAll("[data-path]").forEach((i) => kit.fill(i, at(start, i.dataset.path)));
    else {
      // another linkage: its manual example to start from
      const other = Object.values(api.components.schemas.MachineOptimiseIn.examples || []).map((e) => e.function).find((f) => f && f.type === type);
      fnBox.querySelectorAll("[data-path]").forEach((i) => kit.fill(i, other ? at({ function: other }, i.dataset.path) : undefined));
    }
  };
  document.getElementById("opt-function.type").addEventListener("change", fnFields);
  fnFields();
  // one window load: its force or torque and where it acts
  put(loadBox, kit.schemaFields("opt", "WindowLoadIn", { skip: ["type"], labels: { force_N: "Force on a slider", torque_Nm: "Torque on a rocker",
    start_deg: "From crank angle", end_deg: "To crank angle", stroke: "Acts in the stroke", direction: "Direction", frame_angle_deg: "Direction in the frame",
    point_m: "Point of action" }, folds: { "": "The load" }, open: true }).map((d) => { d.id = "opt-load-fields"; d.querySelectorAll("[data-path]").forEach((i) => { i.dataset.path = `loads.0.${i.dataset.path}`; i.id = `opt-${i.dataset.path}`; i.closest(".row").dataset.field = i.dataset.path; }); return d; }));
  loadBox.querySelectorAll("label[for]").forEach((l) => { l.htmlFor = `opt-loads.0.${l.htmlFor.replace(/^opt-/, "")}`; });
  loadBox.querySelectorAll(".msg").forEach((m) => { m.id = `opt-loads.0.${m.id.replace(/^opt-/, "")}`; });
  loadBox.querySelectorAll("[data-path]").forEach((i) => kit.fill(i, at(start, i.dataset.path)));
  // the weights, shown when the objective is a weighted sum
  put(weightsBox, Object.keys(OBJECTIVES).map((k) => {
    const row = kit.schemaField("opt", { path: `weights.${k}`, label: `Weight of the ${OBJECTIVES[k]}`, schema: ["MachineOptimiseIn", "weights"] });
    const input = row.querySelector("input, textarea");
    const plain = h("input", { id: `opt-weights.${k}`, name: `weights.${k}`, type: "text", inputmode: "decimal", autocomplete: "off", title: input.title,
      placeholder: "0", dataset: { path: `weights.${k}`, type: "number", kind: "plain", unit: "–" } });
    input.replaceWith(plain);
    row.querySelector(".unit").textContent = "–";
    kit.fill(plain, at(start, `weights.${k}`));
    return row;
  }));
  const showWeights = () => { weightsBox.hidden = document.getElementById("opt-objective").value !== "weights"; };
  document.getElementById("opt-objective").addEventListener("change", showWeights);
  showWeights();
  // the rest of the request from the example
  box.querySelectorAll("details [data-path]").forEach((i) => {
    if (!i.dataset.path.startsWith("function.") && !i.dataset.path.startsWith("loads.")) kit.fill(i, at(start, i.dataset.path));
  });

  /** The request the form holds: every field filled, the rest the API's defaults. */
  function request() {
    const body = { function: { type: document.getElementById("opt-function.type").value } };
    box.querySelectorAll("[data-path]").forEach((input) => {
      const path = input.dataset.path;
      if (path.startsWith("weights.") && weightsBox.hidden) return;
      const v = kit.readSchemaField(input);
      if (v !== undefined) setPath(body, path, v);
    });
    if (body.loads && body.loads[0]) body.loads[0].type = "window";
    const objective = document.getElementById("opt-objective").value;
    if (objective !== "weights") body.objective = objective;
    body.pareto = [document.getElementById("opt-pareto.0").value, document.getElementById("opt-pareto.1").value];
    const cells = document.getElementById("opt-search_cells").value;
    if (cells) body.search_cells = cells === "all" ? "all" : Number(cells);
    const n = Number(document.getElementById("opt-drive.stages.count").value);
    setPath(body, "drive.stages", Array.from({ length: n }, () => document.getElementById("opt-drive.stages.type").value));
    return body;
  }

  async function openMember(m) {
    if (!lastRequest || !m.mechanism) return;
    const body = { mechanism: m.mechanism };
    for (const k of MACHINE_FIELDS) if (lastRequest[k] !== undefined) body[k] = lastRequest[k];
    put(member, h("p", { class: "note" }, "designing that member…"));
    try {
      const d = await post("/v1/machines/design", body);
      put(member, designSummary(d, m));
      done("member");
    } catch (err) {
      put(member);
      showProblem(problem, err);
      done("member-problem");
    }
  }

  async function run() {
    kit.clearPanel("opt");
    put(member);
    if (!kit.checkSchemaFields("optimise")) { done("problem"); return; }
    const body = request();
    put(result);
    const step = longStep(progress, "opt", "optimising…");
    document.getElementById("opt-run").disabled = true;
    try {
      const a = await post("/v1/machines/optimise", body, { signal: step.signal });
      lastRequest = body;
      const unit = (g) => (g.unit === "currency" ? "currency" : g.unit);
      const gains = a.gains.map((g) => [OBJECTIVES[g.objective] || g.objective.replace(/_/g, " "), fmt(g.chain), fmt(g.optimum), unit(g)]);
      put(result,
        h("h3", {}, `The machine: member u = ${fmt(a.parameter)}, motor ${a.design.drive.motor.name}, `
          + `${a.design.passed ? "every check passed" : "a check failed"}`),
        table(["objective", "chain's machine", "optimum", "unit"], gains, { id: "opt-gains" }),
        a.parts ? h("p", { id: "opt-parts" }, `Machine mass ${fmt(a.parts.machine_mass_kg, 4)} kg (counterweights `
          + `${fmt(a.parts.counterweights_kg, 3)} kg, flywheel ${fmt(a.parts.flywheel_kg, 3)} kg, gears ${fmt(a.parts.gears_kg, 3)} kg, `
          + `motor ${a.parts.motor} ${fmt(a.parts.motor_kg, 3)} kg); cost ${fmt(a.parts.cost, 4)} currency (the prices' own)`) : null,
        h("h3", {}, `Every member designed: ${OBJECTIVES[a.pareto_objectives[0]]} against ${OBJECTIVES[a.pareto_objectives[1]]}`),
        h("p", { class: "note" }, "Blue: the Pareto set; ringed red: the optimum; grey: the other feasible members."),
        scatter(a, openMember),
        cells(a.certificate),
        h("details", { id: "opt-certificate" }, h("summary", {}, "How the family was covered (the certificate)"),
          h("p", {}, a.certificate.statement)));
      done("optimised");
    } catch (err) {
      put(result);
      if (cancelled(err)) { put(status, "cancelled: the last answer was not changed"); done("cancelled"); }
      else {
        kit.panelProblem("opt", err);
        done("problem");
      }
    } finally {
      step.end();
      document.getElementById("opt-run").disabled = false;
    }
  }
  document.body.dataset.optimiseReady = "1";
}

admitted.then(async (ok) => {
  if (!ok) return;
  await panelsReady;
  await kit.loadCatalogues();
  build(await get("/openapi.json"));
});
