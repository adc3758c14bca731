"""The page of ``warpoptics view``: plain HTML and JavaScript, no external resources.

The script asks ``/state`` for the controls, then loops: fetch ``/frame.jpg`` (the server adds one
pass and answers with the mean so far; headers ``X-Generation``, ``X-Passes``, ``X-Draft``), show it,
repeat; when the preview has all its passes it asks again every 300 ms.  Dragging on the image
orbits (left/right) and tilts (up/down) the camera, the wheel changes the distance; sliders and
menus change the scene.  Changes are sent as one ``POST /controls`` at a time (later ones are
merged while one is in flight), so a fast drag costs one restart per frame, not per mouse event.
``?frames=N`` stops the loop after N frames (for a headless browser to settle); ``?set=NAME=VALUE``
(numbers only) sends one change after the controls are built, as a slider would (for a headless
browser to drive the page).  Every ``POST`` carries the launch's token, which the server writes
into the page's ``warpoptics-token`` meta tag (``@WARPOPTICS_TOKEN@`` below), in the
``X-Warpoptics-Token`` header, as JSON: the server refuses writes without them.
"""

from __future__ import annotations

__all__ = ["PAGE"]

PAGE = r"""<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="warpoptics-token" content="@WARPOPTICS_TOKEN@">
<title>warpoptics view</title>
<style>
  body { font: 14px system-ui, sans-serif; margin: 12px; background: #1e1e1e; color: #ddd; }
  #wrap { display: flex; gap: 16px; align-items: flex-start; }
  #frame { cursor: grab; image-rendering: auto; background: #000; touch-action: none; user-select: none; }
  #frame.drag { cursor: grabbing; }
  #status { font-family: monospace; margin-top: 6px; white-space: pre; }
  #error { color: #f77; margin-top: 6px; }
  form { display: grid; grid-template-columns: auto 14em 5em; gap: 6px 8px; align-items: center; }
  label { text-align: right; }
  output { font-family: monospace; }
</style>
</head>
<body>
<div id="wrap">
  <div>
    <img id="frame" alt="warpoptics preview" draggable="false">
    <div id="status" data-passes="0" data-generation="0" data-frames="0">starting</div>
    <div id="error"></div>
    <div><a id="snapshot" href="/frame.png" download="warpoptics-view.png">PNG of this view</a></div>
  </div>
  <form id="controls" onsubmit="return false"></form>
</div>
<script>
"use strict";
const params = new URLSearchParams(location.search);
const maxFrames = params.has("frames") ? parseInt(params.get("frames")) : Infinity;
const token = document.querySelector('meta[name="warpoptics-token"]').content;
const img = document.getElementById("frame");
const statusEl = document.getElementById("status");
const errorEl = document.getElementById("error");
const form = document.getElementById("controls");
const inputs = {};
const values = {};
const pending = {};
let sending = false;
let frames = 0;
const times = [];

function sleep(ms) { return new Promise(r => setTimeout(r, ms)); }

function show(name, v) {
  const inp = inputs[name];
  if (!inp) return;
  inp.value = v;
  if (inp.out) inp.out.textContent = (+v).toFixed(inp.digits) + (inp.unit ? " " + inp.unit : "");
}

function set(name, v) {
  values[name] = v;
  pending[name] = v;
  show(name, v);
  send();
}

async function send() {
  if (sending || Object.keys(pending).length === 0) return;
  sending = true;
  const body = Object.assign({}, pending);
  for (const k of Object.keys(body)) delete pending[k];
  try {
    const r = await fetch("/controls", {
      method: "POST",
      headers: { "Content-Type": "application/json", "X-Warpoptics-Token": token },
      body: JSON.stringify(body),
    });
    const j = await r.json();
    errorEl.textContent = r.ok ? "" : j.error;
    for (const [k, v] of Object.entries(j.values || {})) {
      if (!(k in pending)) { values[k] = v; show(k, v); }
    }
  } catch (e) {
    errorEl.textContent = String(e);
  }
  sending = false;
  if (Object.keys(pending).length) send();
}

function build(controls) {
  for (const c of controls) {
    const label = document.createElement("label");
    label.textContent = c.label;
    label.htmlFor = "c_" + c.name;
    let inp, out = document.createElement("output");
    if (c.kind === "range") {
      inp = document.createElement("input");
      inp.type = "range";
      inp.min = c.lo; inp.max = c.hi; inp.step = c.step;
      inp.digits = Math.max(0, Math.min(4, Math.ceil(-Math.log10(c.step))));
      inp.unit = c.unit;
      inp.out = out;
      inp.addEventListener("input", () => set(c.name, parseFloat(inp.value)));
    } else {
      inp = document.createElement("select");
      for (const ch of c.choices) {
        const o = document.createElement("option");
        o.value = ch; o.textContent = ch;
        inp.appendChild(o);
      }
      inp.addEventListener("change", () => set(c.name, inp.value));
    }
    inp.id = "c_" + c.name;
    inp.dataset.name = c.name;
    inputs[c.name] = inp;
    values[c.name] = c.value;
    form.append(label, inp, out);
    show(c.name, c.value);
  }
}

// orbit (drag left/right), tilt (drag up/down), distance (wheel)
let drag = null;
img.addEventListener("pointerdown", e => {
  drag = { x: e.clientX, y: e.clientY, az: values.azimuth, el: values.elevation };
  img.setPointerCapture(e.pointerId);
  img.classList.add("drag");
});
img.addEventListener("pointermove", e => {
  if (!drag) return;
  const az = drag.az - 0.4 * (e.clientX - drag.x);
  const lim = +inputs.elevation.max;
  const el = Math.max(-lim, Math.min(lim, drag.el + 0.3 * (e.clientY - drag.y)));
  values.azimuth = ((az + 180) % 360 + 360) % 360 - 180;
  values.elevation = el;
  pending.azimuth = values.azimuth; pending.elevation = el;
  show("azimuth", values.azimuth); show("elevation", el);
  send();
});
function endDrag() { drag = null; img.classList.remove("drag"); }
img.addEventListener("pointerup", endDrag);
img.addEventListener("pointercancel", endDrag);
img.addEventListener("wheel", e => {
  e.preventDefault();
  const d = inputs.distance;
  const v = Math.max(+d.min, Math.min(+d.max, values.distance * Math.exp(0.001 * e.deltaY)));
  set("distance", v);
}, { passive: false });

async function loop() {
  let last = null;
  while (frames < maxFrames) {
    let r;
    try {
      r = await fetch("/frame.jpg?n=" + frames, { cache: "no-store" });
    } catch (e) {
      statusEl.textContent = "the server has stopped";
      return;
    }
    const blob = await r.blob();
    const url = URL.createObjectURL(blob);
    img.src = url;
    try { await img.decode(); } catch (e) { /* a frame replaced by the next one */ }
    if (last) URL.revokeObjectURL(last);
    last = url;
    frames += 1;
    const now = performance.now();
    times.push(now);
    while (times.length && now - times[0] > 2000) times.shift();
    const fps = times.length > 1 ? (times.length - 1) * 1000 / (now - times[0]) : 0;
    const passes = r.headers.get("X-Passes"), gen = r.headers.get("X-Generation");
    const draft = r.headers.get("X-Draft") === "1";
    const ms = 1000 * parseFloat(r.headers.get("X-Pass-Seconds") || "0");
    statusEl.dataset.passes = passes;
    statusEl.dataset.generation = gen;
    statusEl.dataset.frames = frames;
    const what = draft ? "draft" : "passes " + passes;
    statusEl.textContent = `${what} (view ${gen})  ${fps.toFixed(1)} frames/s  ${ms.toFixed(0)} ms/pass`;
    if (r.headers.get("X-Done") === "1") await sleep(300);
  }
}

fetch("/state").then(r => r.json()).then(s => {
  img.width = s.width; img.height = s.height;
  build(s.controls);
  for (const item of params.getAll("set")) {
    const i = item.indexOf("=");
    if (i > 0 && inputs[item.slice(0, i)]) set(item.slice(0, i), parseFloat(item.slice(i + 1)));
  }
  loop();
});
</script>
</body>
</html>
"""
