// The Library panel: the workbench's design saved as a revision of a design in the office's library
// (/v1/library), found again, opened (its stored answer shown, read only), compared with another revision,
// checked, approved or returned with a comment, and its design record downloaded. Signed in, each person sees
// the buttons their roles and the revision allow, and no name field (the service knows who they are). Like the
// rest of the page, a client of the public API only.

import { post, get, Problem } from "./api.js";
import { csrf } from "./signin.js";
import { h, put, table } from "./dom.js";
import { longStep, cancelled } from "./progress.js";

const LIB = "/v1/library";
const KINDS = [["/v1/machines/design", "machine + record"], ["/v1/analysis", "linkage"]];
const panel = document.getElementById("panel-library");
// The revision the workbench's design was opened from or last saved as: the parent of the next save.
let current = null;
let seq = 0;
// Who is at the page: {auth: "on"|"off", signed_in, name, roles}; with authentication off anyone may press anything
// and types their name.
let me = { auth: "off", signed_in: false, name: null, roles: [] };
// The last search, run again after every action so that its rows never go stale.
let lastSearch = null;

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

function who() { const f = el("lib-name"); return (f && f.value.trim()) || null; }

const signedIn = () => me.auth === "on" && me.signed_in;
const holds = (...roles) => !signedIn() || roles.some((r) => me.roles.includes(r));
/** What this person may do to revision ``r`` (a row of a history): the service refuses the rest anyway. */
function may(r) {
  const notAuthor = !signedIn() || r.author !== me.name;
  return {
    save: holds("engineer", "admin"),
    check: r.state === "draft" && holds("checker") && notAuthor,
    approve: r.state === "checked" && holds("approver") && notAuthor && (!signedIn() || r.checked_by !== me.name),
    ret: (r.state === "draft" || r.state === "checked") && holds("checker", "approver") && notAuthor,
  };
}

function result(r) {
  if (r.passed === true) return h("span", { class: "pass" }, "passed");
  if (r.passed === false) return h("span", { class: "fail" }, "FAILED");
  return r.state === "imported" ? h("span", { class: "note" }, "not computed here") : "—";
}

const KIND = { returned: "returned", check: "checker's remark", approve: "approver's remark", deviation: "deviation", comment: "comment" };
function commentsOf(r) {
  return (r.comments || []).map((c) => `${KIND[c.kind] || c.kind} by ${c.author} ${day(c.created_at)}: ${c.text}`).join("; ");
}

async function save(branch = false) {
  const project = el("lib-project").value.trim(), design = el("lib-design").value.trim();
  const endpoint = el("lib-kind").value;
  put(el("lib-stale"));
  if (!project || !design) { say("Name the project and the design to save it.", true); return; }
  const same = current && current.project === project && current.design === design;
  const body = { endpoint, request: requestFor(endpoint), message: el("lib-message").value, author: who(),
    parent: same ? current.number : null, branch };
  say("");
  const step = longStep(el("lib-progress-box"), "lib", endpoint === "/v1/machines/design" ? "saving: the machine is designed and its record written…" : "saving…");
  el("lib-save").disabled = true;
  try {
    const r = await post(`${path(project, design)}/revisions`, body, { signal: step.signal });
    current = { project, design, number: r.number, endpoint };
    say(`Saved as revision ${r.number} of ${project}/${design} (${r.state}, ${r.passed === false ? "its answer FAILED a check: it is signed only with a deviation" : "passed"}); content hash ${r.content_hash.slice(0, 12)}…`, r.passed === false);
    await refresh(project, design);
    done("saved");
  } catch (err) {
    if (err instanceof Problem && err.status === 409 && err.body.head_revision) {
      const head = err.body.head_revision;
      say(`Not saved: ${project}/${design} is at revision ${head}, saved by somebody since you opened revision ${body.parent}. ` +
        `Saving would overwrite their work.`, true);
      put(el("lib-stale"),
        h("button", { id: "lib-branch", onclick: () => save(true) }, `Save as a branch from revision ${body.parent}`),
        h("button", { class: "secondary", onclick: () => { history(project, design); open(project, design, head); } }, `Open revision ${head}`));
    } else if (cancelled(err)) {
      // the page stopped waiting; the service finishes what it started, so the history says whether it was saved
      say(`Stopped waiting: the service may still save this revision; the history of ${project}/${design} shows whether it did.`, true);
      done("cancelled");
      return;
    } else say(`Not saved: ${problemText(err)}`, true);
    done("refused");
  } finally {
    step.end();
    el("lib-save").disabled = false;
  }
}

async function search(again = false) {
  const q = again && lastSearch ? lastSearch : new URLSearchParams();
  if (!again) {
    const name = el("lib-find").value.trim(), project = el("lib-project").value.trim();
    if (name) q.set("name", name);
    if (project && el("lib-only-project").checked) q.set("project", project);
    if (el("lib-only-deviations").checked) q.set("deviation", "true");
    lastSearch = q;
  }
  try {
    const found = await get(`${LIB}/revisions?${q}`);
    put(el("lib-found"), found.length ? table(["project", "design", "revision", "type", "author", "result", "state", "deviation", "comments", "saved", ""],
      found.map((r) => [r.project, r.design, [String(r.number), { class: "num" }], r.endpoint.replace("/v1/", ""), r.author, result(r),
        [r.state, { class: `state ${r.state}` }], r.deviation || "", commentsOf(r), day(r.created_at),
        h("button", { class: "secondary", onclick: () => history(r.project, r.design) }, "History")]), { class: "lib-list", id: "lib-found-table" })
      : h("p", { class: "note" }, "Nothing in the library matches."));
    if (!again) done("found");
  } catch (err) { say(problemText(err), true); }
}

/** After an action: the design's history and the last search again, so no table shows a state that moved. */
async function refresh(project, design) {
  await history(project, design);
  if (lastSearch) await search(true);
}

async function open(project, design, number) {
  try {
    const r = await get(`${path(project, design)}/revisions/${number}`);
    current = { project, design, number, endpoint: r.endpoint };
    el("lib-project").value = project; el("lib-design").value = design; el("lib-kind").value = r.endpoint;
    say(`Opened revision ${number} of ${project}/${design} (${r.state})` +
      (may(r).save ? ": the next save starts from it." : holds("checker", "approver")
        ? ": read only; its stored answer is below, and the linkage is analysed again as it was saved."
        : ": read only; its stored answer is below (analysing the linkage again needs the engineer, checker or approver role)."));
    showAnswer(r);
    await wb().setDesign(designOf(r.request));
    done("opened");
  } catch (err) { say(problemText(err), true); }
}

// The unit a figure's name carries (the service's own rule: the name's suffix).
const UNITS = [["_Nm_rad", "N·m/rad"], ["_kg_m3", "kg/m³"], ["_m_s2", "m/s²"], ["_kgm2", "kg·m²"], ["_m_s", "m/s"], ["_rad_s2", "rad/s²"],
  ["_rad_s", "rad/s"], ["_rpm", "rpm"], ["_deg", "°"], ["_Nm", "N·m"], ["_MPa", "MPa"], ["_Pa", "Pa"], ["_kg", "kg"], ["_W", "W"], ["_N", "N"],
  ["_m", "m"], ["_s", "s"], ["_h", "h"]];
const unitOf = (p) => { const k = p.split(".").filter((x) => !/^\d+$/.test(x)).pop() || ""; return (UNITS.find(([s]) => k.endsWith(s)) || ["", ""])[1]; };

/** Every figure of a stored answer (numbers; a curve as its length and range), its checks, pass or fail. */
function showAnswer(r) {
  const box = el("lib-answer");
  if (!r.answer) { put(box, h("p", { class: "note" }, `Revision ${r.number} keeps no answer (a study).`)); return; }
  const rows = [];
  const walk = (v, p) => {
    if (Array.isArray(v) && v.length && v.every((x) => typeof x === "number")) {
      rows.push([p, unitOf(p), v.length <= 4 ? v.map(fmt).join(", ") : `${v.length} values, ${fmt(Math.min(...v))} … ${fmt(Math.max(...v))}`]);
    } else if (Array.isArray(v) && v.length > 16) rows.push([p, "", `${v.length} items`]);
    else if (Array.isArray(v)) v.forEach((x, k) => walk(x, `${p}.${k}`));
    else if (v && typeof v === "object") Object.entries(v).forEach(([k, x]) => walk(x, p ? `${p}.${k}` : k));
    else if (typeof v === "number" || typeof v === "boolean") rows.push([p, unitOf(p), typeof v === "number" ? fmt(v) : String(v)]);
    else if (typeof v === "string" && p.split(".").pop() !== "request_sha256") rows.push([p, "", v]);
  };
  walk(r.answer, "");
  const origin = r.answer_origin === "imported"
    ? `imported: computed elsewhere and not verified here (${r.imported_note || ""}); restore it to compute it here`
    : "computed by this service from exactly this request when it was saved";
  const problem = r.answer.problem ? h("p", { class: "problem" }, `Refused by the engine: ${r.answer.problem.detail}`) : null;
  put(box, h("h3", {}, `Stored answer of revision ${r.number} (read only): `, result(r)),
    h("p", { class: "note" }, origin), problem,
    r.deviation ? h("p", { class: "problem" }, `Deviation: ${r.deviation}`) : null,
    h("details", { id: "lib-answer-figures", open: rows.length <= 40 }, h("summary", {}, `Every figure of the answer (${rows.length})`),
      table(["figure", "unit", "value"], rows.map(([p, u, v]) => [p, u, [v, { class: "num" }]]), { class: "lib-diff" })));
}

async function sign(project, design, number, role, passed) {
  const remark = el("lib-remark").value.trim();
  const body = { name: who() };
  if (role === "return") {
    if (!remark) { say("Say why it goes back: write the comment first.", true); done("refused"); return; }
    body.comment = remark;
  } else if (passed === false) {
    if (!remark) { say(`Revision ${number} FAILED a check: it is signed only as a deviation. Write the reason it is released anyway, then sign.`, true); done("refused"); return; }
    body.deviation = remark;
  } else if (remark) body.comment = remark;
  try {
    const r = await post(`${path(project, design)}/revisions/${number}/${role}`, body);
    const what = { check: `checked by ${r.checked_by}`, approve: `approved by ${r.approved_by}`, return: "returned to its author" }[role];
    say(`Revision ${number} is ${r.state}: ${what}.`);
    el("lib-remark").value = "";
    await refresh(project, design);
    done(role);
  } catch (err) { say(`Not signed: ${problemText(err)}`, true); done("refused"); }
}

async function restore(project, design, number) {
  try {
    const r = await post(`${path(project, design)}/revisions/${number}/restore`, { author: who(), message: el("lib-message").value.trim() });
    current = { project, design, number: r.number, endpoint: r.endpoint };
    say(`Revision ${number} restored as revision ${r.number} (${r.state}); revision ${number} itself is unchanged.`);
    await refresh(project, design);
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
    el("lib-project").value = project; el("lib-design").value = design;
    const last = d.revisions.length;
    const pick = (name, n) => h("input", { type: "radio", name, value: String(n), checked: n === (name === "lib-from" ? Math.max(1, last - 1) : last),
      "aria-label": `${name === "lib-from" ? "compare from" : "compare to"} revision ${n}` });
    const signedBy = (by, at) => (by ? `${by} ${day(at)}` : "");
    const rows = d.revisions.map((r) => {
      const can = may(r);
      return h("tr", { dataset: { revision: String(r.number) } },
        h("td", {}, pick("lib-from", r.number)), h("td", {}, pick("lib-to", r.number)),
        h("td", { class: "num" }, String(r.number)), h("td", {}, r.parent === null ? "" : String(r.parent)),
        h("td", {}, `${r.author} ${day(r.created_at)}`), h("td", {}, r.message), h("td", { class: "result" }, result(r)),
        h("td", { class: `state ${r.state}` }, r.state),
        h("td", {}, signedBy(r.checked_by, r.checked_at)), h("td", {}, signedBy(r.approved_by, r.approved_at)),
        h("td", { class: "deviation" }, r.deviation || ""), h("td", { class: "comments" }, commentsOf(r)),
        h("td", { class: "actions" },
          h("button", { class: "secondary", onclick: () => open(project, design, r.number) }, "Open"),
          r.number < last && can.save ? h("button", { class: "secondary", title: `save revision ${r.number}'s request again as the newest revision`,
            onclick: () => restore(project, design, r.number) }, "Restore") : null,
          can.check ? h("button", { class: "secondary", onclick: () => sign(project, design, r.number, "check", r.passed) }, r.passed === false ? "Check as a deviation" : "Check") : null,
          can.approve ? h("button", { class: "secondary", onclick: () => sign(project, design, r.number, "approve", r.passed) }, r.passed === false ? "Approve as a deviation" : "Approve") : null,
          can.ret ? h("button", { class: "secondary", title: "send it back to its author with the comment written above",
            onclick: () => sign(project, design, r.number, "return", r.passed) }, "Return") : null,
          r.links.record ? h("button", { class: "secondary", onclick: () => record(project, design, r.number) }, "Record (PDF)") : null));
    });
    put(el("lib-history"), h("h3", {}, `History of ${project}/${design} (${d.endpoint})`),
      h("table", { class: "lib-list" }, h("tr", {}, ["from", "to", "rev.", "parent", "saved by", "message", "result", "state", "checked", "approved", "deviation", "comments", ""].map((t) => h("th", {}, t))), rows),
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
    signedIn() ? h("p", { class: "note", id: "lib-who" }, `Signed in as ${me.name} (${me.roles.join(", ") || "no role"}). You may ` +
      ([holds("engineer", "admin") ? "save and restore designs" : null, holds("checker") ? "check revisions" : null,
        holds("approver") ? "approve revisions" : null, holds("checker", "approver") ? "return them with a comment" : null]
        .filter(Boolean).join(", ") || "open any revision and its stored answer, read only") + ".") : null,
    h("div", { class: "controls" },
      row("lib-project", "Project", h("input", { id: "lib-project", type: "text", value: "press-line", pattern: "[A-Za-z0-9._\\-]+", maxlength: 100 })),
      row("lib-design", "Design", h("input", { id: "lib-design", type: "text", value: "crank-rocker", maxlength: 100 })),
      holds("engineer", "admin") ? row("lib-kind", "Save", h("select", { id: "lib-kind" }, KINDS.map(([v, l]) => h("option", { value: v }, l)))) : h("select", { id: "lib-kind", hidden: true }, KINDS.map(([v, l]) => h("option", { value: v }, l))),
      holds("engineer", "admin") ? row("lib-message", "Message", h("input", { id: "lib-message", type: "text", maxlength: 2000, placeholder: "why this revision" })) : h("input", { id: "lib-message", type: "hidden" }),
      signedIn() ? null : row("lib-name", "Your name", h("input", { id: "lib-name", type: "text", maxlength: 100, autocomplete: "name",
        title: "Who saves or signs (the service has no sign-in)" })),
      holds("checker", "approver") ? row("lib-remark", "Comment or deviation", h("input", { id: "lib-remark", type: "text", maxlength: 2000,
        placeholder: "with Check, Approve or Return: why; for a revision that FAILED, the reason it is released anyway" })) : h("input", { id: "lib-remark", type: "hidden" })),
    holds("engineer", "admin") ? h("div", { class: "actions" }, h("button", { class: "run", id: "lib-save", onclick: () => save(false) }, "Save to the library"),
      h("span", { id: "lib-stale" })) : h("span", { id: "lib-stale" }),
    h("div", { id: "lib-progress-box", hidden: true }),
    h("p", { id: "lib-status", class: "note", role: "status" }),
    h("div", { class: "actions" },
      h("label", { for: "lib-find" }, "Find designs named"), h("input", { id: "lib-find", type: "search", placeholder: "part of a name" }),
      h("label", {}, h("input", { id: "lib-only-project", type: "checkbox" }), " in this project only"),
      h("label", {}, h("input", { id: "lib-only-deviations", type: "checkbox" }), " deviations only"),
      h("button", { class: "secondary", id: "lib-search", onclick: () => search(false) }, "Search")),
    h("div", { id: "lib-found" }), h("div", { id: "lib-history" }), h("div", { id: "lib-answer" }), h("div", { id: "lib-diff" }),
    h("a", { id: "lib-download", hidden: true }, "record"));
  el("lib-find").addEventListener("keydown", (e) => { if (e.key === "Enter") search(false); });
}

async function whoIsHere() {
  try {
    const r = await fetch("/v1/auth/session", { headers: { accept: "application/json" } });
    if (r.ok) me = await r.json();
  } catch { /* an open service: nobody signed in */ }
  render();
}

render();
whoIsHere();
