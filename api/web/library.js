// The Library panel: the workbench's design saved as a revision of a design in the office's library
// (/v1/library), found again, opened, compared with another revision, checked, approved, and its design record
// downloaded. Like the rest of the page, a client of the public API only.

import { post, get, Problem } from "./api.js";
import { csrf } from "./signin.js";
import { h, put, table } from "./dom.js";

const LIB = "/v1/library";
const KINDS = [["/v1/machines/design", "machine + record"], ["/v1/analysis", "linkage"]];
const panel = document.getElementById("panel-library");
// The revision the workbench's design was opened from or last saved as: the parent of the next save.
let current = null;
let seq = 0;

const wb = () => window.workbench;
const el = (id) => document.getElementById(id);
const path = (project, design) => `${LIB}/projects/${encodeURIComponent(project)}/designs/${encodeURIComponent(design)}`;

function done(what) {
  if (what !== "refused") put(el("lib-stale"));
  seq += 1;
  document.body.dataset.library = `${what}-${seq}`;
}

function say(text, problem = false) {
  const box = el("lib-status");
  box.className = problem ? "problem" : "note";
  put(box, text);
}

function problemText(err) {
  const body = err instanceof Problem ? err.body : {};
  return `${err.message}${body.field ? ` (field ${body.field})` : ""}`;
}

function fmt(x) {
  if (typeof x !== "number") return x === null || x === undefined ? "—" : JSON.stringify(x);
  return Math.abs(x) >= 1e5 || (x !== 0 && Math.abs(x) < 1e-3) ? x.toExponential(4) : String(Number(x.toPrecision(6)));
}

const day = (iso) => (iso ? iso.slice(0, 10) : "");

/** The fields of the workbench's design a request of ``endpoint`` takes, with the machine's own choices. */
function requestFor(endpoint) {
  const { state } = wb();
  const schema = endpoint === "/v1/machines/design" ? "MachineIn" : "AnalysisIn";
  const props = state.openapi.components.schemas[schema].properties || {};
  const body = Object.fromEntries(Object.entries(structuredClone(state.design)).filter(([k]) => k in props));
  if (endpoint === "/v1/machines/design") {
    // the Machine panel's own first choices: the target δ, a static balance, one helical stage to a 1500 rev/min motor
    Object.assign(body, { delta: 0.02, balancing: { mode: "static" }, drive: { stages: ["helical"], synchronous_rpm: 1500 }, alternatives: false });
  }
  return body;
}

/** A kept request opened as the workbench's design: the linkage fields the analysis takes. */
function designOf(request) {
  const props = wb().state.openapi.components.schemas.AnalysisIn.properties || {};
  return Object.fromEntries(Object.entries(structuredClone(request)).filter(([k]) => k in props));
}

function who() { return el("lib-name").value.trim() || null; }

async function save(branch = false) {
  const project = el("lib-project").value.trim(), design = el("lib-design").value.trim();
  const endpoint = el("lib-kind").value;
  put(el("lib-stale"));
  if (!project || !design) { say("Name the project and the design to save it.", true); return; }
  const same = current && current.project === project && current.design === design;
  const body = { endpoint, request: requestFor(endpoint), message: el("lib-message").value, author: who(),
    parent: same ? current.number : null, branch };
  say(endpoint === "/v1/machines/design" ? "saving: the machine is designed and its record written…" : "saving…");
  try {
    const r = await post(`${path(project, design)}/revisions`, body);
    current = { project, design, number: r.number, endpoint };
    say(`Saved as revision ${r.number} of ${project}/${design} (${r.state}); content hash ${r.content_hash.slice(0, 12)}…`);
    await history(project, design);
    done("saved");
  } catch (err) {
    if (err instanceof Problem && err.status === 409 && err.body.head_revision) {
      const head = err.body.head_revision;
      say(`Not saved: ${project}/${design} is at revision ${head}, saved by somebody since you opened revision ${body.parent}. ` +
        `Saving would overwrite their work.`, true);
      put(el("lib-stale"),
        h("button", { id: "lib-branch", onclick: () => save(true) }, `Save as a branch from revision ${body.parent}`),
        h("button", { class: "secondary", onclick: () => { history(project, design); open(project, design, head); } }, `Open revision ${head}`));
    } else say(`Not saved: ${problemText(err)}`, true);
    done("refused");
  }
}

async function search() {
  const q = new URLSearchParams();
  const name = el("lib-find").value.trim(), project = el("lib-project").value.trim();
  if (name) q.set("name", name);
  if (project && el("lib-only-project").checked) q.set("project", project);
  try {
    const found = await get(`${LIB}/revisions?${q}`);
    put(el("lib-found"), found.length ? table(["project", "design", "revision", "type", "author", "state", "saved", ""],
      found.map((r) => [r.project, r.design, [String(r.number), { class: "num" }], r.endpoint.replace("/v1/", ""), r.author, r.state, day(r.created_at),
        h("button", { class: "secondary", onclick: () => history(r.project, r.design) }, "History")]), { class: "lib-list" })
      : h("p", { class: "note" }, "Nothing in the library matches."));
    done("found");
  } catch (err) { say(problemText(err), true); }
}

async function open(project, design, number) {
  try {
    const r = await get(`${path(project, design)}/revisions/${number}`);
    current = { project, design, number, endpoint: r.endpoint };
    el("lib-project").value = project; el("lib-design").value = design; el("lib-kind").value = r.endpoint;
    say(`Opened revision ${number} of ${project}/${design} (${r.state}): the next save starts from it.`);
    await wb().setDesign(designOf(r.request));
    done("opened");
  } catch (err) { say(problemText(err), true); }
}

async function sign(project, design, number, role) {
  try {
    const r = await post(`${path(project, design)}/revisions/${number}/${role}`, { name: who() });
    say(`Revision ${number} is ${r.state}: ${role === "check" ? `checked by ${r.checked_by}` : `approved by ${r.approved_by}`}.`);
    await history(project, design);
    done(role);
  } catch (err) { say(`Not signed: ${problemText(err)}`, true); done("refused"); }
}

async function restore(project, design, number) {
  try {
    const r = await post(`${path(project, design)}/revisions/${number}/restore`, { author: who(), message: el("lib-message").value.trim() });
    current = { project, design, number: r.number, endpoint: r.endpoint };
    say(`Revision ${number} restored as revision ${r.number} (${r.state}); revision ${number} itself is unchanged.`);
    await history(project, design);
    done("restored");
  } catch (err) { say(`Not restored: ${problemText(err)}`, true); done("refused"); }
}

async function record(project, design, number) {
  say("writing the design record…");
  const r = await fetch(`${path(project, design)}/revisions/${number}/record`, { headers: csrf() });
  if (!r.ok) { say(`No record: ${(await r.json().catch(() => ({}))).detail || r.status}`, true); return; }
  const a = el("lib-download");
  if (a.href) URL.revokeObjectURL(a.href);
  a.href = URL.createObjectURL(await r.blob());
  a.download = `${project}-${design}-r${number}.pdf`;
  a.click();
  say(`Design record of revision ${number} downloaded.`);
  done("record");
}

async function history(project, design) {
  try {
    const d = await get(path(project, design));
    const last = d.revisions.length;
    const pick = (name, n) => h("input", { type: "radio", name, value: String(n), checked: n === (name === "lib-from" ? Math.max(1, last - 1) : last),
      "aria-label": `${name === "lib-from" ? "compare from" : "compare to"} revision ${n}` });
    const signedBy = (by, at) => (by ? `${by} ${day(at)}` : "");
    const rows = d.revisions.map((r) => h("tr", { dataset: { revision: String(r.number) } },
      h("td", {}, pick("lib-from", r.number)), h("td", {}, pick("lib-to", r.number)),
      h("td", { class: "num" }, String(r.number)), h("td", {}, r.parent === null ? "" : String(r.parent)),
      h("td", {}, `${r.author} ${day(r.created_at)}`), h("td", {}, r.message), h("td", { class: `state ${r.state}` }, r.state),
      h("td", {}, signedBy(r.checked_by, r.checked_at)), h("td", {}, signedBy(r.approved_by, r.approved_at)),
      h("td", { class: "actions" },
        h("button", { class: "secondary", onclick: () => open(project, design, r.number) }, "Open"),
        r.number < last ? h("button", { class: "secondary", title: `save revision ${r.number}'s request again as the newest revision`,
          onclick: () => restore(project, design, r.number) }, "Restore") : null,
        r.state === "draft" ? h("button", { class: "secondary", onclick: () => sign(project, design, r.number, "check") }, "Check") : null,
        r.state === "checked" ? h("button", { class: "secondary", onclick: () => sign(project, design, r.number, "approve") }, "Approve") : null,
        r.links.record ? h("button", { class: "secondary", onclick: () => record(project, design, r.number) }, "Record (PDF)") : null)));
    put(el("lib-history"), h("h3", {}, `History of ${project}/${design} (${d.endpoint})`),
      h("table", { class: "lib-list" }, h("tr", {}, ["from", "to", "rev.", "parent", "saved by", "message", "state", "checked", "approved", ""].map((t) => h("th", {}, t))), rows),
      h("div", { class: "actions" }, h("button", { id: "lib-compare", disabled: last < 2, onclick: () => compare(project, design) }, "Compare the two revisions")));
    put(el("lib-diff"));
  } catch (err) { say(problemText(err), true); }
}

async function compare(project, design) {
  const from = panel.querySelector("input[name=lib-from]:checked").value, to = panel.querySelector("input[name=lib-to]:checked").value;
  try {
    const d = await get(`${path(project, design)}/diff?from=${from}&to=${to}`);
    const rel = (c) => (c.change_rel === null ? "" : `${c.change_rel >= 0 ? "+" : ""}${(100 * c.change_rel).toFixed(1)} %`);
    put(el("lib-diff"), h("h3", {}, `Revision ${d.before} → ${d.after}`),
      d.request.length ? table(["input", "unit", "old", "new"], d.request.map((c) => [c.path, c.unit, [fmt(c.before), { class: "num" }], [fmt(c.after), { class: "num" }]]), { class: "lib-diff", id: "lib-diff-inputs" })
        : h("p", { class: "note" }, "The inputs are the same."),
      h("h3", {}, `Figures of the answer that moved, the largest relative change first (${d.answer.length}; ${d.unchanged_figures} unchanged` +
        `${d.noise_figures ? `; ${d.noise_figures} within the answers' own tolerance left out` : ""})`),
      figures(d.answer, rel));
    done("compared");
  } catch (err) { say(problemText(err), true); }
}

// The answer's single figures in a table; its curves (a value per crank angle, hundreds each) one row a curve, with
// how many of its values moved and the largest change, so that a machine's diff stays readable.
const SHOWN = 15;
const isCurve = (path) => path.split(".").some((p) => /^\d+$/.test(p));

function figures(changes, rel) {
  const single = changes.filter((c) => !isCurve(c.path));
  const curves = new Map();
  for (const c of changes.filter((x) => isCurve(x.path))) {
    const name = c.path.split(".").map((p) => (/^\d+$/.test(p) ? "[]" : p)).join(".").replace(/\.\[\]/g, "[]");
    const g = curves.get(name) || { unit: c.unit, count: 0, largest: 0 };
    g.count += 1;
    if (c.change !== null && Math.abs(c.change) > Math.abs(g.largest)) g.largest = c.change;
    curves.set(name, g);
  }
  const rows = single.map((c, k) => h("tr", { dataset: { path: c.path }, hidden: k >= SHOWN },
    h("td", {}, c.path), h("td", {}, c.unit), h("td", { class: "num" }, fmt(c.before)), h("td", { class: "num" }, fmt(c.after)),
    h("td", { class: "num" }, rel(c))));
  const more = single.length > SHOWN ? h("button", { class: "secondary", id: "lib-diff-all", onclick: (e) => {
    rows.forEach((r) => { r.hidden = false; }); e.currentTarget.hidden = true;
  } }, `Show all ${single.length} figures`) : null;
  return [
    single.length ? h("table", { class: "lib-diff", id: "lib-diff-figures" },
      h("tr", {}, ["figure", "unit", "old", "new", "change"].map((t) => h("th", {}, t))), rows) : null,
    h("div", { class: "actions" }, more),
    curves.size ? h("details", { id: "lib-diff-lists" }, h("summary", {}, `Curves and lists that moved (${curves.size})`),
      table(["curve or list", "unit", "values moved", "largest change"],
        [...curves].map(([name, g]) => [name, g.unit, [String(g.count), { class: "num" }], [fmt(g.largest), { class: "num" }]]),
        { class: "lib-diff", id: "lib-diff-curves" })) : null];
}

function render() {
  const row = (id, label, input) => h("div", { class: "row" }, h("label", { for: id }, label), input);
  put(panel, h("h2", {}, "The design library: save, find, compare and sign designs"),
    h("div", { class: "controls" },
      row("lib-project", "Project", h("input", { id: "lib-project", type: "text", value: "press-line", pattern: "[A-Za-z0-9._\\-]+", maxlength: 100 })),
      row("lib-design", "Design", h("input", { id: "lib-design", type: "text", value: "crank-rocker", maxlength: 100 })),
      row("lib-kind", "Save", h("select", { id: "lib-kind" }, KINDS.map(([v, l]) => h("option", { value: v }, l)))),
      row("lib-message", "Message", h("input", { id: "lib-message", type: "text", maxlength: 2000, placeholder: "why this revision" })),
      row("lib-name", "Your name", h("input", { id: "lib-name", type: "text", maxlength: 100, autocomplete: "name",
        title: "Who saves or signs, when the service has no sign-in (signed in, the service knows)" }))),
    h("div", { class: "actions" }, h("button", { class: "run", id: "lib-save", onclick: () => save(false) }, "Save to the library"),
      h("span", { id: "lib-stale" })),
    h("p", { id: "lib-status", class: "note", role: "status" }),
    h("div", { class: "actions" },
      h("label", { for: "lib-find" }, "Find designs named"), h("input", { id: "lib-find", type: "search", placeholder: "part of a name" }),
      h("label", {}, h("input", { id: "lib-only-project", type: "checkbox" }), " in this project only"),
      h("button", { class: "secondary", id: "lib-search", onclick: search }, "Search")),
    h("div", { id: "lib-found" }), h("div", { id: "lib-history" }), h("div", { id: "lib-diff" }),
    h("a", { id: "lib-download", hidden: true }, "record"));
  el("lib-find").addEventListener("keydown", (e) => { if (e.key === "Enter") search(); });
}

render();
