// quatspline view: the page. Every number it shows comes from the server's
// quatspline.ops.design.evaluate; this file only draws and edits.
import * as THREE from "three";

const TOKEN = document.querySelector('meta[name="quatspline-token"]').content;
const $ = (id) => document.getElementById(id);
const state = {
  quats: [], times: [], methods: [], method: "c3", params: {}, compare: "", compareParams: {},
  result: null, other: null, undo: [], redo: [], selected: -1, playing: false, phase: 0,
};
window.qsState = state;  // read by the browser test
window.qsLatency = [];   // ms from a control change to redrawn plots (read by the browser test)
window.qsEvaluations = 0;

async function api(path, body) {
  const r = await fetch(path, {
    method: body === undefined ? "GET" : "POST",
    headers: { "X-Quatspline-Token": TOKEN, "Content-Type": "application/json" },
    body: body === undefined ? undefined : JSON.stringify(body),
  });
  if (!r.ok) {
    let msg = `${r.status}`;
    try { msg = (await r.json()).error || msg; } catch (e) { /* not JSON */ }
    throw new Error(msg);
  }
  return r;
}

function status(msg, error = false) {
  $("status").textContent = msg;
  $("status").className = error ? "error" : "";
}

// ---- quaternions (w, x, y, z) -------------------------------------------------------------
function qmul(a, b) {
  return [a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
    a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
    a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
    a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]];
}
function rotate(q, v) {  // q v q*
  const p = qmul(qmul(q, [0, v[0], v[1], v[2]]), [q[0], -q[1], -q[2], -q[3]]);
  return [p[1], p[2], p[3]];
}
function fromEulerXYZ(deg) {  // scipy "xyz" (extrinsic): q = qz qy qx
  const h = deg.map((d) => (d * Math.PI) / 360);
  const qx = [Math.cos(h[0]), Math.sin(h[0]), 0, 0];
  const qy = [Math.cos(h[1]), 0, Math.sin(h[1]), 0];
  const qz = [Math.cos(h[2]), 0, 0, Math.sin(h[2])];
  return qmul(qz, qmul(qy, qx));
}
function toEulerXYZ(q) {  // inverse of fromEulerXYZ (degrees), away from gimbal lock
  const [w, x, y, z] = q;
  const sy = Math.max(-1, Math.min(1, 2 * (w * y - z * x)));
  return [Math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)), Math.asin(sy),
    Math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))].map((r) => (r * 180) / Math.PI);
}

// ---- method and parameter controls ----------------------------------------------------------
function paramControls(container, spec, values, onChange) {
  container.innerHTML = "";
  for (const p of spec.params) {
    const label = document.createElement("label");
    label.title = p.help;
    label.append(`${p.name} `);
    let input;
    if (p.choices) {
      input = document.createElement("select");
      for (const c of p.choices) input.add(new Option(c, c));
      input.value = values[p.name] ?? p.default;
    } else if (p.kind === "bool") {
      input = document.createElement("input");
      input.type = "checkbox";
      input.checked = values[p.name] ?? p.default;
    } else if (p.kind === "float" || p.kind === "int") {
      const v = values[p.name] ?? p.default ?? 0;
      const span = Math.max(1, Math.abs(v) * 4);
      const range = document.createElement("input");
      range.type = "range"; range.min = -span; range.max = span;
      range.step = p.kind === "int" ? 1 : span / 500; range.value = v;
      range.dataset.param = p.name;
      input = document.createElement("input");
      input.type = "number"; input.step = "any"; input.value = v;
      range.addEventListener("input", () => { input.value = range.value; input.dispatchEvent(new Event("input")); });
      label.append(range);
    } else {
      input = document.createElement("input");
      input.type = "text"; input.value = values[p.name] ?? p.default ?? "";
    }
    input.name = p.name;
    input.dataset.param = input.dataset.param || p.name;
    input.addEventListener(p.choices || p.kind === "bool" ? "change" : "input", () => {
      let v = p.kind === "bool" ? input.checked : input.value;
      if (p.kind === "float" || p.kind === "int") {
        v = Number(v);
        if (!Number.isFinite(v)) { input.classList.add("bad"); return; }
        input.classList.remove("bad");
      }
      values[p.name] = v;
      onChange();
    });
    label.append(input);
    container.append(label);
  }
}

function setMethod(name) {
  state.method = name;
  state.params = {};
  const spec = state.methods.find((m) => m.name === name);
  paramControls($("params"), spec, state.params, requestEval);
}

function setCompare(name) {
  state.compare = name;
  state.compareParams = {};
  const spec = state.methods.find((m) => m.name === name);
  if (spec) paramControls($("compare-params"), spec, state.compareParams, requestEval);
  else $("compare-params").innerHTML = "";
}

// ---- evaluation (one request in flight; the latest change wins) ----------------------------
let inflight = false, pending = null;
function requestEval() {
  pending = performance.now();
  if (!inflight) runEval();
}
async function runEval() {
  const t0 = pending;
  pending = null;
  inflight = true;
  const body = (method, params) => ({
    method, params, quats: state.quats, times: state.times, samples: Number($("samples").value),
  });
  try {
    const jobs = [api("/api/evaluate", body(state.method, state.params)).then((r) => r.json())];
    if (state.compare) jobs.push(api("/api/evaluate", body(state.compare, state.compareParams)).then((r) => r.json()));
    const [res, other] = await Promise.all(jobs);
    state.result = res;
    state.other = other || null;
    drawAll();
    window.qsEvaluations += 1;
    status(`${res.method}: ${res.t.length} samples, ${state.quats.length} keys`);
    requestAnimationFrame(() => {
      const ms = performance.now() - t0;
      window.qsLatency.push(ms);
      $("latency").textContent = ms.toFixed(0);
    });
  } catch (e) {
    status(`error: ${e.message}`, true);
  }
  inflight = false;
  if (pending !== null) runEval();
}

// ---- plots -----------------------------------------------------------------------------------
const plots = {};
function keyLines(u) {
  const ctx = u.ctx;
  ctx.save();
  ctx.strokeStyle = "rgba(0,0,0,0.25)";
  ctx.setLineDash([3, 3]);
  const step = Math.max(1, Math.ceil(state.times.length / 60));
  for (let i = 0; i < state.times.length; i += step) {
    const x = u.valToPos(state.times[i], "x", true);
    ctx.beginPath(); ctx.moveTo(x, u.bbox.top); ctx.lineTo(x, u.bbox.top + u.bbox.height); ctx.stroke();
  }
  ctx.restore();
}
function drawPlots() {
  const r = state.result, o = state.other;
  const quantities = [["speed", "|ω| (rad/s)"], ["acceleration", "|α| (rad/s²)"], ["jerk", "|jerk| (rad/s³)"]];
  const width = Math.max(400, $("views").clientWidth - 20);
  for (const [key, label] of quantities) {
    const series = [{ label: "t (s)" }, { label: `${r.method}`, stroke: "#1f5fbf", width: 1.5 }];
    const data = [r.t, r[key]];
    if (o) {
      series.push({ label: `${o.method}`, stroke: "#d9480f", width: 1.2, dash: [6, 4] });
      // the other curve on this curve's grid (same domain for interpolating methods)
      data.push(r.t.map((t) => interp(o.t, o[key], t)));
    }
    const opts = {
      title: label, width, height: 150, series, hooks: { draw: [keyLines] },
      axes: [{ label: "time (s)" }, { label, size: 70 }], scales: { x: { time: false } },
    };
    if (plots[key] && plots[key].series.length === series.length) {
      plots[key].setData(data);
      plots[key].setSize({ width, height: 150 });
    } else {
      if (plots[key]) plots[key].destroy();
      const div = document.createElement("div");
      div.id = `plot-${key}`;
      const old = $(`plot-${key}`);
      if (old) old.replaceWith(div); else $("plots").append(div);
      plots[key] = new uPlot(opts, data, div);
    }
  }
  window.qsPlotData = { speed: r.speed, acceleration: r.acceleration, jerk: r.jerk };
}
function interp(xs, ys, x) {
  if (x <= xs[0]) return ys[0];
  if (x >= xs[xs.length - 1]) return ys[ys.length - 1];
  let lo = 0, hi = xs.length - 1;
  while (hi - lo > 1) { const m = (lo + hi) >> 1; if (xs[m] <= x) lo = m; else hi = m; }
  const f = (x - xs[lo]) / (xs[hi] - xs[lo]);
  return ys[lo] + f * (ys[hi] - ys[lo]);
}

// ---- certificate, keys, python -------------------------------------------------------------
function drawCertificate() {
  const r = state.result;
  const rows = r.joints.map((j, i) =>
    `<tr><td>${i + 1}</td><td>${j.time.toPrecision(6)}</td><td>C${j.order < 0 ? "⁻" : j.order}</td>` +
    j.jumps.map((x) => `<td>${x === null ? "" : x.toExponential(1)}</td>`).join("") + "</tr>");
  const lowest = r.joints.length ? Math.min(...r.joints.map((j) => j.order)) : "–";
  $("certificate").innerHTML =
    `<div id="cert-summary">method ${r.method}: guaranteed C${r.continuity ?? "∞"}, lowest order found C${lowest}</div>` +
    `<table id="cert-table"><tr><th>joint</th><th>time</th><th>order</th><th>jump q</th><th>q'</th><th>q''</th><th>q'''</th></tr>${rows.join("")}</table>`;
  $("python").textContent = r.python;
}

function drawKeys() {
  const rows = state.times.map((t, i) => {
    const e = toEulerXYZ(state.quats[i]).map((v) => v.toFixed(2));
    return `<tr class="key${i === state.selected ? " selected" : ""}" data-i="${i}"><td>${i}</td><td>${t.toPrecision(6)}</td><td>${e.join("</td><td>")}</td></tr>`;
  });
  $("keytable").innerHTML = `<table><tr><th>#</th><th>t</th><th>x°</th><th>y°</th><th>z°</th></tr>${rows.join("")}</table>`;
  for (const tr of $("keytable").querySelectorAll("tr.key")) tr.onclick = () => selectKey(Number(tr.dataset.i));
}

function selectKey(i) {
  state.selected = i;
  $("editor").hidden = false;
  $("ed-index").textContent = String(i);
  $("ed-time").value = state.times[i];
  const e = toEulerXYZ(state.quats[i]);
  ["ed-ex", "ed-ey", "ed-ez"].forEach((id, k) => { $(id).value = e[k].toFixed(6); });
  $("ed-q").value = state.quats[i].map((v) => v.toFixed(9)).join(" ");
  $("ed-msg").textContent = "";
  drawKeys();
}

function applyEdit(q) {
  const i = state.selected;
  const t = Number($("ed-time").value);
  const msg = (m) => { $("ed-msg").textContent = m; };
  if (!Number.isFinite(t)) return msg("time: not a finite number");
  if (i > 0 && !(t > state.times[i - 1])) return msg(`time: must be after key ${i - 1} (${state.times[i - 1]})`);
  if (i < state.times.length - 1 && !(t < state.times[i + 1])) return msg(`time: must be before key ${i + 1} (${state.times[i + 1]})`);
  if (!q.every(Number.isFinite)) return msg("rotation: not finite");
  const n = Math.hypot(...q);
  if (!(n > 1e-12)) return msg("quaternion: zero");
  state.undo.push({ quats: state.quats.map((x) => x.slice()), times: state.times.slice() });
  state.redo = [];
  state.quats[i] = q.map((v) => v / n);
  state.times[i] = t;
  msg("");
  selectKey(i);
  requestEval();
}

function restore(from, to) {
  const s = from.pop();
  if (!s) return;
  to.push({ quats: state.quats.map((x) => x.slice()), times: state.times.slice() });
  state.quats = s.quats; state.times = s.times;
  if (state.selected >= 0) selectKey(Math.min(state.selected, state.times.length - 1));
  drawKeys();
  requestEval();
}

async function download(fmt, body, name) {
  try {
    const r = await api("/api/export", { format: fmt, ...body });
    const blob = await r.blob();
    const a = document.createElement("a");
    a.href = URL.createObjectURL(blob);
    a.download = name;
    document.body.append(a); a.click(); a.remove();
    status(`exported ${name}`);
  } catch (e) {
    status(`export failed: ${e.message}`, true);
  }
}

// ---- 3D: the body and the sphere ------------------------------------------------------------
const AXES = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
const COLOURS = [0xd62728, 0x2ca02c, 0x1f77b4];
function makeRenderer(canvas) {
  const r = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  r.setClearColor(0xfbfbfd);
  return r;
}
const body = { renderer: null, scene: new THREE.Scene(), camera: new THREE.PerspectiveCamera(40, 4 / 3, 0.1, 100), obj: new THREE.Group() };
const sphere = { renderer: null, scene: new THREE.Scene(), camera: new THREE.PerspectiveCamera(35, 1, 0.1, 100), traces: [], keys: null, marker: [] };
function initScenes() {
  body.renderer = makeRenderer($("body3d"));
  sphere.renderer = makeRenderer($("sphere3d"));
  for (const s of [body, sphere]) {
    s.camera.position.set(3.2, 2.4, 2.6);
    s.camera.up.set(0, 0, 1);
    s.camera.lookAt(0, 0, 0);
    s.scene.add(new THREE.AmbientLight(0xffffff, 0.7));
    const light = new THREE.DirectionalLight(0xffffff, 0.8);
    light.position.set(3, 2, 4);
    s.scene.add(light);
  }
  body.camera.position.multiplyScalar(1.1);
  const box = new THREE.Mesh(new THREE.BoxGeometry(1.2, 0.6, 0.25),
    new THREE.MeshStandardMaterial({ color: 0xb0b8c8, metalness: 0.1, roughness: 0.7 }));
  body.obj.add(box);
  AXES.forEach((a, k) => {
    const g = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(0, 0, 0), new THREE.Vector3(...a).multiplyScalar(1.1)]);
    body.obj.add(new THREE.Line(g, new THREE.LineBasicMaterial({ color: COLOURS[k] })));
  });
  body.scene.add(body.obj);
  body.scene.add(new THREE.AxesHelper(0.4));
  const wire = new THREE.LineSegments(new THREE.WireframeGeometry(new THREE.SphereGeometry(1, 24, 12)),
    new THREE.LineBasicMaterial({ color: 0xcfd3dc }));
  wire.rotation.x = Math.PI / 2;
  sphere.scene.add(wire);
  sphere.marker = AXES.map((_, k) => {
    const m = new THREE.Mesh(new THREE.SphereGeometry(0.05, 12, 8), new THREE.MeshBasicMaterial({ color: COLOURS[k] }));
    sphere.scene.add(m);
    return m;
  });
}
function drawTraces() {
  for (const t of sphere.traces) { sphere.scene.remove(t); t.geometry.dispose(); t.material.dispose(); }
  sphere.traces = [];
  const r = state.result;
  AXES.forEach((a, k) => {
    const pts = r.quats.map((q) => new THREE.Vector3(...rotate(q, a)));
    const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints(pts), new THREE.LineBasicMaterial({ color: COLOURS[k] }));
    sphere.traces.push(line);
    sphere.scene.add(line);
    const keyPts = r.key_quats.map((q) => new THREE.Vector3(...rotate(q, a)));
    const dots = new THREE.Points(new THREE.BufferGeometry().setFromPoints(keyPts), new THREE.PointsMaterial({ color: 0x000000, size: 6, sizeAttenuation: false }));
    sphere.traces.push(dots);
    sphere.scene.add(dots);
  });
}
function poseAt(phase) {
  const r = state.result;
  if (!r) return null;
  const i = Math.min(r.quats.length - 1, Math.max(0, Math.round(phase * (r.quats.length - 1))));
  return { q: r.quats[i], t: r.t[i] };
}
let dirty = true;  // the 3D views are drawn only when something changed (software GL is slow)
function render() {
  dirty = false;
  const p = poseAt(state.phase);
  if (p) {
    const [w, x, y, z] = p.q;
    body.obj.quaternion.set(x, y, z, w);
    sphere.marker.forEach((m, k) => m.position.set(...rotate(p.q, AXES[k])));
    $("clock").textContent = `t = ${p.t.toFixed(3)} s`;
  }
  body.renderer.render(body.scene, body.camera);
  sphere.renderer.render(sphere.scene, sphere.camera);
}
let last = null;
function tick(now) {
  if (state.playing && state.result && last !== null) {
    const [a, b] = state.result.domain;
    const dur = Math.max(b - a, 1e-9);
    state.phase = (state.phase + ((now - last) / 1000) * Number($("speed").value) / dur) % 1;
    $("scrub").value = String(Math.round(state.phase * 1000));
  }
  last = now;
  if (state.playing || dirty) render();
  requestAnimationFrame(tick);
}

function drawAll() {
  drawPlots();
  drawCertificate();
  drawTraces();
  dirty = true;  // the next animation frame redraws the 3D views
}

// ---- start -----------------------------------------------------------------------------------
async function main() {
  initScenes();
  const s = await (await api("/api/state")).json();
  state.quats = s.quats; state.times = s.times; state.methods = s.methods;
  $("source").textContent = s.name;
  for (const m of s.methods) {
    $("method").add(new Option(`${m.name} (${m.continuity})`, m.name));
    $("compare").add(new Option(m.name, m.name));
  }
  $("method").value = "c3";
  $("method").onchange = () => { setMethod($("method").value); requestEval(); };
  $("compare").onchange = () => { setCompare($("compare").value); requestEval(); };
  $("samples").onchange = requestEval;
  setMethod("c3");
  $("undo").onclick = () => restore(state.undo, state.redo);
  $("redo").onclick = () => restore(state.redo, state.undo);
  $("save").onclick = () => download("keys", { quats: state.quats, times: state.times, method: state.method }, "keys.json");
  $("ed-apply-euler").onclick = () => applyEdit(fromEulerXYZ(["ed-ex", "ed-ey", "ed-ez"].map((id) => Number($(id).value))));
  $("ed-apply-q").onclick = () => applyEdit($("ed-q").value.trim().split(/[\s,]+/).map(Number));
  for (const b of document.querySelectorAll("button[data-export]")) {
    const fmt = b.dataset.export;
    b.onclick = () => download(fmt, { method: state.method, params: state.params, quats: state.quats, times: state.times, samples: Number($("samples").value) }, `design.${fmt === "glb" ? "glb" : fmt}`);
  }
  $("play").onclick = () => { state.playing = !state.playing; $("play").textContent = state.playing ? "pause" : "play"; };
  $("scrub").oninput = () => { state.phase = Number($("scrub").value) / 1000; dirty = true; };
  drawKeys();
  requestEval();
  requestAnimationFrame(tick);
}
main().catch((e) => status(`error: ${e.message}`, true));
