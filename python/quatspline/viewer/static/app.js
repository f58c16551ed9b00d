// quatspline view: the page. Every number it shows comes from the server's
// quatspline.ops.design.evaluate; this file only draws and edits.
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { TransformControls } from "three/addons/controls/TransformControls.js";

const TOKEN = document.querySelector('meta[name="quatspline-token"]').content;
const $ = (id) => document.getElementById(id);
const state = {
  quats: [], times: [], methods: [], method: "c3", params: {}, compare: "", compareParams: {},
  result: null, other: null, undo: [], redo: [], selected: -1, playing: false, phase: 0,
};
window.qsState = state;  // read by the browser test
window.qsLatency = [];   // ms from a control change to redrawn plots (read by the browser test)
window.qsEvaluations = 0;
const CERT_PAGE = 50;     // certificate rows per page
const CERT_OPEN_MAX = 20; // more joints than this: the table starts folded
const MAX_KEY_DOTS = 60;  // key marks drawn on the sphere at most (thinned beyond)
const MAX_TRACE = 800;    // points per axis trace on the sphere at most
const GIZMO_SNAP_DEG = 5;

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

// An evaluation's float arrays arrive as their float64 bytes ({shape, f8: base64}); they
// become plain (nested) arrays here.
function unpack(v) {
  if (!v || typeof v !== "object" || typeof v.f8 !== "string") return v;
  const bin = atob(v.f8), bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  const f = new Float64Array(bytes.buffer);
  if (v.shape.length === 1) return Array.from(f);
  const w = v.shape[1], rows = new Array(v.shape[0]);
  for (let i = 0; i < rows.length; i++) rows[i] = Array.from(f.subarray(i * w, (i + 1) * w));
  return rows;
}
const unpacked = (d) => Object.fromEntries(Object.entries(d).map(([k, v]) => [k, unpack(v)]));

function status(msg, error = false) {
  $("status").textContent = msg;
  $("status").className = error ? "error" : "";
}
const message = (m) => { $("ed-msg").textContent = m; };

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
const unit = (q) => { const n = Math.hypot(...q); return q.map((v) => v / n); };

// ---- undo / redo: every edit is a snapshot of the design before it -----------------------------
// parameters copied with their per-key arrays (an edit replaces an array, never changes it)
const copyParams = (p) => Object.fromEntries(Object.entries(p).map(([k, v]) => [k, Array.isArray(v) ? v.slice() : v]));
function snapshot() {
  return {
    quats: state.quats.map((x) => x.slice()), times: state.times.slice(), method: state.method,
    params: copyParams(state.params), compare: state.compare, compareParams: copyParams(state.compareParams),
    selected: state.selected,
  };
}
let lastTag = null, lastTagTime = 0;
// Remembers the design before an edit; consecutive changes of one control within a second
// (a slider moving) are one edit.
function remember(tag = null) {
  const now = performance.now();
  if (tag !== null && tag === lastTag && now - lastTagTime < 1000) { lastTagTime = now; return; }
  lastTag = tag; lastTagTime = now;
  state.undo.push(snapshot());
  state.redo = [];
}
function restore(from, to) {
  const s = from.pop();
  if (!s) return;
  to.push(snapshot());
  lastTag = null;
  state.quats = s.quats; state.times = s.times;
  state.method = s.method; state.params = s.params;
  state.compare = s.compare; state.compareParams = s.compareParams;
  $("method").value = s.method; $("compare").value = s.compare;
  buildParamControls();
  state.selected = Math.min(s.selected, state.times.length - 1);
  refreshKeys();
  requestEval();
}

// ---- method and parameter controls ----------------------------------------------------------
function paramControls(container, spec, values, tag) {
  container.innerHTML = "";
  for (const p of spec.params) {
    const label = document.createElement("label");
    label.title = p.help;
    // a per-key parameter's control here sets every key's value at once
    label.append(`${p.name}${p.per && tag === "param" ? " (all keys)" : ""} `);
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
      let v = values[p.name] ?? p.default ?? 0;
      if (Array.isArray(v)) v = v[Math.max(0, Math.min(state.selected, v.length - 1))];  // per key: the selected one's
      if (typeof v !== "number") v = 0;
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
      remember(`${tag} ${p.name}`);
      values[p.name] = v;
      if (tag === "param") drawKeyShapes();
      requestEval();
    });
    label.append(input);
    container.append(label);
  }
}

// ---- per-key shape parameters: one value for all keys, or an array of one per key ---------------
// (per segment for the C³ spline's patent variant: N − 1 open, N round a closed loop). The
// registry marks them (spec "per"); the request carries the arrays as they are.
const PER_RANGE = { tension: [-1, 1], continuity: [-1, 1], bias: [-1, 1], beta1: [0.1, 10], beta2: [0, 20], alpha: [0, 1], beta: [-6, 6] };
function perSpecs() {
  const spec = state.methods.find((m) => m.name === state.method);
  return spec ? spec.params.filter((p) => p.per) : [];
}
const perUnit = () => (state.method === "c3" && (state.params.variant ?? "knot") === "patent" ? "segment" : "key");
function perCount() {
  let n = state.times.length;
  if (state.method !== "c3") return n;
  const closed = (state.params.ends ?? "open") === "closed";
  // a C³ loop whose last key equals the first (q or −q): that closing key is dropped
  // (as the registry decides: the angle between them at most 1e-12 rad)
  const [a0, ...a1] = state.quats[0];
  const d = qmul([a0, ...a1.map((v) => -v)], state.quats[n - 1]);
  if (closed && 2 * Math.atan2(Math.hypot(d[1], d[2], d[3]), Math.abs(d[0])) <= 1e-12) n -= 1;
  return perUnit() === "key" || closed ? n : n - 1;
}
// The value every key has while a parameter is one number ("auto" of the C³ spline: (1/2, −3)).
function perScalar(p) {
  const v = state.params[p.name] ?? p.default;
  if (typeof v === "number") return v;
  if (p.name === "alpha") return 0.5;
  if (p.name === "beta" && state.params.alpha === "auto") return -3;
  return 0;
}
function perValue(p, i) {
  const v = state.params[p.name];
  return Array.isArray(v) ? v[i] : perScalar(p);
}
function setPerValue(p, i, x) {
  remember(`perkey ${p.name} ${i}`);
  const v = Array.isArray(state.params[p.name]) ? state.params[p.name].slice() : new Array(perCount()).fill(perScalar(p));
  v[i] = x;
  state.params[p.name] = v;
  for (const el of $("params").querySelectorAll(`input[data-param="${p.name}"]`)) el.value = x;
  requestEval();
}
// Arrays kept one per key (segment): a key added copies its neighbour's value (a segment split,
// the split one's), a key deleted takes its value (a merged segment keeps the earlier one's).
function perInsert(at) {
  for (const p of perSpecs()) {
    const v = state.params[p.name];
    if (!Array.isArray(v)) continue;
    const w = v.slice();
    w.splice(Math.min(at, w.length), 0, w[Math.max(0, Math.min(at - 1, w.length - 1))]);
    state.params[p.name] = w;
  }
}
function perDelete(i) {
  for (const p of perSpecs()) {
    const v = state.params[p.name];
    if (!Array.isArray(v)) continue;
    const w = v.slice();
    w.splice(Math.min(i, w.length - 1), 1);
    state.params[p.name] = w;
  }
}
// After a variant or end change (knot ↔ patent): arrays cut or extended by their last value.
function perConform() {
  const n = perCount();
  for (const p of perSpecs()) {
    const v = state.params[p.name];
    if (!Array.isArray(v) || v.length === n) continue;
    const w = v.slice(0, n);
    while (w.length < n) w.push(v[v.length - 1]);
    state.params[p.name] = w;
  }
}
function drawKeyShapes() {
  const box = $("key-shapes");
  box.innerHTML = "";
  const specs = perSpecs();
  if (!specs.length) return;
  const i = state.selected, unit = perUnit(), n = state.times.length;
  if (i < 0 || i >= n) { box.textContent = `select a key to set its own ${specs.map((p) => p.name).join(", ")}`; return; }
  if (i >= perCount()) { box.textContent = `key ${i} starts no segment (the ${specs.map((p) => p.name).join(", ")} of the patent variant belong to segments)`; return; }
  const head = document.createElement("div");
  head.id = "key-shapes-head";
  head.textContent = unit === "key" ? `key ${i} only:` : `segment ${i} (key ${i} → ${(i + 1) % n}) only:`;
  box.append(head);
  for (const p of specs) {
    const [lo, hi] = PER_RANGE[p.name] ?? [-1, 1];
    const v = perValue(p, i);
    const label = document.createElement("label");
    label.title = `${p.help} — this ${unit} only`;
    label.append(`${p.name}[${i}] `);
    const range = document.createElement("input");
    range.type = "range"; range.min = Math.min(lo, v); range.max = Math.max(hi, v);
    range.step = (hi - lo) / 1000; range.value = v; range.dataset.perkey = p.name;
    const input = document.createElement("input");
    input.type = "number"; input.step = "any"; input.value = v; input.dataset.perkey = p.name;
    range.addEventListener("input", () => { input.value = range.value; setPerValue(p, i, Number(range.value)); });
    input.addEventListener("input", () => {
      const x = Number(input.value);
      if (input.value.trim() === "" || !Number.isFinite(x)) { input.classList.add("bad"); return; }
      input.classList.remove("bad");
      range.value = x;
      setPerValue(p, i, x);
    });
    const all = document.createElement("button");
    all.textContent = "→ all keys";
    all.title = `every ${unit} takes this value (one number again)`;
    all.dataset.perkeyAll = p.name;
    all.addEventListener("click", () => {
      remember();
      state.params[p.name] = perValue(p, i);
      buildParamControls();
      requestEval();
    });
    label.append(range, input, all);
    box.append(label);
  }
}
function buildParamControls() {
  const spec = state.methods.find((m) => m.name === state.method);
  paramControls($("params"), spec, state.params, "param");
  const shapes = perSpecs().map((p) => p.name);
  $("shape-note").textContent = shapes.length
    ? `${shapes.join(", ")}: the controls above set every ${perUnit()} at once; below, the selected ${perUnit()}'s own value`
    : "";
  drawKeyShapes();
  const other = state.methods.find((m) => m.name === state.compare);
  if (other) paramControls($("compare-params"), other, state.compareParams, "compare");
  else $("compare-params").innerHTML = "";
}

// ---- evaluation (one request in flight; the latest change wins) ----------------------------
let inflight = false, pending = null;
function requestEval() {
  perConform();
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
    const jobs = [api("/api/evaluate", body(state.method, state.params)).then((r) => r.json()).then(unpacked)];
    if (state.compare) jobs.push(api("/api/evaluate", body(state.compare, state.compareParams)).then((r) => r.json()).then(unpacked));
    const [res, other] = await Promise.all(jobs);
    window.qsDrawMs.answer = performance.now() - t0;  // the change to the parsed answer
    state.result = res;
    state.other = other || null;
    drawAll();
    const drawn = performance.now();
    queueMicrotask(() => { window.qsDrawMs.uplotCommit = performance.now() - drawn; });  // after uPlot's own
    window.qsEvaluations += 1;
    status(`${res.method}: ${res.t.length} samples, ${state.quats.length} keys`);
    requestAnimationFrame(() => {
      const ms = performance.now() - t0;
      window.qsLatency.push(ms);
      $("latency").textContent = ms.toFixed(0);
    });
  } catch (e) {
    window.qsErrors = (window.qsErrors || 0) + 1;
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
// One uPlot chart, updated in place when its series are the same (labels included: a
// method switch renames the legend), made anew otherwise.
function chart(id, parent, opts, data) {
  const u = plots[id];
  const same = u && u.series.length === opts.series.length && u.series.every((s, k) => s.label === opts.series[k].label);
  if (same) {
    u.setData(data);
    u.setSize({ width: opts.width, height: opts.height });
    return u;
  }
  if (u) u.destroy();
  const div = document.createElement("div");
  div.id = id;
  const old = $(id);
  if (old) old.replaceWith(div); else $(parent).append(div);
  plots[id] = new uPlot(opts, data, div);
  return plots[id];
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
    chart(`plot-${key}`, "plots", {
      title: label, width, height: 150, series, hooks: { draw: [keyLines] },
      axes: [{ label: "time (s)" }, { label, size: 70 }], scales: { x: { time: false } },
    }, data);
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

// ---- graph editor: Euler angles (keys draggable) and ω per axis ------------------------------
const AXIS_COLOURS = ["#d62728", "#2ca02c", "#1f77b4"];
const graph = { drag: null };  // drag: {key, axis, value}
function keyEuler(i) {
  if (graph.drag && graph.drag.key === i) {
    const e = toEulerXYZ(state.quats[i]);
    e[graph.drag.axis] = graph.drag.value;
    return e;
  }
  return toEulerXYZ(state.quats[i]);
}
function drawKeyPoints(u) {
  const ctx = u.ctx;
  ctx.save();
  for (let i = 0; i < state.times.length; i++) {
    const e = keyEuler(i);
    const x = u.valToPos(state.times[i], "x", true);
    for (let k = 0; k < 3; k++) {
      const y = u.valToPos(e[k], "y", true);
      ctx.fillStyle = AXIS_COLOURS[k];
      ctx.strokeStyle = i === state.selected ? "#000" : "#fff";
      ctx.lineWidth = i === state.selected ? 2 : 1;
      ctx.beginPath(); ctx.arc(x, y, 4 * devicePixelRatio, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
    }
  }
  ctx.restore();
}
function drawGraph() {
  const r = state.result;
  const width = Math.max(400, $("views").clientWidth - 20);
  const euler = [[], [], []];
  // an angle wrapping at ±180° is drawn with a gap, not a vertical line across the plot
  let prev = null;
  for (const q of r.quats) {
    const e = toEulerXYZ(q);
    for (let k = 0; k < 3; k++) euler[k].push(prev && Math.abs(e[k] - prev[k]) > 180 ? null : e[k]);
    prev = e;
  }
  const keyRange = (u, lo, hi) => {
    for (let i = 0; i < state.times.length; i++) for (const v of keyEuler(i)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    return [lo - 10, hi + 10];
  };
  const axisSeries = (name) => ["x", "y", "z"].map((a, k) => ({ label: `${name} ${a}`, stroke: AXIS_COLOURS[k], width: 1.3 }));
  const u = chart("graph-euler", "graph", {
    title: "Euler angles xyz (°), keys ● draggable", width, height: 240,
    series: [{ label: "t (s)" }, ...axisSeries("angle")], hooks: { draw: [drawKeyPoints] },
    cursor: { drag: { x: false, y: false } },
    axes: [{ label: "time (s)" }, { label: "degrees", size: 60, space: 18 }], scales: { x: { time: false }, y: { range: keyRange } },
  }, [r.t, ...euler]);
  if (!u.over.dataset.editor) { u.over.dataset.editor = "1"; graphEditor(u); }
  const omega = [0, 1, 2].map((k) => r.omega.map((w) => w[k]));
  chart("graph-omega", "graph", {
    title: "ω per axis, world frame (rad/s)", width, height: 150,
    series: [{ label: "t (s)" }, ...axisSeries("ω")], hooks: { draw: [keyLines] },
    axes: [{ label: "time (s)" }, { label: "rad/s", size: 60, space: 18 }], scales: { x: { time: false } },
  }, [r.t, ...omega]);
  window.qsGraph = { euler: plots["graph-euler"], omega: plots["graph-omega"] };
}
function graphEditor(u) {
  const over = u.over;
  const pos = (ev) => { const b = over.getBoundingClientRect(); return [ev.clientX - b.left, ev.clientY - b.top]; };
  over.addEventListener("pointerdown", (ev) => {
    const plot = plots["graph-euler"];
    const [px, py] = pos(ev);
    let best = null, bestD = 8;
    for (let i = 0; i < state.times.length; i++) {
      const e = toEulerXYZ(state.quats[i]);
      const x = plot.valToPos(state.times[i], "x");
      for (let k = 0; k < 3; k++) {
        const d = Math.hypot(x - px, plot.valToPos(e[k], "y") - py);
        if (d < bestD) { bestD = d; best = { key: i, axis: k, value: e[k] }; }
      }
    }
    if (!best) return;
    ev.preventDefault();
    over.setPointerCapture(ev.pointerId);
    graph.drag = best;
    selectKey(best.key);
  });
  over.addEventListener("pointermove", (ev) => {
    if (!graph.drag) return;
    graph.drag.value = plots["graph-euler"].posToVal(pos(ev)[1], "y");
    graph.drag.moved = true;
    plots["graph-euler"].redraw(false, false);
  });
  const end = () => {
    const d = graph.drag;
    graph.drag = null;
    if (!d || !d.moved) return;
    const e = toEulerXYZ(state.quats[d.key]);
    e[d.axis] = d.value;
    setKey(d.key, fromEulerXYZ(e), state.times[d.key]);
  };
  over.addEventListener("pointerup", end);
  over.addEventListener("pointercancel", () => { graph.drag = null; });
}

// ---- certificate (folded and paged when long), keys, python ----------------------------------
let certPage = 0;
function drawCertificate() {
  const r = state.result;
  const pages = Math.max(1, Math.ceil(r.joints.length / CERT_PAGE));
  certPage = Math.min(certPage, pages - 1);
  const first = certPage * CERT_PAGE;
  const rows = r.joints.slice(first, first + CERT_PAGE).map((j, n) =>
    `<tr><td>${first + n + 1}</td><td>${j.time.toPrecision(6)}</td><td>C${j.order < 0 ? "⁻" : j.order}</td>` +
    j.jumps.map((x) => `<td>${x === null ? "" : x.toExponential(1)}</td>`).join("") + "</tr>");
  const lowest = r.joints.length ? Math.min(...r.joints.map((j) => j.order)) : "–";
  const below = r.joints.filter((j) => r.continuity !== null && j.order < r.continuity).length;
  const old = $("cert-details");
  const open = old ? old.open : r.joints.length <= CERT_OPEN_MAX;
  const pager = pages > 1
    ? `<div class="row" id="cert-pager"><button id="cert-prev">◀</button><span>joints ${first + 1}–${Math.min(first + CERT_PAGE, r.joints.length)} of ${r.joints.length}</span><button id="cert-next">▶</button></div>`
    : "";
  $("certificate").innerHTML =
    `<div id="cert-summary">method ${r.method}: guaranteed C${r.continuity ?? "∞"}, lowest order found C${lowest}` +
    `${below ? `, ${below} joint(s) below the guarantee` : ""}</div>` +
    `<details id="cert-details"${open ? " open" : ""}><summary>${r.joints.length} joints</summary>${pager}` +
    `<table id="cert-table"><tr><th>joint</th><th>time</th><th>order</th><th>jump q</th><th>q'</th><th>q''</th><th>q'''</th></tr>${rows.join("")}</table></details>`;
  if (pages > 1) {
    $("cert-prev").onclick = () => { certPage = Math.max(0, certPage - 1); drawCertificate(); };
    $("cert-next").onclick = () => { certPage = Math.min(pages - 1, certPage + 1); drawCertificate(); };
  }
  $("python").textContent = r.python;
}

function drawKeys() {
  const rows = state.times.map((t, i) => {
    const e = toEulerXYZ(state.quats[i]).map((v) => v.toFixed(2));
    return `<tr class="key${i === state.selected ? " selected" : ""}" data-i="${i}"><td>${i}</td><td>${t.toPrecision(6)}</td><td>${e.join("</td><td>")}</td></tr>`;
  });
  $("keytable").innerHTML = `<table><tr><th>#</th><th>t</th><th>x°</th><th>y°</th><th>z°</th></tr>${rows.join("")}</table>`;
  for (const tr of $("keytable").querySelectorAll("tr.key")) tr.onclick = () => selectKey(Number(tr.dataset.i));
  const sel = $("keytable").querySelector("tr.selected");
  if (sel) sel.scrollIntoView({ block: "nearest" });
}

function fillEditor() {
  const i = state.selected;
  $("editor").hidden = i < 0;
  if (i < 0) return;
  $("ed-index").textContent = String(i);
  $("ed-time").value = state.times[i];
  const e = toEulerXYZ(state.quats[i]);
  ["ed-ex", "ed-ey", "ed-ez"].forEach((id, k) => { $(id).value = e[k].toFixed(6); });
  $("ed-q").value = state.quats[i].map((v) => v.toFixed(9)).join(" ");
}

// Everything that shows the keys (not the curve): table, editor, gizmo, timeline, graph marks.
function refreshKeys() {
  drawKeys();
  fillEditor();
  drawKeyShapes();
  attachGizmo();
  drawTimeline();
  if (plots["graph-euler"]) plots["graph-euler"].redraw(false, false);
}

function selectKey(i) {
  state.selected = i;
  message("");
  refreshKeys();
}

// One key's new value and time (an undoable edit), or a message saying why not.
function setKey(i, q, t) {
  if (!Number.isFinite(t)) return message("time: not a finite number");
  if (i > 0 && !(t > state.times[i - 1])) return message(`time: must be after key ${i - 1} (${state.times[i - 1]})`);
  if (i < state.times.length - 1 && !(t < state.times[i + 1])) return message(`time: must be before key ${i + 1} (${state.times[i + 1]})`);
  if (!q.every(Number.isFinite)) return message("rotation: not finite");
  const n = Math.hypot(...q);
  if (!(n > 1e-12)) return message("quaternion: zero");
  remember();
  // the hemisphere of the key it replaces (q and −q are one rotation)
  const old = state.quats[i], sign = q.reduce((a, v, k) => a + v * old[k], 0) < 0 ? -1 : 1;
  state.quats[i] = q.map((v) => (sign * v) / n);
  state.times[i] = t;
  state.selected = i;
  message("");
  refreshKeys();
  requestEval();
}
const applyEdit = (q) => setKey(state.selected, q, Number($("ed-time").value));

function addKeyAtPlayhead() {
  const r = state.result;
  if (!r) return;
  const s = sampleIndex();
  const t = r.t[s], q = r.quats[s];  // the current curve's value at the playhead
  if (state.times.includes(t)) return message(`add: a key is already at t = ${t}`);
  const k = state.times.findIndex((x) => x > t);
  const at = k < 0 ? state.times.length : k;
  remember();
  state.times.splice(at, 0, t);
  state.quats.splice(at, 0, q.slice());
  perInsert(at);
  state.selected = at;
  message(`added key ${at} at t = ${t.toPrecision(6)}`);
  refreshKeys();
  requestEval();
}

function deleteKey() {
  const i = state.selected;
  if (i < 0) return message("delete: select a key first");
  if (state.times.length <= 2) return message("delete: a design keeps at least 2 keys");
  remember();
  state.times.splice(i, 1);
  state.quats.splice(i, 1);
  perDelete(i);
  state.selected = Math.min(i, state.times.length - 1);
  message(`deleted key ${i}`);
  refreshKeys();
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

// ---- timeline: keys in time, the playhead ------------------------------------------------------
const timeline = { drag: null, margin: 12 };
function timeSpan() {
  const r = state.result;
  let a = state.times[0], b = state.times[state.times.length - 1];
  if (r) { a = Math.min(a, r.domain[0]); b = Math.max(b, r.domain[1]); }
  if (timeline.drag) [a, b] = timeline.drag.span;  // the scale holds still while dragging
  return [a, b];
}
function timeToX(t) {
  const c = $("timeline"), [a, b] = timeSpan(), m = timeline.margin;
  return m + ((t - a) / (b - a || 1)) * (c.clientWidth - 2 * m);
}
function xToTime(x) {
  const c = $("timeline"), [a, b] = timeSpan(), m = timeline.margin;
  return a + ((x - m) / (c.clientWidth - 2 * m)) * (b - a);
}
function sampleIndex() {
  const r = state.result;
  return Math.min(r.t.length - 1, Math.max(0, Math.round(state.phase * (r.t.length - 1))));
}
function drawTimeline() {
  const c = $("timeline");
  const w = Math.max(400, $("views").clientWidth - 20);
  if (c.width !== Math.round(w * devicePixelRatio)) {
    c.style.width = `${w}px`; c.style.height = "56px";
    c.width = Math.round(w * devicePixelRatio); c.height = Math.round(56 * devicePixelRatio);
  }
  const ctx = c.getContext("2d");
  ctx.setTransform(devicePixelRatio, 0, 0, devicePixelRatio, 0, 0);
  ctx.clearRect(0, 0, w, 56);
  ctx.fillStyle = "#f3f4f7"; ctx.fillRect(0, 0, w, 56);
  ctx.strokeStyle = "#99a"; ctx.beginPath(); ctx.moveTo(timeline.margin, 28); ctx.lineTo(w - timeline.margin, 28); ctx.stroke();
  for (let i = 0; i < state.times.length; i++) {
    const t = timeline.drag && timeline.drag.key === i ? timeline.drag.time : state.times[i];
    const x = timeToX(t), sel = i === state.selected, s = sel ? 7 : 5;
    ctx.fillStyle = timeline.drag && timeline.drag.key === i && timeline.drag.refused ? "#c00" : sel ? "#f0a000" : "#334";
    ctx.beginPath(); ctx.moveTo(x, 28 - s); ctx.lineTo(x + s, 28); ctx.lineTo(x, 28 + s); ctx.lineTo(x - s, 28); ctx.closePath(); ctx.fill();
  }
  if (state.result) {
    const x = timeToX(state.result.t[sampleIndex()]);
    ctx.strokeStyle = "#c00"; ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.moveTo(x, 4); ctx.lineTo(x, 52); ctx.stroke(); ctx.lineWidth = 1;
  }
  const [a, b] = timeSpan();
  ctx.fillStyle = "#555"; ctx.font = "10px system-ui";
  ctx.fillText(`${a.toPrecision(4)} s`, 2, 52);
  ctx.textAlign = "right"; ctx.fillText(`${b.toPrecision(4)} s`, w - 2, 52); ctx.textAlign = "left";
}
function timelineEditor() {
  const c = $("timeline");
  const px = (ev) => ev.clientX - c.getBoundingClientRect().left;
  c.addEventListener("pointerdown", (ev) => {
    const x = px(ev);
    // keys are hit on their line (±10 px); above or below it the click moves the playhead
    const onLine = Math.abs(ev.clientY - c.getBoundingClientRect().top - 28) <= 10;
    let best = -1, bestD = 7;
    if (onLine) state.times.forEach((t, i) => { const d = Math.abs(timeToX(t) - x); if (d < bestD || (d === bestD && i === state.selected)) { bestD = d; best = i; } });
    if (best >= 0) {
      c.setPointerCapture(ev.pointerId);
      timeline.drag = { key: best, time: state.times[best], x0: x, span: timeSpan(), moved: false };
      selectKey(best);
      return;
    }
    if (!state.result) return;  // empty timeline: move the playhead to the nearest sample
    const r = state.result, t = xToTime(x);
    let s = Math.round(((t - r.t[0]) / (r.t[r.t.length - 1] - r.t[0])) * (r.t.length - 1));
    s = Math.min(r.t.length - 1, Math.max(0, s));
    state.phase = s / (r.t.length - 1);
    $("scrub").value = String(Math.round(state.phase * 1000));
    dirty = true;
    drawTimeline();
  });
  c.addEventListener("pointermove", (ev) => {
    const d = timeline.drag;
    if (!d) return;
    const x = px(ev);
    if (!d.moved && Math.abs(x - d.x0) < 2) return;
    d.moved = true;
    const t = xToTime(x);
    const i = d.key, lo = i > 0 ? state.times[i - 1] : -Infinity, hi = i < state.times.length - 1 ? state.times[i + 1] : Infinity;
    // a key never reaches or passes a neighbour: shown stopped there, and refused on release
    d.refused = null;
    if (t <= lo) d.refused = `key ${i} cannot pass key ${i - 1}`;
    else if (t >= hi) d.refused = `key ${i} cannot pass key ${i + 1}`;
    message(d.refused ?? "");
    d.time = Math.min(hi, Math.max(lo, t));
    drawTimeline();
  });
  const end = () => {
    const d = timeline.drag;
    timeline.drag = null;
    if (d && d.moved && !d.refused && d.time !== state.times[d.key]) setKey(d.key, state.quats[d.key], d.time);
    else drawTimeline();
  };
  c.addEventListener("pointerup", end);
  c.addEventListener("pointercancel", () => { timeline.drag = null; drawTimeline(); });
}

// ---- 3D: the body, the gizmo and the sphere --------------------------------------------------
const AXES = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
const COLOURS = [0xd62728, 0x2ca02c, 0x1f77b4];
function makeRenderer(canvas) {
  const r = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  r.setClearColor(0xfbfbfd);
  return r;
}
const body = { renderer: null, scene: new THREE.Scene(), camera: new THREE.PerspectiveCamera(40, 4 / 3, 0.1, 100), obj: new THREE.Group(), key: new THREE.Group(), orbit: null, gizmo: null };
const sphere = { renderer: null, scene: new THREE.Scene(), camera: new THREE.PerspectiveCamera(35, 1, 0.1, 100), traces: [], keys: null, marker: [], orbit: null };
window.qsCameras = { body: body.camera, sphere: sphere.camera };  // read by the browser test
function axesObject(length, opacity) {
  const g = new THREE.Group();
  AXES.forEach((a, k) => {
    const geo = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(0, 0, 0), new THREE.Vector3(...a).multiplyScalar(length)]);
    g.add(new THREE.Line(geo, new THREE.LineBasicMaterial({ color: COLOURS[k], transparent: opacity < 1, opacity })));
  });
  return g;
}
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
  body.obj.add(axesObject(1.1, 1));
  body.scene.add(body.obj);
  body.scene.add(new THREE.AxesHelper(0.4));
  // the selected key: a wire box with its axes, rotated by the gizmo
  body.key.add(new THREE.LineSegments(new THREE.EdgesGeometry(new THREE.BoxGeometry(1.2, 0.6, 0.25)),
    new THREE.LineBasicMaterial({ color: 0xf0a000 })));
  body.key.add(axesObject(1.3, 0.6));
  body.key.visible = false;
  body.scene.add(body.key);
  // the gizmo first: its pointer handlers run before the orbit's
  body.gizmo = new TransformControls(body.camera, $("body3d"));
  body.gizmo.setMode("rotate");
  body.gizmo.setSpace("world");
  body.gizmo.setRotationSnap(THREE.MathUtils.degToRad(GIZMO_SNAP_DEG));
  body.scene.add(body.gizmo.getHelper());
  window.qsGizmo = body.gizmo;  // read by the browser test
  let before = null;
  body.gizmo.addEventListener("dragging-changed", (e) => {
    body.orbit.enabled = !e.value;
    if (e.value) { before = body.key.quaternion.clone(); return; }
    const q = body.key.quaternion;  // three.js (x, y, z, w)
    if (state.selected >= 0 && before && !q.equals(before)) setKey(state.selected, [q.w, q.x, q.y, q.z], state.times[state.selected]);
  });
  body.gizmo.addEventListener("change", () => { dirty = true; });
  body.orbit = new OrbitControls(body.camera, $("body3d"));
  sphere.orbit = new OrbitControls(sphere.camera, $("sphere3d"));
  for (const o of [body.orbit, sphere.orbit]) { o.addEventListener("change", () => { dirty = true; }); o.update(); }
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
function attachGizmo() {
  const i = state.selected;
  if (i < 0 || i >= state.quats.length) {
    body.key.visible = false;
    body.gizmo.detach();
  } else {
    const [w, x, y, z] = state.quats[i];
    body.key.quaternion.set(x, y, z, w);
    body.key.visible = true;
    body.gizmo.attach(body.key);
  }
  dirty = true;
}
// Where a point of a gizmo ring is on the page (for the browser test to aim at): the ring of
// rotations about world axis "X", "Y" or "Z", at angle `deg` around it.
window.qsGizmoRingPoint = (axis, deg) => {
  const cam = body.camera, c = body.key.position;
  const factor = c.distanceTo(cam.position) * Math.min(1.9 * Math.tan(Math.PI * cam.fov / 360) / cam.zoom, 7);
  const r = 0.5 * factor * body.gizmo.size / 4, a = THREE.MathUtils.degToRad(deg);
  const p = { X: [0, Math.cos(a), Math.sin(a)], Y: [Math.cos(a), 0, Math.sin(a)], Z: [Math.cos(a), Math.sin(a), 0] }[axis];
  const v = new THREE.Vector3(...p).multiplyScalar(r).add(c).project(cam);
  const b = $("body3d").getBoundingClientRect();
  return [b.left + ((v.x + 1) / 2) * b.width, b.top + ((1 - v.y) / 2) * b.height];
};
function drawTraces() {
  for (const t of sphere.traces) { sphere.scene.remove(t); t.geometry.dispose(); t.material.dispose(); }
  sphere.traces = [];
  const r = state.result;
  // thinned: at most MAX_TRACE points per trace and MAX_KEY_DOTS key marks (every k-th key)
  const qs = r.quats.filter((_, i) => i % Math.ceil(r.quats.length / MAX_TRACE) === 0 || i === r.quats.length - 1);
  const keyStep = Math.ceil(r.key_quats.length / MAX_KEY_DOTS);
  const keys = r.key_quats.filter((_, i) => i % keyStep === 0);
  const faint = r.key_quats.length > 100;
  AXES.forEach((a, k) => {
    const pts = qs.map((q) => new THREE.Vector3(...rotate(q, a)));
    const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints(pts),
      new THREE.LineBasicMaterial({ color: COLOURS[k], transparent: faint, opacity: faint ? 0.55 : 1 }));
    sphere.traces.push(line);
    sphere.scene.add(line);
    const keyPts = keys.map((q) => new THREE.Vector3(...rotate(q, a)));
    const dots = new THREE.Points(new THREE.BufferGeometry().setFromPoints(keyPts), new THREE.PointsMaterial({ color: 0x000000, size: faint ? 4 : 6, sizeAttenuation: false }));
    sphere.traces.push(dots);
    sphere.scene.add(dots);
  });
  window.qsSphere = { tracePoints: qs.length, keyDots: keys.length, keyStep };
}
function poseAt() {
  const r = state.result;
  if (!r) return null;
  const i = sampleIndex();
  return { q: r.quats[i], t: r.t[i] };
}
let dirty = true;  // the 3D views are drawn only when something changed (software GL is slow)
function render() {
  dirty = false;
  const p = poseAt();
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
    drawTimeline();
  }
  last = now;
  if (state.playing || dirty) { const t0 = performance.now(); render(); window.qsDrawMs.render3d = performance.now() - t0; }
  requestAnimationFrame(tick);
}

window.qsDrawMs = {};  // the last redraw's time per part (read by benchmarks/viewer_latency.py)
function drawAll() {
  for (const [name, draw] of [["plots", drawPlots], ["graph", drawGraph], ["certificate", drawCertificate], ["sphere", drawTraces], ["timeline", drawTimeline]]) {
    const t0 = performance.now();
    draw();
    window.qsDrawMs[name] = performance.now() - t0;
  }
  dirty = true;  // the next animation frame redraws the 3D views
}

// ---- keyboard: undo, redo, delete ------------------------------------------------------------
function onKey(ev) {
  const typing = ev.target instanceof HTMLInputElement && ev.target.type === "text";
  if ((ev.ctrlKey || ev.metaKey) && ev.key.toLowerCase() === "z" && !typing) {
    ev.preventDefault();
    if (ev.shiftKey) restore(state.redo, state.undo); else restore(state.undo, state.redo);
  } else if ((ev.ctrlKey || ev.metaKey) && ev.key.toLowerCase() === "y" && !typing) {
    ev.preventDefault();
    restore(state.redo, state.undo);
  } else if (ev.key === "Delete" && !(ev.target instanceof HTMLInputElement)) {
    deleteKey();
  }
}

// ---- start -----------------------------------------------------------------------------------
async function main() {
  initScenes();
  timelineEditor();
  const s = await (await api("/api/state")).json();
  state.quats = s.quats; state.times = s.times; state.methods = s.methods;
  $("source").textContent = s.name;
  for (const m of s.methods) {
    $("method").add(new Option(`${m.name} (${m.continuity})`, m.name));
    $("compare").add(new Option(m.name, m.name));
  }
  $("method").value = "c3";
  $("method").onchange = () => {
    remember();
    state.method = $("method").value; state.params = {};
    buildParamControls(); requestEval();
  };
  $("compare").onchange = () => {
    remember();
    state.compare = $("compare").value; state.compareParams = {};
    buildParamControls(); requestEval();
  };
  $("samples").onchange = requestEval;
  buildParamControls();
  $("undo").onclick = () => restore(state.undo, state.redo);
  $("redo").onclick = () => restore(state.redo, state.undo);
  $("add-key").onclick = addKeyAtPlayhead;
  $("delete-key").onclick = deleteKey;
  document.addEventListener("keydown", onKey);
  $("save").onclick = () => download("keys", { quats: state.quats, times: state.times, method: state.method }, "keys.json");
  $("ed-apply-euler").onclick = () => applyEdit(fromEulerXYZ(["ed-ex", "ed-ey", "ed-ez"].map((id) => Number($(id).value))));
  $("ed-apply-q").onclick = () => applyEdit($("ed-q").value.trim().split(/[\s,]+/).map(Number));
  for (const b of document.querySelectorAll("button[data-export]")) {
    const fmt = b.dataset.export;
    b.onclick = () => download(fmt, { method: state.method, params: state.params, quats: state.quats, times: state.times, samples: Number($("samples").value) }, `design.${fmt === "glb" ? "glb" : fmt}`);
  }
  $("play").onclick = () => { state.playing = !state.playing; $("play").textContent = state.playing ? "pause" : "play"; };
  $("scrub").oninput = () => { state.phase = Number($("scrub").value) / 1000; dirty = true; drawTimeline(); };
  refreshKeys();
  requestEval();
  requestAnimationFrame(tick);
}
main().catch((e) => status(`error: ${e.message}`, true));
