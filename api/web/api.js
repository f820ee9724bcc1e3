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

function alternatives(schema) {
  schema = deref(schema);
  if (!schema) return [];
  const alts = schema.anyOf || schema.oneOf;
  if (alts) return alts.flatMap(alternatives);
  return [schema];
}

/** The schema of a field of a request model by dotted path; `choose` picks a union member (the mechanism type). */
export function fieldSchema(model, path, choose = {}) {
  let schema = deref({ $ref: `#/components/schemas/${model}` });
  for (const part of path.split(".")) {
    if (!schema) return null;
    if (/^\d+$/.test(part)) { schema = alternatives(schema).find((s) => s.items)?.items; schema = deref(schema); continue; }
    const options = alternatives(schema).filter((s) => s.properties && s.properties[part]);
    const wanted = options.find((s) => Object.entries(choose).every(([k, v]) => !s.properties[k] || s.properties[k].const === v ||
      (s.properties[k].enum || []).includes(v) || s.properties[k].default === v)) || options[0];
    schema = wanted ? wanted.properties[part] : null;
  }
  return schema;
}

/** A field's description, and its SI unit as the description's last bracket gives it ("Crank O-A [m]."). */
export function describe(model, path, choose = {}) {
  const s = fieldSchema(model, path, choose);
  const flat = s ? (deref(s).description ? deref(s) : s) : null;
  const text = (s && s.description) || (flat && flat.description) || "";
  const m = text.match(/\[([^\]]+)\][^[]*$/);
  const bounds = {};
  for (const alt of s ? alternatives(s) : []) {
    for (const k of ["minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"]) if (alt[k] !== undefined) bounds[k] = alt[k];
  }
  if (s) for (const k of ["minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"]) if (s[k] !== undefined) bounds[k] = s[k];
  return { text, unit: m ? m[1] : "", bounds, default: s ? s.default : undefined };
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
export async function postFile(path, body) {
  const r = await fetch(path, { method: "POST", headers: { "content-type": "application/json", ...csrf() }, body: JSON.stringify(body) });
  if (!r.ok) return answer(r);
  return r.blob();
}
