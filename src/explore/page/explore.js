"use strict";
// pointshade explore: the page's script. Every value it shows comes from the server's API
// (docs/explore.md, "The HTTP API"); this file keeps the state, builds the controls and draws.

// ---------------------------------------------------------------- helpers

// Shorthand for document.getElementById.
const $ = (id) => document.getElementById(id);

// Create an element; `value` is set last so that a range's min and max apply to it first.
function el(tag, props = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(props)) if (k !== "value") e[k] = v;
  if ("value" in props) e.value = props.value;
  e.append(...children);
  return e;
}

// A deep copy of plain JSON data (the state and materials).
const clone = (x) => JSON.parse(JSON.stringify(x));

// Relative luminance of an RGB triple, or the number itself (for D, G and grey values).
const lum = (c) => (Array.isArray(c) ? 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2] : +c);

// A number with `d` decimals, or a vector of them in parentheses.
const fmt = (x, d = 3) =>
  Array.isArray(x) ? `(${x.map((v) => fmt(v, d)).join(", ")})` : Number.isFinite(+x) ? (+x).toFixed(d) : String(x);

// Listen to both input and change: setters ignore values that did not change.
function onEdit(elem, handler) {
  elem.addEventListener("input", handler);
  elem.addEventListener("change", handler);
}

// Call `handler(event, dx, dy)` on a mouse press on `target` and on each move until the release
// (mouse events on the window, so that a drag may leave the element).
function onDrag(target, handler) {
  let last = null;
  target.addEventListener("mousedown", (e) => { e.preventDefault(); last = e; handler(e, 0, 0); });
  window.addEventListener("mousemove", (e) => {
    if (!last) return;
    handler(e, e.clientX - last.clientX, e.clientY - last.clientY);
    last = e;
  });
  window.addEventListener("mouseup", () => { last = null; });
}

// The API's arrays of colours may come as [[r,g,b], …] or flat [r,g,b,r,g,b,…]: make them the first.
function triples(values, n) {
  if (!Array.isArray(values)) return null;
  if (values.length === 3 * n && !Array.isArray(values[0])) {
    return Array.from({ length: n }, (_, i) => values.slice(3 * i, 3 * i + 3));
  }
  return values;
}

// ---------------------------------------------------------------- page state

const explore = {
  ready: false, session: null, state: null, plot: null, lobe: null, albedo: null, pixel: null,
  pins: [], renders: 0, passes: 0, shownSpp: null, renderBytes: null, renderState: null,
  timings: { polar: [], render: [], firstPass: [], firstPassServer: [] },
};
window.explore = explore;

let session = null;          // GET /api/session's answer
let state = null;            // the state sent to the server (docs/explore.md, "A state")
let keyInfo = new Map();     // key name → the session's description of it
let notice = "";             // a message kept beside the render time (a bad URL fragment)

// What the polar plot, lobe, sphere and albedo show: a material and the direction ω_i.
const view = {
  current: null,        // the name of the material in state.materials that the plots follow
  pixelMaterial: null,  // a clicked pixel's material, when it is not one of the state's
  theta_i: 45, phi_i: 0,
  brdf: null,           // the last /api/brdf answer
  marker: null,         // the clicked pixel's ω_o: { theta (signed, plane of incidence), value, theta_o, phi_o }
};

// The material the plots show.
function viewMaterial() {
  return view.pixelMaterial || (state && state.materials[view.current]) || {};
}

// ---------------------------------------------------------------- status and requests

// Show a message in the status line; errors in red.
function setStatus(text, error = false) {
  const s = $("status");
  s.textContent = text;
  s.classList.toggle("error", error);
}

// Show an error (a 400's message, a network failure) instead of throwing it.
function report(err) {
  setStatus(err && err.message ? err.message : String(err), true);
}

// Send a request (a POST with a JSON body, or a GET without one); a non-2xx answer throws an
// Error carrying the server's `error` message.
async function request(path, body, signal) {
  const init = body === undefined ? { signal } :
    { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body), signal };
  const res = await fetch(path, init);
  if (res.ok) return res;
  let message = `${path}: HTTP ${res.status}`;
  try {
    const answer = await res.json();
    if (answer && typeof answer.error === "string") message = answer.error;
  } catch (_) { /* not JSON: keep the status code */ }
  throw new Error(message);
}

// POST and parse the JSON answer.
const postJson = async (path, body) => (await request(path, body)).json();

// A channel where the latest call wins: one request in flight, at most one waiting (the newest).
// The returned promise settles once the channel is idle again; errors go to the status line.
function latest(run) {
  let next = null, running = null;
  async function pump() {
    while (next) {
      const job = next;
      next = null;
      try { await run(job); } catch (e) { report(e); }
    }
    running = null;
  }
  return (job) => {
    next = job;
    if (!running) running = pump();
    return running;
  };
}

// Show PNG bytes in an <img> through a blob URL; resolves on its load event.
function showPng(img, bytes) {
  return new Promise((resolve, reject) => {
    const url = URL.createObjectURL(new Blob([bytes], { type: "image/png" }));
    const old = img.dataset.url;
    img.onload = () => {
      if (old) URL.revokeObjectURL(old);
      img.dataset.url = url;
      resolve();
    };
    img.onerror = () => { URL.revokeObjectURL(url); reject(new Error("the server's PNG did not decode")); };
    img.src = url;
  });
}

// ---------------------------------------------------------------- requests behind the views

// The live render. Each edit starts a progressive series of passes: a scene at 1, 4, 16, …
// samples per pixel below its film's, then the film's (POST /api/render?spp=N, then
// /api/render); a normal image in one pass. A newer edit aborts the request in flight (the
// server, seeing the newer request, stops the render it made stale) and starts again. The
// returned promise settles once no render is running.
let renderRun = null;  // { controller, done }: the newest series
let lastFullPass = null;  // ms the last film's pass took from request to image shown
let imageShown;           // resolves firstImage
const firstImage = new Promise((resolve) => { imageShown = resolve; });

// A film's pass this quick is shown at once, without coarser passes before it (they would
// only delay it: re-shading kept points is fast; tracing anew is not).
const INTERACTIVE_MS = 150;

// The passes of a series: sample counts, null for the film's own.
function renderPasses() {
  const passes = [];
  const spp = session && session.spp;
  const quick = lastFullPass !== null && lastFullPass < INTERACTIVE_MS;
  for (let n = 1; spp && !quick && n < spp; n *= 4) passes.push(n);
  passes.push(null);
  return passes;
}

// The milliseconds the server says it took (its `Server-Timing` header), or null.
function serverMs(res) {
  const m = /dur=([0-9.]+)/.exec(res.headers.get("Server-Timing") || "");
  return m ? Number(m[1]) : null;
}

function renderChannel(job) {
  if (renderRun) renderRun.controller.abort();
  const run = { controller: new AbortController() };
  run.done = renderSeries(run, job).catch((e) => { if (e.name !== "AbortError") report(e); });
  renderRun = run;
  return untilRendersSettle();
}

async function untilRendersSettle() {
  for (;;) {
    const run = renderRun;
    await run.done;
    if (renderRun === run) return;
  }
}

async function renderSeries(run, job) {
  const sent = clone(state);
  const passes = renderPasses();
  for (const spp of passes) {
    const start = performance.now();
    const path = spp === null ? "api/render" : `api/render?spp=${spp}`;
    const res = await request(path, sent, run.controller.signal);
    const bytes = new Uint8Array(await res.arrayBuffer());
    if (renderRun !== run) return;
    await showPng($("render-image"), bytes);
    const now = performance.now();
    imageShown();
    explore.passes += 1;
    explore.shownSpp = spp === null ? (session.spp || 1) : spp;
    if (spp === passes[0]) {
      explore.timings.firstPass.push(now - job.t0);
      explore.timings.firstPassServer.push(serverMs(res));
    }
    const samples = session.spp ? ` at ${explore.shownSpp} of ${session.spp} spp` : "";
    if (spp !== null) {
      setStatus(`refining: pass rendered in ${Math.round(now - start)} ms${samples}`);
      continue;
    }
    lastFullPass = now - start;
    explore.renderBytes = bytes;
    explore.renderState = sent;
    explore.renders += 1;
    explore.timings.render.push(now - job.t0);
    setStatus(`rendered in ${Math.round(now - start)} ms${samples}` + (notice ? ` · ${notice}` : ""));
  }
}

// f_r in the plane of incidence for the view's material and ω_i, and the pins' at the same ω_i.
const polarChannel = latest(async (job) => {
  const [brdf] = await Promise.all([
    postJson("api/brdf", plotBody(viewMaterial(), { samples: 181 })),
    ...explore.pins.map(refreshPin),
  ]);
  view.brdf = brdf;
  drawPolar();
  explore.timings.polar.push(performance.now() - job.t0);
});

// A plot request's body: a material's keys at the view's ω_i, with the state's preset when it has
// one (a normal image's: the preset's material fills the missing keys, as in the render).
function plotBody(material, extra = {}, preset = state && state.preset) {
  const body = { material, theta_i: view.theta_i, phi_i: view.phi_i, ...extra };
  if (preset) body.preset = preset;
  return body;
}

// The body of /api/albedo: the material (and preset) alone.
function albedoBody(material, preset = state && state.preset) {
  return preset ? { material, preset } : { material };
}

// Fetch a pin's curve again when ω_i moved since it was fetched.
async function refreshPin(pin) {
  const at = `${view.theta_i},${view.phi_i}`;
  if (pin.at === at) return;
  pin.brdf = await postJson("api/brdf", plotBody(pin.material, { samples: 181 }, pin.preset));
  pin.at = at;
}

// f_r's luminance over the hemisphere (POST /api/lobe), drawn in 3D.
const lobeChannel = latest(async () => {
  explore.lobe = await postJson("api/lobe", plotBody(viewMaterial(), { theta_steps: 32, phi_steps: 64 }));
  if (lobeView) lobeView.update();
});

// The lit sphere (POST /api/sphere).
const sphereChannel = latest(async () => {
  const bytes = await (await request("api/sphere", plotBody(viewMaterial(), { size: 256 }))).arrayBuffer();
  await showPng($("sphere"), bytes);
});

// The directional albedo against θ_i (POST /api/albedo).
const albedoChannel = latest(async () => {
  explore.albedo = await postJson("api/albedo", albedoBody(viewMaterial()));
  drawAlbedo();
});

let albedoTimer = 0;
// Albedo after a material change, debounced: integrating is the slowest request.
function scheduleAlbedo() {
  clearTimeout(albedoTimer);
  albedoTimer = setTimeout(() => albedoChannel({}), 150);
}

// Everything that depends on ω_i or the view's material; returns once all have been drawn.
function updateViews(t0) {
  if (!state) return Promise.resolve();
  return Promise.all([polarChannel({ t0 }), lobeChannel({ t0 }), sphereChannel({ t0 })]);
}

// ---------------------------------------------------------------- edits

// After any edit of the state: keep it in the URL, re-render, and refresh the plots when a
// material changed (`material` is its name).
function edited(material) {
  const t0 = performance.now();
  history.replaceState(null, "", "#" + encodeURIComponent(JSON.stringify(state)));
  notice = "";
  renderChannel({ t0 });
  if (material === undefined) return;
  view.current = material;
  view.pixelMaterial = null;
  view.marker = null;
  $("material").value = material;
  updateViews(t0);
  scheduleAlbedo();
}

// Set ω_i (degrees) from a slider, the sphere or a pixel, and redraw what depends on it.
function setAngles(theta, phi, keepMarker = false) {
  const t0 = performance.now();
  view.theta_i = Math.min(89, Math.max(0, theta));
  view.phi_i = ((phi % 360) + 360) % 360;
  if (!keepMarker) view.marker = null;
  showAngles();
  return updateViews(t0);
}

// Reflect view.theta_i/phi_i in the two sliders and their read-outs.
function showAngles() {
  $("theta-i").value = view.theta_i;
  $("phi-i").value = view.phi_i;
  $("theta-i-value").textContent = view.theta_i.toFixed(1);
  $("phi-i-value").textContent = view.phi_i.toFixed(1);
}

// ---------------------------------------------------------------- the parameters panel

// A labelled row of controls.
function row(label, forId, ...controls) {
  return el("div", { className: "row" }, el("label", { textContent: label, htmlFor: forId }), ...controls);
}

// A number box (no range enforced: the server judges) that calls `set` with each finite value.
function numberBox(id, value, set, className = "") {
  const box = el("input", { type: "number", id, className, step: "any", value });
  onEdit(box, () => { const v = parseFloat(box.value); if (Number.isFinite(v)) set(v); });
  return box;
}

// A range slider (with `id`) and a number box (`id`-num) for one number; `set` gets the value.
// Without a finite maximum (or a huge one) the slider covers a few times the value.
function numberInputs(id, value, info, set) {
  const min = Number.isFinite(info.min) ? info.min : 0;
  const wide = !Number.isFinite(info.max) || info.max - min > 1000;
  const max = wide ? Math.max(min + 1, 4 * Math.abs(+value || 1), 10) : info.max;
  const range = el("input", { type: "range", id, min, max, step: "any", value });
  const box = numberBox(id + "-num", value, (v) => { range.value = v; set(v); });
  onEdit(range, () => { box.value = range.value; set(+range.value); });
  return [range, box];
}

// Three number boxes (`id`-0..2) for a vector; `set` gets all three once each is a number.
function vectorInputs(id, value, set) {
  const boxes = [0, 1, 2].map((i) => numberBox(`${id}-${i}`, value[i], () => {
    const vals = boxes.map((b) => parseFloat(b.value));
    if (vals.every(Number.isFinite)) set(vals);
  }, "small"));
  return boxes;
}

// A colour picker (`id`, an sRGB display) beside three number boxes (`id`-0..2) holding the linear floats.
function colorInputs(id, value, set) {
  const vec = Array.isArray(value) ? value.slice(0, 3) : [+value || 0, +value || 0, +value || 0];
  const picker = el("input", { type: "color", id, value: linearToHex(vec), title: "sRGB display of the linear values" });
  const boxes = vectorInputs(id, vec, (vals) => { picker.value = linearToHex(vals); set(vals); });
  onEdit(picker, () => {
    const vals = hexToLinear(picker.value);
    boxes.forEach((b, i) => { b.value = vals[i]; });
    set(vals);
  });
  return [picker, ...boxes];
}

// Linear RGB floats → "#rrggbb" through the sRGB curve (for the picker only; clamped to 0..1).
function linearToHex(vec) {
  const enc = (l) => { l = Math.min(1, Math.max(0, l)); return l <= 0.0031308 ? 12.92 * l : 1.055 * l ** (1 / 2.4) - 0.055; };
  return "#" + vec.map((l) => Math.round(enc(l) * 255).toString(16).padStart(2, "0")).join("");
}

// "#rrggbb" → linear RGB floats (4 decimals).
function hexToLinear(hex) {
  const dec = (c) => (c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4);
  return [1, 3, 5].map((i) => +dec(parseInt(hex.slice(i, i + 2), 16) / 255).toFixed(4));
}

// A <select>; `blank`, when given, is the label of an empty option meaning "key absent".
function choiceInput(id, choices, value, set, blank) {
  const select = el("select", { id });
  if (blank) select.append(el("option", { value: "", textContent: blank }));
  for (const c of choices) select.append(el("option", { value: c, textContent: c }));
  select.value = value === undefined || value === null ? "" : String(value);
  onEdit(select, () => set(select.value));
  return [select];
}

// A checkbox for a bool key.
function boolInput(id, value, set) {
  const box = el("input", { type: "checkbox", id, checked: !!value });
  onEdit(box, () => set(box.checked));
  return [box];
}

// Store `value` under `key` in `obj` and report whether it changed.
function assign(obj, key, value) {
  if (key in obj && JSON.stringify(obj[key]) === JSON.stringify(value)) return false;
  obj[key] = value;
  return true;
}

// Whether a key applies to a material: to its model (no list: every model) and, for keys that
// list Fresnel terms (metallic, ior, eta, k), to its Fresnel term.
function applies(info, mat) {
  const models = info.models;
  if (Array.isArray(models) && models.length && !models.includes(modelOf(mat))) return false;
  return !Array.isArray(info.fresnel) || info.fresnel.includes(fresnelOf(mat));
}

// A material's Fresnel term: written, else conductor where eta or k is written, else the default.
function fresnelOf(mat) {
  const info = keyInfo.get("fresnel");
  return mat.fresnel || ("eta" in mat || "k" in mat ? "conductor" : (info && info.default) || "schlick");
}

// Drop the keys that do not apply to a material any more (the server refuses them).
function prune(mat) {
  for (const key of Object.keys(mat)) {
    const info = keyInfo.get(key);
    if (key !== "model" && info && !applies(info, mat)) delete mat[key];
  }
}

// The models the model select offers: the `model` key's choices, else those the keys name.
function modelChoices() {
  const info = keyInfo.get("model");
  if (info && Array.isArray(info.choices) && info.choices.length) return info.choices;
  const names = new Set(["lambert", "blinn-phong", "cook-torrance"]);
  for (const k of keyInfo.values()) (k.models || []).forEach((m) => names.add(m));
  return [...names];
}

// A material's model, or the default one.
function modelOf(mat) {
  const info = keyInfo.get("model");
  return mat.model || (info && info.default) || "lambert";
}

// Change a material's model, dropping the keys that do not apply to the new one (an error otherwise).
function setModel(name, model) {
  const mat = state.materials[name];
  if (!assign(mat, "model", model)) return;
  prune(mat);
  buildParams();
  edited(name);
}

// The row of one material key: its control and a button that removes the key.
function keyRow(name, info) {
  const mat = state.materials[name];
  const id = `key-${name}-${info.key}`;
  const value = info.key in mat ? mat[info.key] : info.default;
  const set = (v) => {
    if (!assign(mat, info.key, v)) return;
    line.classList.remove("unset");
    if (info.key === "fresnel") { prune(mat); buildParams(); }  // it decides which keys apply
    edited(name);
  };
  let controls;
  if (info.kind === "number") controls = numberInputs(id, value ?? 0, info, set);
  else if (info.kind === "color") controls = colorInputs(id, value ?? [0, 0, 0], set);
  else if (info.kind === "bool") controls = boolInput(id, value, set);
  else controls = choiceInput(id, info.choices || [], value, set);
  const reset = el("button", { type: "button", className: "reset", textContent: "↺", title: "remove the key: its default applies" });
  reset.addEventListener("click", () => {
    if (!(info.key in mat)) return;
    delete mat[info.key];
    buildParams();
    edited(name);
  });
  const line = row(info.key, id, ...controls, reset);
  if (!(info.key in mat)) line.classList.add("unset");
  return line;
}

// The fieldset of one material: its model and the keys that apply to that model.
function materialBox(name) {
  const mat = state.materials[name];
  const box = el("fieldset", {}, el("legend", { textContent: `material ${name}` }));
  const model = choiceInput(`key-${name}-model`, modelChoices(), modelOf(mat), (v) => setModel(name, v));
  box.append(row("model", `key-${name}-model`, ...model));
  for (const info of keyInfo.values()) {
    if (info.key !== "model" && applies(info, mat)) box.append(keyRow(name, info));
  }
  return box;
}

// The fieldset of light `i`: position (or direction), colour, intensity and falloff.
function lightBox(light, i) {
  const set = (key) => (v) => {
    if (v === "") { if (!(key in light)) return; delete light[key]; }
    else if (!assign(light, key, v)) return;
    edited();
  };
  const p = `light-${i}`;
  const box = el("fieldset", {}, el("legend", { textContent: `light ${i} (${light.type || "point"})` }));
  for (const key of ["position", "direction"]) {
    if (key in light || (key === "position" && light.type !== "directional")) {
      box.append(row(key, `${p}-${key}-0`, ...vectorInputs(`${p}-${key}`, light[key] || [0, 0, 0], set(key))));
    }
  }
  box.append(row("color", `${p}-color`, ...colorInputs(`${p}-color`, light.color ?? [1, 1, 1], set("color"))));
  box.append(row("intensity", `${p}-intensity`, numberBox(`${p}-intensity`, light.intensity ?? 1, set("intensity"))));
  const falloffs = light.type === "spot" ? ["inverse-square", "none", "mitsuba"] : ["inverse-square", "none"];
  box.append(row("falloff", `${p}-falloff`, ...choiceInput(`${p}-falloff`, falloffs, light.falloff, set("falloff"), "(default)")));
  if (light.type === "spot") {
    box.append(row("inner_cone", `${p}-inner_cone`, numberBox(`${p}-inner_cone`, light.inner_cone ?? 0, set("inner_cone"))));
    box.append(row("outer_cone", `${p}-outer_cone`, numberBox(`${p}-outer_cone`, light.outer_cone ?? 45, set("outer_cone"))));
  }
  return box;
}

// The preset select (normal images) and the exposure slider (hidden under tp, where it is an error).
function filmBox() {
  const box = el("fieldset", {}, el("legend", { textContent: session.mode === "normal-image" ? "preset and film" : "film" }));
  if (session.mode === "normal-image") {
    box.append(row("preset", "preset", ...choiceInput("preset", ["tp", "physical"], state.preset || "physical", (v) => {
      if (!assign(state, "preset", v)) return;
      if (v === "tp") delete state.exposure;
      buildParams();
      edited();
      updateViews(performance.now());
      scheduleAlbedo();
    })));
  }
  const exposure = row("exposure", "exposure", ...numberInputs("exposure", state.exposure ?? 0, { min: -10, max: 10 }, (v) => {
    if (assign(state, "exposure", v)) edited();
  }));
  exposure.hidden = session.mode === "normal-image" && state.preset === "tp";
  box.append(exposure);
  return box;
}

// (Re)build the whole parameters panel from the session's keys and the state.
function buildParams() {
  const params = $("params");
  const scroll = $("panel-params").scrollTop;
  params.textContent = "";
  params.append(filmBox());
  for (const name of Object.keys(state.materials)) params.append(materialBox(name));
  (state.lights || []).forEach((light, i) => params.append(lightBox(light, i)));
  $("panel-params").scrollTop = scroll;
}

// The select of the material the plots follow (shown when there are several).
function buildMaterialSelect() {
  const select = $("material");
  const names = Object.keys(state.materials);
  select.textContent = "";
  for (const n of names) select.append(el("option", { value: n, textContent: n }));
  select.value = view.current;
  $("material-row").hidden = names.length < 2;
}

// ---------------------------------------------------------------- canvas drawing

// Size a canvas's backing store to its CSS width × devicePixelRatio at `aspect` (height/width);
// returns a 2D context drawing in CSS pixels.
function prepare(canvas, aspect) {
  const dpr = window.devicePixelRatio || 1;
  const w = canvas.clientWidth || 400;
  const h = Math.round(w * aspect);
  canvas.style.height = `${h}px`;
  if (canvas.width !== Math.round(w * dpr)) canvas.width = Math.round(w * dpr);
  if (canvas.height !== Math.round(h * dpr)) canvas.height = Math.round(h * dpr);
  const ctx = canvas.getContext("2d");
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.clearRect(0, 0, w, h);
  ctx.font = "11px system-ui, sans-serif";
  return { ctx, w, h };
}

// The smallest 1, 2 or 5 × 10^k at least x.
function niceCeil(x) {
  if (!(x > 0)) return 1;
  const p = 10 ** Math.floor(Math.log10(x));
  return [1, 2, 5, 10].map((m) => m * p).find((v) => v >= x * (1 - 1e-9));
}

const DECADES = 3;  // the log scale's range below the maximum

// Map a value to a radius in 0..1: linear up to `max`, or DECADES decades below it on a log scale.
function radiusScale(max, log) {
  if (!(max > 0)) return () => 0;
  if (!log) return (v) => Math.max(0, v) / max;
  const lo = Math.log10(max) - DECADES;
  return (v) => (v > 0 ? Math.max(0, (Math.log10(v) - lo) / DECADES) : 0);
}

// Stroke a polyline through points [[x, y], …], with an optional dash pattern.
function polyline(ctx, pts, color, width = 1.5, dash = []) {
  ctx.save();
  ctx.strokeStyle = color; ctx.lineWidth = width; ctx.setLineDash(dash);
  ctx.beginPath();
  pts.forEach(([x, y], i) => (i ? ctx.lineTo(x, y) : ctx.moveTo(x, y)));
  ctx.stroke();
  ctx.restore();
}

// Write the legend entries [[label, colour, dash], …] in a column from (x, y).
function legend(ctx, entries, x, y) {
  entries.forEach(([label, color, dash = []], i) => {
    polyline(ctx, [[x, y + 14 * i - 4], [x + 18, y + 14 * i - 4]], color, 2, dash);
    ctx.fillStyle = "#1d2330";
    ctx.fillText(label, x + 22, y + 14 * i);
  });
}

const TERM_STYLE = { D: ["#444", [7, 3]], G: ["#444", [2, 3]], F: ["#444", [9, 3, 2, 3]] };
const RGB_COLORS = ["#d62728", "#2ca02c", "#1f62c4"];

// The polar plot: f_r (or f_r·cos θ_o) against θ_o in the plane of incidence, the terms D, G, F
// each scaled to its own maximum, the pins, ω_i and a clicked pixel's ω_o.
function drawPolar() {
  const { ctx, w, h } = prepare($("polar"), 0.6);
  const b = view.brdf;
  if (!b || !Array.isArray(b.theta_o)) { explore.plot = null; return; }
  const cos = $("polar-cos").checked, log = $("log-scale").checked, rgb = $("polar-rgb").checked;
  const base = cos ? "f_r_cos" : "f_r";
  const n = b.theta_o.length;
  const colours = triples(b[base], n) || [];
  const curves = { [base]: colours.map(lum) };
  if (rgb) ["R", "G", "B"].forEach((c, i) => { curves[`${base}.${c}`] = colours.map((v) => (Array.isArray(v) ? v[i] : v)); });
  for (const t of ["D", "G", "F"]) {
    const values = triples(b[t], n);
    if ($(`show-${t}`).checked && values) curves[t] = values.map(lum);
  }
  const pins = explore.pins.filter((p) => p.brdf).map((p) => ({
    color: p.color, label: p.label, theta_o: p.brdf.theta_o, values: (triples(p.brdf[base], p.brdf.theta_o.length) || []).map(lum),
  }));
  const fr = [curves[base], ...(rgb ? [0, 1, 2].map((i) => curves[`${base}.${"RGB"[i]}`]) : []), ...pins.map((p) => p.values)];
  const peak = Math.max(0, ...fr.flat().filter(Number.isFinite));
  const max = log ? peak : niceCeil(peak);
  const radius = radiusScale(max, log);

  const cx = w / 2, cy = h - 22, R = Math.min(w / 2 - 34, h - 44);
  const at = (theta, r) => [cx - R * r * Math.sin(theta * Math.PI / 180), cy - R * r * Math.cos(theta * Math.PI / 180)];
  polarGrid(ctx, cx, cy, R, max, log);
  const curvePts = (theta, values, rad) => theta.map((t, i) => at(t, rad(values[i])));
  for (const p of pins) polyline(ctx, curvePts(p.theta_o, p.values, radius), p.color, 1.5);
  for (const t of ["D", "G", "F"]) {
    if (!curves[t]) continue;
    const tmax = Math.max(0, ...curves[t].filter(Number.isFinite));
    polyline(ctx, curvePts(b.theta_o, curves[t], (v) => radius(tmax > 0 ? v / tmax * max : 0)), TERM_STYLE[t][0], 1.3, TERM_STYLE[t][1]);
  }
  if (rgb) [0, 1, 2].forEach((i) => polyline(ctx, curvePts(b.theta_o, curves[`${base}.${"RGB"[i]}`], radius), RGB_COLORS[i], 1));
  polyline(ctx, curvePts(b.theta_o, curves[base], radius), "#111", 2);
  polarArrow(ctx, at, view.theta_i);
  if (view.marker) polarMarker(ctx, at, radius, cos);

  const entries = [[cos ? "f_r·cos θₒ (luminance)" : "f_r (luminance)", "#111"]];
  for (const t of ["D", "G", "F"]) if (curves[t]) entries.push([`${t} (÷ its max)`, ...TERM_STYLE[t]]);
  legend(ctx, entries, 8, 14);
  explore.plot = { theta_o: b.theta_o.slice(), curves, pins: pins.map((p) => ({ label: p.label, color: p.color, values: p.values })) };
}

// Rings with their values (log: at powers of ten), spokes every 30° of θ_o, the surface line.
function polarGrid(ctx, cx, cy, R, max, log) {
  ctx.strokeStyle = "#dde1e8"; ctx.fillStyle = "#6b7385"; ctx.lineWidth = 1;
  const rings = [[1, log ? "" : max]];
  if (log && max > 0) {
    const top = Math.log10(max);
    for (let k = Math.ceil(top - DECADES); k <= top; k++) rings.push([(k - top + DECADES) / DECADES, 10 ** k]);
  } else if (!log) [1, 2, 3].forEach((k) => rings.push([k / 4, max * k / 4]));
  ctx.textAlign = "left";
  for (const [r, value] of rings) {
    ctx.beginPath(); ctx.arc(cx, cy, R * r, Math.PI, 2 * Math.PI); ctx.stroke();
    if (value !== "" && r > 0.05) ctx.fillText(String(+value.toPrecision(3)), cx + R * r + 2, cy + 12);
  }
  ctx.textAlign = "center";
  for (let t = -90; t <= 90; t += 30) {
    const s = Math.sin(t * Math.PI / 180), c = Math.cos(t * Math.PI / 180);
    ctx.beginPath(); ctx.moveTo(cx, cy); ctx.lineTo(cx - R * s, cy - R * c); ctx.stroke();
    ctx.fillText(`${t}°`, cx - (R + 16) * s, cy - (R + 8) * c + (Math.abs(t) === 90 ? -5 : 4));
  }
  polyline(ctx, [[cx - R - 10, cy], [cx + R + 10, cy]], "#555", 1.5);
  ctx.textAlign = "left";
}

// ω_i as an arrow from the surface point, on the positive side of θ_o.
function polarArrow(ctx, at, theta) {
  const [x0, y0] = at(0, 0), [x1, y1] = at(theta, 1.02);
  const a = Math.atan2(y1 - y0, x1 - x0);
  polyline(ctx, [[x0, y0], [x1, y1]], "#d11a1a", 2);
  ctx.fillStyle = "#d11a1a";
  ctx.beginPath();
  ctx.moveTo(x1, y1);
  ctx.lineTo(x1 - 9 * Math.cos(a - 0.35), y1 - 9 * Math.sin(a - 0.35));
  ctx.lineTo(x1 - 9 * Math.cos(a + 0.35), y1 - 9 * Math.sin(a + 0.35));
  ctx.fill();
  const [xl, yl] = at(theta + 4, 0.8);
  ctx.fillText("ωᵢ", xl - 8, yl);
}

// A clicked pixel's θ_o: a dashed spoke, and a dot at its f_r (not for the cos-weighted plot).
function polarMarker(ctx, at, radius, cos) {
  const m = view.marker;
  polyline(ctx, [at(m.theta, 0), at(m.theta, 1)], "#d0109a", 1.2, [3, 3]);
  if (cos || !Number.isFinite(m.value)) return;
  const [x, y] = at(m.theta, radius(m.value));
  ctx.fillStyle = "#d0109a";
  ctx.beginPath(); ctx.arc(x, y, 4, 0, 2 * Math.PI); ctx.fill();
}

// The albedo plot: R, G, B against θ_i from 0 to 90°, y from 0 to max(1, data); pins as luminance.
function drawAlbedo() {
  const { ctx, w, h } = prepare($("albedo"), 0.55);
  const a = explore.albedo;
  const series = [];
  if (a && Array.isArray(a.theta_i)) {
    const rgb = triples(a.albedo, a.theta_i.length) || [];
    [0, 1, 2].forEach((i) => series.push({ x: a.theta_i, y: rgb.map((v) => (Array.isArray(v) ? v[i] : v)), color: RGB_COLORS[i], width: 1.8 }));
  }
  for (const p of explore.pins) {
    if (!p.albedo) continue;
    series.push({ x: p.albedo.theta_i, y: (triples(p.albedo.albedo, p.albedo.theta_i.length) || []).map(lum), color: p.color, width: 1.5, dash: [5, 3] });
  }
  const ymax = Math.max(1, ...series.flatMap((s) => s.y).filter(Number.isFinite));
  const L = 40, T = 10, W = w - L - 12, H = h - T - 30;
  const px = (x) => L + W * x / 90, py = (y) => T + H * (1 - y / ymax);
  ctx.strokeStyle = "#dde1e8"; ctx.fillStyle = "#6b7385"; ctx.lineWidth = 1;
  ctx.textAlign = "center";
  for (let x = 0; x <= 90; x += 15) {
    ctx.beginPath(); ctx.moveTo(px(x), T); ctx.lineTo(px(x), T + H); ctx.stroke();
    ctx.fillText(`${x}°`, px(x), T + H + 14);
  }
  ctx.fillText("θᵢ", L + W / 2, T + H + 27);
  ctx.textAlign = "right";
  const step = niceCeil(ymax / 5);
  for (let y = 0; y <= ymax + 1e-9; y += step) {
    ctx.beginPath(); ctx.moveTo(L, py(y)); ctx.lineTo(L + W, py(y)); ctx.stroke();
    ctx.fillText(Number(y.toPrecision(3)).toString(), L - 4, py(y) + 4);
  }
  ctx.textAlign = "left";
  polyline(ctx, [[L, T], [L, T + H], [L + W, T + H]], "#555", 1);
  for (const s of series) polyline(ctx, s.x.map((x, i) => [px(x), py(s.y[i])]), s.color, s.width, s.dash);
  if (series.length) legend(ctx, [["R", RGB_COLORS[0]], ["G", RGB_COLORS[1]], ["B", RGB_COLORS[2]]], L + W - 40, T + 12);
}

// ---------------------------------------------------------------- the 3D lobe (WebGL2)

const LOBE_VS = `#version 300 es
layout(location = 0) in vec3 aPos;
layout(location = 1) in float aValue;
uniform mat4 uModelView, uProjection;
out vec3 vView;
out float vValue;
void main() {
  vec4 p = uModelView * vec4(aPos, 1.0);
  vView = p.xyz;
  vValue = aValue;
  gl_Position = uProjection * p;
}`;

// Lobe fragments: a colour ramp by radius times |n·l| with n from the screen-space derivatives of
// the view-space position (flat facets) and a light near the viewer; other geometry: uColor.
const LOBE_FS = `#version 300 es
precision highp float;
in vec3 vView;
in float vValue;
uniform vec4 uColor;
uniform int uShade;
out vec4 outColor;
void main() {
  if (uShade == 0) { outColor = uColor; return; }
  vec3 n = normalize(cross(dFdx(vView), dFdy(vView)));
  float d = abs(dot(n, normalize(vec3(0.35, 0.6, 1.0))));
  vec3 ramp = mix(vec3(0.20, 0.35, 0.80), vec3(0.95, 0.50, 0.15), clamp(vValue, 0.0, 1.0));
  outColor = vec4(ramp * (0.3 + 0.7 * d), 1.0);
}`;

// 4×4 matrices, column-major as WebGL expects.
const M4 = {
  mul(a, b) {
    const o = new Float32Array(16);
    for (let c = 0; c < 4; c++) for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      o[c * 4 + r] = s;
    }
    return o;
  },
  perspective(fovy, aspect, n, f) {
    const t = 1 / Math.tan(fovy / 2);
    return new Float32Array([t / aspect, 0, 0, 0, 0, t, 0, 0, 0, 0, (f + n) / (n - f), -1, 0, 0, 2 * f * n / (n - f), 0]);
  },
  translate: (x, y, z) => new Float32Array([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x, y, z, 1]),
  rotX(a) { const c = Math.cos(a), s = Math.sin(a); return new Float32Array([1, 0, 0, 0, 0, c, s, 0, 0, -s, c, 0, 0, 0, 0, 1]); },
  rotZ(a) { const c = Math.cos(a), s = Math.sin(a); return new Float32Array([c, s, 0, 0, -s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]); },
};

// The unit direction at polar angle θ and azimuth φ (degrees), z along the normal.
function direction(theta, phi) {
  const t = theta * Math.PI / 180, p = phi * Math.PI / 180;
  return [Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)];
}

// The lobe's grid: rows of θ_o and columns of φ_o, from the answer's length (the docs leave
// open whether the last θ row and the φ = 360° column are included).
function lobeShape(count, T, P) {
  for (const [rows, cols] of [[T + 1, P], [T, P], [T + 1, P + 1], [T, P + 1]]) if (rows * cols === count) return [rows, cols];
  return [Math.floor(count / P), P];
}

// Triangles (xyz + normalised radius per vertex, and indices) of the lobe r(θ, φ)·direction(θ, φ).
function lobeMesh(answer, log) {
  const T = answer.theta_steps, P = answer.phi_steps, f = answer.f_r || [];
  const [rows, cols] = lobeShape(f.length, T, P);
  const ring = cols === P ? P + 1 : cols;  // wrap φ back to 0 when 360° is not in the data
  const radius = radiusScale(Math.max(0, ...f.filter(Number.isFinite)), log);
  const verts = new Float32Array(rows * ring * 4);
  for (let j = 0; j < rows; j++) for (let k = 0; k < ring; k++) {
    const r = radius(f[j * cols + (k % cols)]);
    const d = direction(90 * j / T, 360 * k / P);
    verts.set([d[0] * r, d[1] * r, d[2] * r, r], (j * ring + k) * 4);
  }
  const index = [];
  for (let j = 0; j + 1 < rows; j++) for (let k = 0; k + 1 < ring; k++) {
    const a = j * ring + k, b = a + ring;
    index.push(a, b, a + 1, a + 1, b, b + 1);
  }
  return { verts, index: new Uint32Array(index) };
}

// Compile and link the lobe's program; null (and a status message) if that fails.
function lobeProgram(gl) {
  const shader = (type, src) => {
    const s = gl.createShader(type);
    gl.shaderSource(s, src);
    gl.compileShader(s);
    return s;
  };
  const prog = gl.createProgram();
  const vs = shader(gl.VERTEX_SHADER, LOBE_VS), fs = shader(gl.FRAGMENT_SHADER, LOBE_FS);
  gl.attachShader(prog, vs);
  gl.attachShader(prog, fs);
  gl.linkProgram(prog);
  if (gl.getProgramParameter(prog, gl.LINK_STATUS)) return prog;
  setStatus(`lobe shader: ${gl.getShaderInfoLog(vs) || gl.getShaderInfoLog(fs) || gl.getProgramInfoLog(prog)}`, true);
  return null;
}

// A vertex array with one interleaved buffer (xyz, value) and an optional index buffer.
function geometry(gl) {
  const vao = gl.createVertexArray(), vbo = gl.createBuffer(), ibo = gl.createBuffer();
  gl.bindVertexArray(vao);
  gl.bindBuffer(gl.ARRAY_BUFFER, vbo);
  gl.enableVertexAttribArray(0);
  gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 16, 0);
  gl.enableVertexAttribArray(1);
  gl.vertexAttribPointer(1, 1, gl.FLOAT, false, 16, 12);
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ibo);
  gl.bindVertexArray(null);
  return {
    vao, count: 0,
    set(verts, index) {
      gl.bindBuffer(gl.ARRAY_BUFFER, vbo);
      gl.bufferData(gl.ARRAY_BUFFER, verts, gl.DYNAMIC_DRAW);
      if (index) {
        gl.bindVertexArray(vao);
        gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, index, gl.DYNAMIC_DRAW);
        gl.bindVertexArray(null);
      }
      this.count = index ? index.length : verts.length / 4;
    },
  };
}

// Points of a circle of radius r in the surface plane (xyz + value 0), `n` segments, closed.
function circle(r, n) {
  const out = [];
  for (let i = 0; i <= n; i++) out.push(r * Math.cos(2 * Math.PI * i / n), r * Math.sin(2 * Math.PI * i / n), 0, 0);
  return out;
}

// The lobe view: a mesh of explore.lobe, the normal, ω_i, a pixel's ω_o and the surface disk;
// dragging turns it. Returns null (with a message in place of the canvas) without WebGL2.
function createLobeView(canvas) {
  const gl = canvas.getContext("webgl2", { antialias: true });
  const prog = gl && lobeProgram(gl);
  if (!prog) {
    canvas.hidden = true;
    const msg = $("lobe-message");
    msg.hidden = false;
    msg.textContent = gl ? "the lobe's shader did not compile" : "WebGL2 is not available in this browser: no 3D lobe.";
    return null;
  }
  const lobe = geometry(gl), lines = geometry(gl), disk = geometry(gl);
  disk.set(new Float32Array([0, 0, 0, 0, ...circle(1.1, 64)]));
  const u = (name) => gl.getUniformLocation(prog, name);
  const uMV = u("uModelView"), uP = u("uProjection"), uColor = u("uColor"), uShade = u("uShade");
  let yaw = -35, elevation = 25;

  // Rebuild the mesh and the direction lines from explore.lobe and the view.
  function update() {
    if (explore.lobe) {
      const mesh = lobeMesh(explore.lobe, $("log-scale").checked);
      lobe.set(mesh.verts, mesh.index);
    }
    const wi = direction(view.theta_i, view.phi_i).map((c) => 1.25 * c);
    const m = view.marker;
    const wo = m ? direction(m.theta_o, m.phi_o).map((c) => 1.25 * c) : [0, 0, 0];
    lines.set(new Float32Array([0, 0, 0, 0, 0, 0, 1.25, 0, 0, 0, 0, 0, ...wi, 0, 0, 0, 0, 0, ...wo, 0]));
    draw();
  }

  // Draw the scene from the current angles.
  function draw() {
    const dpr = window.devicePixelRatio || 1;
    const w = canvas.clientWidth || 400, h = Math.round(w * 0.7);
    canvas.style.height = `${h}px`;
    if (canvas.width !== Math.round(w * dpr)) canvas.width = Math.round(w * dpr);
    if (canvas.height !== Math.round(h * dpr)) canvas.height = Math.round(h * dpr);
    gl.viewport(0, 0, canvas.width, canvas.height);
    gl.clearColor(1, 1, 1, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.useProgram(prog);
    const rad = Math.PI / 180;
    const mv = M4.mul(M4.translate(0, -0.1, -3.4), M4.mul(M4.rotX(-(90 - elevation) * rad), M4.mul(M4.rotZ(yaw * rad), M4.translate(0, 0, -0.35))));
    gl.uniformMatrix4fv(uMV, false, mv);
    gl.uniformMatrix4fv(uP, false, M4.perspective(38 * rad, w / h, 0.1, 20));
    gl.enable(gl.DEPTH_TEST);
    gl.disable(gl.BLEND);
    gl.depthMask(true);
    if (lobe.count) {
      gl.uniform1i(uShade, 1);
      gl.bindVertexArray(lobe.vao);
      gl.drawElements(gl.TRIANGLES, lobe.count, gl.UNSIGNED_INT, 0);
    }
    gl.uniform1i(uShade, 0);
    gl.bindVertexArray(lines.vao);
    [[0.45, 0.45, 0.45, 1], [0.82, 0.1, 0.1, 1], [0.82, 0.06, 0.6, 1]].forEach((c, i) => {
      if (i === 2 && !view.marker) return;
      gl.uniform4fv(uColor, c);
      gl.drawArrays(gl.LINES, 2 * i, 2);
    });
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
    gl.depthMask(false);
    gl.bindVertexArray(disk.vao);
    gl.uniform4fv(uColor, [0.55, 0.6, 0.68, 0.25]);
    gl.drawArrays(gl.TRIANGLE_FAN, 0, disk.count);
    gl.uniform4fv(uColor, [0.35, 0.38, 0.45, 0.9]);
    gl.drawArrays(gl.LINE_STRIP, 1, disk.count - 1);
    gl.bindVertexArray(null);
  }

  // Drag: horizontal turns about the normal, vertical tilts the view.
  onDrag(canvas, (e, dx, dy) => {
    yaw += 0.5 * dx;
    elevation = Math.min(89, Math.max(-30, elevation + 0.5 * dy));
    draw();
  });
  return { update, draw };
}

let lobeView = null;

// ---------------------------------------------------------------- sphere and pixel picking

// ω_i from a pointer on the sphere image: the unit sphere point under it (x right, y up,
// z to the viewer; outside the disk: its rim).
function sphereAngles(e) {
  const r = $("sphere").getBoundingClientRect();
  let x = 2 * (e.clientX - r.left) / r.width - 1, y = 1 - 2 * (e.clientY - r.top) / r.height;
  const d = Math.hypot(x, y);
  if (d > 1) { x /= d; y /= d; }
  const z = Math.sqrt(Math.max(0, 1 - x * x - y * y));
  return [Math.acos(z) * 180 / Math.PI, Math.atan2(y, x) * 180 / Math.PI];
}


let pixelSeq = 0;
// A click on the render: ask for that pixel (in image pixels) of the image shown, then show it.
async function onRenderClick(e) {
  const img = $("render-image");
  if (!img.naturalWidth) return;
  const r = img.getBoundingClientRect();
  const x = Math.min(img.naturalWidth - 1, Math.max(0, Math.floor((e.clientX - r.left) * img.naturalWidth / r.width)));
  const y = Math.min(img.naturalHeight - 1, Math.max(0, Math.floor((e.clientY - r.top) * img.naturalHeight / r.height)));
  const seq = ++pixelSeq;
  try {
    const answer = await postJson("api/pixel", { state: explore.renderState || state, x, y });
    if (seq !== pixelSeq) return;
    explore.pixel = answer;
    showPixel(answer, x, y);
  } catch (err) { report(err); }
}

// The pixel's answer in #pixel-info and a marker on the image; when hit, its material and
// angles drive the plots, with its θ_o marked.
function showPixel(p, x, y) {
  const img = $("render-image"), marker = $("pixel-marker");
  marker.style.left = `${(x + 0.5) * img.clientWidth / img.naturalWidth}px`;
  marker.style.top = `${(y + 0.5) * img.clientHeight / img.naturalHeight}px`;
  marker.hidden = false;
  if (!p.hit) { $("pixel-info").textContent = `pixel (${x}, ${y}): no surface`; return; }
  const name = typeof p.material === "string" ? p.material : null;
  const keys = p.material_keys || (name === null ? p.material : null);
  const label = name || labelOf(keys || {});
  $("pixel-info").textContent = [
    `pixel     (${x}, ${y})`, `n         ${fmt(p.n)}`, `wi        ${fmt(p.wi)}`, `wo        ${fmt(p.wo)}`,
    `material  ${label}`, `f_r       ${fmt(p.f_r)}`,
    `θi, φi    ${fmt(p.theta_i, 1)}°, ${fmt(p.phi_i, 1)}°`, `θo, φo    ${fmt(p.theta_o, 1)}°, ${fmt(p.phi_o, 1)}°`,
  ].join("\n");
  if (name && state.materials[name]) { view.current = name; view.pixelMaterial = null; $("material").value = name; }
  else if (keys && typeof keys === "object") view.pixelMaterial = clone(keys);
  const side = Math.cos((p.phi_o - p.phi_i) * Math.PI / 180) >= 0 ? 1 : -1;
  view.marker = { theta: p.theta_o < 0 ? p.theta_o : side * p.theta_o, value: lum(p.f_r), theta_o: Math.abs(p.theta_o), phi_o: p.phi_o };
  if (Number.isFinite(p.theta_i) && Number.isFinite(p.phi_i)) setAngles(p.theta_i, p.phi_i, true);
  else updateViews(performance.now());
  scheduleAlbedo();
}

// ---------------------------------------------------------------- pins, Mitsuba, save

const PALETTE = ["#ff7f0e", "#9467bd", "#8c564b", "#17becf", "#e377c2", "#bcbd22"];

// A short label of a material: its model and the keys it sets.
function labelOf(mat) {
  const keys = Object.entries(mat).filter(([k]) => k !== "model").slice(0, 4);
  return [modelOf(mat), ...keys.map(([k, v]) => `${k}=${Array.isArray(v) ? fmt(v, 2) : typeof v === "number" ? +v.toPrecision(3) : v}`)].join(" ");
}

// Pin the current material: keep its polar and albedo curves in a colour of its own (6 at most).
async function addPin() {
  if (explore.pins.length === PALETTE.length) explore.pins.shift();
  const material = clone(viewMaterial()), preset = state.preset;
  const color = PALETTE.find((c) => !explore.pins.some((p) => p.color === c));
  const pin = { color, label: labelOf(material), material, preset, brdf: null, at: null, albedo: null };
  explore.pins.push(pin);
  listPins();
  try {
    [, pin.albedo] = await Promise.all([refreshPin(pin), postJson("api/albedo", albedoBody(material, preset))]);
  } catch (err) { report(err); }
  drawPolar();
  drawAlbedo();
}

// The pins' list: a colour swatch and the label each.
function listPins() {
  const list = $("pins");
  list.textContent = "";
  for (const p of explore.pins) {
    const swatch = el("span", { className: "swatch" });
    swatch.style.background = p.color;
    list.append(el("li", {}, swatch, el("span", { textContent: p.label })));
  }
}

// Compare with Mitsuba 3 (POST /api/mitsuba): its message, or the heatmap and the share within 1e-3.
async function runMitsuba() {
  const button = $("mitsuba"), heatmap = $("mitsuba-heatmap");
  button.disabled = true;
  $("mitsuba-message").textContent = "running Mitsuba…";
  $("mitsuba-within").textContent = "";
  try {
    const a = await postJson("api/mitsuba", clone(state));
    $("mitsuba-message").textContent = a.message || "";
    heatmap.hidden = !a.available || !a.heatmap;
    $("mitsuba-legend").hidden = heatmap.hidden;
    if (a.available) {
      if (a.heatmap) heatmap.src = a.heatmap;
      if (Number.isFinite(a.within)) {
        $("mitsuba-within").textContent =
          `${(a.within * 100).toFixed(4)} % of the pixels within ${a.tolerance.toPrecision(1)} at pixel centres; ` +
          `mean relative error ${a.mean_relative_error.toExponential(2)} (Mitsuba ${a.variant}, ${a.mitsuba_seconds.toFixed(2)} s)`;
      }
    }
    explore.mitsuba = a;
  } catch (err) {
    $("mitsuba-message").textContent = err.message;
    report(err);
  }
  button.disabled = false;
}

// Save: the state as a scene file (POST /api/save), downloaded as scene.toml.
async function saveScene() {
  try {
    const text = await (await request("api/save", clone(state))).text();
    const url = URL.createObjectURL(new Blob([text], { type: "text/plain" }));
    const a = el("a", { href: url, download: "scene.toml" });
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 10000);
    setStatus("saved scene.toml");
  } catch (err) { report(err); }
}

// Copy Python: the call that renders the state, in #python-text and on the clipboard if allowed.
async function copyPython() {
  try {
    const text = await (await request("api/python", clone(state))).text();
    $("python-text").value = text;
    try {
      if (!navigator.clipboard) throw new Error("no clipboard");
      await navigator.clipboard.writeText(text);
      setStatus("Python call copied to the clipboard");
    } catch (_) {
      setStatus("the clipboard is not available: the Python call is in the text box");
    }
  } catch (err) { report(err); }
}

// ---------------------------------------------------------------- start-up

// The state in the URL's fragment, null without one; throws on a fragment that is not a state.
function fragmentState() {
  const raw = location.hash.slice(1);
  if (!raw) return null;
  const s = JSON.parse(decodeURIComponent(raw));
  if (!s || typeof s !== "object" || Array.isArray(s) || !s.materials || typeof s.materials !== "object" ||
      Array.isArray(s.materials) || !Object.keys(s.materials).length || ("lights" in s && !Array.isArray(s.lights))) {
    throw new Error("not a state");
  }
  return s;
}

// Hook up the controls that exist in the HTML from the start.
function wireStatic() {
  onEdit($("theta-i"), () => { if (+$("theta-i").value !== view.theta_i) setAngles(+$("theta-i").value, view.phi_i); });
  onEdit($("phi-i"), () => { if (+$("phi-i").value !== view.phi_i) setAngles(view.theta_i, +$("phi-i").value); });
  for (const id of ["polar-cos", "polar-rgb", "show-D", "show-G", "show-F"]) $(id).addEventListener("change", drawPolar);
  $("log-scale").addEventListener("change", () => { drawPolar(); if (lobeView) lobeView.update(); });
  $("material").addEventListener("change", () => {
    view.current = $("material").value;
    view.pixelMaterial = null;
    view.marker = null;
    updateViews(performance.now());
    scheduleAlbedo();
  });
  $("render-image").addEventListener("click", onRenderClick);
  $("pin").addEventListener("click", addPin);
  $("clear-pins").addEventListener("click", () => { explore.pins.length = 0; listPins(); drawPolar(); drawAlbedo(); });
  $("mitsuba").addEventListener("click", runMitsuba);
  $("save").addEventListener("click", saveScene);
  $("copy-python").addEventListener("click", copyPython);
  window.addEventListener("resize", () => { drawPolar(); drawAlbedo(); if (lobeView) lobeView.draw(); });
  onDrag($("sphere"), (e) => setAngles(...sphereAngles(e)));  // the channels keep only the newest
}

// Load the session, take the state (the fragment's if it holds one), build the page, draw
// everything once, then set explore.ready.
async function init() {
  wireStatic();
  try {
    session = await (await request("api/session")).json();
  } catch (err) { report(err); return; }
  explore.session = session;
  keyInfo = new Map((session.keys || []).map((k) => [k.key, k]));
  $("session-name").textContent = session.name || "";
  $("session-mode").textContent = session.mode || "";
  state = clone(session.state);
  try {
    const s = fragmentState();
    if (s) state = s;
  } catch (err) {
    notice = `the URL fragment is not a state (${err.message}): the session's state is used`;
    setStatus(notice, true);
  }
  state.materials = state.materials || {};
  explore.state = state;
  view.current = Object.keys(state.materials)[0] || null;
  if (session.mitsuba && !session.mitsuba.available) $("mitsuba-message").textContent = session.mitsuba.message || "";
  // The image first: the plots (the lobe's WebGL set-up above all, in software on a machine
  // without a GPU) would share the cores with its first trace.
  const t0 = performance.now();
  const rendered = renderChannel({ t0 });
  buildParams();
  buildMaterialSelect();
  showAngles();
  await Promise.race([firstImage, rendered]);
  lobeView = createLobeView($("lobe"));
  drawPolar();
  drawAlbedo();
  await Promise.all([rendered, updateViews(t0), albedoChannel({ t0 })]);
  explore.ready = true;
}

init();
