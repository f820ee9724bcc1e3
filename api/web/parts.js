// The Parts panel: the current linkage's bars sized for the cycle's forces (POST /v1/strength), each drawn along its
// length with the points where its checks are least; and a machine design's strength block shown under its answer.
// Like the rest of the page, a client of the public API only.

import { post, Problem } from "./api.js";
import { h, s, put, table } from "./dom.js";
import { state } from "./app.js";
import { admitted } from "./signin.js";

const panel = document.getElementById("panel-parts");
const LINKAGE = ["mechanism", "speed_rpm", "gravity", "loads", "torques", "counterweights"];
const GRADES = ["S235JR", "S355J2", "C45E+N", "C45E+QT", "42CrMo4+QT", "EN AW-6082-T6"];
const CHECKS = [["static", "static"], ["fatigue", "fatigue"], ["buckling_in_plane", "buckling in plane"],
  ["buckling_out_of_plane", "buckling out of plane"]];
const MARKS = { static: "#c0392b", fatigue: "#e67e22", buckling_in_plane: "#2e6fd0", buckling_out_of_plane: "#7d3cc0" };
let seq = 0;

function done(kind) {
  seq += 1;
  document.body.dataset.parts = `${kind}-${seq}`;
}

function fmt(x, digits = 3) { return x === null || x === undefined ? "∞" : Number(x).toPrecision(digits); }

function numberRow(id, label, value, unit, attrs = {}) {
  return h("div", { class: "row" }, h("label", { for: id }, label),
    h("input", { id, type: "number", value, step: "any", ...attrs }), h("span", { class: "unit" }, unit));
}

function selectRow(id, label, options, value) {
  return h("div", { class: "row" }, h("label", { for: id }, label),
    h("select", { id }, options.map(([v, text]) => h("option", { value: v, selected: v === value ? "" : undefined }, text))));
}

const value = (id) => document.getElementById(id).value;

function request() {
  const body = {};
  for (const k of LINKAGE) if (state.design[k] !== undefined && state.design[k] !== null) body[k] = structuredClone(state.design[k]);
  body.samples = 180;
  body.material = { grade: value("parts-grade") };
  body.section = { kind: value("parts-kind"), ratio: Number(value("parts-ratio")), min_size_mm: Number(value("parts-min")) };
  body.limits = { static_safety: Number(value("parts-static")), fatigue_safety: Number(value("parts-fatigue")),
    buckling_safety: Number(value("parts-buckling")) };
  return body;
}

/** One link along its length: the bar, its load points and where each check is least (lengths to scale). */
function linkDrawing(link) {
  const w = 520, pad = 30, hgt = 46;
  const span = Math.max(link.length_m, 1e-9);
  const x = (m) => pad + ((m - link.start_m) / span) * (w - 2 * pad);
  const bar = Math.min(16, Math.max(6, (link.dimensions_mm.height_mm || link.dimensions_mm.diameter_mm
    || link.dimensions_mm.outer_diameter_mm || 10) / 2));
  const svg = s("svg", { width: w, height: hgt + 18, class: "parts-link", "data-link": link.link,
    role: "img", "aria-label": `${link.link} drawn along its length` });
  svg.appendChild(s("rect", { x: x(link.start_m), y: hgt / 2 - bar / 2, width: x(link.start_m + span) - x(link.start_m),
    height: bar, fill: "#d5d8de", stroke: "#333" }));
  for (const [name, at] of Object.entries(link.points_m)) {
    if (name === "process_force" || name.startsWith("counterweight")) continue;
    svg.appendChild(s("circle", { cx: x(at), cy: hgt / 2, r: 4, fill: "#fff", stroke: "#333" }));
    svg.appendChild(s("text", { x: x(at), y: 10, "text-anchor": "middle", "font-size": 10 }, name));
  }
  // the four checks' marks one above the other, so marks at one section stay apart
  link.checks.forEach((c, i) => {
    svg.appendChild(s("circle", { cx: x(c.x_m), cy: hgt / 2 + (i - 1.5) * 7, r: 3.5, fill: MARKS[c.name], class: `mark-${c.name}` },
      s("title", {}, `${c.name.replace(/_/g, " ")}: n = ${fmt(c.safety)} (≥ ${c.required}) at ${fmt(c.crank_angle_deg, 3)}°`)));
  });
  svg.appendChild(s("text", { x: pad, y: hgt + 14, "font-size": 10 }, `${link.link}: ${link.section}, ${fmt(link.mass_kg)} kg`));
  return svg;
}

function linkTable(links, id) {
  return table(["link", "material", "section", "mass [kg]", ...CHECKS.map(([, label]) => `n ${label}`), "passed"],
    links.map((l) => {
      const by = Object.fromEntries(l.checks.map((c) => [c.name, c]));
      return [l.link, l.material, l.section, fmt(l.mass_kg, 4),
        ...CHECKS.map(([k]) => [fmt(by[k].safety), { class: by[k].passed ? "" : "fail", title: by[k].method }]),
        l.passed ? "yes" : "no"];
    }), { id, class: "data" });
}

function showProblem(problem, err) {
  const body = err instanceof Problem ? err.body : {};
  const where = body.link ? ` (link ${body.link}, ${body.check}, crank angle ${fmt(body.crank_angle_deg, 4)}°)`
    : body.field ? ` (field ${body.field})` : "";
  put(problem, `${err.message}${where}`);
  problem.hidden = false;
}

function build() {
  const problem = h("p", { id: "parts-problem", class: "problem", role: "alert", hidden: true });
  const result = h("div", { id: "parts-result", "aria-live": "polite" });
  const runButton = h("button", { id: "parts-run", class: "run" }, "Size the links");
  async function run() {
    problem.hidden = true;
    result.replaceChildren();
    try {
      const out = await post("/v1/strength", request());
      put(result,
        h("p", { id: "parts-summary" }, `${out.links.length} bars, ${fmt(out.mass_kg, 4)} kg in all, `
          + `${out.passed ? "every check met" : "a check fails"}; the fixed point settled in ${out.analyses} analyses `
          + `(mass residual ${fmt(out.mass_residual_kg, 2)} kg, beam closure ${out.closure_N.toExponential(1)} N).`),
        linkTable(out.links, "parts-table"),
        h("div", { id: "parts-drawings" }, out.links.map(linkDrawing)),
        out.notes.length ? h("p", { class: "note" }, out.notes.join(" ")) : null,
        h("p", { class: "note" }, "Marks: red static, orange fatigue, blue buckling in plane, purple out of plane; "
          + "hover a mark for its factor of safety and crank angle."));
      done("sized");
    } catch (err) {
      showProblem(problem, err);
      done("problem");
    }
  }
  runButton.addEventListener("click", run);
  put(panel, h("h2", {}, "Parts: the links sized for the cycle's forces"),
    h("p", { class: "note" }, "Each bar of the current linkage as a beam under its joint reactions and its own weight and "
      + "inertia at every crank angle: the least section of the shape that meets the static, fatigue and buckling checks; "
      + "the sized masses go back into the analysis until no section changes (POST /v1/strength)."),
    h("div", { class: "controls" },
      selectRow("parts-grade", "Material", GRADES.map((g) => [g, g]), "S355J2"),
      selectRow("parts-kind", "Section", [["rectangle", "flat bar"], ["round", "round bar"], ["tube", "tube"], ["ipe", "IPE"]], "rectangle"),
      numberRow("parts-ratio", "Height/width (tube: wall/diameter)", 3, "", { min: 0 }),
      numberRow("parts-min", "Smallest size", 6, "mm", { min: 0 }),
      numberRow("parts-static", "Least factor of safety, static", 1.5, "", { min: 1 }),
      numberRow("parts-fatigue", "Least factor of safety, fatigue", 1.5, "", { min: 1 }),
      numberRow("parts-buckling", "Least factor of safety, buckling", 2.5, "", { min: 1 })),
    h("div", { class: "actions" }, runButton), problem, result);
  document.body.dataset.partsReady = "1";
}

// --- the Machine panel's strength block ----------------------------------------------------------------------------

function machineStrength(res, m) {
  if (!m.strength) return;
  const st = m.strength;
  const parts = st.parts;
  res.appendChild(h("h3", {}, "Parts sized for strength"));
  res.appendChild(h("p", { id: "mac-strength-note" }, `Links ${fmt(st.link_mass_kg, 4)} kg after ${st.iterations.length} passes; `
    + (parts.crank_shaft ? `crank shaft ${fmt(parts.crank_shaft.diameter_mm, 3)} mm; ` : "")
    + `${parts.passed ? "every part's check met" : "a part fails a check"}.`));
  res.appendChild(linkTable(st.links, "mac-strength-links"));
  res.appendChild(table(["joint", "pin [mm]", "bearing", "passed"], parts.joints.map((j) => [j.joint, fmt(j.pin.diameter_mm),
    j.rolling ? j.rolling.designation : `${j.bushing.material} ${fmt(j.bushing.bore_mm)}×${fmt(j.bushing.length_mm)} mm`,
    j.passed ? "yes" : "no"]), { id: "mac-strength-joints", class: "data" }));
}

document.addEventListener("machine-answer", (evt) => machineStrength(evt.target, evt.detail));

admitted.then((ok) => { if (ok && panel) build(); });
