// How a stored result reads, for the dashboard and the printable report alike: its score, the
// test's name, local times with the zone, each item's question and answer in words, drawings.
"use strict";

const TIMED = "get_up_and_go";
let TESTS = {};  // test -> its definition as /api/tests gives it

async function loadTests() {
  const offered = await (await fetch("/api/tests")).json();
  TESTS = Object.fromEntries(offered.map((t) => [t.test, t]));
  return offered;
}

function testName(t) { return TESTS[t.test] ? TESTS[t.test].title : t.test; }
function score(t) {
  // a provisional total: items the robot could not understand wait for the clinician
  if (t.test !== TIMED && t.provisional && t.total_range)
    return `${t.total_range[0]}-${t.total_range[1]}/${t.max_total}, provisional`;
  if (t.test !== TIMED) return `${t.total}/${t.max_total}`;
  return t.outcome === "unable" ? "unable to perform" : `${t.tug_seconds.toFixed(1)} s`;
}
// the band, or why there is none yet (items the robot could not understand wait for a score)
function bandOf(t) { return t.band === null ? "no band until the clinician scores" : t.band; }
// a stored time (ISO 8601, any zone) in this browser's local time, with its zone
function localTime(iso) {
  // (dateStyle cannot go with timeZoneName: the fields one by one)
  return new Date(iso).toLocaleString(undefined, { year: "numeric", month: "short", day: "numeric",
    hour: "2-digit", minute: "2-digit", timeZoneName: "short" });
}
function itemOf(t, key) {
  const test = TESTS[t.test];
  return test ? test.items.find((i) => i.key === key) : undefined;
}
// the answer in words: the option chosen, the words heard, the shapes touched
function answerWords(t, i) {
  if (i.answer) return i.answer;
  const spec = itemOf(t, i.item);
  const option = spec && i.points !== null ? spec.options.find((o) => o.points === i.points) : null;
  return option ? option.text : (i.via ? "" : "no answer");
}
function drawingSvg(path) {
  const ns = "http://www.w3.org/2000/svg";
  const svg = document.createElementNS(ns, "svg");
  svg.setAttribute("viewBox", "0 0 300 200");
  svg.setAttribute("class", "drawing");
  const p = document.createElementNS(ns, "path");
  p.setAttribute("d", path);
  svg.append(p);
  return svg;
}
function cell(tr, content) {
  const td = tr.insertCell();
  if (content instanceof Node) td.append(content); else td.textContent = content;
  return td;
}
// the items of a result as a table: item, question, answer, points, way, tries
function itemsTable(t) {
  const table = document.createElement("table");
  table.id = "items";
  const head = table.createTHead().insertRow();
  const timed = t.test === TIMED;
  for (const h of timed ? ["Phase", "Seconds"] : ["Item", "Question", "Answer", "Points", "How", "Tries"]) {
    const th = document.createElement("th"); th.textContent = h; head.append(th);
  }
  const body = table.createTBody();
  const parts = timed && t.phases ? { reaction: t.reaction_seconds, ...t.phases } : {};
  for (const [phase, seconds] of Object.entries(parts)) {
    const tr = body.insertRow();
    cell(tr, phase === "still" ? "standing still" : phase.replace("_", " "));
    cell(tr, `${seconds.toFixed(1)} s`);
  }
  for (const reason of timed ? t.void_reasons || [] : []) {  // why a trial did not count
    const tr = body.insertRow();
    tr.className = "void";
    cell(tr, "void trial");
    cell(tr, reason);
  }
  for (const i of t.items || []) {
    const spec = itemOf(t, i.item) || { title: i.item, question: "", max: i.max };
    const max = i.max !== undefined ? i.max : spec.max;
    const tr = body.insertRow();
    tr.dataset.item = i.item;
    cell(tr, spec.title);
    cell(tr, spec.question);
    const answer = cell(tr, answerWords(t, i));
    if (i.drawing) answer.append(drawingSvg(i.drawing));
    if (i.heard && i.points === null) {  // what the robot heard and could not understand
      const heard = document.createElement("div");
      heard.className = "heard";
      heard.textContent = `heard: "${i.heard}"`;
      answer.append(heard);
    }
    (i.audio || []).forEach((_, k) => {  // the clips of what was said, to listen to
      const player = document.createElement("audio");
      player.controls = true;
      player.preload = "none";
      player.className = "clip";
      player.src = `/api/results/${t.id}/audio/${encodeURIComponent(i.item)}/${k}`;
      answer.append(player);
    });
    const waiting = i.needs_clinician && i.points === null;
    cell(tr, waiting ? (i.via ? "to score" : "unanswered") : i.points === null ? "unanswered" : `${i.points}/${max}`);
    cell(tr, i.via || "–");
    cell(tr, `${i.attempts} ${i.attempts === 1 ? "try" : "tries"}`);
  }
  return table;
}
