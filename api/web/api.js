// The page's only way to the engine: the public HTTP API, and the OpenAPI document for field descriptions.

import { csrf } from "./signin.js";

let openapi = null;

export async function loadOpenApi() {
  const r = await fetch("/openapi.json");
  openapi = await r.json();
  return openapi;
}

function deref(schema) {
  while (schema && schema.$ref) schema = openapi.components.schemas[schema.$ref.split("/").pop()];
  return schema;
}

/** A property that only constrains (`{not: {type: "null"}}` in a member of a top-level oneOf) is no field. */
function constraintOnly(prop) { return prop && Object.keys(prop).length === 1 && prop.not !== undefined; }

/** The concrete shapes a schema may take: a `$ref` followed, `allOf` merged into one, every member of `anyOf` and
 *  `oneOf` (and the schema itself when it also has properties of its own, as a model with a oneOf of required
 *  fields has), `null` left out. */
export function alternatives(schema) {
  schema = deref(schema);
  if (!schema) return [];
  if (schema.allOf) {
    const merged = { ...schema, properties: { ...(schema.properties || {}) } };
    delete merged.allOf;
    for (const part of schema.allOf.flatMap(alternatives)) {
      for (const [k, v] of Object.entries(part)) if (k !== "properties" && merged[k] === undefined) merged[k] = v;
      Object.assign(merged.properties, part.properties || {});
    }
    if (!Object.keys(merged.properties).length) delete merged.properties;
    return alternatives(merged);
  }
  const out = [];
  const own = schema.properties && Object.values(schema.properties).some((p) => !constraintOnly(p));
  if (own || schema.enum || schema.const !== undefined || (schema.type && schema.type !== "null")) out.push(schema);
  for (const m of [...(schema.anyOf || []), ...(schema.oneOf || [])]) out.push(...alternatives(m));
  return out;
}

/** The properties of every shape of a schema, the first shape's wins: name -> schema. */
export function properties(schema) {
  const props = {};
  for (const alt of alternatives(schema)) {
    for (const [k, v] of Object.entries(alt.properties || {})) if (!constraintOnly(v) && props[k] === undefined) props[k] = v;
  }
  return props;
}

/** The schema of a field of a request model by dotted path; `choose` picks a union member (the mechanism type). */
export function fieldSchema(model, path, choose = {}) {
  let schema = deref({ $ref: `#/components/schemas/${model}` });
  for (const part of path.split(".")) {
    if (!schema) return null;
    if (/^\d+$/.test(part)) { schema = alternatives(schema).find((s) => s.items)?.items; schema = deref(schema); continue; }
    const options = alternatives(schema).filter((s) => s.properties && s.properties[part] && !constraintOnly(s.properties[part]));
    const wanted = options.find((s) => Object.entries(choose).every(([k, v]) => !s.properties[k] || s.properties[k].const === v ||
      (s.properties[k].enum || []).includes(v) || s.properties[k].default === v)) || options[0];
    schema = wanted ? wanted.properties[part] : null;
  }
  return schema;
}

// The unit a field's name carries when its description gives none (design.md: names carry their unit).
const NAME_UNITS = [["_rad_s2", "rad/s²"], ["_rad_s", "rad/s"], ["_m_s2", "m/s²"], ["_m_s", "m/s"], ["_kg_m3", "kg/m³"],
  ["_Nm_rad", "N·m/rad"], ["_mm2_s", "mm²/s"], ["_kgm2", "kg·m²"], ["_rpm", "rev/min"], ["_deg", "°"], ["_mm", "mm"],
  ["_MPa", "MPa"], ["_Pa", "Pa"], ["_Nm", "N·m"], ["_kg", "kg"], ["_Hz", "Hz"], ["_W", "W"], ["_N", "N"], ["_J", "J"],
  ["_h", "h"], ["_s", "s"], ["_m", "m"]];

/** The unit of a field: the description's last bracket ("Crank O-A [m]."), else its name's suffix, else "–" (a
 *  pure number). */
export function unitOf(name, text) {
  const m = (text || "").match(/\[([^\],]+)\][^[]*$/);
  if (m) return m[1] === "-" ? "–" : m[1];
  const hit = NAME_UNITS.find(([suffix]) => name.endsWith(suffix));
  return hit ? hit[1] : "–";
}

/** A field's description, unit, bounds, default, type and choices (an enumeration's values, or yes/no). */
export function describe(model, path, choose = {}) {
  const s = fieldSchema(model, path, choose);
  const flat = s ? (deref(s).description ? deref(s) : s) : null;
  const text = (s && s.description) || (flat && flat.description) || "";
  const alts = s ? alternatives(s) : [];
  const bounds = {};
  for (const alt of alts) {
    for (const k of ["minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"]) if (alt[k] !== undefined) bounds[k] = alt[k];
  }
  if (s) for (const k of ["minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"]) if (s[k] !== undefined) bounds[k] = s[k];
  const types = alts.map((a) => a.type || (a.enum ? "string" : a.const !== undefined ? typeof a.const : undefined)).filter(Boolean);
  const type = ["integer", "number", "boolean", "string", "array", "object"].find((t) => types.includes(t)) || "number";
  let choices = [...new Set(alts.flatMap((a) => a.enum || (a.const !== undefined ? [a.const] : [])))];
  if (!choices.length && type === "boolean") choices = [true, false];
  const name = path.split(".").filter((p) => !/^\d+$/.test(p)).pop() || path;
  let unit = unitOf(name, text);
  if (choices.length) unit = "choice";
  else if (type === "string") unit = "text";
  else if (type === "array" || type === "object") {
    const items = alts.find((a) => a.items);
    const numbers = items && alternatives(items.items).every((a) => a.type === "number" || a.type === "integer");
    unit = numbers ? `${unit === "–" ? "" : `${unit}, `}list` : "JSON";
  }
  const nullable = Boolean(s && [...(s.anyOf || []), ...(s.oneOf || [])].some((a) => a.type === "null"));
  const dflt = s ? (s.default !== undefined ? s.default : deref(s)?.default) : undefined;
  return { text, unit, bounds, default: dflt, type, choices, nullable };
}

/** Every leaf field of a request model, nested objects walked (their fields as dotted paths), in the schema's
 *  order: [{path, group}] with group the top-level object a field sits in; `skip` holds paths (with their
 *  subtrees) the panel fills another way. */
export function leaves(model, skip = []) {
  const out = [];
  const walk = (schema, prefix, group, depth) => {
    for (const [name, prop] of Object.entries(properties(schema))) {
      const path = prefix + name;
      if (skip.some((p) => p === path || path.startsWith(`${p}.`))) continue;
      const shapes = alternatives(prop);
      const nested = shapes.find((a) => a.properties && !a.additionalProperties);
      if (nested && depth < 4 && !shapes.some((a) => a.type === "array")) walk(prop, `${path}.`, group || name, depth + 1);
      else out.push({ path, group });
    }
  };
  walk({ $ref: `#/components/schemas/${model}` }, "", "", 0);
  return out;
}

export class Problem extends Error {
  constructor(body, status) {
    super(body.detail || body.title || `HTTP ${status}`);
    this.body = body;
    this.status = status;
  }
}

/** POST a JSON body; the JSON answer, or a Problem carrying the RFC 9457 body. */
export async function post(path, body, { signal } = {}) {
  const r = await fetch(path, {
    method: "POST", headers: { "content-type": "application/json", accept: "application/json", ...csrf() },
    body: JSON.stringify(body), signal,
  });
  return answer(r);
}

export async function get(path) { return answer(await fetch(path, { headers: { accept: "application/json" } })); }

export async function del(path) { return answer(await fetch(path, { method: "DELETE", headers: csrf() })); }

async function answer(r) {
  const text = await r.text();
  let body = null;
  try { body = JSON.parse(text); } catch { body = { detail: text.slice(0, 300) }; }
  if (!r.ok) throw new Problem(body || {}, r.status);
  return body;
}

/** POST a JSON body and take the answer as a file (a PDF, a PNG). */
export async function postFile(path, body, { signal } = {}) {
  const r = await fetch(path, { method: "POST", headers: { "content-type": "application/json", ...csrf() }, body: JSON.stringify(body), signal });
  if (!r.ok) return answer(r);
  return r.blob();
}
