// Sign-in to an office server (SYNTH_AUTH=on): a form when nobody is signed in, the user's name and a sign-out
// button when someone is. The session cookie is HttpOnly; its CSRF token, in a cookie the page may read, goes
// with every change the page asks for (csrf(), used by api.js). With authentication off this shows nothing.

import { h } from "./dom.js";

const CSRF_COOKIES = ["__Host-synth_csrf", "synth_csrf"];

/** The header a change (POST, PUT, PATCH, DELETE) carries when this browser is signed in; {} otherwise. */
export function csrf() {
  const jar = Object.fromEntries(document.cookie.split(";").map((c) => c.trim().split("=")).filter((p) => p.length === 2));
  const token = CSRF_COOKIES.map((n) => jar[n]).find(Boolean);
  return token ? { "x-csrf-token": token } : {};
}

async function send(method, path, body) {
  const headers = { accept: "application/json", ...csrf() };
  if (body !== undefined) headers["content-type"] = "application/json";
  const r = await fetch(path, { method, headers, body: body === undefined ? undefined : JSON.stringify(body) });
  let answer = null;
  try { answer = await r.json(); } catch { answer = null; }
  return { ok: r.ok, status: r.status, body: answer };
}

function signInForm() {
  const name = h("input", { id: "signin-name", name: "username", autocomplete: "username", required: true });
  const password = h("input", { id: "signin-password", name: "password", type: "password",
    autocomplete: "current-password", required: true });
  const problem = h("p", { id: "signin-problem", class: "problem", role: "alert", hidden: true });
  const form = h("form", { id: "signin-form", class: "signin", "aria-label": "Sign in" },
    h("h2", {}, "Sign in"),
    h("p", {}, "This service asks who you are before it runs anything."),
    h("label", {}, "Name ", name),
    h("label", {}, "Password ", password),
    problem,
    h("button", { type: "submit" }, "Sign in"));
  form.addEventListener("submit", async (event) => {
    event.preventDefault();
    const r = await send("POST", "/v1/auth/signin", { name: name.value, password: password.value });
    if (r.ok) { window.location.reload(); return; }
    problem.textContent = (r.body && r.body.detail) || `sign-in failed (HTTP ${r.status})`;
    problem.hidden = false;
  });
  return h("div", { id: "signin", class: "signin-backdrop" }, form);
}

function signedIn(session) {
  const out = h("button", { id: "signout", type: "button", title: "End this browser's session" }, "Sign out");
  out.addEventListener("click", async () => {
    await send("POST", "/v1/auth/signout");
    window.location.reload();
  });
  return h("span", { id: "signed-in", class: "signed-in" },
    h("span", { title: `roles: ${session.roles.join(", ")}` }, session.name), " ", out);
}

/** Whether the page may call the API: with authentication off, or once signed in. Signed out, the sign-in form is
 *  shown and nothing else asks the service anything (the page reloads once the sign-in succeeds). */
async function start() {
  const r = await send("GET", "/v1/auth/session");
  if (!r.ok || !r.body || r.body.auth !== "on") return true;
  document.body.dataset.auth = r.body.signed_in ? "signed-in" : "signed-out";
  if (r.body.signed_in) {
    (document.querySelector("header .file") || document.body).append(signedIn(r.body));
    return true;
  }
  document.body.append(signInForm());
  document.getElementById("signin-name").focus();
  return false;
}

export const admitted = start();
