// The clinician's dashboard: Start, the running test live, the results and the history.
"use strict";

const $ = (id) => document.getElementById(id);
let results = [];

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
  started: (e) => `Start: ${e.patient}`,
  following: (e) => `test of ${e.patient} under way: item ${e.position}/10 ${e.item}`,
  item: (e) => `item ${e.position}/10: ${e.item}`,
  answer: (e) => `${e.item}: ${e.points} points (${e.via})`,
  no_answer: (e) => `${e.item}: no answer (try ${e.attempt})`,
  not_understood: (e) => `${e.item}: not understood "${e.heard}"`,
  skip: (e) => `${e.item}: skip asked`,
  window_interrupted: (e) => `${e.item}: cut by a restart, asked again`,
  unanswered: (e) => `${e.item}: unanswered`,
  person_lost: () => "the patient left",
  person_back: () => "the patient is back",
  clinician_called: (e) => `you are called (${e.unanswered.join(", ")} unanswered)`,
  finished: (e) => `finished: ${score(e.result)} (${e.result.band})`,
  error: (e) => `error: ${e.message}`,
};
const ALERTS = new Set(["person_lost", "clinician_called", "error"]);

function onStep(e) {
  const text = DESCRIBE[e.event] ? DESCRIBE[e.event](e) : null;
  if (text) logEvent(text, ALERTS.has(e.event));
  if (e.event === "started" || e.event === "following") { setRunning(true); $("live-patient").textContent = e.patient; $("live-answer").textContent = "–"; }
  if (e.event === "item") $("live-item").textContent = `${e.position}/10 ${e.item}`;
  if (e.event === "answer") $("live-answer").textContent = `${e.item}: ${e.points} points by ${e.via}`;
  if (e.event === "unanswered") $("live-answer").textContent = `${e.item}: unanswered`;
  if (e.event === "finished" || e.event === "error") { setRunning(false, e.event === "finished"); loadResults(); }
}

function cell(tr, text) { tr.insertCell().textContent = text; }

const TIMED = "get_up_and_go";
function score(t) { return t.test === TIMED ? `${t.tug_seconds.toFixed(1)} s` : `${t.total}/100`; }
function testName(t) { return t.test === TIMED ? "Get Up & Go" : "Barthel"; }
// a stored time (ISO 8601, any zone) in this browser's local time, with its zone
function localTime(iso) {
  // (dateStyle cannot go with timeZoneName: the fields one by one)
  return new Date(iso).toLocaleString(undefined, { year: "numeric", month: "short", day: "numeric",
    hour: "2-digit", minute: "2-digit", timeZoneName: "short" });
}

function validation(t) {
  const p = document.createElement("p");
  p.id = "validation";
  if (t.validated_by) {
    p.textContent = `Validated by ${t.validated_by}, ${localTime(t.validated_at)}. This result can no longer change.`;
    return p;
  }
  const name = document.createElement("input");
  name.id = "clinician";
  name.placeholder = "your name";
  const button = document.createElement("button");
  button.id = "validate";
  button.textContent = "Validate";
  const error = document.createElement("span");
  error.id = "validate-error";
  button.addEventListener("click", async () => {
    const r = await fetch(`/api/results/${t.id}/validate`, { method: "POST",
      headers: { "Content-Type": "application/json" }, body: JSON.stringify({ clinician: name.value }) });
    if (!r.ok) { error.textContent = await r.text(); return; }
    await loadResults();
    showResult(results.find((x) => x.id === t.id));
  });
  p.append("Not validated yet. ", name, button, error);
  return p;
}

function showResult(t) {
  const div = $("result-detail");
  div.innerHTML = "";
  const h = document.createElement("h3");
  h.textContent = `Test ${t.id}: ${t.patient}, ${testName(t)} ${score(t)} (${t.band})` +
    (t.test === TIMED && t.fall_risk ? ", fall risk" : "");
  const when = document.createElement("p");
  when.textContent = `Started ${localTime(t.started)}` + (t.finished ? `, finished ${localTime(t.finished)}` : "");
  const table = document.createElement("table");
  table.id = "items";
  for (const [phase, seconds] of Object.entries(t.test === TIMED ? t.phases : {})) {
    const tr = table.insertRow();
    cell(tr, phase);
    cell(tr, `${seconds.toFixed(1)} s`);
  }
  for (const i of t.items || []) {
    const tr = table.insertRow();
    cell(tr, i.item);
    cell(tr, i.points === null ? "unanswered" : `${i.points} points`);
    cell(tr, i.via || "–");
    cell(tr, `${i.attempts} ${i.attempts === 1 ? "try" : "tries"}`);
  }
  const history = results.filter((r) => r.patient === t.patient && r.test === t.test);
  const p = document.createElement("p");
  p.textContent = `History of ${t.patient} (${testName(t)}): ` + history.map((r) => `${new Date(r.started).toLocaleDateString()} ${score(r)}`).join(", ");
  div.append(h, when, table, p, validation(t));
}

async function loadResults() {
  results = await (await fetch("/api/results")).json();
  const body = $("results").tBodies[0];
  body.innerHTML = "";
  for (const t of [...results].reverse()) {
    const tr = body.insertRow();
    tr.dataset.id = String(t.id);
    cell(tr, String(t.id));
    cell(tr, t.patient);
    cell(tr, localTime(t.started));
    cell(tr, `${testName(t)} ${score(t)}`);
    cell(tr, t.band);
    const notes = [];
    if (t.test === TIMED && t.fall_risk) notes.push("fall risk");
    if ((t.unanswered || []).length) notes.push(`${t.unanswered.length} unanswered`);
    if (t.clinician_called) notes.push("clinician called");
    if (t.person_lost) notes.push("patient left");
    notes.push(t.validated_by ? `validated by ${t.validated_by}` : "to validate");
    cell(tr, notes.join(", "));
    tr.addEventListener("click", () => showResult(t));
  }
  $("patients").innerHTML = "";
  for (const name of new Set(results.map((r) => r.patient))) $("patients").append(new Option(name));
  document.body.dataset.results = String(results.length);
}

$("start").addEventListener("click", async () => {
  $("start-error").textContent = "";
  const r = await fetch("/api/start", { method: "POST", headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ patient: $("patient").value }) });
  if (!r.ok) $("start-error").textContent = await r.text();
});

const events = new EventSource("/api/events");
events.addEventListener("status", (m) => {  // from the DSR: right even if an event was missed
  const s = JSON.parse(m.data);
  const ended = document.body.dataset.running === "true" && !s.running;
  setRunning(s.running, ended);
  if (ended) loadResults();
  if (s.patient) $("live-patient").textContent = s.patient;
  if (s.item) $("live-item").textContent = `${s.position}/10 ${s.item}`;
});
events.addEventListener("step", (m) => onStep(JSON.parse(m.data)));
events.addEventListener("pelea", (m) => onStep(JSON.parse(m.data)));  // PELEA's errors
events.addEventListener("speaker", (m) => {
  const s = JSON.parse(m.data);
  if (s.event === "start") $("live-question").textContent = s.text;
});
events.addEventListener("notification", (m) => logEvent(`to you: ${JSON.parse(m.data).message}`, false));
loadResults();
