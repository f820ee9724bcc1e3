// The Cams panel: a disc cam as the JSON request of POST /v1/cams/analysis, analysed or made the least cam for
// pressure-angle limits (POST /v1/cams/synthesis), with the service's figure, its checks and the point table and
// drawing as files. Like the rest of the page, a client of the public API only.

import { post, postFile, get, Problem } from "./api.js";
import { h, put } from "./dom.js";
import { admitted } from "./signin.js";

const panel = document.getElementById("panel-cams");
let seq = 0;
// The base-radius bounds in the form's length unit (the editor's choice at the top), metres on the wire.
const LENGTH = { mm: 1e-3, m: 1 };
const lengthUnit = () => document.getElementById("unit-length").value;

function numberRow(id, label, value, unit, attrs = {}) {
  return h("div", { class: "row" }, h("label", { for: id }, label),
    h("input", { id, type: "number", value, step: "any", ...attrs }), h("span", { class: "unit" }, unit));
}

function done(kind) {
  seq += 1;
  document.body.dataset.cam = `${kind}-${seq}`;
}

function fmt(x, digits = 4) { return Number(x).toPrecision(digits); }

async function exampleRequest() {
  try {
    const api = await get("/openapi.json");
    const examples = api.components.schemas.CamAnalysisIn.examples;
    return examples && examples[0];
  } catch {
    return null;
  }
}

function readRequest(textarea, problem) {
  try {
    const body = JSON.parse(textarea.value);
    if (!body || typeof body !== "object" || Array.isArray(body)) throw new Error("not an object");
    return body;
  } catch {
    put(problem, "The cam is not a JSON object: write it as the request of POST /v1/cams/analysis.");
    problem.hidden = false;
    return null;
  }
}

function showProblem(problem, err) {
  const body = err instanceof Problem ? err.body : {};
  const where = body.field ? ` (field ${body.field})` : body.constraint ? ` (constraint ${body.constraint})` : "";
  put(problem, `${err.message}${where}`);
  problem.hidden = false;
}

function download(link, blob, name) {
  if (link.href) URL.revokeObjectURL(link.href);
  link.href = URL.createObjectURL(blob);
  link.download = name;
  link.hidden = false;
}

function summary(out, least) {
  const p = out.profile;
  const c = out.checks;
  const lines = [];
  if (least) {
    lines.push(h("p", { id: "cam-least" }, `Least base radius ${fmt(least.base_radius_m * 1000, 5)} mm at offset `
      + `${fmt(least.offset_m * 1000, 4)} mm; active: ${least.active_constraint}.`));
  }
  lines.push(h("p", {}, `Base radius ${fmt(p.base_radius_m * 1000, 5)} mm; largest pressure angle `
    + `${fmt(p.max_pressure_angle_rise_deg)}° in the rise, ${fmt(p.max_pressure_angle_return_deg)}° in the return; `
    + `least radius of curvature ${fmt(p.min_curvature_radius_m * 1000)} mm at ${fmt(p.min_curvature_radius_at_deg)}°.`));
  if (out.forces) {
    lines.push(h("p", {}, `Contact force ${fmt(out.forces.min_contact_force_N)} to ${fmt(out.forces.max_contact_force_N)} N; `
      + `peak driving torque ${fmt(out.forces.peak_driving_torque_Nm)} N·m.`));
  }
  lines.push(h("p", { id: "cam-checks" }, `Checks: pressure angle from the point table within `
    + `${c.table_pressure_angle_error_deg.toExponential(1)}°, curvature within ${c.table_curvature_error.toExponential(1)}`
    + (c.torque_virtual_power_error === null ? "" : `, torque by virtual power within ${c.torque_virtual_power_error.toExponential(1)}`) + "."));
  return lines;
}

async function build() {
  const example = await exampleRequest();
  const textarea = h("textarea", { id: "cam-json", rows: 16, spellcheck: "false", "aria-label": "The cam as JSON" });
  textarea.value = JSON.stringify(example || {}, null, 1);
  const rise = numberRow("cam-alpha-rise", "Largest pressure angle, rise", 30, "deg", { min: 1, max: 89 });
  const ret = numberRow("cam-alpha-return", "Largest pressure angle, return", 45, "deg", { min: 1, max: 89 });
  let unit = lengthUnit();
  const lo = numberRow("cam-rb-min", "Base radius from", 0.005 / LENGTH[unit], unit, { min: 0 });
  const hi = numberRow("cam-rb-max", "Base radius to", 0.2 / LENGTH[unit], unit, { min: 0 });
  // the form's unit changed: the same bounds shown in the new one
  document.getElementById("unit-length").addEventListener("change", () => {
    const next = lengthUnit();
    for (const row of [lo, hi]) {
      const input = row.querySelector("input");
      if (input.value !== "") input.value = String(Number(((Number(input.value) * LENGTH[unit]) / LENGTH[next]).toPrecision(10)));
      row.querySelector(".unit").textContent = next;
    }
    unit = next;
  });
  const problem = h("p", { id: "cam-problem", class: "problem", role: "alert", hidden: true });
  const result = h("div", { id: "cam-summary", "aria-live": "polite" });
  const figure = h("img", { id: "cam-figure", alt: "s, v, a, jerk and pressure angle over the turn; the cam with its follower", hidden: true });
  figure.style.maxWidth = "100%";
  const csv = h("a", { id: "cam-csv", hidden: true }, "Point table (CSV)");
  const dxf = h("a", { id: "cam-dxf", hidden: true }, "Profile (DXF)");
  const analyse = h("button", { id: "cam-analyse", class: "run" }, "Analyse");
  const least = h("button", { id: "cam-least-run", class: "run" }, "Least cam");

  async function run(kind) {
    problem.hidden = true;
    const body = readRequest(textarea, problem);
    if (!body) return done("problem");
    let request = body;
    let path = "/v1/cams/analysis";
    if (kind === "least") {
      const { base_radius_m: _unused, ...rest } = body;
      request = { ...rest, max_pressure_angle_rise_deg: Number(rise.querySelector("input").value),
        max_pressure_angle_return_deg: Number(ret.querySelector("input").value),
        base_radius_bounds_m: [lo, hi].map((row) => Number(row.querySelector("input").value) * LENGTH[unit]) };
      path = "/v1/cams/synthesis";
    }
    // the figure and the figures beside it are of the last cam until the new answer is in: greyed and said so
    const updating = [figure, result];
    const note = document.getElementById("cam-updating");
    updating.forEach((el) => el.classList.add("stale-view"));
    note.hidden = false;
    note.textContent = kind === "least" ? "Finding the least cam… the figure below is of the last cam." : "Analysing… the figure below is of the last cam.";
    panel.dataset.updating = "1";
    const settled = () => { updating.forEach((el) => el.classList.remove("stale-view")); note.hidden = true; panel.dataset.updating = ""; };
    try {
      const out = await post(path, request);
      const cam = kind === "least" ? out.cam : out;
      put(result, summary(cam, kind === "least" ? out : null));
      if (kind === "least") {
        // the least cam becomes the cam of the editor, so Analyse and the files show it
        body.base_radius_m = out.base_radius_m;
        body.follower = { ...(body.follower || {}), offset_m: out.offset_m };
        textarea.value = JSON.stringify(body, null, 1);
      }
      const request2 = readRequest(textarea, problem);
      const [png, table, drawing] = await Promise.all(["png", "csv", "dxf"].map((f) => postFile(`/v1/cams/analysis?format=${f}`, request2)));
      if (figure.src) URL.revokeObjectURL(figure.src);
      figure.src = URL.createObjectURL(png);
      figure.hidden = false;
      download(csv, table, "cam.csv");
      download(dxf, drawing, "cam.dxf");
      settled();
      done(kind === "least" ? "synthesised" : "analysed");
    } catch (err) {
      settled();
      showProblem(problem, err);
      done("problem");
    }
  }

  analyse.addEventListener("click", () => run("analyse"));
  least.addEventListener("click", () => run("least"));
  put(panel, h("h2", {}, "Disc cam: motion law, profile, pressure angle, the least cam"),
    h("p", {}, "The cam as the request of POST /v1/cams/analysis (SI units; see the API manual for every field). "
      + "Least cam keeps the program and the follower and finds the least base circle for the limits."),
    h("div", { class: "row" }, textarea),
    h("div", { class: "controls" }, rise, ret, lo, hi),
    h("div", { class: "actions" }, analyse, least, csv, dxf),
    problem, h("p", { id: "cam-updating", class: "stale-note", role: "status", hidden: true }), result, figure);
  document.body.dataset.camReady = "1";
}

admitted.then((ok) => { if (ok && panel) build(); });
