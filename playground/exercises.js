// The Exercises tab: a menu of tasks (playground/exercises.ml), each with a
// starting program, agents, loop settings and host events. The student
// changes the program or the settings and presses Check my answer: the page
// runs the events on the current program and settings until every agent is
// idle, and the exercise's check (compiled in, the same one the tests hold
// to the solutions) judges the run. Hints come one at a time; the solution
// can be shown. Solved exercises are ticked in the menu and remembered.
"use strict";

(function () {
  const PG = window.PG;
  if (!PG) return;
  const { $, el, call, S } = PG;
  const X = { list: [], current: null, hints: {}, solved: {}, verdicts: {} };
  PG.exercises = X;

  const copy = (fs) => fs.map((f) => ({ name: f.name, text: f.text }));
  const settingsOf = (s) => ({ agents: s.agents, variant: s.variant, tie: s.tie, budget: s.budget, o2a_capacity: s.o2a_capacity, seed: null });

  function renderMenu() {
    const sel = $("exercise");
    sel.replaceChildren(...X.list.map((x) => el("option", { value: x.id, text: (X.solved[x.id] ? "✓ " : "") + x.title })));
    if (X.current) sel.value = X.current.id;
  }
  function renderPanel() {
    const x = X.current;
    if (!x) return;
    $("exercise-task").textContent = x.task;
    const shown = X.hints[x.id] || 0;
    $("exercise-hints").replaceChildren(...x.hints.slice(0, shown).map((h) => el("li", { text: h })));
    $("exercise-hint").disabled = shown >= x.hints.length;
    $("exercise-hint").textContent = shown >= x.hints.length ? "No more hints" : `Hint (${shown + 1} of ${x.hints.length})`;
    const v = X.verdicts[x.id];
    const box = $("exercise-verdict");
    box.hidden = !v;
    if (v) {
      box.className = "final " + (v.solved ? "ok" : "bad");
      box.textContent = v.solved ? `✓ Solved. ${v.says} ${x.why}` : `✗ Not yet. ${v.says}`;
    }
    PG.explain($("exercise-panel"));
  }

  // Opens an exercise on its starting program (the session is started, the
  // events are not done yet).
  function open(id) {
    const x = X.list.find((e) => e.id === id);
    if (!x) return;
    X.current = x;
    S.files = copy(x.start.files); S.file = 0; S.example = null;
    PG.setSettings(settingsOf(x.start));
    PG.showFile();
    S.events = x.events;
    delete X.verdicts[x.id];
    PG.start_session();
    renderMenu(); renderPanel();
  }

  function check() {
    const x = X.current;
    if (!x) return;
    const s = PG.setup();
    const r = call("exerciseCheck", x.id, JSON.stringify(s));
    S.traceShown = 0;
    if (!r.ok) {
      S.loaded = false; S.started = null;
      PG.showDiagnostics(r.errors || [r.error]);
      PG.status("not started: fix the errors above");
      PG.renderNone();
      X.verdicts[x.id] = { solved: false, says: "The program does not start: " + (r.errors || [r.error]).join("; ") };
    } else {
      S.loaded = true; S.started = s;
      S.eventIndex = x.events.length;
      PG.showDiagnostics([], "the program type-checks; the agents are created");
      PG.status("checked " + new Date().toLocaleTimeString());
      X.verdicts[x.id] = r.verdict;
      if (r.verdict.solved) X.solved[x.id] = true;
      PG.say(r.verdict.solved ? "solved: the events were done and the run went on until every agent was idle"
        : "not yet: the events were done and the run went on until every agent was idle; see the verdict", r.verdict.solved ? "info" : "error");
      PG.render(r, true);
    }
    renderMenu(); renderPanel();
    PG.saveSoon();
  }

  function solution() {
    const x = X.current;
    if (!x) return;
    S.files = copy(x.solution.files); S.file = 0;
    PG.setSettings(settingsOf(x.solution));
    PG.showFile();
    PG.checkNow();
    PG.start_session();
    PG.say("the solution is in the editor and the settings: Check my answer runs it", "info");
    PG.saveSoon();
  }

  PG.modes.exercise = {
    ws: "exercise", panels: ["exercise-panel"],
    enter(fresh) {
      if (fresh || !X.current) open(X.current ? X.current.id : X.list[0].id);
      else { renderMenu(); renderPanel(); }
    },
  };
  // for share.js: what the tab is, and its base program
  PG.exerciseBase = () => (X.current ? X.current.start.files : null);
  PG.exerciseEvents = () => (X.current ? X.current.events : []);
  PG.exerciseState = () => ({ id: X.current ? X.current.id : null, hints: X.hints, solved: X.solved, verdicts: X.verdicts });
  PG.exerciseRestore = (st) => {
    if (!st) return;
    X.current = X.list.find((e) => e.id === st.id) || null;
    X.hints = st.hints || {}; X.solved = st.solved || {}; X.verdicts = st.verdicts || {};
    renderMenu();
  };

  PG.onInit.push(() => {
    const l = call("exercises");
    X.list = Array.isArray(l) ? l : [];
    renderMenu();
    $("exercise").addEventListener("change", () => open($("exercise").value));
    $("exercise-check").addEventListener("click", check);
    $("exercise-hint").addEventListener("click", () => {
      const x = X.current;
      if (!x) return;
      X.hints[x.id] = Math.min(x.hints.length, (X.hints[x.id] || 0) + 1);
      renderPanel();
      PG.saveSoon();
    });
    $("exercise-solution").addEventListener("click", solution);
    $("exercise-reset").addEventListener("click", () => { if (X.current) open(X.current.id); PG.saveSoon(); });
  });
})();
