// A stored test's one-page report, to print: the patient, the test, when, the score and its
// band, every item's question, answer and points (or the trial's phases), and the validation.
"use strict";

function fact(list, name, value) {
  const dt = document.createElement("dt"); dt.textContent = name;
  const dd = document.createElement("dd"); dd.textContent = value;
  list.append(dt, dd);
}

async function main() {
  const id = Number(location.pathname.split("/").pop());
  await loadTests();
  const answer = await fetch("/api/results");
  if (answer.status === 401) { location.assign("/login"); return; }
  const results = await answer.json();
  const t = results.find((r) => r.id === id);
  if (!t) { document.getElementById("score").textContent = `There is no test ${id}.`; return; }
  document.title = `${testName(t)}: ${t.patient} (test ${t.id})`;
  document.getElementById("title").textContent = testName(t);
  const facts = document.getElementById("facts");
  fact(facts, "Patient", t.patient + (t.patient_id ? ` (record #${t.patient_id})` : ""));
  fact(facts, "Test", `#${t.id}, ${testName(t)}`);
  fact(facts, "Started", localTime(t.started));
  if (t.finished) fact(facts, "Finished", localTime(t.finished));
  const notes = [];
  if (t.clinician_called) notes.push("the clinician was called during the test");
  if (t.person_lost) notes.push(`the patient left ${t.person_lost_count} time(s)`);
  if (t.test === TIMED) notes.push(`${t.trials} trial(s)`);
  if (notes.length) fact(facts, "Course", notes.join("; "));
  const bands = TESTS[t.test] && TESTS[t.test].bands ? ` · bands: ${TESTS[t.test].bands.map((b) => `${b.min}–${b.max} ${b.name}`).join(", ")}` : "";
  document.getElementById("score").textContent = `Result: ${score(t)}, ${bandOf(t)}` +
    (t.test === TIMED && t.fall_risk ? ", fall risk" : "") + (t.complete === false ? " (provisional: items to score)" : "") + bands;
  document.getElementById("detail").append(itemsTable(t));
  document.getElementById("signed").textContent = t.validated_by ?
    `Validated by ${t.validated_by}, ${localTime(t.validated_at)}.` :
    "Not validated yet. Clinician: ______________________  Date: ____________";
  document.body.dataset.ready = "true";
}
document.getElementById("print").addEventListener("click", () => window.print());
main();
