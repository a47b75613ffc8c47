// The designer's bench: the controls make scenes, the server solves them
// (docs/serve.md), and the answers are drawn in SVG. Each view keeps only
// the answer to its latest request: a newer request aborts the older one,
// and an answer that is not the latest is dropped.
"use strict";

const SVG = "http://www.w3.org/2000/svg";
const $ = (id) => document.getElementById(id);
const num = (id) => Number($(id).value);

// ------------------------------------------------------------ the scenes

function actuatorKeys() {
  return {
    model: { name: $("model").value },
    actuator: { pemc: { eps0: num("eps0") } },
    partition: { elements: $("partition").value === "auto" ? "auto" : num("elements") },
  };
}

function fingerScene() {
  return { ...actuatorKeys(), load: { pressure_kpa: num("pressure"), kappa: num("kappa") } };
}

function perFinger() {
  return num("weight") / num("fingers");
}

function graspSection() {
  if ($("kind").value === "sphere") {
    return { kind: "sphere", pressure_kpa: num("pressure"), r_mm: num("radius"), lift_n: perFinger(), beta_deg: num("beta") };
  }
  return { kind: "cuboid", pressure_kpa: num("pressure"), d_mm: num("width"), friction_n: perFinger() };
}

function gripperScene(withGrasp) {
  const gripper = { mounting_angle_deg: num("angle"), overlap_mm: num("overlap"), fingers: num("fingers"), mu: num("mu") };
  if (withGrasp) gripper.grasp = graspSection();
  return { ...actuatorKeys(), gripper };
}

// ------------------------------------------------------------ requests

const latest = {};
const inflight = {};
let busy = 0;

function setBusy(delta) {
  busy += delta;
  document.body.dataset.busy = String(busy);
  $("status").textContent = busy > 0 ? "computing" : "up to date";
}

// POSTs `body` to `url` for the view `name`; `done(ok, value)` runs only
// for the latest request of that view.
async function request(name, url, body, done) {
  const seq = (latest[name] = (latest[name] || 0) + 1);
  if (inflight[name]) inflight[name].abort();
  const ctl = new AbortController();
  inflight[name] = ctl;
  setBusy(1);
  try {
    const r = await fetch(url, {
      method: "POST",
      headers: { "content-type": "application/json" },
      body: JSON.stringify(body),
      signal: ctl.signal,
    });
    const v = await r.json();
    if (seq === latest[name]) done(r.ok, v);
  } catch (e) {
    if (e.name !== "AbortError" && seq === latest[name]) {
      done(false, { field: "network", message: String(e) });
    }
  } finally {
    if (inflight[name] === ctl) inflight[name] = null;
    setBusy(-1);
  }
}

// ------------------------------------------------------------ drawing

function el(tag, attrs, parent, text) {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  if (parent) parent.appendChild(e);
  return e;
}

function niceStep(span) {
  const raw = span / 6;
  const p = Math.pow(10, Math.floor(Math.log10(raw)));
  for (const m of [1, 2, 5, 10]) if (m * p >= raw) return m * p;
  return 10 * p;
}

// A plot in `svg`: the ranges [x0, x1] x [y0, y1] (data units), axes with
// ticks and labels; `equal` keeps one scale on both axes (drawn to
// scale); `down` draws y growing downwards. Returns the map to pixels.
function frame(svg, o) {
  svg.replaceChildren();
  const [W, H] = svg.getAttribute("viewBox").split(" ").slice(2).map(Number);
  const m = { l: 48, r: 10, t: 10, b: 36 };
  let [x0, x1, y0, y1] = [o.x0, o.x1, o.y0, o.y1];
  if (!(x1 > x0)) { x0 -= 1; x1 += 1; }
  if (!(y1 > y0)) { y0 -= 1; y1 += 1; }
  let sx = (W - m.l - m.r) / (x1 - x0);
  let sy = (H - m.t - m.b) / (y1 - y0);
  if (o.equal) {
    const s = Math.min(sx, sy);
    const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
    sx = sy = s;
    x0 = cx - (W - m.l - m.r) / s / 2; x1 = cx + (W - m.l - m.r) / s / 2;
    y0 = cy - (H - m.t - m.b) / s / 2; y1 = cy + (H - m.t - m.b) / s / 2;
  }
  const X = (x) => m.l + (x - x0) * sx;
  const Y = o.down ? (y) => m.t + (y - y0) * sy : (y) => H - m.b - (y - y0) * sy;
  const gx = niceStep(x1 - x0), gy = niceStep(y1 - y0);
  for (let t = Math.ceil(x0 / gx) * gx; t <= x1 + 1e-9; t += gx) {
    el("line", { x1: X(t), x2: X(t), y1: m.t, y2: H - m.b, class: "grid" }, svg);
    el("text", { x: X(t), y: H - m.b + 13, "text-anchor": "middle" }, svg, fmt(t));
  }
  for (let t = Math.ceil(y0 / gy) * gy; t <= y1 + 1e-9; t += gy) {
    el("line", { x1: m.l, x2: W - m.r, y1: Y(t), y2: Y(t), class: "grid" }, svg);
    el("text", { x: m.l - 4, y: Y(t) + 4, "text-anchor": "end" }, svg, fmt(t));
  }
  el("rect", { x: m.l, y: m.t, width: W - m.l - m.r, height: H - m.t - m.b, fill: "none", class: "axis" }, svg);
  el("text", { x: (m.l + W - m.r) / 2, y: H - 4, "text-anchor": "middle" }, svg, o.xlabel);
  el("text", { x: 12, y: (m.t + H - m.b) / 2, "text-anchor": "middle", transform: `rotate(-90 12 ${(m.t + H - m.b) / 2})` }, svg, o.ylabel);
  return { X, Y, svg };
}

function fmt(t) {
  const a = Math.abs(t);
  if (a !== 0 && (a < 0.01 || a >= 1e5)) return t.toExponential(1);
  return String(Math.round(t * 1000) / 1000);
}

function path(p, pts, cls) {
  if (pts.length === 0) return null;
  const d = pts.map((q, i) => `${i ? "L" : "M"}${p.X(q[0]).toFixed(2)},${p.Y(q[1]).toFixed(2)}`).join("");
  return el("path", { d, class: cls }, p.svg);
}

function bounds(sets, pad) {
  let [x0, x1, y0, y1] = [Infinity, -Infinity, Infinity, -Infinity];
  for (const s of sets) for (const [x, y] of s) {
    x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
  }
  return { x0: x0 - pad, x1: x1 + pad, y0: y0 - pad, y1: y1 + pad };
}

// The elements a finding names, drawn over the mid-plane `pts` (sampled
// equally per element, root to tip) in red with the element's number.
function markElements(p, pts, v, flip) {
  const n = v.elements;
  const per = Math.round((pts.length - 1) / n);
  const named = new Set(v.warnings.filter((w) => Number.isInteger(w.element)).map((w) => w.element));
  for (const e of named) {
    if (!(e >= 0 && e < n) || per < 1) continue;
    const seg = pts.slice(e * per, (e + 1) * per + 1);
    for (const q of flip ? [seg, mirror(seg)] : [seg]) {
      const mark = path(p, q, "marked");
      if (mark) mark.setAttribute("data-element", String(e));
    }
    const mid = seg[Math.floor(seg.length / 2)];
    if (mid) el("text", { x: p.X(mid[0]) + 6, y: p.Y(mid[1]), class: "note" }, p.svg, `element ${e}`);
  }
}

function note(p, text) {
  el("text", { x: 56, y: 26, class: "note" }, p.svg, text);
}

// ------------------------------------------------------------ the finger

function drawFinger(ok, v) {
  const svg = $("finger-view");
  const list = $("finger-findings");
  if (!ok) {
    const p = frame(svg, { x0: 0, x1: 100, y0: -60, y1: 20, equal: true, xlabel: "X (mm)", ylabel: "Z (mm)" });
    note(p, `no finger: ${v.message}`);
    fill(list, [`${v.field}: ${v.message}`], true);
    return;
  }
  const pts = v.points_mm;
  const b = bounds([pts, [[0, 0]]], 8);
  const p = frame(svg, { ...b, equal: true, xlabel: "X (mm)", ylabel: "Z (mm)" });
  el("line", { x1: p.X(-5), x2: p.X(5), y1: p.Y(0), y2: p.Y(0), class: "palm" }, svg);
  path(p, pts, v.validity ? "held" : "held bad");
  markElements(p, pts, v, false);
  const [tx, tz] = v.tip_mm;
  el("circle", {
    id: "finger-tip", cx: p.X(tx), cy: p.Y(tz), r: 4, class: "tip",
    "data-tip-x-mm": String(tx), "data-tip-z-mm": String(tz),
    "data-eps0": String(v.scene.actuator.pemc.eps0),
  }, svg);
  el("text", { x: p.X(tx) + 6, y: p.Y(tz) - 6 }, svg, `tip (${tx.toFixed(2)}, ${tz.toFixed(2)}) mm`);
  fill(list, v.warning_messages.length ? v.warning_messages : ["none"], v.warning_messages.length > 0);
}

function fill(list, items, bad) {
  list.replaceChildren();
  for (const t of items) {
    const li = document.createElement("li");
    li.textContent = t;
    if (bad) li.className = "finding";
    list.appendChild(li);
  }
}

// ------------------------------------------------------------ the grasp

let lastGrasp = null;

function mirror(pts) {
  return pts.map(([x, z]) => [-x, z]);
}

function drawGrasp(ok, v) {
  const verdict = $("verdict");
  const svg = $("gripper-view");
  const set = (id, x) => { $(id).textContent = x === undefined || x === null ? "" : Number(x).toFixed(3); };
  if (!ok) {
    lastGrasp = null;
    verdict.className = "invalid";
    verdict.textContent = `Not held: ${v.message}`;
    for (const id of ["n-F", "n-f", "n-fmax", "n-fv", "n-d", "n-gap", "n-h"]) set(id, null);
    fill($("findings"), [`${v.field}: ${v.message}`], true);
    const p = frame(svg, { x0: -100, x1: 100, y0: 0, y1: 120, equal: true, down: true, xlabel: "Xg (mm)", ylabel: "Zg (mm, down)" });
    note(p, "no grasp (see the verdict)");
    return;
  }
  lastGrasp = v;
  const g = v.grasp;
  verdict.className = g.valid ? "valid" : "invalid";
  verdict.textContent = g.valid ? "Held: the grasp is valid." : `Not held: ${g.invalid ? g.invalid.message : "invalid"}`;
  set("n-F", g.normal_force_n); set("n-f", g.friction_n); set("n-fmax", g.friction_limit_n);
  set("n-fv", g.lift_n); set("n-d", g.size_mm); set("n-gap", g.tip_gap_mm); set("n-h", g.height_mm);
  fill($("findings"), v.warning_messages.length ? v.warning_messages : ["none"], v.warning_messages.length > 0);

  const rest = v.rest_points_gripper_mm, held = v.points_gripper_mm;
  const palm = v.gripper.palm_mm;
  const objs = [];
  if (g.kind === "sphere") {
    const [cx, cz] = g.sphere_center_gripper_mm, r = g.sphere_radius_mm;
    objs.push([cx - r, cz - r], [cx + r, cz + r]);
  } else {
    const d = g.size_mm;
    objs.push([-d / 2, g.height_mm - d / 2], [d / 2, g.height_mm + d / 2]);
  }
  const b = bounds([rest, mirror(rest), held, mirror(held), objs, [[-palm / 2, 0], [palm / 2, 0]]], 8);
  const p = frame(svg, { ...b, equal: true, down: true, xlabel: "Xg (mm)", ylabel: "Zg (mm, down)" });
  if (g.kind === "sphere") {
    const [cx, cz] = g.sphere_center_gripper_mm;
    el("circle", { cx: p.X(cx), cy: p.Y(cz), r: Math.abs(p.X(cx + g.sphere_radius_mm) - p.X(cx)), class: "object" }, svg);
  } else {
    const d = g.size_mm;
    el("rect", { x: p.X(-d / 2), y: p.Y(g.height_mm - d / 2), width: p.X(d / 2) - p.X(-d / 2), height: p.Y(g.height_mm + d / 2) - p.Y(g.height_mm - d / 2), class: "object" }, svg);
  }
  el("line", { x1: p.X(-palm / 2), x2: p.X(palm / 2), y1: p.Y(0), y2: p.Y(0), class: "palm" }, svg);
  path(p, rest, "rest"); path(p, mirror(rest), "rest");
  const cls = g.valid ? "held" : "held bad";
  path(p, held, cls); path(p, mirror(held), cls);
  markElements(p, held, v, true);
  const [tx, tz] = g.tip_gripper_mm;
  el("circle", { id: "grasp-tip", cx: p.X(tx), cy: p.Y(tz), r: 4, class: "tip", "data-tip-xg-mm": String(tx), "data-tip-zg-mm": String(tz) }, svg);
  if (!g.valid) note(p, `not held: ${g.invalid ? g.invalid.kind : "invalid"}`);
}

// ------------------------------------------------------------ the curves

let lastLift = null;
let lastEnvelope = null;

function drawLift(ok, v) {
  lastLift = ok ? v : null;
  const svg = $("lift-view");
  if (!ok) {
    const p = frame(svg, { x0: 0, x1: 200, y0: 0, y1: 1, xlabel: "grasping size d (mm)", ylabel: "max lift f_v (N per finger)" });
    note(p, `no curve: ${v.message}`);
    return;
  }
  const good = v.points.filter((q) => q.valid).map((q) => [q.size_mm, q.lift_n]);
  const bad = v.points.filter((q) => !q.valid).map((q) => [q.size_mm, q.lift_n]);
  const obj = $("kind").value === "cuboid" ? [num("width"), perFinger()] : null;
  const all = v.points.map((q) => [q.size_mm, q.lift_n]).concat(obj ? [obj] : [], [[0, 0]]);
  const b = bounds([all], 0);
  const p = frame(svg, { x0: 0, x1: b.x1 * 1.05, y0: 0, y1: b.y1 * 1.1, xlabel: "grasping size d (mm)", ylabel: "max lift f_v (N per finger)" });
  path(p, good, "curve");
  for (const [x, y] of bad) el("circle", { cx: p.X(x), cy: p.Y(y), r: 2.5, class: "off" }, svg);
  if (obj) el("circle", { id: "lift-object", cx: p.X(obj[0]), cy: p.Y(obj[1]), r: 5, class: "mark" }, svg);
  if (v.stopped) note(p, `sweep stopped at ${fmt(v.stopped.at)} mm`);
}

function drawEnvelope(ok, v) {
  lastEnvelope = ok ? v : null;
  const svg = $("envelope-view");
  if (!ok) {
    const p = frame(svg, { x0: 0, x1: 100, y0: 0, y1: 1, xlabel: "sphere radius r (mm)", ylabel: "max lift f_v (N per finger)" });
    note(p, `no envelope: ${v.message}`);
    return;
  }
  const pts = v.points.filter((q) => q.best).map((q) => [q.radius_mm, q.best.lift_n]);
  const obj = $("kind").value === "sphere" ? [num("radius"), perFinger()] : null;
  const b = bounds([pts.concat(obj ? [obj] : [], [[0, 0], [v.r_max_mm, 0]])], 0);
  const p = frame(svg, { x0: 0, x1: b.x1 * 1.05, y0: 0, y1: b.y1 * 1.1, xlabel: "sphere radius r (mm)", ylabel: "max lift f_v (N per finger)" });
  path(p, pts, "curve");
  if (obj) el("circle", { id: "envelope-object", cx: p.X(obj[0]), cy: p.Y(obj[1]), r: 5, class: "mark" }, svg);
}

// ------------------------------------------------------------ the load path

function drawPath(ok, v) {
  const svg = $("path-view");
  const axes = { xlabel: "tip force (N)", ylabel: "tip X, Z (mm)" };
  if (!$("path-on").checked) {
    const p = frame(svg, { x0: 0, x1: 1, y0: -100, y1: 100, ...axes });
    note(p, "off: tick \"follow a tip force\"");
    return;
  }
  if (!ok) {
    const p = frame(svg, { x0: 0, x1: 1, y0: -100, y1: 100, ...axes });
    note(p, `no path: ${v.message}`);
    return;
  }
  const xs = v.points.map((q) => [q.force_n, q.tip_mm[0]]);
  const zs = v.points.map((q) => [q.force_n, q.tip_mm[1]]);
  const b = bounds([xs, zs, [[0, 0]]], 0);
  const pad = 0.05 * (b.y1 - b.y0 || 1);
  const p = frame(svg, { x0: Math.min(0, b.x0), x1: b.x1, y0: b.y0 - pad, y1: b.y1 + pad, ...axes });
  path(p, xs, "curve");
  path(p, zs, "curve z");
  v.points.forEach((q, i) => {
    if (!q.stable) for (const s of [xs[i], zs[i]]) el("circle", { cx: p.X(s[0]), cy: p.Y(s[1]), r: 2.5, class: "off" }, svg);
  });
  for (const f of v.folds) {
    for (const y of f.tip_mm) el("circle", { cx: p.X(f.lambda), cy: p.Y(y), r: 5, class: "mark" }, svg);
    el("text", { x: p.X(f.lambda) + 6, y: p.Y(f.tip_mm[0]) - 6, class: "note" }, svg, f.is_fold ? `fold at ${f.lambda.toFixed(3)} N` : `stability changes at ${f.lambda.toFixed(3)} N`);
  }
  if (v.termination !== "ReachedTarget") note(p, `the path ended early (${v.termination})`);
  const end = v.points[v.points.length - 1];
  if (end) {
    svg.dataset.endForceN = String(end.force_n);
    svg.dataset.endTipXMm = String(end.tip_mm[0]);
    svg.dataset.endTipZMm = String(end.tip_mm[1]);
  }
}

function updatePath() {
  if (!$("path-on").checked) {
    // an answer still on its way is no longer wanted
    latest.path = (latest.path || 0) + 1;
    if (inflight.path) inflight.path.abort();
    drawPath(true, null);
    return;
  }
  const a = (num("path-angle") * Math.PI) / 180;
  request("path", "/api/load-path", { scene: fingerScene(), direction: [Math.cos(a), Math.sin(a)], max_force_n: num("path-max") }, drawPath);
}

// ------------------------------------------------------------ updates

function updateFast() {
  request("finger", "/api/finger", { scene: fingerScene() }, drawFinger);
  request("grasp", "/api/grasp", { scene: gripperScene(true) }, drawGrasp);
  updatePath();
}

function updateCurves() {
  const scene = gripperScene(false);
  request("lift", "/api/lift-curve", { scene, points: 40 }, drawLift);
  request("envelope", "/api/envelope", { scene, radii: 24, samples: 24 }, drawEnvelope);
}

// The curves do not depend on the object or the pressure: only a change
// of the design recomputes them (after the slider rests for a moment).
const DESIGN = new Set(["eps0", "elements", "partition", "model", "angle", "overlap", "fingers", "mu"]);
let frameQueued = false;
let curveTimer = null;
let curvesFor = "";

function showValues() {
  for (const o of document.querySelectorAll("output")) {
    o.textContent = $(o.htmlFor.value).value;
  }
  $("elements").disabled = $("partition").value === "auto";
  $("path-angle").disabled = !$("path-on").checked;
  $("path-max").disabled = !$("path-on").checked;
  $("width").disabled = $("kind").value !== "cuboid";
  $("radius").disabled = $("kind").value !== "sphere";
  $("beta").disabled = $("kind").value !== "sphere";
}

function changed(ev) {
  showValues();
  if (!frameQueued) {
    frameQueued = true;
    requestAnimationFrame(() => { frameQueued = false; updateFast(); });
  }
  const key = JSON.stringify(gripperScene(false));
  if (ev && DESIGN.has(ev.target.id) && key !== curvesFor) {
    // a pending recomputation counts as work in progress (data-busy)
    if (curveTimer === null) setBusy(1);
    clearTimeout(curveTimer);
    curveTimer = setTimeout(() => {
      curveTimer = null;
      setBusy(-1);
      curvesFor = key;
      updateCurves();
    }, 150);
  } else if (ev && (ev.target.id === "kind" || ev.target.id === "weight" || ev.target.id === "width" || ev.target.id === "radius")) {
    // the object's mark moves; the curves stay
    if (lastLift) drawLift(true, lastLift);
    if (lastEnvelope) drawEnvelope(true, lastEnvelope);
  }
}


// ------------------------------------------------------------ files

function toToml(obj) {
  const lines = [];
  const value = (v) => (typeof v === "string" ? JSON.stringify(v) : String(v));
  const walk = (o, prefix) => {
    const tables = [];
    for (const [k, v] of Object.entries(o)) {
      if (v !== null && typeof v === "object" && !Array.isArray(v)) tables.push([k, v]);
      else lines.push(`${k} = ${value(v)}`);
    }
    for (const [k, v] of tables) {
      const name = prefix ? `${prefix}.${k}` : k;
      const scalars = Object.values(v).some((x) => x === null || typeof x !== "object" || Array.isArray(x));
      if (scalars) { lines.push("", `[${name}]`); }
      walk(v, name);
    }
  };
  walk(obj, "");
  return lines.join("\n").trim() + "\n";
}

function writeScene() {
  $("scene-text").value = "# written by fpc serve: the grasp of the page's controls\n" + toToml(gripperScene(true));
}

function solveScene() {
  const text = $("scene-text").value;
  const isGrasp = /^\s*\[gripper/m.test(text);
  const out = $("scene-result");
  out.textContent = "solving";
  request("scene", isGrasp ? "/api/grasp" : "/api/finger", { toml: text }, (ok, v) => {
    if (!ok) { out.className = "invalid"; out.textContent = `${v.field}: ${v.message}`; return; }
    out.className = v.validity ? "valid" : "invalid";
    const lines = [`kind ${v.kind}, ${v.elements} elements, tip (${v.tip_mm[0].toFixed(4)}, ${v.tip_mm[1].toFixed(4)}) mm, valid: ${v.validity}`];
    if (v.grasp) {
      const g = v.grasp;
      lines.push(`F = ${g.normal_force_n.toFixed(4)} N, f = ${g.friction_n.toFixed(4)} N, f_v = ${g.lift_n.toFixed(4)} N, d = ${g.size_mm.toFixed(3)} mm, h = ${g.height_mm.toFixed(3)} mm`);
      if (g.invalid) lines.push(`not held: ${g.invalid.message}`);
      drawGrasp(true, v);
    }
    for (const w of v.warning_messages) lines.push(`finding: ${w}`);
    out.textContent = lines.join("\n");
    out.dataset.tipXMm = String(v.tip_mm[0]);
    out.dataset.tipZMm = String(v.tip_mm[1]);
    if (v.grasp) out.dataset.normalForceN = String(v.grasp.normal_force_n);
  });
}

function downloadScene() {
  const blob = new Blob([$("scene-text").value], { type: "text/plain" });
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = "scene.toml";
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

function runDesign() {
  const out = $("design-result");
  out.textContent = "designing (a few seconds)";
  request("design", "/api/design", { toml: $("design-text").value }, (ok, v) => {
    out.replaceChildren();
    const p = document.createElement("p");
    if (!ok) { p.className = "invalid"; p.textContent = `${v.field}: ${v.message}`; out.appendChild(p); return; }
    p.className = v.feasible ? "valid" : "invalid";
    p.textContent = `${v.feasible ? "Feasible" : "Not feasible"}: eps0 = ${v.design.eps0.toFixed(4)}, mounting angle = ${v.design.mounting_angle_deg.toFixed(2)} deg, overlap = ${v.design.overlap_mm.toFixed(2)} mm; worst margin ${v.worst_margin.toFixed(3)}` + (v.failure ? ` (${v.failure})` : "");
    out.appendChild(p);
    const t = document.createElement("table");
    t.innerHTML = "<thead><tr><th>requirement</th><th>margin</th><th>notes</th></tr></thead>";
    const body = document.createElement("tbody");
    for (const m of v.margins) {
      const tr = document.createElement("tr");
      const name = document.createElement("td");
      name.textContent = m.requirement || m.name || JSON.stringify(m);
      const val = document.createElement("td");
      val.textContent = typeof m.margin === "number" ? m.margin.toFixed(3) : "";
      if (typeof m.margin === "number" && m.margin < 0) val.className = "invalid";
      const notes = document.createElement("td");
      notes.textContent = (m.notes || []).join("; ");
      tr.append(name, val, notes);
      body.appendChild(tr);
    }
    t.appendChild(body);
    out.appendChild(t);
  });
}

// ------------------------------------------------------------ start

for (const c of document.querySelectorAll("#controls input, #controls select")) {
  c.addEventListener("input", changed);
  c.addEventListener("change", changed);
}
$("scene-from-controls").addEventListener("click", writeScene);
$("scene-solve").addEventListener("click", solveScene);
$("scene-download").addEventListener("click", downloadScene);
$("scene-file").addEventListener("change", async (ev) => {
  const f = ev.target.files[0];
  if (f) { $("scene-text").value = await f.text(); solveScene(); }
});
$("design-run").addEventListener("click", runDesign);
showValues();
writeScene();
updateFast();
curvesFor = JSON.stringify(gripperScene(false));
updateCurves();
