// The Machine panel's optimisation: the machine's function in (the request of POST /v1/machines/optimise as
// JSON), the optimised machine out, its gains, its certificate, and the Pareto scatter of every member designed;
// a point opens that member's design (POST /v1/machines/design with the optimisation's machine around it).
// It lives beside the Machine panel and shows with it. Like the rest of the page, a client of the public API.

import { post, get, Problem } from "./api.js";
import { h, s, put, table } from "./dom.js";
import { admitted } from "./signin.js";

const MACHINE_FIELDS = ["loads", "speed_rpm", "samples", "delta", "machine_type", "drive", "balancing", "flywheel",
  "speed_tolerance", "friction", "brake_torque_Nm", "start_under_load", "max_startup_time_s", "max_rundown_time_s"];
const UNITS = { motor_power: "W", added_mass: "kg", rms_shaking_force: "N", machine_mass: "kg", cost: "" };
const KEYS = { motor_power: "motor_power_W", added_mass: "added_mass_kg", rms_shaking_force: "rms_shaking_force_N",
  machine_mass: "machine_mass_kg", cost: "cost" };

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
    "aria-label": `Every feasible member designed: ${a} against ${b}` },
  s("rect", { x: L, y: T, width: W - L - R, height: H - B - T, fill: "none", stroke: "#999" }),
  s("text", { x: (L + W - R) / 2, y: H - 8, "text-anchor": "middle", "font-size": 12 }, `${a} [${UNITS[a]}]`),
  s("text", { x: 14, y: (T + H - B) / 2, "text-anchor": "middle", "font-size": 12, transform: `rotate(-90 14 ${(T + H - B) / 2})` }, `${b} [${UNITS[b]}]`),
  [x0, x1].map((v, i) => s("text", { x: i ? W - R : L, y: H - B + 14, "text-anchor": i ? "end" : "start", "font-size": 10 }, fmt(v, 4))),
  [y0, y1].map((v, i) => s("text", { x: L - 4, y: i ? T + 10 : H - B, "text-anchor": "end", "font-size": 10 }, fmt(v, 4))),
  pts.map((m) => {
    const chosen = m.parameter === answer.parameter, onFront = front.has(m.parameter);
    return s("circle", { cx: X(m[KEYS[a]]), cy: Y(m[KEYS[b]]), r: chosen ? 7 : 4.5, class: "opt-point",
      fill: onFront ? "#1f6fb2" : "#bbb", stroke: chosen ? "#c0392b" : "#555", "stroke-width": chosen ? 2.5 : 0.8,
      tabindex: 0, role: "button", dataset: { parameter: String(m.parameter), stage: m.stage },
      onclick: () => onOpen(m), onkeydown: (e) => { if (e.key === "Enter") onOpen(m); } },
    s("title", {}, `u = ${fmt(m.parameter)} (${m.stage}): ${a} ${fmt(m[KEYS[a]])}, ${b} ${fmt(m[KEYS[b]])}`));
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

function build() {
  const machine = document.getElementById("panel-machine");
  // not a .panel: the tabs show one .panel at a time, and this box shows with the Machine panel
  const box = h("div", { id: "panel-optimise", role: "region", "aria-label": "Optimise the machine" });
  machine.after(box);
  const follow = () => { box.hidden = machine.hidden; };
  new MutationObserver(follow).observe(machine, { attributes: true, attributeFilter: ["hidden"] });
  follow();
  const text = h("textarea", { id: "opt-json", rows: 12, cols: 90, spellcheck: "false",
    "aria-label": "The request of POST /v1/machines/optimise" });
  const status = h("span", { id: "opt-status", class: "note" });
  const problem = h("p", { id: "opt-problem", class: "problem", hidden: true });
  const result = h("div", { id: "opt-result" });
  const member = h("div", { id: "opt-member" });
  put(box, h("h2", {}, "Optimise the machine as a whole, from its function"),
    h("p", { class: "note" }, "The function (swing or stroke and time ratio), the load, the speed, the drive and what to "
      + "minimise, as POST /v1/machines/optimise takes them: the service chooses the linkage's member with its "
      + "counterweights, flywheel, motor and ratio. Each point of the scatter is a member designed; click one to open its design."),
    text, h("div", {}, h("button", { class: "run", id: "opt-run", onclick: () => run() }, "Optimise"), " ", status),
    problem, result, member);

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
    problem.hidden = true;
    put(member);
    let body;
    try {
      body = JSON.parse(text.value);
      if (!body || typeof body !== "object" || Array.isArray(body)) throw new Error("not an object");
    } catch {
      put(problem, "The request is not a JSON object: write it as the request of POST /v1/machines/optimise.");
      problem.hidden = false;
      done("problem");
      return;
    }
    put(status, "optimising…");
    try {
      const a = await post("/v1/machines/optimise", body);
      lastRequest = body;
      const gains = a.gains.map((g) => [g.objective, fmt(g.chain), fmt(g.optimum), g.unit === "currency" ? "" : g.unit]);
      put(result,
        h("h3", {}, `The machine: member u = ${fmt(a.parameter)}, motor ${a.design.drive.motor.name}, `
          + `${a.design.passed ? "every check passed" : "a check failed"}`),
        table(["objective", "chain's machine", "optimum", "unit"], gains, { id: "opt-gains" }),
        a.parts ? h("p", { id: "opt-parts" }, `Machine mass ${fmt(a.parts.machine_mass_kg, 4)} kg (counterweights `
          + `${fmt(a.parts.counterweights_kg, 3)}, flywheel ${fmt(a.parts.flywheel_kg, 3)}, gears ${fmt(a.parts.gears_kg, 3)}, `
          + `motor ${a.parts.motor} ${fmt(a.parts.motor_kg, 3)} kg); cost ${fmt(a.parts.cost, 4)}`) : null,
        h("h3", {}, `Every member designed: ${a.pareto_objectives[0]} against ${a.pareto_objectives[1]}`),
        h("p", { class: "note" }, "Blue: the Pareto set; ringed red: the optimum; grey: the other feasible members."),
        scatter(a, openMember),
        cells(a.certificate),
        h("details", { id: "opt-certificate" }, h("summary", {}, "How the family was covered (the certificate)"),
          h("p", {}, a.certificate.statement)));
      put(status, "");
      done("optimised");
    } catch (err) {
      put(status, "");
      put(result);
      showProblem(problem, err);
      done("problem");
    }
  }

  get("/openapi.json").then((api) => {
    // the manual's slider-crank press, its Pareto set between the added mass and the shaking force: members
    // that differ in both, so the scatter spreads
    const ex = api.components.schemas.MachineOptimiseIn.examples;
    const start = ex && (ex[1] || ex[0]);
    if (start) text.value = JSON.stringify({ ...start, pareto: ["added_mass", "rms_shaking_force"] }, null, 2);
  }).catch(() => {}).finally(() => { document.body.dataset.optimiseReady = "1"; });
}

admitted.then((ok) => { if (ok) build(); });
