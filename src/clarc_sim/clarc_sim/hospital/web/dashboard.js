// The clinician's dashboard: Start for a patient and a test, the running test live, the results
// (each item's question and answer, the clinician's scores, validation), a patient's history as
// a chart, and a printable report; an admin's users and audit trail. results_view.js draws a
// result. Who may do what is the server's word: the page only hides what a role cannot use.
"use strict";

const $ = (id) => document.getElementById(id);
let results = [];
let me = null;  // {name, role, csrf}: the logged-in user and the session's CSRF token

function setRunning(running, finished) {
  document.body.dataset.running = String(running);
  $("start").disabled = running;
  $("state").textContent = running ? "running" : finished ? "finished" : "idle";
  $("state").className = "badge " + (running ? "running" : finished ? "finished" : "");
}

function logEvent(text, alert) {
  const li = document.createElement("li");
  li.textContent = `${new Date().toLocaleTimeString()}  ${text}`;
  if (alert) li.classList.add("alert");
  $("events").prepend(li);
}

// The steps of the test, read from the DSR by CGAmed (clarc_agents/course.py).
const DESCRIBE = {
  start_requested: (e) => `Start pressed for ${e.patient}`,
  started: (e) => `Start: ${e.patient}, ${testName({ test: e.test || "barthel" })}`,
  following: (e) => `test of ${e.patient} under way: item ${e.position}/${e.of} ${e.item}`,
  item: (e) => `item ${e.position}/${e.of}: ${e.item}`,
  answer: (e) => e.points === null ? `${e.item}: drawn (${e.via}), to score` : `${e.item}: ${e.points} points (${e.via})`,
  no_answer: (e) => `${e.item}: no answer (try ${e.attempt})`,
  not_understood: (e) => `${e.item}: not understood "${e.heard}"`,
  skip: (e) => `${e.item}: skip asked`,
  window_interrupted: (e) => `${e.item}: cut by a restart, asked again`,
  unanswered: (e) => `${e.item}: unanswered`,
  person_lost: () => "the patient left",
  person_back: () => "the patient is back",
  clinician_called: (e) => `you are called (${e.unanswered.join(", ")} unanswered)`,
  finished: (e) => e.result.test === TIMED && !e.result.tug_seconds ? "finished: unable to perform" :
    `finished: ${score(e.result)} (${bandOf(e.result)})`,
  error: (e) => `error: ${e.message}`,
};
const ALERTS = new Set(["person_lost", "clinician_called", "error"]);

function onStep(e) {
  const text = DESCRIBE[e.event] ? DESCRIBE[e.event](e) : null;
  if (text) logEvent(text, ALERTS.has(e.event));
  if (e.event === "started" || e.event === "following") { setRunning(true); $("live-patient").textContent = e.patient; $("live-answer").textContent = "–"; }
  if (e.event === "item") $("live-item").textContent = `${e.position}/${e.of} ${e.item}`;
  if (e.event === "answer") $("live-answer").textContent = DESCRIBE.answer(e);
  if (e.event === "unanswered") $("live-answer").textContent = `${e.item}: unanswered`;
  if (e.event === "finished" || e.event === "error") { setRunning(false, e.event === "finished"); loadResults(); }
}

async function post(url, doc) {
  const r = await fetch(url, {
    method: "POST",
    headers: { "Content-Type": "application/json", "X-CSRF-Token": me.csrf },
    body: JSON.stringify(doc),
  });
  if (r.status === 401) location.assign("/login");  // the session ended
  return r;
}

async function getJson(url) {
  const r = await fetch(url);
  if (r.status === 401) { location.assign("/login"); throw new Error("logged out"); }
  return r.json();
}

const CLINICIAN = () => me !== null && me.role === "clinician";  // scores and validates

// -- the clinician's part of a result: scores, then validation --------------------------------

async function refresh(id) {
  await loadResults();
  showResult(results.find((x) => x.id === id));
}

function scoring(t, table) {
  if (t.validated_by || !CLINICIAN()) return;
  for (const i of t.items || []) {
    if (!i.needs_clinician || i.points !== null) continue;
    const row = table.querySelector(`tr[data-item='${i.item}']`);
    const select = document.createElement("select");
    select.className = "score";
    // an item with options is scored by one of them; any other from 0 to its maximum
    const spec = itemOf(t, i.item);
    const scores = spec && spec.options && spec.options.length
      ? spec.options.map((o) => o.points) : Array.from({ length: i.max + 1 }, (_, p) => p);
    for (const p of scores) select.append(new Option(String(p), String(p)));
    const button = document.createElement("button");
    button.className = "score-button";
    button.textContent = "Score";
    button.addEventListener("click", async () => {
      const r = await post(`/api/results/${t.id}/score`, { item: i.item, points: Number(select.value) });
      if (!r.ok) { $("validate-error").textContent = await r.text(); return; }
      await refresh(t.id);
    });
    row.cells[3].textContent = "";
    row.cells[3].append(select, button);
  }
}

function validation(t) {
  const p = document.createElement("p");
  p.id = "validation";
  if (t.validated_by) {
    p.textContent = `Validated by ${t.validated_by}, ${localTime(t.validated_at)}. This result can no longer change.`;
    return p;
  }
  const waiting = (t.items || []).filter((i) => i.needs_clinician && i.points === null).map((i) => i.item);
  p.append(waiting.length ? `To score: ${waiting.join(", ")}. ` : "Not validated yet. ");
  const error = document.createElement("span");
  error.id = "validate-error";
  if (CLINICIAN()) {
    const button = document.createElement("button");
    button.id = "validate";
    button.textContent = `Validate as ${me.name}`;
    button.addEventListener("click", async () => {
      // the version seen: a result scored again meanwhile is not validated unseen
      const r = await post(`/api/results/${t.id}/validate`, { version: t.version });
      if (!r.ok) { error.textContent = await r.text(); return; }
      await refresh(t.id);
    });
    p.append(button);
  } else {
    p.append("A clinician validates it.");
  }
  p.append(error);
  return p;
}

// -- a patient's history of one test, as a chart over time ------------------------------------
function samePatient(a, b) {
  return a.patient_id !== null && a.patient_id !== undefined ? a.patient_id === b.patient_id : a.patient === b.patient;
}
function historyChart(t) {
  const history = results.filter((r) => samePatient(r, t) && r.test === t.test && (r.test !== TIMED || r.tug_seconds))
    .sort((a, b) => new Date(a.started) - new Date(b.started));
  const value = (r) => r.test === TIMED ? r.tug_seconds : r.total;
  const top = t.test === TIMED ? Math.max(30, ...history.map(value)) : t.max_total;
  const ns = "http://www.w3.org/2000/svg";
  const W = 560, H = 200, L = 40, B = 30, T = 10, R = 40;
  const svg = document.createElementNS(ns, "svg");
  svg.id = "history-chart";
  svg.setAttribute("viewBox", `0 0 ${W} ${H}`);
  const el = (name, attrs, text) => {
    const e = document.createElementNS(ns, name);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
    if (text !== undefined) e.textContent = text;
    svg.append(e);
    return e;
  };
  const times = history.map((r) => new Date(r.started).getTime());
  const t0 = Math.min(...times), t1 = Math.max(...times);
  const x = (ms) => L + (t1 === t0 ? (W - L - R) / 2 : (ms - t0) / (t1 - t0) * (W - L - R));
  const y = (v) => H - B - v / top * (H - B - T);
  el("line", { x1: L, y1: H - B, x2: W - R, y2: H - B, class: "axis" });
  el("line", { x1: L, y1: T, x2: L, y2: H - B, class: "axis" });
  for (const v of [0, top / 2, top]) el("text", { x: L - 6, y: y(v) + 4, "text-anchor": "end" }, String(Math.round(v)));
  el("polyline", { points: history.map((r, k) => `${x(times[k])},${y(value(r))}`).join(" "), class: "line" });
  history.forEach((r, k) => {
    const dot = el("circle", { cx: x(times[k]), cy: y(value(r)), r: r.id === t.id ? 6 : 4, class: "point" });
    dot.dataset.id = String(r.id);
    el("title", {}, `${localTime(r.started)}: ${score(r)} (${bandOf(r)})`);
    dot.append(svg.lastChild);
    el("text", { x: x(times[k]), y: H - B + 16, "text-anchor": "middle" }, new Date(r.started).toLocaleDateString());
  });
  const figure = document.createElement("figure");
  const caption = document.createElement("figcaption");
  caption.textContent = `History of ${t.patient}: ${testName(t)}, ${history.length} test${history.length === 1 ? "" : "s"}` +
    (t.test === TIMED ? " (seconds)" : " (total)");
  figure.append(caption, svg);
  return figure;
}

function showResult(t) {
  const div = $("result-detail");
  div.innerHTML = "";
  const h = document.createElement("h3");
  h.textContent = `Test ${t.id}: ${t.patient}, ${testName(t)} ${score(t)} (${bandOf(t)})` +
    (t.test === TIMED && t.fall_risk ? ", fall risk" : "") + (t.complete === false ? ", to score" : "");
  const when = document.createElement("p");
  when.textContent = `Started ${localTime(t.started)}` + (t.finished ? `, finished ${localTime(t.finished)}` : "");
  const report = document.createElement("a");
  report.id = "report";
  report.href = `/report/${t.id}`;
  report.target = "_blank";
  report.textContent = "Printable report";
  const table = itemsTable(t);
  const check = validation(t);
  div.append(h, when, report, table, check, historyChart(t));
  scoring(t, table);
}

async function loadResults() {
  results = await getJson("/api/results");
  const body = $("results").tBodies[0];
  body.innerHTML = "";
  for (const t of [...results].reverse()) {
    const tr = body.insertRow();
    tr.dataset.id = String(t.id);
    cell(tr, String(t.id));
    cell(tr, t.patient);
    cell(tr, localTime(t.started));
    cell(tr, `${testName(t)} ${score(t)}`);
    cell(tr, bandOf(t));
    const notes = [];
    if (t.test === TIMED && t.fall_risk) notes.push("fall risk");
    if (t.complete === false) notes.push("to score");
    if ((t.unanswered || []).length) notes.push(`${t.unanswered.length} unanswered`);
    if (t.clinician_called) notes.push("clinician called");
    if (t.person_lost) notes.push("patient left");
    notes.push(t.validated_by ? `validated by ${t.validated_by}` : "to validate");
    cell(tr, notes.join(", "));
    tr.addEventListener("click", () => showResult(t));
  }
  document.body.dataset.results = String(results.length);
}

async function loadPatients(chosen) {
  const patients = await getJson("/api/patients");
  const select = $("patient-id");
  select.length = 1;
  for (const p of patients) select.append(new Option(`${p.name} (#${p.id})`, String(p.id)));
  if (chosen !== undefined) select.value = String(chosen);
  document.body.dataset.patients = String(patients.length);
}

$("add-patient").addEventListener("click", async () => {
  $("start-error").textContent = "";
  const r = await post("/api/patients", { name: $("new-patient").value });
  if (!r.ok) { $("start-error").textContent = await r.text(); return; }
  $("new-patient").value = "";
  await loadPatients((await r.json()).id);
});

$("start").addEventListener("click", async () => {
  $("start-error").textContent = "";
  const r = await post("/api/start", { patient_id: $("patient-id").value, test: $("test").value });
  if (!r.ok) $("start-error").textContent = await r.text();
});

function showStatus(s) {
  if (s.patient) $("live-patient").textContent = s.patient;
  if (s.test) $("live-test").textContent = testName(s);
  if (s.item) $("live-item").textContent = `${s.position}/${s.of} ${s.item}`;
}

// -- an admin's part: the users and the audit trail ------------------------------------------
async function loadAdmin() {
  const users = await getJson("/api/users");
  const body = $("users").tBodies[0];
  body.innerHTML = "";
  for (const u of users) {
    const tr = body.insertRow();
    tr.dataset.user = u.name;
    cell(tr, u.name);
    cell(tr, u.role);
    cell(tr, u.disabled ? "disabled" : "active");
    const button = document.createElement("button");
    button.textContent = u.disabled ? "Enable" : "Disable";
    button.disabled = u.name === me.name;
    button.addEventListener("click", async () => {
      const r = await post(`/api/users/${encodeURIComponent(u.name)}/${u.disabled ? "enable" : "disable"}`, {});
      if (!r.ok) { $("user-error").textContent = await r.text(); return; }
      await loadAdmin();
    });
    tr.insertCell().append(button);
  }
  const trail = $("audit").tBodies[0];
  trail.innerHTML = "";
  for (const a of await getJson("/api/audit")) {
    const tr = trail.insertRow();
    for (const v of [localTime(a.time), a.user, a.action, a.test_id === null ? "" : `#${a.test_id}`, a.detail]) cell(tr, v);
  }
}

$("add-user").addEventListener("click", async () => {
  $("user-error").textContent = "";
  const doc = { name: $("user-name").value, role: $("user-role").value, password: $("user-password").value };
  const r = await post("/api/users", doc);
  if (!r.ok) { $("user-error").textContent = await r.text(); return; }
  $("user-name").value = $("user-password").value = "";
  await loadAdmin();
});

$("logout").addEventListener("click", async () => {
  await post("/api/logout", {});
  location.assign("/login");
});

async function main() {
  me = await getJson("/api/me");
  $("who").textContent = `${me.name} (${me.role})`;
  document.body.dataset.role = me.role;
  if (me.role === "admin") {
    $("admin-panel").hidden = false;
    $("start-panel").hidden = true;
    await loadAdmin();
  }
  for (const t of await loadTests()) $("test").append(new Option(t.title, t.test));
  await Promise.all([loadResults(), loadPatients()]);
  const events = new EventSource("/api/events");
  events.addEventListener("status", (m) => {  // from the DSR: right even if an event was missed
    const s = JSON.parse(m.data);
    const ended = document.body.dataset.running === "true" && !s.running;
    setRunning(s.running, ended);
    if (ended) loadResults();
    showStatus(s);
  });
  events.addEventListener("step", (m) => onStep(JSON.parse(m.data)));
  events.addEventListener("pelea", (m) => onStep(JSON.parse(m.data)));  // PELEA's errors
  events.addEventListener("speaker", (m) => {
    const s = JSON.parse(m.data);
    if (s.event === "start") $("live-question").textContent = s.text;
  });
  events.addEventListener("notification", (m) => logEvent(`to you: ${JSON.parse(m.data).message}`, false));
  document.body.dataset.ready = "true";
}
main();
