// A long request's progress: an indeterminate bar with the seconds since it was sent, and a Cancel button that
// aborts the request (the page stops waiting; the answer, when it comes, is dropped).
import { h, put } from "./dom.js";

/** Show the progress of a request in `box` (emptied when it ends); returns the AbortSignal to give fetch and
 *  `end()`. `id` names the elements: `${id}-progress`, `${id}-elapsed`, `${id}-cancel`. */
export function longStep(box, id, text) {
  const controller = new AbortController();
  const t0 = performance.now();
  const elapsed = h("span", { id: `${id}-elapsed`, class: "note" });
  const tick = () => { elapsed.textContent = `${text} ${Math.floor((performance.now() - t0) / 1000)} s`; };
  tick();
  const timer = setInterval(tick, 250);
  put(box, h("div", { class: "long-step", id: `${id}-progress`, role: "status" }, h("progress", { "aria-label": text }), elapsed,
    h("button", { class: "secondary", id: `${id}-cancel`, type: "button", onclick: () => controller.abort() }, "Cancel")));
  box.hidden = false;
  return {
    signal: controller.signal,
    end() { clearInterval(timer); put(box); box.hidden = true; },
  };
}

/** Whether an error is the abort of a cancelled request. */
export function cancelled(err) { return err && err.name === "AbortError"; }
