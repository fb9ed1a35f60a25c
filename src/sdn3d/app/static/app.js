// sdn3d editor page: plain JavaScript on a canvas (no build step). The server owns the scene and draws every
// picture; this page keeps the state (a spec: boxes + ops), its undo history, and draws the objects' 3D boxes
// (projected here, so a dragged or turned box follows the pointer before the server answers).
"use strict";

const $ = (id) => document.getElementById(id);
const canvas = $("view");
const ctx = canvas.getContext("2d");

const app = {
  info: null,        // /api/info
  view: null,        // the server's view of the session (objects, spec, command, camera, ...)
  history: [],       // states {objects, ops} the server accepted; history[index] is shown
  index: -1,
  selected: null,    // instance id
  drag: null,        // {kind: 'move' | 'turn' | 'box', ...}
  implied: null,     // [x0, y0, x1, y1]: the box the last click on a car implied (shown dashed)
  edited: null,      // Image: the current picture
  before: null,      // Image: the input
  labels: null,      // Image: the semantic map (working size)
  inFlight: 0,       // requests running
  pending: null,     // the newest state waiting for the running request (latest wins)
  lastLatencyMs: null,
};
window.sdn3dApp = app;  // the browser tests read the view and wait for idle through it

// -- geometry (KITTI camera frame: x right, y down, z forward; box centre c, dims (l, h, w), yaw ry) -------------

function project(p, cam) {
  if (p[2] <= 0.1) return null;
  return [cam.fx * p[0] / p[2] + cam.cx, cam.fy * p[1] / p[2] + cam.cy];
}

function boxCorners(center, dims, ry) {
  const [l, h, w] = dims, c = Math.cos(ry), s = Math.sin(ry), out = [];
  for (const x of [-0.5, 0.5]) for (const y of [-0.5, 0.5]) for (const z of [-0.5, 0.5]) {
    const px = x * l, py = y * h, pz = z * w;  // R_y(ry) diag(l, h, w) v + c
    out.push([c * px + s * pz + center[0], py + center[1], -s * px + c * pz + center[2]]);
  }
  return out;
}

// the point of the ground plane y = height under pixel (u, v), or null (at or above the horizon)
function groundPoint(u, v, height, cam) {
  const d = [(u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1];
  if (d[1] <= 1e-9) return null;
  const t = height / d[1];
  return t > 0 ? [d[0] * t, d[1] * t, d[2] * t] : null;
}

function handlePoint(obj, ry) {  // the turn handle: in front of the car's nose
  const r = obj.dims[0] / 2 + 0.8;
  return [obj.center[0] + Math.cos(ry) * r, obj.center[1], obj.center[2] - Math.sin(ry) * r];
}

const wrapDeg = (a) => ((a + 180) % 360 + 360) % 360 - 180;
const round1 = (x) => Math.round(x * 10) / 10;

// -- state: every change is a spec the server applies --------------------------------------------------------

const state = () => (app.index >= 0 ? app.history[app.index] : { objects: [], ops: [] });
const clone = (s) => JSON.parse(JSON.stringify(s));

// A new op; the same kind on the same object right after the last op is merged into it (a drag in several steps
// stays one move; turns add up; distance changes multiply), so the spec stays short.
function withOp(op) {
  const next = clone(state()), last = next.ops[next.ops.length - 1];
  if (last && last.op === op.op && last.id === op.id) {
    if (op.op === "move") { last.to = op.to; return next; }
    if (op.op === "rotate") {
      last.ry_deg = round1(wrapDeg(last.ry_deg + op.ry_deg));
      if (last.ry_deg === 0) next.ops.pop();
      return next;
    }
    if (op.op === "zoom") { last.zoom = Math.round(last.zoom * op.zoom * 1e6) / 1e6; return next; }
  }
  next.ops.push(op);
  return next;
}

async function api(method, url, body, type) {
  const init = { method, headers: {} };
  if (body !== undefined) {
    init.body = type ? body : JSON.stringify(body);
    init.headers["Content-Type"] = type || "application/json";
  }
  const response = await fetch(url, init);
  const text = await response.text();
  let data = null;
  try { data = JSON.parse(text); } catch (e) { data = { error: text || response.statusText }; }
  if (!response.ok) {
    const error = new Error(data.error || response.statusText);
    error.data = data;  // e.g. refused_objects: the boxes where no vehicle is (the page offers to add them anyway)
    throw error;
  }
  return data;
}

function loadImage(url) {
  return new Promise((resolve, reject) => {
    const img = new Image();
    img.onload = () => resolve(img);
    img.onerror = () => reject(new Error("could not load " + url));
    img.src = url;
  });
}

function setBusy(delta) {
  app.inFlight += delta;
  $("busy").hidden = app.inFlight === 0;
}

// An error line; `anyway`: a function that does it all the same, offered as a button (an object refused as no
// vehicle is added only when the user says so).
function showError(message, anyway) {
  $("error").hidden = !message;
  $("error-text").textContent = message || "";
  app.anyway = message && anyway ? anyway : null;
  $("anyway").hidden = !app.anyway;
}

// Send a state; on success it becomes history[index + 1] (redo is dropped), on failure nothing changes.
// `started`: when the user let go (performance.now()), for the latency shown.
// `keepImplied`: this state adds the box a click implied (it stays shown); any other state removes it.
async function commit(next, started, historyIndex, keepImplied) {
  if (!app.view) return;
  if (app.inFlight) { app.pending = { next, started, historyIndex, keepImplied }; return; }
  setBusy(1);
  try {
    const view = await api("POST", `/api/s/${app.view.sid}/edit`, next);
    const img = await loadImage(`/api/s/${view.sid}/edited.png?v=${view.version}`);
    app.edited = img;
    if (historyIndex !== undefined) app.index = historyIndex;
    else { app.history = app.history.slice(0, app.index + 1); app.history.push(clone(next)); app.index++; }
    if (!keepImplied) app.implied = null;
    applyView(view);
    app.lastLatencyMs = performance.now() - started;
    const t = view.timings_ms || {};
    $("status").textContent = `picture updated ${Math.round(app.lastLatencyMs)} ms after release` +
      (t.edit_ms !== undefined ? ` (server: edit ${Math.round(t.edit_ms)} ms, draw ${Math.round(t.photo_ms ||
        t.render_ms || 0)} ms)` : "");
    showError(null);
    if (app.labels && $("show-labels").checked) loadLabels();
  } catch (e) {
    const refused = (e.data && e.data.refused_objects) || [];
    if (refused.length) {  // boxes where GrabCut, the road plane or the fit see no vehicle: nothing was added
      if (keepImplied) app.implied = null;
      $("status").textContent = "";
      showError(e.message, () => {
        const forced = clone(next);
        for (const i of refused) forced.objects[i].force = true;
        commit(forced, performance.now(), historyIndex, keepImplied);
      });
    } else showError(e.message);
  } finally {
    setBusy(-1);
    draw();
    if (app.pending) {
      const p = app.pending; app.pending = null; commit(p.next, p.started, p.historyIndex, p.keepImplied);
    }
  }
}

function applyView(view) {
  app.view = view;
  if (app.selected !== null && !objectById(app.selected)) app.selected = null;
  $("spec").textContent = view.spec;
  $("command").textContent = view.command;
  $("warnings").replaceChildren(...(view.warnings || []).map((w) => {
    const line = document.createElement("div");
    line.textContent = w;
    return line;
  }));
  for (const [id, name] of [["dl-spec", "spec.yaml"], ["dl-command", "command.txt"], ["dl-png", "edited.png"],
                            ["dl-json", "edit.json"], ["dl-glb", "edited_scene.glb"]]) {
    $(id).href = `/api/s/${view.sid}/download/${name}?v=${view.version}`;
  }
  $("undo").disabled = app.index <= 0;
  $("reset").disabled = false;
  $("redo").disabled = app.index >= app.history.length - 1;
  legend();
  panel();
}

async function opened(view) {
  // the page shows one image: the one it showed before is closed, so its session does not hold a place on the server
  if (app.view && app.view.sid !== view.sid) api("DELETE", `/api/s/${app.view.sid}`).catch(() => {});
  app.view = null;
  app.history = [clone(view.state)];
  app.index = 0;
  app.selected = null;
  app.labels = null;
  app.implied = null;
  canvas.width = view.input.width;
  canvas.height = view.input.height;
  [app.before, app.edited] = await Promise.all([loadImage(`/api/s/${view.sid}/input.png`),
                                                loadImage(`/api/s/${view.sid}/edited.png?v=${view.version}`)]);
  applyView(view);
  $("status").textContent = `${view.input.name}: ${view.input.width}x${view.input.height}, ` +
    `${(view.objects || []).length} object(s)`;
  showError(null);
  if ($("show-labels").checked) loadLabels();
  draw();
  canvas.focus();
}

async function openUpload(file) {
  const params = new URLSearchParams();
  for (const k of ["fx", "fy", "cx", "cy"]) if ($(k).value !== "") params.set(k, $(k).value);
  params.set("name", file.name);  // shown as the image's name (the server stores the upload as input.png)
  setBusy(1);
  $("status").textContent = "de-rendering " + file.name + "...";
  try {
    await opened(await api("POST", "/api/open?" + params, await file.arrayBuffer(),
                           file.type || "application/octet-stream"));
  } catch (e) { showError(e.message); $("status").textContent = ""; } finally { setBusy(-1); }
}

async function openFrame(index) {
  setBusy(1);
  $("status").textContent = "de-rendering frame " + app.info.frames[index] + "...";
  try { await opened(await api("POST", "/api/open_frame", { frame: index })); }
  catch (e) { showError(e.message); $("status").textContent = ""; } finally { setBusy(-1); }
}

async function loadLabels() {
  if (!app.view) return;
  app.labels = await loadImage(`/api/s/${app.view.sid}/labels.png?v=${app.view.version}`);
  draw();
}

// -- objects ----------------------------------------------------------------------------------------------

const objects = () => (app.view && app.view.objects) || [];
const objectById = (id) => objects().find((o) => o.id === id) || null;

// The outline of an object (its 3D box projected; a 2D box without geometry), as [[u, v], ...] edges.
function outline(obj, center, ry) {
  if (!obj.geometry) {
    if (!obj.box) return [];
    const [x0, y0, x1, y1] = obj.box;
    return [[[x0, y0], [x1, y0]], [[x1, y0], [x1, y1]], [[x1, y1], [x0, y1]], [[x0, y1], [x0, y0]]];
  }
  const pts = boxCorners(center || obj.center, obj.dims, ry === undefined ? obj.ry : ry)
    .map((p) => project(p, app.view.camera));
  const edges = [[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7], [0, 4], [1, 5], [2, 6], [3, 7]];
  return edges.filter(([a, b]) => pts[a] && pts[b]).map(([a, b]) => [pts[a], pts[b]]);
}

function hull(obj) {  // the bounding rectangle of its outline, for picking
  const segments = outline(obj);
  if (!segments.length) return null;
  const xs = segments.flat().map((p) => p[0]), ys = segments.flat().map((p) => p[1]);
  return [Math.min(...xs), Math.min(...ys), Math.max(...xs), Math.max(...ys)];
}

function pick(u, v) {  // the object under (u, v): the nearest (smallest distance) whose outline holds the point
  let best = null;
  for (const obj of objects()) {
    const r = hull(obj);
    if (!r || u < r[0] || u > r[2] || v < r[1] || v > r[3]) continue;
    const d = obj.distance_m === null ? 1e9 : obj.distance_m;
    if (!best || d < best.d) best = { obj, d };
  }
  return best ? best.obj : null;
}

// -- drawing ----------------------------------------------------------------------------------------------

function draw() {
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (!app.view || !app.edited) return;
  ctx.drawImage(app.edited, 0, 0);
  const split = Number($("compare").value) / 100 * canvas.width;
  if (split > 0 && app.before) {
    ctx.drawImage(app.before, 0, 0, split, canvas.height, 0, 0, split, canvas.height);
    ctx.strokeStyle = "#fff"; ctx.lineWidth = 2;
    ctx.beginPath(); ctx.moveTo(split, 0); ctx.lineTo(split, canvas.height); ctx.stroke();
    label("before", split - 60, 18, "#000a"); label("after", split + 8, 18, "#000a");
  }
  if ($("show-labels").checked && app.labels) {
    const f = app.view.frame, [sx, sy] = f.scale, [ox, oy] = f.crop_offset;
    ctx.globalAlpha = 0.45;
    ctx.drawImage(app.labels, ox / sx, oy / sy, app.view.working_size[0] / sx, app.view.working_size[1] / sy);
    ctx.globalAlpha = 1;
  }
  if ($("show-boxes").checked) for (const obj of objects()) drawObject(obj);
  if (app.implied) {  // the box the last click implied
    const [x0, y0, x1, y1] = app.implied;
    ctx.setLineDash([3, 3]); ctx.strokeStyle = "#0ff"; ctx.lineWidth = 2;
    ctx.strokeRect(x0, y0, x1 - x0, y1 - y0); ctx.setLineDash([]);
    label("clicked box", x0, Math.min(canvas.height - 4, y1 + 18), "#0088");  // below: the object's own label is above
  }
  if (app.drag && app.drag.kind === "box" && app.drag.now) {
    const [a, b] = [app.drag.start, app.drag.now];
    ctx.setLineDash([6, 4]); ctx.strokeStyle = "#ff0"; ctx.lineWidth = 2;
    ctx.strokeRect(a[0], a[1], b[0] - a[0], b[1] - a[1]); ctx.setLineDash([]);
  }
}

function label(text, x, y, background) {
  ctx.font = "bold 14px system-ui, sans-serif";
  const w = ctx.measureText(text).width + 8;
  ctx.fillStyle = background || "#000b"; ctx.fillRect(x, y - 15, w, 19);
  ctx.fillStyle = "#fff"; ctx.fillText(text, x + 4, y);
}

function drawObject(obj) {
  const selected = obj.id === app.selected, drag = app.drag && app.drag.id === obj.id ? app.drag : null;
  let center = obj.center, ry = obj.ry;
  if (drag && drag.kind === "move" && drag.center) center = drag.center;
  if (drag && drag.kind === "turn" && drag.ry !== undefined) ry = drag.ry;
  const segments = outline(obj, center, ry);
  ctx.strokeStyle = selected ? "#ffd400" : obj.geometry ? "#35e0ff" : "#ff8c3a";
  ctx.lineWidth = selected ? 3 : 2;
  if (!obj.geometry) ctx.setLineDash([6, 4]);
  ctx.beginPath();
  for (const [a, b] of segments) { ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); }
  ctx.stroke();
  ctx.setLineDash([]);
  if (!segments.length) return;
  const top = Math.min(...segments.flat().map((p) => p[1])), left = Math.min(...segments.flat().map((p) => p[0]));
  const dist = obj.geometry ? (drag && center !== obj.center ? Math.hypot(...center) : obj.distance_m) : null;
  label(`${obj.id} ${obj.class}` + (dist !== null ? ` ${dist.toFixed(1)} m` : ""), left, Math.max(16, top - 4),
        selected ? "#6b5800d0" : "#000b");
  if (selected && obj.geometry) {
    const c = project(center, app.view.camera), h = project(handlePoint(obj, ry), app.view.camera);
    if (c && h) {
      ctx.strokeStyle = "#ffd400"; ctx.lineWidth = 2;
      ctx.beginPath(); ctx.moveTo(c[0], c[1]); ctx.lineTo(h[0], h[1]); ctx.stroke();
      ctx.fillStyle = "#ffd400"; ctx.beginPath(); ctx.arc(h[0], h[1], 8, 0, 2 * Math.PI); ctx.fill();
      ctx.beginPath(); ctx.arc(c[0], c[1], 4, 0, 2 * Math.PI); ctx.fill();
      const deg = ry * 180 / Math.PI;
      label(`${deg.toFixed(1)}\u00b0` + (drag && drag.kind === "turn" ? ` (${drag.delta >= 0 ? "+" : ""}` +
            `${drag.delta.toFixed(1)}\u00b0)` : ""), h[0] + 10, h[1] + 5, "#6b5800d0");
    }
  }
}

function legend() {
  const box = $("legend");
  box.innerHTML = "";
  if (!$("show-labels").checked || !app.view) return;
  if (app.view.labels_note) {
    const note = document.createElement("div");
    note.className = "note";
    note.textContent = app.view.labels_note;
    box.append(note);
  }
  for (const c of app.view.classes.filter((c) => (app.view.present_classes || []).includes(c.id))) {
    const span = document.createElement("span");
    span.innerHTML = `<i style="background: rgb(${c.color.join(",")})"></i>`;
    span.append(c.name);
    box.append(span);
  }
}

function panel() {
  const obj = app.selected === null ? null : objectById(app.selected);
  $("selected").hidden = !obj;
  $("nothing").hidden = !!obj;
  if (!obj) return;
  $("sel-title").textContent = `${obj.id} ${obj.class}`;
  $("sel-facts").textContent = obj.geometry
    ? `centre (${obj.centre.map(round1).join(", ")}) px, ${obj.distance_m} m, template ${obj.template}`
    : "no 3D geometry (mask only): it can be deleted or recoloured";
  $("yaw").textContent = obj.geometry ? `yaw ${obj.yaw_deg}\u00b0` : "";
  $("distance").value = obj.geometry ? obj.distance_m : "";
  for (const el of document.querySelectorAll("[data-turn], #distance, #closer, #farther, #duplicate")) {
    el.disabled = !obj.geometry;
  }
}

// -- actions ----------------------------------------------------------------------------------------------

function act(op) { commit(withOp(op), performance.now()); }
function turn(id, degrees) { act({ op: "rotate", id, ry_deg: round1(degrees) }); }
function zoomTo(obj, distance) {
  if (!(distance > 0)) return;
  act({ op: "zoom", id: obj.id, zoom: Math.round(obj.distance_m / distance * 1e6) / 1e6, on_ground: true });
}
function duplicate(obj) {
  const to = [round1(obj.centre[0] + 0.08 * canvas.width * (obj.centre[0] < canvas.width / 2 ? 1 : -1)),
              round1(obj.centre[1])];
  act({ op: "duplicate", id: obj.id, to });
}

// A click on a car: the server finds the box it implies (road-plane size, GrabCut); the page shows that box, dashed,
// and adds it as an object, which the next edit fits like a drawn one.
async function addByClick(u, v) {
  $("add-click").classList.remove("active");
  $("status").textContent = "finding the object under the click...";
  setBusy(1);
  let found;
  try {
    found = await api("POST", `/api/s/${app.view.sid}/box_at`, { u: round1(u), v: round1(v) });
  } catch (e) { showError(e.message); $("status").textContent = ""; return; } finally { setBusy(-1); }
  const box = found.box;
  const add = (force) => {
    app.implied = box;
    draw();
    const next = clone(state());
    next.objects.push(force ? { box, class: "Car", force: true } : { box, class: "Car" });
    $("status").textContent = `the click implies the box [${box.join(", ")}]; fitting it (GrabCut mask, 3D fit)...`;
    showError(null);
    return commit(next, performance.now(), undefined, true);
  };
  if (found.refused) {  // nothing is added unless the user says so
    $("status").textContent = "";
    showError(`${found.refused}. Nothing was added.`, () => add(true));
    return;
  }
  await add(false);
}

function undo() { if (app.index > 0) commit(app.history[app.index - 1], performance.now(), app.index - 1); }
function redo() {
  if (app.index < app.history.length - 1) commit(app.history[app.index + 1], performance.now(), app.index + 1);
}

function pointer(event) {  // canvas pixels = the input image's pixels
  const r = canvas.getBoundingClientRect();
  return [(event.clientX - r.left) * canvas.width / r.width, (event.clientY - r.top) * canvas.height / r.height];
}

canvas.addEventListener("mousedown", (event) => {
  if (!app.view || event.button !== 0) return;
  canvas.focus();
  const [u, v] = pointer(event);
  if (event.shiftKey || $("add-box").classList.contains("active")) {
    app.drag = { kind: "box", start: [u, v], now: null };
    return;
  }
  if (event.altKey || $("add-click").classList.contains("active")) {
    event.preventDefault();
    addByClick(u, v);
    return;
  }
  const sel = app.selected === null ? null : objectById(app.selected);
  if (sel && sel.geometry) {
    const h = project(handlePoint(sel, sel.ry), app.view.camera);
    if (h && Math.hypot(h[0] - u, h[1] - v) < 14) {
      const g = groundPoint(u, v, sel.center[1], app.view.camera);
      if (g) {
        app.drag = { kind: "turn", id: sel.id, a0: Math.atan2(-(g[2] - sel.center[2]), g[0] - sel.center[0]),
                     ry: sel.ry, delta: 0 };
        return;
      }
    }
  }
  const obj = pick(u, v);
  app.selected = obj ? obj.id : null;
  if (obj && obj.geometry && obj.centre) app.drag = { kind: "move", id: obj.id, start: [u, v], moved: false };
  panel();
  draw();
});

window.addEventListener("mousemove", (event) => {
  const drag = app.drag;
  if (!drag || !app.view) return;
  const [u, v] = pointer(event);
  if (drag.kind === "box") drag.now = [u, v];
  else if (drag.kind === "move") {
    const obj = objectById(drag.id);
    if (Math.hypot(u - drag.start[0], v - drag.start[1]) > 3) drag.moved = true;
    if (drag.moved && obj) {  // the 3D centre follows the pointer on the object's ground plane
      drag.to = [round1(obj.centre[0] + u - drag.start[0]), round1(obj.centre[1] + v - drag.start[1])];
      drag.center = groundPoint(drag.to[0], drag.to[1], obj.center[1], app.view.camera) || drag.center;
    }
  } else if (drag.kind === "turn") {
    const obj = objectById(drag.id), g = obj && groundPoint(u, v, obj.center[1], app.view.camera);
    if (g) {
      const a = Math.atan2(-(g[2] - obj.center[2]), g[0] - obj.center[0]);
      drag.delta = round1(wrapDeg((a - drag.a0) * 180 / Math.PI));
      drag.ry = obj.ry + drag.delta * Math.PI / 180;
    }
  }
  draw();
});

window.addEventListener("mouseup", () => {
  const drag = app.drag;
  app.drag = null;
  if (!drag) return;
  const released = performance.now();
  if (drag.kind === "move" && drag.moved && drag.to) commit(withOp({ op: "move", id: drag.id, to: drag.to }), released);
  else if (drag.kind === "turn" && drag.delta) commit(withOp({ op: "rotate", id: drag.id, ry_deg: drag.delta }),
                                                      released);
  else if (drag.kind === "box" && drag.now) {
    const [a, b] = [drag.start, drag.now];
    const box = [Math.min(a[0], b[0]), Math.min(a[1], b[1]), Math.max(a[0], b[0]), Math.max(a[1], b[1])]
      .map((x) => Math.round(x));
    if (box[2] - box[0] >= 4 && box[3] - box[1] >= 4) {
      const next = clone(state());
      next.objects.push({ box, class: "Car" });
      $("status").textContent = "fitting the new object (GrabCut mask, 3D fit)...";
      commit(next, released);
    }
    $("add-box").classList.remove("active");
  }
  draw();
});

canvas.addEventListener("keydown", (event) => {
  if ((event.ctrlKey || event.metaKey) && event.key.toLowerCase() === "z") {
    event.preventDefault(); if (event.shiftKey) redo(); else undo(); return;
  }
  if ((event.ctrlKey || event.metaKey) && event.key.toLowerCase() === "y") { event.preventDefault(); redo(); return; }
  const obj = app.selected === null ? null : objectById(app.selected);
  if (event.key === "Escape") { app.selected = null; panel(); draw(); return; }
  if (!obj) return;
  const step = event.shiftKey ? 15 : 5, key = event.key.length === 1 ? event.key.toLowerCase() : event.key;
  if (key === "Delete" || key === "Backspace") act({ op: "delete", id: obj.id });
  else if (!obj.geometry) return;
  else if (key === "q" || key === "ArrowLeft") turn(obj.id, step);
  else if (key === "e" || key === "ArrowRight") turn(obj.id, -step);
  else if (key === "d") duplicate(obj);
  else if (key === "+" || key === "=" || key === "ArrowUp") zoomTo(obj, obj.distance_m / 1.1);
  else if (key === "-" || key === "_" || key === "ArrowDown") zoomTo(obj, obj.distance_m * 1.1);
  else return;
  event.preventDefault();
});

$("file").addEventListener("change", () => { if ($("file").files.length) openUpload($("file").files[0]); });
$("frames").addEventListener("change", () => { if ($("frames").value !== "") openFrame(Number($("frames").value)); });
$("anyway").addEventListener("click", () => { const f = app.anyway; showError(null); if (f) f(); });
$("undo").addEventListener("click", undo);
$("redo").addEventListener("click", redo);
$("reset").addEventListener("click", () => { if (app.view) commit({ objects: [], ops: [] }, performance.now()); });
$("add-box").addEventListener("click", () => $("add-box").classList.toggle("active"));
$("add-click").addEventListener("click", () => $("add-click").classList.toggle("active"));
$("compare").addEventListener("input", draw);
$("show-boxes").addEventListener("change", draw);
$("show-labels").addEventListener("change", () => { legend(); if ($("show-labels").checked) loadLabels(); draw(); });
for (const el of document.querySelectorAll("[data-turn]")) {
  el.addEventListener("click", () => app.selected !== null && turn(app.selected, Number(el.dataset.turn)));
}
$("distance").addEventListener("change", () => {
  const obj = objectById(app.selected);
  if (obj) zoomTo(obj, Number($("distance").value));
});
$("closer").addEventListener("click", () => { const o = objectById(app.selected); if (o) zoomTo(o, o.distance_m / 1.1); });
$("farther").addEventListener("click", () => { const o = objectById(app.selected); if (o) zoomTo(o, o.distance_m * 1.1); });
$("duplicate").addEventListener("click", () => { const o = objectById(app.selected); if (o) duplicate(o); });
$("delete").addEventListener("click", () => app.selected !== null && act({ op: "delete", id: app.selected }));

(async function start() {
  try {
    app.info = await api("GET", "/api/info");
  } catch (e) { showError(e.message); return; }
  for (const c of app.info.palette) {
    const b = document.createElement("button");
    b.title = c.name;
    b.dataset.color = c.name;
    b.style.background = `rgb(${c.rgb.join(",")})`;
    b.addEventListener("click", () => app.selected !== null && act({ op: "recolor", id: app.selected, color: c.name }));
    $("palette").append(b);
  }
  if (app.info.frames.length) {
    $("frames").hidden = false;
    app.info.frames.forEach((key, i) => {
      const o = document.createElement("option");
      o.value = String(i); o.textContent = key; $("frames").append(o);
    });
  }
  const frame = new URLSearchParams(location.search).get("frame");
  if (frame !== null && app.info.frames.length) openFrame(Number(frame));
})();

// a closed or reloaded tab cannot come back to its session: close it, so it does not hold a place on the server
window.addEventListener("pagehide", () => {
  if (app.view) fetch(`/api/s/${app.view.sid}`, { method: "DELETE", keepalive: true }).catch(() => {});
});
window.addEventListener("pageshow", (event) => { if (event.persisted && app.view) location.reload(); });
