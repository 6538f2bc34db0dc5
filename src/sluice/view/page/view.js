// The page of `sluice view`: the frames drawn with WebGL (2D, and 3D with an orbiting camera), a time
// slider, the probe and body series, the diagnostics, and in live mode the run's controls. Plain
// JavaScript, no libraries: everything it needs comes from the sluice server.
"use strict";

const params = new URLSearchParams(location.search);
const token = params.get("token") || "";
const $ = (id) => document.getElementById(id);
const api = (path) => path + (token ? (path.includes("?") ? "&" : "?") + "token=" + encodeURIComponent(token) : "");

const state = {
  run: null, frames: [], current: -1, field: "speed", colormaps: null, cache: new Map(),
  shown: null, range: null, bounds: null, camera: { azimuth: -0.9, elevation: 0.45, distance: 1.7, pan: [0, 0] },
  playing: false, loading: false, wanted: -1, drawn: 0,
};

// ---- WebGL -------------------------------------------------------------------------------------

const canvas = $("gl");
// The drawing buffer is not kept after it is shown (keeping it costs a copy a frame): what reads its
// pixels draws first, in the same task (report).
const gl = canvas.getContext("webgl", { preserveDrawingBuffer: false, antialias: false, alpha: false });
const vertexShader = `
attribute vec3 position; attribute float value; attribute float kind;
uniform mat4 matrix; uniform float size; uniform float perspective; uniform float lo; uniform float hi;
varying float t; varying float wall;
void main() {
  gl_Position = matrix * vec4(position, 1.0);
  gl_PointSize = max(1.5, size / mix(1.0, gl_Position.w, perspective));
  t = clamp((value - lo) / max(hi - lo, 1e-30), 0.0, 1.0);
  wall = kind;
}`;
const fragmentShader = `
precision mediump float;
varying float t; varying float wall;
uniform sampler2D colormap; uniform float wallAlpha; uniform float pass;
void main() {
  vec2 c = gl_PointCoord - 0.5;
  if (dot(c, c) > 0.25) discard;
  if ((pass == 1.0 && wall > 0.5) || (pass == 2.0 && wall < 0.5)) discard;
  if (wall > 0.5) { float g = wall > 1.5 ? 0.45 : 0.6; gl_FragColor = vec4(g, g, g, wallAlpha); }
  else gl_FragColor = vec4(texture2D(colormap, vec2(t, 0.5)).rgb, 1.0);
}`;

function compile(type, source) {
  const s = gl.createShader(type);
  gl.shaderSource(s, source);
  gl.compileShader(s);
  if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
  return s;
}
const program = gl.createProgram();
gl.attachShader(program, compile(gl.VERTEX_SHADER, vertexShader));
gl.attachShader(program, compile(gl.FRAGMENT_SHADER, fragmentShader));
gl.linkProgram(program);
const loc = {};
for (const n of ["position", "value", "kind"]) loc[n] = gl.getAttribLocation(program, n);
for (const n of ["matrix", "size", "perspective", "lo", "hi", "colormap", "wallAlpha", "pass"]) loc[n] = gl.getUniformLocation(program, n);
const buffers = { position: gl.createBuffer(), value: gl.createBuffer(), kind: gl.createBuffer() };
const texture = gl.createTexture();

function setColormap(name) {
  const table = state.colormaps[name];
  const bytes = new Uint8Array(256 * 4);
  table.forEach((c, k) => bytes.set([c[0], c[1], c[2], 255], 4 * k));
  gl.bindTexture(gl.TEXTURE_2D, texture);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA, 256, 1, 0, gl.RGBA, gl.UNSIGNED_BYTE, bytes);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
}

// Column-major 4x4 matrices.
function multiply(a, b) {
  const r = new Float32Array(16);
  for (let i = 0; i < 4; i++) for (let j = 0; j < 4; j++) {
    let s = 0;
    for (let k = 0; k < 4; k++) s += a[k * 4 + j] * b[i * 4 + k];
    r[i * 4 + j] = s;
  }
  return r;
}

// The matrix from the world to the canvas, and the pixels a particle's spacing covers.
function view(frame) {
  const w = canvas.width, h = canvas.height, b = state.bounds;
  if (frame.dimension === 2) {
    const sx = (b.hi[0] - b.lo[0]), sy = (b.hi[1] - b.lo[1]);
    const scale = 0.96 * Math.min(w / sx, h / sy);  // pixels per metre
    const cx = (b.lo[0] + b.hi[0]) / 2, cy = (b.lo[1] + b.hi[1]) / 2;
    const m = new Float32Array([2 * scale / w, 0, 0, 0, 0, 2 * scale / h, 0, 0, 0, 0, 1, 0,
      -2 * scale * cx / w, -2 * scale * cy / h, 0, 1]);
    return { matrix: m, size: frame.dx * scale, perspective: 0 };
  }
  // 3D: z up; the camera orbits the box's centre at `distance` box sizes.
  const c = state.camera, size = Math.hypot(b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]);
  const target = [(b.lo[0] + b.hi[0]) / 2, (b.lo[1] + b.hi[1]) / 2, (b.lo[2] + b.hi[2]) / 2];
  const d = c.distance * size;
  const eye = [target[0] + d * Math.cos(c.elevation) * Math.cos(c.azimuth),
    target[1] + d * Math.cos(c.elevation) * Math.sin(c.azimuth), target[2] + d * Math.sin(c.elevation)];
  const f = norm(sub(target, eye)), s = norm(cross(f, [0, 0, 1])), u = cross(s, f);
  const lookAt = new Float32Array([s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
    -dot(s, eye) + c.pan[0] * size, -dot(u, eye) + c.pan[1] * size, dot(f, eye), 1]);
  const fov = 0.6, near = d * 0.05, far = d * 4, aspect = w / h, k = 1 / Math.tan(fov / 2);
  const proj = new Float32Array([k / aspect, 0, 0, 0, 0, k, 0, 0, 0, 0, (far + near) / (near - far), -1,
    0, 0, 2 * far * near / (near - far), 0]);
  return { matrix: multiply(proj, lookAt), size: frame.dx * k * h / 2, perspective: 1 };
}
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const norm = (a) => { const l = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / l, a[1] / l, a[2] / l]; };

function upload(frame) {
  gl.bindBuffer(gl.ARRAY_BUFFER, buffers.position);
  gl.bufferData(gl.ARRAY_BUFFER, frame.position, gl.DYNAMIC_DRAW);
  gl.bindBuffer(gl.ARRAY_BUFFER, buffers.value);
  gl.bufferData(gl.ARRAY_BUFFER, frame.value, gl.DYNAMIC_DRAW);
  gl.bindBuffer(gl.ARRAY_BUFFER, buffers.kind);
  gl.bufferData(gl.ARRAY_BUFFER, frame.kind, gl.DYNAMIC_DRAW);
}

function draw() {
  if (!state.shown) return;
  drawScene();
  state.drawn++;
  report();
}

function drawScene() {
  const frame = state.shown;
  const dpr = window.devicePixelRatio || 1;
  const w = Math.round(canvas.clientWidth * dpr), h = Math.round(canvas.clientHeight * dpr);
  if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
  gl.viewport(0, 0, w, h);
  gl.clearColor(1, 1, 1, 1);
  gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
  gl.useProgram(program);
  const v = view(frame);
  gl.uniformMatrix4fv(loc.matrix, false, v.matrix);
  gl.uniform1f(loc.size, v.size * dpr / dpr);
  gl.uniform1f(loc.perspective, v.perspective);
  gl.uniform1f(loc.lo, state.range[0]);
  gl.uniform1f(loc.hi, state.range[1]);
  gl.uniform1i(loc.colormap, 0);
  gl.activeTexture(gl.TEXTURE0);
  gl.bindTexture(gl.TEXTURE_2D, texture);
  const dims = frame.dimension;
  gl.bindBuffer(gl.ARRAY_BUFFER, buffers.position);
  gl.enableVertexAttribArray(loc.position);
  gl.vertexAttribPointer(loc.position, dims, gl.FLOAT, false, 0, 0);
  gl.bindBuffer(gl.ARRAY_BUFFER, buffers.value);
  gl.enableVertexAttribArray(loc.value);
  gl.vertexAttribPointer(loc.value, 1, gl.FLOAT, false, 0, 0);
  gl.bindBuffer(gl.ARRAY_BUFFER, buffers.kind);
  gl.enableVertexAttribArray(loc.kind);
  gl.vertexAttribPointer(loc.kind, 1, gl.UNSIGNED_BYTE, false, 0, 0);
  // 2D: every particle opaque, in one pass. 3D: the water with depth first, then the walls faint over
  // it without writing depth (so that no wall hides the water behind it).
  gl.enable(gl.BLEND);
  gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
  if (dims === 3) {
    gl.enable(gl.DEPTH_TEST);
    gl.uniform1f(loc.wallAlpha, 0.06);
    gl.uniform1f(loc.pass, 1);
    gl.depthMask(true);
    gl.drawArrays(gl.POINTS, 0, frame.n);
    gl.uniform1f(loc.pass, 2);
    gl.depthMask(false);
    gl.drawArrays(gl.POINTS, 0, frame.n);
    gl.depthMask(true);
  } else {
    gl.disable(gl.DEPTH_TEST);
    gl.uniform1f(loc.wallAlpha, 1.0);
    gl.uniform1f(loc.pass, 0);
    gl.drawArrays(gl.POINTS, 0, frame.n);
  }
}

// ---- frames ------------------------------------------------------------------------------------

// A frame, from the page's cache of the last 24 (a request on its way counts: asked twice, fetched once).
function fetchFrame(index, field) {
  const key = index + "/" + field;
  if (state.cache.has(key)) return state.cache.get(key);
  const promise = requestFrame(index, field);
  promise.catch(() => state.cache.delete(key));
  state.cache.set(key, promise);
  if (state.cache.size > 24) state.cache.delete(state.cache.keys().next().value);
  return promise;
}

async function requestFrame(index, field) {
  const response = await fetch(api(`/api/frame/${index}?field=${field}`));
  if (!response.ok) {
    const e = await response.json().catch(() => ({ error: response.statusText }));
    throw new Error(e.error || response.statusText);
  }
  const bytes = await response.arrayBuffer();
  const length = new DataView(bytes).getUint32(0, true);
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(bytes, 4, length)));
  const n = header.n, d = header.dimension;
  let at = 4 + length;
  return Object.assign(header, {
    position: new Float32Array(bytes, at, n * d),
    value: new Float32Array(bytes, at + 4 * n * d, n),
    kind: new Uint8Array(bytes, at + 4 * n * d + 4 * n, n),
  });
}

function boundsOf(frame) {
  const d = frame.dimension, lo = new Array(d).fill(Infinity), hi = new Array(d).fill(-Infinity);
  for (let i = 0; i < frame.n; i++) for (let k = 0; k < d; k++) {
    const x = frame.position[i * d + k];
    if (x < lo[k]) lo[k] = x;
    if (x > hi[k]) hi[k] = x;
  }
  for (let k = 0; k < d; k++) { lo[k] -= frame.dx; hi[k] += frame.dx; }
  return { lo, hi };
}

// Shows frame k: fetched (the latest request wins while one is on its way), drawn, labelled.
async function show(k) {
  state.wanted = k;
  if (state.loading) return;
  state.loading = true;
  try {
    while (state.wanted !== state.current || state.fieldChanged) {
      const want = state.wanted, field = state.field;
      state.fieldChanged = false;
      const entry = state.frames[want];
      if (!entry) break;
      // The next frame the way the slider moves is asked for while this one is drawn.
      const ahead = state.frames[want + (want < state.current ? -1 : 1)];
      const frame = await fetchFrame(entry.index, field);
      if (ahead) fetchFrame(ahead.index, field).catch(() => {});
      if (!state.bounds) state.bounds = boundsOf(frame);
      if (!state.range || state.rangeField !== field) {
        state.range = await runRange(field, frame);
        state.rangeField = field;
        setColormap(frame.colormap);
        drawBar(frame);
      }
      state.current = want;
      state.shown = frame;
      upload(frame);
      draw();
      $("time").textContent = `t = ${frame.time.toFixed(3)} s  (frame ${frame.index}, ${want + 1} of ${state.frames.length})`;
      $("slider").value = want;
      message("");
    }
  } catch (e) {
    message(e.message);
    state.current = state.wanted;
  } finally {
    state.loading = false;
  }
}

// The colour range, fixed for a run once chosen: the water's values in its first, middle and last
// frames (from 0 for magnitudes, symmetric for signed fields).
async function runRange(field, shown) {
  const n = state.frames.length, picks = new Set([0, Math.floor(n / 2), n - 1]);
  let lo = Infinity, hi = -Infinity;
  for (const k of picks) {
    const f = k === state.wanted ? shown : await fetchFrame(state.frames[k].index, field).catch(() => null);
    if (f && f.min !== undefined) { lo = Math.min(lo, f.min); hi = Math.max(hi, f.max); }
  }
  return rangeOf(Object.assign({}, shown, { min: isFinite(lo) ? lo : undefined, max: isFinite(hi) ? hi : undefined }));
}

function rangeOf(frame) {
  let lo = frame.min ?? 0, hi = frame.max ?? 1;
  if (frame.signed) { const m = Math.max(Math.abs(lo), Math.abs(hi)) || 1; return [-m, m]; }
  if (frame.field === "speed") lo = 0;
  if (hi <= lo) hi = lo + 1;
  return [lo, hi];
}

function drawBar(frame) {
  const bar = $("bar"), c = bar.getContext("2d"), table = state.colormaps[frame.colormap];
  const top = 24, bottom = bar.height - 24, x0 = 10, width = 22;
  c.clearRect(0, 0, bar.width, bar.height);
  for (let y = top; y < bottom; y++) {
    const t = 1 - (y - top) / (bottom - top), rgb = table[Math.round(t * 255)];
    c.fillStyle = `rgb(${rgb[0]},${rgb[1]},${rgb[2]})`;
    c.fillRect(x0, y, width, 1);
  }
  c.fillStyle = "#222";
  c.font = "12px system-ui, sans-serif";
  c.fillText(frame.unit, x0, 14);
  for (let k = 0; k <= 4; k++) {
    const v = state.range[0] + (state.range[1] - state.range[0]) * k / 4;
    const y = bottom - (bottom - top) * k / 4;
    c.fillRect(x0 + width, y, 4, 1);
    c.fillText(Math.abs(v) >= 1000 || (Math.abs(v) < 0.01 && v !== 0) ? v.toExponential(1) : v.toFixed(2), x0 + width + 6, y + 4);
  }
  $("hint").textContent = `${frame.title}` + (frame.stride > 1 ? ` — every ${frame.stride}th of ${frame.total} particles shown` : "") +
    (frame.dimension === 3 ? " — drag to turn, wheel to zoom, shift-drag to pan" : "");
}

function message(text) {
  $("message").hidden = !text;
  $("message").textContent = text;
  report();
}

// What the tests read: the frame shown, its time, and how much of the canvas is drawn on (samples of
// every 7th pixel: not white, and in colour, which walls never are). The pixels are read once the
// drawing has rested for 300 ms, so that reading them never slows scrubbing.
let pixelTimer = null;
const pixels = { coloured: 0, water: 0 };
function report() {
  writeStatus();
  clearTimeout(pixelTimer);
  pixelTimer = setTimeout(() => {
    pixels.coloured = 0;
    pixels.water = 0;
    if (state.shown) {
      const w = canvas.width, h = canvas.height, data = new Uint8Array(4 * w * h);
      drawScene();
      gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, data);
      for (let i = 0; i < data.length; i += 4 * 7) {
        const r = data[i], g = data[i + 1], b = data[i + 2];
        if (r < 250 || g < 250 || b < 250) pixels.coloured++;
        if (Math.max(r, g, b) - Math.min(r, g, b) > 40) pixels.water++;
      }
    }
    writeStatus();
  }, 300);
}

function writeStatus() {
  $("status").textContent = JSON.stringify({
    frame: state.shown ? state.shown.index : null, time: state.shown ? state.shown.time : null,
    label: $("time").textContent, frames: state.frames.length, coloured: pixels.coloured, water: pixels.water,
    draws: state.drawn, message: $("message").hidden ? "" : $("message").textContent,
    dimension: state.shown ? state.shown.dimension : null,
    references: [...document.querySelectorAll(".plot")].filter((b) => b.dataset.reference).length,
  });
}

// ---- series and diagnostics ----------------------------------------------------------------------

// A series' columns against time, each on its own vertical scale; a reference (a validation case's
// experiment, dashed grey) shares the scale of the column it is drawn against, and the time axis
// spans both.
function plot(name, table, reference) {
  let box = document.querySelector(`.plot[data-name="${CSS.escape(name)}"]`);
  if (!box) {
    box = document.createElement("div");
    box.className = "plot";
    box.dataset.name = name;
    box.innerHTML = `<div class="name"></div><canvas></canvas>`;
    $("plots").appendChild(box);
  }
  const columns = table.columns.slice(1, 4);
  box.querySelector(".name").textContent = `${name}: ${columns.join(", ")} against ${table.columns[0]}` +
    (reference ? `; dashed: ${reference.label}` : "");
  box.dataset.reference = reference ? reference.label : "";
  const cv = box.querySelector("canvas"), c = cv.getContext("2d");
  cv.width = cv.clientWidth; cv.height = cv.clientHeight;
  c.clearRect(0, 0, cv.width, cv.height);
  const rows = table.rows;
  if (rows.length < 2) return;
  const refColumn = reference ? columns.indexOf(reference.column) : -1;
  let ref = null;
  if (refColumn >= 0 && reference.t.length > 1) {
    const first = rows[0][refColumn + 1];
    const base = reference.from_first_value && first !== null ? first : 0;
    ref = { t: reference.t, v: reference.value.map((v) => v + base) };
  }
  let t0 = rows[0][0], t1 = rows[rows.length - 1][0];
  if (ref) { t0 = Math.min(t0, ref.t[0]); t1 = Math.max(t1, ref.t[ref.t.length - 1]); }
  const xOf = (t) => 4 + (cv.width - 8) * (t - t0) / (t1 - t0 || 1);
  const colours = ["#1f77b4", "#d62728", "#2ca02c"];
  columns.forEach((col, j) => {
    const values = rows.map((r) => r[j + 1]).filter((v) => v !== null && isFinite(v));
    if (!values.length) return;
    let lo = Math.min(...values), hi = Math.max(...values);
    if (ref && j === refColumn) for (const v of ref.v) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    if (hi - lo < 1e-12) { lo -= 1; hi += 1; }
    const yOf = (v) => cv.height - 4 - (cv.height - 8) * (v - lo) / (hi - lo);
    if (ref && j === refColumn) {
      c.strokeStyle = "#777";
      c.setLineDash([4, 3]);
      c.beginPath();
      ref.t.forEach((t, i) => { if (i === 0) c.moveTo(xOf(t), yOf(ref.v[i])); else c.lineTo(xOf(t), yOf(ref.v[i])); });
      c.stroke();
      c.setLineDash([]);
    }
    c.strokeStyle = colours[j];
    c.beginPath();
    rows.forEach((r, i) => {
      if (i === 0) c.moveTo(xOf(r[0]), yOf(r[j + 1])); else c.lineTo(xOf(r[0]), yOf(r[j + 1]));
    });
    c.stroke();
  });
  if (state.shown) {  // the frame shown
    const x = xOf(state.shown.time);
    c.strokeStyle = "#999";
    c.beginPath(); c.moveTo(x, 0); c.lineTo(x, cv.height); c.stroke();
  }
}

async function refreshSeries() {
  const series = await (await fetch(api("/api/series"))).json();
  const references = series.references || [];
  for (const group of ["probes", "bodies"])
    for (const [name, table] of Object.entries(series[group] || {}))
      if (table.rows)
        plot((group === "bodies" ? "body " : "") + name, table,
             references.find((r) => r.group === group && r.series === name));
  const d = await (await fetch(api("/api/diagnostics"))).json();
  if (d.rows && d.rows.length) {
    const last = d.rows[d.rows.length - 1];
    const show = ["time", "step", "dt", "max_speed", "min_density", "max_density", "leaks", "min_particle_distance", "wall_time"];
    $("diagnostics").innerHTML = show.filter((n) => d.columns.includes(n)).map((n) => {
      const v = last[d.columns.indexOf(n)];
      return `<tr><td>${n}</td><td>${typeof v === "number" ? +v.toPrecision(5) : v}</td></tr>`;
    }).join("");
  }
}

// ---- the run, live or finished -------------------------------------------------------------------

async function refreshRun() {
  const run = await (await fetch(api("/api/run"))).json();
  const before = state.frames.length;
  state.run = run;
  state.frames = run.frames;
  $("case").textContent = `${run.case} — ${run.directory}`;
  $("state").textContent = run.live ? (run.paused ? "paused" : "running") : (run.running ? "running" : "finished");
  $("controls").hidden = !(run.live && token);
  $("slider").max = Math.max(0, state.frames.length - 1);
  if (state.frames.length && (state.current < 0 || ($("follow").checked && state.frames.length > before && state.current === before - 1)))
    show(state.frames.length - 1);
  if (!state.frames.length) message("no frames yet");
  return run;
}

async function control(action) {
  const r = await fetch(api(`/api/control/${action}`), { method: "POST", body: "" });
  const answer = await r.json();
  if (!r.ok) message(answer.error);
  refreshRun();
}

async function start() {
  state.colormaps = await (await fetch(api("/api/colormaps"))).json();
  await refreshRun();  // shows the newest frame
  refreshSeries();
  $("slider").addEventListener("input", (e) => { $("follow").checked = false; show(+e.target.value); });
  $("field").addEventListener("change", (e) => { state.field = e.target.value; state.range = null; state.fieldChanged = true; show(state.current); });
  $("play").addEventListener("click", () => {
    state.playing = !state.playing;
    $("play").innerHTML = state.playing ? "&#10074;&#10074;" : "&#9654;";
    const step = () => {
      if (!state.playing) return;
      if (!state.loading) show((state.current + 1) % state.frames.length);
      setTimeout(step, 50);
    };
    step();
  });
  for (const b of document.querySelectorAll("#controls button")) b.addEventListener("click", () => control(b.dataset.action));
  orbit();
  window.addEventListener("resize", draw);
  // A running run: new frames and series as they come.
  setInterval(async () => {
    const r = await refreshRun().catch(() => null);
    if (r && (r.running || r.live)) refreshSeries().catch(() => {});
  }, 1000);
}

// 3D: drag turns the camera, shift-drag pans, the wheel zooms.
function orbit() {
  let last = null;
  canvas.addEventListener("mousedown", (e) => { last = e; });
  window.addEventListener("mouseup", () => { last = null; });
  window.addEventListener("mousemove", (e) => {
    if (!last || !state.shown || state.shown.dimension !== 3) return;
    const dx = (e.clientX - last.clientX) / canvas.clientWidth, dy = (e.clientY - last.clientY) / canvas.clientHeight;
    const c = state.camera;
    if (e.shiftKey) { c.pan[0] += dx; c.pan[1] -= dy; }
    else { c.azimuth -= 3 * dx; c.elevation = Math.max(-1.5, Math.min(1.5, c.elevation + 3 * dy)); }
    last = e;
    draw();
  });
  canvas.addEventListener("wheel", (e) => {
    if (!state.shown || state.shown.dimension !== 3) return;
    e.preventDefault();
    state.camera.distance *= Math.exp(e.deltaY * 0.001);
    draw();
  }, { passive: false });
}

start().catch((e) => message(e.message));
