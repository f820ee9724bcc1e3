// What the page hands on: the analysis as CSV, the drawing as SVG and DXF, the diagrams as PNG (each the API's own
// rendering of the same request), and vectors drawn on the linkage: velocities, accelerations, joint reactions.
import { postFile } from "./api.js";
import { h } from "./dom.js";

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

/** The export buttons and the vector choice, under the drawing. */
export function installExports({ state, request, redraw, setStatus }) {
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
    button("PNG", "The diagrams and the mechanism as one figure", () => `/v1/analysis?format=png&angle_deg=${angle()}`, "analysis.png"));
  document.querySelector("#drawing-box figcaption").appendChild(bar);
}
