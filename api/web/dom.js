// The page's one way to put names and text from a design or an answer on the page: elements built node by node,
// every string a text node or an attribute value, never HTML parsed from strings that hold data.

const SVG_NS = "http://www.w3.org/2000/svg";

function fill(node, attrs, children) {
  for (const [k, v] of Object.entries(attrs || {})) {
    if (v === null || v === undefined || v === false) continue;
    if (k === "dataset") Object.assign(node.dataset, v);
    else if (k === "text") node.textContent = String(v);
    else if (k === "style" && typeof v === "object") Object.assign(node.style, v);   // CSSOM: allowed by a strict CSP
    else if (k.startsWith("on") && typeof v === "function") node.addEventListener(k.slice(2), v);
    else if (k === "class") node.setAttribute("class", Array.isArray(v) ? v.filter(Boolean).join(" ") : String(v));
    else node.setAttribute(k, v === true ? "" : String(v));
  }
  append(node, children);
  return node;
}

/** Append children: strings and numbers as text nodes, nodes as they are, arrays flattened, null skipped. */
export function append(node, children) {
  for (const c of children.flat(Infinity)) {
    if (c === null || c === undefined || c === false) continue;
    node.appendChild(c instanceof Node ? c : document.createTextNode(String(c)));
  }
  return node;
}

/** An HTML element: h("td", { class: "num" }, "3 kg"). */
export function h(tag, attrs = {}, ...children) { return fill(document.createElement(tag), attrs, children); }

/** An SVG element: s("circle", { cx: 0, cy: 0, r: 1 }). */
export function s(tag, attrs = {}, ...children) { return fill(document.createElementNS(SVG_NS, tag), attrs, children); }

/** Replace an element's content. */
export function put(node, ...children) { node.replaceChildren(); return append(node, children); }

/** A table: a header row of strings and rows of cells (a cell is a string, a node or [text, attrs]). */
export function table(head, rows, attrs = {}) {
  const cell = (tag, c) => (Array.isArray(c) && c.length === 2 && c[1] && typeof c[1] === "object" && !(c[1] instanceof Node)
    ? h(tag, c[1], c[0]) : h(tag, {}, c));
  return h("table", attrs, head ? h("tr", {}, head.map((c) => cell("th", c))) : null,
    rows.map((r) => (r instanceof Node ? r : h("tr", {}, r.map((c) => cell("td", c))))));
}
