// What the page hands on: the analysis as CSV, the drawing as SVG and DXF, the diagrams as PNG (each the API's own
// rendering of the same request), and vectors drawn on the linkage: velocities, accelerations, joint reactions.
import { postFile } from "./api.js";
import { h, s } from "./dom.js";
import { drawLinkage } from "./draw.js";

const VECTORS = [["", "no vectors"], ["velocity", "velocities"], ["acceleration", "accelerations"], ["reaction", "joint reactions"]];

function download(blob, name) {
  const a = h("a", { href: URL.createObjectURL(blob), download: name });
  document.body.appendChild(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 5000);
}

/** The arrows to draw at sample `i`: each point's velocity or acceleration, or each joint's reaction, scaled so the
 *  longest is a quarter of the drawing. */
export function vectorsAt(answer, kind, i, span) {
  if (!kind || !answer) return [];
  const list = [];
  if (kind === "reaction") {
    for (const [joint, forces] of Object.entries(answer.joint_reactions_N || {})) {
      if (answer.points[joint]) list.push({ point: joint, value: forces[i], unit: "N" });
    }
  } else {
    const key = kind === "velocity" ? "velocity_m_s" : "acceleration_m_s2", unit = kind === "velocity" ? "m/s" : "m/s²";
    for (const [name, p] of Object.entries(answer.points)) {
      if (name.startsWith("cw") || !p[key]) continue;
      list.push({ point: name, value: p[key][i], unit });
    }
  }
  const longest = Math.max(...list.map((v) => Math.hypot(v.value[0], v.value[1])), 0);
  const scale = longest > 0 ? (0.25 * span) / longest : 0;
  return list.map((v) => ({ ...v, kind, scale,
    label: `${kind} at ${v.point}: ${Math.hypot(v.value[0], v.value[1]).toPrecision(4)} ${v.unit} at ${(Math.atan2(v.value[1], v.value[0]) * 180 / Math.PI).toFixed(1)}°` }));
}

// The drawing's look, written into the file: an SVG opened on its own has none of the page's style sheet.
const ANIMATION_STYLE = `text { font-family: sans-serif; fill: #223047; } .link { stroke: #2d3e5c; stroke-linecap: round; fill: none; }
.link.crank { stroke: #1f5fbf; } .joint { fill: #fff; stroke: #2d3e5c; } .ground { fill: #8a93a3; } .path-curve { fill: none; stroke: #c25e00; }
.crank-circle { fill: none; stroke: #9fb4d9; } .guide { stroke: #8a93a3; } .cw { fill: #e8a25f; stroke: #6d3500; } .com { fill: #2d3e5c; }
.target { fill: #d0243a; stroke: #fff; } .slider { fill: #dfe7f3; stroke: #2d3e5c; } .scale-bar { stroke: #223047; }`;

/** The linkage turning through one cycle as one animated SVG: `frames` drawings of the answer, each shown in turn
 *  for its share of the cycle (SMIL, played by every browser; no script), at the real cycle time kept between 1 and
 *  10 s. */
export function animation(state, extrasAt, frames = 72) {
  const a = state.answer, n = a.crank_angle_deg.length, lay = state.layout;
  const count = Math.min(frames, n);
  const period = 60 / (state.design.speed_rpm || 60), dur = Math.min(10, Math.max(1, period));
  const w = lay.x1 - lay.x0, hgt = lay.y1 - lay.y0;
  const out = s("svg", { xmlns: "http://www.w3.org/2000/svg", viewBox: `${lay.x0} ${-lay.y1} ${w} ${hgt}`, width: 800, height: Math.round((800 * hgt) / w) },
    s("title", {}, `The linkage over one crank turn: ${count} frames in ${dur.toPrecision(3)} s` +
      (Math.abs(dur - period) > 1e-9 ? ` (the real cycle takes ${period.toPrecision(3)} s)` : "")),
    s("style", {}, ANIMATION_STYLE), s("rect", { x: lay.x0, y: -lay.y1, width: w, height: hgt, fill: "#fff" }));
  const scratch = s("svg", {});
  for (let k = 0; k < count; k++) {
    const i = Math.round((k * n) / count) % n;
    drawLinkage(scratch, a, state.design, i, lay, extrasAt(i));
    const g = scratch.firstChild;
    g.setAttribute("class", "frame");
    g.dataset.angle = String(a.crank_angle_deg[i]);
    g.setAttribute("visibility", k === 0 ? "visible" : "hidden");
    // visible from k/count to (k+1)/count of the period
    const values = [], times = [];
    if (k > 0) { values.push("hidden"); times.push(0); }
    values.push("visible"); times.push(k / count);
    if (k + 1 < count) { values.push("hidden"); times.push((k + 1) / count); }
    g.appendChild(s("animate", { attributeName: "visibility", values: values.join(";"), keyTimes: times.map((x) => x.toFixed(6)).join(";"),
      calcMode: "discrete", dur: `${dur.toPrecision(4)}s`, repeatCount: "indefinite" }));
    out.appendChild(g);
  }
  return new XMLSerializer().serializeToString(out);
}

/** The export buttons and the vector choice, under the drawing. */
export function installExports({ state, request, redraw, setStatus, extrasAt }) {
  const bar = h("span", { class: "exports" });
  const choose = h("select", { id: "vectors", title: "Arrows drawn at the joints at this crank angle" },
    VECTORS.map(([v, l]) => h("option", { value: v }, l)));
  choose.addEventListener("change", () => { state.vectors = choose.value; redraw(); });
  const angle = () => (state.answer ? state.answer.crank_angle_deg[state.index] : 0);
  const get = async (path, name) => {
    try {
      setStatus(`preparing ${name}…`);
      const blob = await postFile(path, request());
      download(blob, name);
      setStatus(`${name} downloaded`);
      document.body.dataset.exported = name;
    } catch (err) { setStatus(`${name}: ${err.message}`); }
  };
  const button = (label, title, path, name) => h("button", { type: "button", class: "export", id: `export-${label.toLowerCase()}`, title,
    onclick: () => get(path(), name) }, label);
  bar.append(choose,
    button("CSV", "Every curve of the analysis, one row per crank angle", () => "/v1/analysis?format=csv", "analysis.csv"),
    button("SVG", "The drawing at this crank angle, to scale in mm", () => `/v1/analysis/drawing?format=svg&angle_deg=${angle()}`, "mechanism.svg"),
    button("DXF", "The drawing at this crank angle, for CAD", () => `/v1/analysis/drawing?format=dxf&angle_deg=${angle()}`, "mechanism.dxf"),
    button("PNG", "The diagrams and the mechanism as one figure", () => `/v1/analysis?format=png&angle_deg=${angle()}`, "analysis.png"),
    h("button", { type: "button", class: "export", id: "export-animation", title: "The linkage turning through one cycle, as an animated SVG",
      onclick: () => {
        if (!state.answer || !state.layout) { setStatus("nothing analysed yet to animate"); return; }
        download(new Blob([animation(state, extrasAt)], { type: "image/svg+xml" }), "mechanism-animation.svg");
        setStatus("mechanism-animation.svg downloaded");
        document.body.dataset.exported = "mechanism-animation.svg";
      } }, "Animation"));
  document.querySelector("#drawing-box figcaption").appendChild(bar);
}
