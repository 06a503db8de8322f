// The DSR viewer: the graph now (live, each change highlighted) or at any past seq (scrubbed).
"use strict";

const state = { live: true, replay: null, seq: 0, firstSeq: 0, shownSeq: 0, selected: null, snapshot: null, deltas: [] };
const $ = (id) => document.getElementById(id);

function colorOf(type) {  // a stable colour per node type
  let h = 0;
  for (const c of type) h = (h * 31 + c.charCodeAt(0)) % 360;
  return `hsl(${h}, 55%, 62%)`;
}

const cy = cytoscape({
  container: $("graph"),
  wheelSensitivity: 0.3,
  style: [
    { selector: "node", style: { "background-color": "data(color)", label: "data(label)", "font-size": 10,
      "text-wrap": "wrap", "text-valign": "bottom", "text-margin-y": 3, width: 22, height: 22 } },
    { selector: "node:selected", style: { "border-width": 3, "border-color": "#1d2733" } },
    { selector: "edge", style: { width: 1.5, "curve-style": "bezier", "target-arrow-shape": "triangle",
      "arrow-scale": 0.8, "line-color": "#7a8794", "target-arrow-color": "#7a8794", label: "data(label)",
      "font-size": 9, "text-background-color": "#fff", "text-background-opacity": 0.8 } },
    { selector: "edge.rt", style: { "line-style": "dashed", "line-color": "#3a7bd5", "target-arrow-color": "#3a7bd5",
      width: 2.5, label: "" } },
    { selector: "node.flash", style: { "background-color": "#ff7f11", "border-width": 4, "border-color": "#ffd166" } },
    { selector: "edge.flash", style: { "line-color": "#ff7f11", "target-arrow-color": "#ff7f11", width: 4 } },
  ],
  elements: [],
});
window.dsrViewer = { state, cy };

function elementsOf(snapshot) {
  const want = new Map();
  for (const n of snapshot.nodes) {
    const id = "n:" + n.name;
    want.set(id, { group: "nodes", data: { id, name: n.name, type: n.type, nid: n.id, version: n.version,
      attrs: n.attrs, color: colorOf(n.type), label: `${n.name}\n(${n.type})` } });
  }
  for (const e of snapshot.edges) {
    const id = `e:${e.from}|${e.type}|${e.to}`;
    want.set(id, { group: "edges", classes: e.type === "RT" ? "rt" : "sym", data: { id, source: "n:" + e.from,
      target: "n:" + e.to, type: e.type, label: e.type, attrs: e.attrs, version: e.version, rt: e.rt || null } });
  }
  return want;
}

function render(snapshot) {
  const want = elementsOf(snapshot);
  let changed = cy.elements().length === 0;
  cy.batch(() => {
    cy.elements().forEach((el) => { if (!want.has(el.id())) { el.remove(); changed = true; } });
    for (const [id, el] of want) {
      const have = cy.getElementById(id);
      if (have.nonempty()) have.data(el.data);
      else { cy.add(el); changed = true; }
    }
  });
  if (changed) {
    const first = cy.nodes().every((n) => n.position().x === 0 && n.position().y === 0);
    cy.layout({ name: "cose", animate: false, randomize: first, fit: first, nodeRepulsion: 9000, idealEdgeLength: 70 }).run();
  }
  state.snapshot = snapshot;
  state.shownSeq = snapshot.seq;
  document.body.dataset.nodes = String(snapshot.nodes.length);
  document.body.dataset.shownSeq = String(snapshot.seq);
  showStatus();
  if (state.selected) inspect(state.selected);
}

function flash(delta) {
  const ids = [];
  for (const op of delta.ops) {
    if (op.name) ids.push("n:" + op.name);
    if (op.node) ids.push("n:" + op.node);
    if (op.from) ids.push(`e:${op.from}|${op.type || "RT"}|${op.to}`, "n:" + op.to);
  }
  const els = cy.collection(ids.map((id) => cy.getElementById(id)).filter((e) => e.nonempty()));
  els.addClass("flash");
  setTimeout(() => els.removeClass("flash"), 1500);
}

let loading = null;  // a live reload in flight; changes meanwhile need one more, not one each
let reloadAgain = false;

async function reloadLive() {
  if (loading) { reloadAgain = true; return loading; }
  loading = (async () => {
    do { reloadAgain = false; await load(); } while (reloadAgain);
  })();
  try { await loading; } finally { loading = null; }
}

async function load(seq) {
  const url = seq === undefined ? "/api/graph" : `/api/graph?seq=${seq}`;
  const response = await fetch(url);
  if (!response.ok) { $("status").textContent = await response.text(); return null; }
  const snapshot = await response.json();
  render(snapshot);
  return snapshot;
}

function showStatus() {
  const past = !state.live;
  if (state.replay) {  // a recording: nothing is live, the timeline runs from its first seq to its last
    $("status").textContent = `replay of ${state.replay}: seq ${state.shownSeq} (${state.firstSeq} to ${state.seq})`;
  } else {
    $("status").textContent = past ? `seq ${state.shownSeq} (past; live is ${state.seq})` : `seq ${state.seq} (live)`;
  }
  $("status").classList.toggle("past", past);
  $("live").hidden = !past;
  document.body.dataset.seq = String(state.seq);
  document.body.dataset.live = String(state.live);
  const scrub = $("scrub");
  scrub.min = String(state.firstSeq);
  scrub.max = String(state.seq);
  if (state.live) scrub.value = String(state.seq);
  $("scrub-seq").textContent = `seq ${past ? state.shownSeq : state.seq}`;
  for (const li of $("deltas").children) {
    const s = Number(li.dataset.seq);
    li.classList.toggle("current", s === state.shownSeq);
    li.classList.toggle("future", s > state.shownSeq);
  }
}

function addDeltaRow(delta) {
  const li = document.createElement("li");
  li.value = delta.seq;
  li.dataset.seq = String(delta.seq);
  li.textContent = delta.text.replace(/^seq\s+\d+\s+/, "");
  li.title = "show the graph as it was after this change";
  li.addEventListener("click", () => scrubTo(delta.seq));
  $("deltas").prepend(li);
  while ($("deltas").children.length > 500) $("deltas").lastChild.remove();
}

async function scrubTo(seq) {
  state.live = seq >= state.seq;
  if (state.live) await load(); else await load(seq);
  $("scrub").value = String(seq);
}

// -- inspector -----------------------------------------------------------------------------
function written(stamp) {
  // provenance: [time (s since the epoch), agent] of the attribute's last write
  return stamp ? `${stamp[1]}, ${new Date(stamp[0] * 1000).toLocaleString()}` : "";
}

function row(table, key, value, node, stamp) {
  const tr = table.insertRow();
  tr.insertCell().textContent = key;
  const cell = tr.insertCell();
  const by = tr.insertCell();
  by.className = "written";
  by.textContent = written(stamp);
  if (value && typeof value === "object" && "$binary" in value) {  // bytes, never in the JSON
    cell.textContent = `<${value.$binary} ${value.shape ? value.shape.join("x") : value.size + " bytes"}>`;
    if (value.shape && (value.shape.length === 2 || (value.shape.length === 3 && value.shape[2] === 3))) {
      const canvas = document.createElement("canvas");
      canvas.className = "image";
      canvas.dataset.attr = key;
      cell.append(document.createElement("br"), canvas);
      showImage(canvas, node, key);
    }
    return;
  }
  cell.textContent = typeof value === "string" ? value : JSON.stringify(value);
}

async function showImage(canvas, node, attr) {
  // the bytes of an image attribute as the DSR holds them: RGB rows, or one value a pixel
  // (depth: nearest white, farthest black, no reading black)
  const r = await fetch(`/api/image?node=${encodeURIComponent(node)}&attr=${encodeURIComponent(attr)}&seq=${state.shownSeq}`);
  if (!r.ok) { canvas.replaceWith(document.createTextNode(await r.text())); return; }
  const dtype = r.headers.get("X-DSR-Dtype");
  const [h, w, c] = r.headers.get("X-DSR-Shape").split(",").map(Number);
  const buffer = await r.arrayBuffer();
  const values = dtype === "float32" ? new Float32Array(buffer) : dtype === "uint16" ? new Uint16Array(buffer) : new Uint8Array(buffer);
  const pixels = new ImageData(w, h);
  const out = pixels.data;
  if (c === 3) {
    for (let i = 0, j = 0; i < w * h; i++, j += 3) { out[4 * i] = values[j]; out[4 * i + 1] = values[j + 1]; out[4 * i + 2] = values[j + 2]; out[4 * i + 3] = 255; }
  } else {
    let max = 0;
    for (const v of values) if (v > max) max = v;
    for (let i = 0; i < w * h; i++) { const g = values[i] > 0 ? 255 - Math.round(200 * values[i] / max) : 0; out[4 * i] = out[4 * i + 1] = out[4 * i + 2] = g; out[4 * i + 3] = 255; }
  }
  canvas.width = w;
  canvas.height = h;
  canvas.getContext("2d").putImageData(pixels, 0, 0);
  canvas.dataset.shown = String(state.shownSeq);
}

function inspect(name) {
  state.selected = name;
  const node = state.snapshot && state.snapshot.nodes.find((n) => n.name === name);
  const details = $("details");
  details.innerHTML = "";
  if (!node) { details.textContent = `${name} does not exist at seq ${state.shownSeq}`; return; }
  const title = document.createElement("h3");
  title.textContent = node.name;
  details.append(title);
  const table = document.createElement("table");
  table.id = "node-table";
  row(table, "id", String(node.id));
  row(table, "type", node.type);
  row(table, "version", String(node.version));
  const prov = node.provenance || {};
  for (const [k, v] of Object.entries(node.attrs)) row(table, k, v, node.name, prov[k]);
  details.append(table);
  const geometric = new Set();
  for (const e of state.snapshot.edges) if (e.type === "RT") { geometric.add(e.from); geometric.add(e.to); }
  if (geometric.has(name)) {
    const label = document.createElement("label");
    label.textContent = "pose in the frame of ";
    const select = document.createElement("select");
    select.id = "frame";
    for (const g of [...geometric].sort()) select.add(new Option(g, g));
    const pose = document.createElement("pre");
    pose.id = "pose";
    select.addEventListener("change", () => showPose(select.value, name, pose));
    label.append(select);
    details.append(label, pose);
    const parent = state.snapshot.edges.find((e) => e.type === "RT" && e.to === name);
    select.value = parent ? parent.from : name;
    const moved = parent && parent.provenance && parent.provenance["$rt"];
    if (moved) {
      const by = document.createElement("p");
      by.id = "moved";
      by.textContent = `pose written by ${written(moved)}`;
      details.append(by);
    }
    showPose(select.value, name, pose);
  }
}

async function showPose(frame, name, pre) {
  const r = await fetch(`/api/transform?from=${encodeURIComponent(frame)}&to=${encodeURIComponent(name)}&seq=${state.shownSeq}`);
  if (!r.ok) { pre.textContent = await r.text(); return; }
  const t = await r.json();
  const f = (xs) => xs.map((x) => x.toFixed(3)).join(", ");
  pre.textContent = `translation [${f(t.translation)}] m\nquaternion wxyz [${f(t.quaternion_wxyz)}]\nchain ${t.chain.join(" → ")}`;
  pre.dataset.translation = JSON.stringify(t.translation);
}

cy.on("tap", "node", (evt) => inspect(evt.target.data("name")));

// -- live updates --------------------------------------------------------------------------
$("scrub").addEventListener("input", (evt) => scrubTo(Number(evt.target.value)));
$("live").addEventListener("click", () => scrubTo(state.seq));

async function start() {
  state.replay = (await (await fetch("/api/info")).json()).replay;
  document.body.dataset.replay = state.replay || "";
  if (state.replay) $("live").textContent = "to the end";
  const snapshot = await load();
  const past = await (await fetch(`/api/deltas?limit=500&since=${Math.max(0, (snapshot ? snapshot.seq : 0) - 500)}`)).json();
  state.firstSeq = past.first_seq;
  state.seq = Math.max(state.seq, past.seq);
  for (const d of past.deltas) addDeltaRow(d);
  showStatus();
  if (state.replay) { await scrubTo(state.firstSeq); return; }  // a recording opens at its start
  const events = new EventSource("/api/events");
  events.addEventListener("hello", (e) => { const h = JSON.parse(e.data); state.firstSeq = h.first_seq; showStatus(); });
  events.addEventListener("delta", async (e) => {
    const delta = JSON.parse(e.data);
    state.seq = delta.seq;
    addDeltaRow(delta);
    if (state.live) { await reloadLive(); flash(delta); } else showStatus();
  });
  events.addEventListener("reset", () => { if (state.live) load(); });
}
start();
