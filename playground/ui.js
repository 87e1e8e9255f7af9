// The playground page: the user interface only. Everything about Jadescript
// (parsing, type checking, the agent loop, evaluation, the trace, the
// exercises' checks) is done by window.jsref, the project's OCaml libraries
// compiled with js_of_ocaml (playground/js/jsref.ml); this script shows what
// they answer. It is the core: the editor, a session's view, the Playground
// and replay tabs, and the tabs' switching. The scripts loaded after it add
// to window.PG: glossary.js (the terms explained), share.js (local storage
// and links), exercises.js (the Exercises tab), compare.js (Side by side),
// corridor.js (RoboMe in the corridor), concurrent.js (Concurrency);
// PG.start() (index.html) runs once they are all loaded.
"use strict";

(function () {
  const $ = (id) => document.getElementById(id);
  // jsref never throws for bad input; this catch is for the browser itself
  // (out of memory, a stack the browser could not map to an OCaml exception).
  const call = (fn, ...args) => {
    try { return JSON.parse(window.jsref[fn](...args)); }
    catch (e) { return { ok: false, error: "internal error: " + e, errors: ["internal error: " + e] }; }
  };
  const el = (tag, attrs, ...kids) => {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (k === "class") e.className = v;
      else if (k === "text") e.textContent = v;
      else if (k.startsWith("on")) e.addEventListener(k.slice(2), v);
      else e.setAttribute(k, v);
    }
    for (const kid of kids) if (kid != null) e.append(kid);
    return e;
  };
  // The session slot jsref acts on: each tab keeps its own session.
  let slotNow = null;
  const use = (slot) => { if (slot !== slotNow) { call("use", slot); slotNow = slot; } };
  const inSlot = (slot, f) => { const before = slotNow; use(slot); try { return f(); } finally { if (before) use(before); } };

  // The workspace on screen (program, settings, events, session) is S's
  // fields; each tab with a program keeps its own in S.ws while another tab
  // is shown (saveWs, loadWs).
  const S = {
    examples: [], replays: [], example: null, files: [], file: 0,
    loaded: false, started: null, traceShown: 0, events: [], eventIndex: 0,
    mode: "play", replay: null, replayStep: 0, replayOk: [], view: null,
    wsName: "play", ws: {}, message: "", messageKind: "",
  };
  const PG = window.PG = { $, el, call, use, inSlot, S, modes: {}, onRender: [], onInit: [], onStart: [] };
  window.playground = S;   // for the browser tests

  // ------------------------------------------------------------ editor

  function renderTabs() {
    const tabs = $("file-tabs");
    tabs.replaceChildren(...S.files.map((f, i) =>
      el("button", { class: i === S.file ? "active" : "", text: f.name, onclick: () => { saveFile(); S.file = i; showFile(); } })));
  }
  function saveFile() { if (S.files[S.file]) S.files[S.file].text = $("source").value; }
  function showFile() {
    $("source").value = S.files[S.file] ? S.files[S.file].text : "";
    renderTabs(); renderGutter();
  }
  const fileName = () => (S.files[S.file] ? S.files[S.file].name : "");

  // Long lines wrap in the editor; the mirror (a copy of the text, line by
  // line, in the same font and width) tells where each line starts and how
  // tall it is, so that the gutter's numbers, the marks of errors and the
  // line that runs next stay on their line.
  let diagLines = {};
  let runAt = null;          // {file, line} of the code the next rule runs
  let boxCache = { text: null, width: -1, boxes: [] };
  function lineBoxes() {
    const ta = $("source"), m = $("mirror");
    const width = ta.clientWidth;
    if (ta.value === boxCache.text && width === boxCache.width) return boxCache.boxes;
    m.style.width = width + "px";
    const lines = ta.value.split("\n");
    m.replaceChildren(...lines.map((l) => el("div", { text: l === "" ? "\u200b" : l })));
    const boxes = [...m.children].map((d) => ({ top: d.offsetTop, height: d.offsetHeight }));
    boxCache = { text: ta.value, width, boxes };
    return boxes;
  }
  let gutterKey = "";
  function renderGutter() {
    const ta = $("source");
    const boxes = lineBoxes();
    const g = $("gutter");
    const name = fileName();
    const run = runAt && runAt.file === name ? runAt.line : 0;
    const key = JSON.stringify([boxes.map((b) => b.height), name, diagLines[name] || {}, run]);
    if (key === gutterKey) { syncScroll(); return; }
    gutterKey = key;
    g.replaceChildren(...boxes.map((b, k) => {
      const i = k + 1;
      const msg = (diagLines[name] || {})[i];
      return el("div", { class: (msg ? "err" : "") + (i === run ? " run" : ""), style: `height:${b.height}px`,
        title: msg || (i === run ? "the next rule runs this line" : ""), text: String(i) });
    }));
    const rl = $("runline");
    if (run && boxes[run - 1]) {
      rl.hidden = false;
      rl.style.top = boxes[run - 1].top + "px";
      rl.style.height = boxes[run - 1].height + "px";
    } else rl.hidden = true;
    syncScroll();
  }
  function syncScroll() {
    const ta = $("source");
    $("gutter").scrollTop = ta.scrollTop;
    $("mirror").style.transform = `translateY(${-ta.scrollTop}px)`;
    $("runline").style.transform = `translateY(${-ta.scrollTop}px)`;
  }
  // FILE:LINE:COL: error: message
  const parseDiag = (d) => { const m = /^(.*?):(\d+):(\d+): (error|warning): (.*)$/.exec(d); return m && { file: m[1], line: +m[2], col: +m[3], sev: m[4], msg: m[5] }; };

  function showDiagnostics(list, okText) {
    diagLines = {};
    const ul = $("diagnostics");
    ul.replaceChildren();
    for (const d of list) {
      const p = parseDiag(d);
      const li = el("li", { class: p && p.sev === "warning" ? "warning" : "", text: d });
      if (p) {
        (diagLines[p.file] = diagLines[p.file] || {})[p.line] = p.msg;
        li.addEventListener("click", () => gotoLine(p.file, p.line, p.col));
      }
      ul.append(li);
    }
    if (list.length === 0 && okText) ul.append(el("li", { class: "ok", text: okText }));
    renderGutter();
  }
  // Puts the cursor at the line and column and scrolls the line into view.
  function gotoLine(file, line, col, focus = true) {
    const i = S.files.findIndex((f) => f.name === file);
    if (i < 0) return false;
    if (i !== S.file) { saveFile(); S.file = i; showFile(); }
    const ta = $("source");
    const lines = ta.value.split("\n");
    let pos = 0;
    for (let k = 0; k < line - 1 && k < lines.length; k++) pos += lines[k].length + 1;
    pos += Math.max(0, col - 1);
    if (focus) { ta.focus(); ta.setSelectionRange(pos, pos); }
    scrollToLine(line);
    return true;
  }
  function scrollToLine(line) {
    const ta = $("source");
    const b = lineBoxes()[line - 1];
    if (!b) return;
    if (b.top < ta.scrollTop || b.top + b.height > ta.scrollTop + ta.clientHeight)
      ta.scrollTop = Math.max(0, b.top - ta.clientHeight / 3);
    syncScroll();
  }
  let checkTimer = null;
  function checkNow() {
    saveFile();
    const ds = call("check", JSON.stringify({ files: S.files }));
    showDiagnostics(Array.isArray(ds) ? ds : [ds.error], "the program type-checks");
  }
  function checkSoon() {
    clearTimeout(checkTimer);
    if (S.loaded) status("edited: Check and start runs the new text");
    checkTimer = setTimeout(() => { checkNow(); PG.saveSoon(); }, 250);
  }
  const status = (t) => { $("load-status").textContent = t; };

  // ---------------------------------------------------------- settings

  function readSettings() {
    const num = (v) => (v.trim() === "" ? null : parseInt(v, 10));
    return {
      variant: $("variant").value, tie: $("tie").value,
      budget: Math.max(1, num($("budget").value) || 1),
      o2a_capacity: num($("capacity").value), seed: num($("seed").value),
    };
  }
  function setSettings(x) {
    $("agents").value = (x.agents || []).join("\n");
    $("variant").value = x.variant || "reference";
    $("tie").value = x.tie || "stable";
    $("budget").value = x.budget || 1;
    $("capacity").value = x.o2a_capacity == null ? "" : x.o2a_capacity;
    $("seed").value = x.seed == null ? "" : x.seed;
    $("budget").disabled = $("variant").value !== "budgeted";
  }
  const agentLines = () => $("agents").value.split("\n").map((s) => s.trim()).filter((s) => s !== "");
  function setup() {
    saveFile();
    return Object.assign({
      files: S.files.map((f) => ({ name: f.name, text: f.text })),
      agents: agentLines(),
      fuel: S.example && S.example.fuel ? S.example.fuel : null,
      max_steps: S.example && S.example.max_steps ? S.example.max_steps : null,
      // the Concurrency tab's sessions: the finer interleaving, its seed (D45)
      interleave: S.wsName === "concurrent" && PG.concurrentSeed ? PG.concurrentSeed() : null,
    }, readSettings());
  }
  PG.setup = setup; PG.setSettings = setSettings; PG.readSettings = readSettings;

  // A setting applies at once: the run starts again with the program and
  // agents it was started with, and the host actions done so far are done
  // again (the rules are not: they depend on the loop).
  function settingsChanged() {
    $("budget").disabled = $("variant").value !== "budgeted";
    if (!S.loaded || !S.started) return;
    const now = readSettings();
    const before = {};
    for (const k of Object.keys(now)) before[k] = S.started[k];
    if (JSON.stringify(now) === JSON.stringify(before)) return;
    const hist = call("export");
    const hostOnly = Array.isArray(hist) ? hist.filter((x) => x.agent !== undefined) : [];
    const s = Object.assign({}, S.started, now);
    const r = call("restore", JSON.stringify(s), JSON.stringify(hostOnly));
    S.traceShown = 0;
    if (!r.ok) { S.loaded = false; showDiagnostics(r.errors || [r.error]); renderNone(); return; }
    S.started = s;
    const what = [];
    if (now.variant !== before.variant) what.push("loop " + now.variant);
    if (now.tie !== before.tie) what.push("ties " + now.tie);
    if (now.budget !== before.budget) what.push("budget " + now.budget);
    if (now.o2a_capacity !== before.o2a_capacity) what.push("O2A capacity " + (now.o2a_capacity == null ? "unbounded" : now.o2a_capacity));
    if (now.seed !== before.seed) what.push("seed " + (now.seed == null ? "none (round-robin)" : now.seed));
    const n = hostOnly.length;
    say(`${what.join(", ")}: applied; the run started again with it` +
      (n ? `, and the host's ${n} action${n === 1 ? " was" : "s were"} done again` : ""), "info");
    status("settings applied " + new Date().toLocaleTimeString());
    render(r, true);
  }

  // ---------------------------------------------------------- examples

  function loadExample(id) {
    const x = S.examples.find((e) => e.id === id);
    if (!x) return;
    S.example = x;
    S.files = x.files.map((f) => ({ name: f.name, text: f.text }));
    S.file = 0;
    setSettings(x);
    showFile();
    S.events = x.events || [];
    start();
  }
  const sameFiles = (a, b) => a.length === b.length && a.every((f, i) => f.name === b[i].name && f.text === b[i].text);
  // The example as shown: the program is the example's, or the student's
  // own, started from it; the example's events are offered only while the
  // agents they name exist.
  function renderExample() {
    const x = S.example;
    const sel = $("example");
    let custom = $("custom-option");
    if (S.wsName !== "play") return;
    const own = x && S.started && !(sameFiles(S.started.files, x.files) && S.started.agents.join("\n") === (x.agents || []).join("\n"));
    if (!x) { $("example-about").textContent = ""; return; }
    if (own) {
      if (!custom) { custom = el("option", { id: "custom-option", value: "" }); sel.prepend(custom); }
      custom.textContent = `Your program (started from ${x.title.split(" (")[0]})`;
      sel.value = "";
      const names = S.view ? S.view.agents.map((a) => a.name) : [];
      const needed = [...new Set(S.events.map((e) => { try { return JSON.parse(e).agent; } catch (_) { return undefined; } }).filter((a) => a))];
      const missing = needed.filter((a) => !names.includes(a));
      $("example-about").textContent = `Your own program and agents, started from the example “${x.title.split(" (")[0]}”.` +
        (S.events.length ? (missing.length ? ` The example's events are for the agent${missing.length > 1 ? "s" : ""} ${missing.join(", ")}, which your agents do not include: they are not offered.`
          : " The example's events are still offered below.") : "");
    } else {
      if (custom) custom.remove();
      sel.value = x.id;
      $("example-about").textContent = x.about;
    }
    PG.explain($("example-about"));
  }
  // The events the page offers: the example's (or the exercise's), unless
  // they name an agent the session does not have.
  function eventsOffered() {
    if (!S.events.length || !S.view) return [];
    const names = S.view.agents.map((a) => a.name);
    const ok = S.events.every((e) => { try { const a = JSON.parse(e).agent; return a === undefined || names.includes(a); } catch (_) { return false; } });
    return ok ? S.events : [];
  }

  // ------------------------------------------------------------ session

  function start() {
    const s = setup();
    const r = call("create", JSON.stringify(s));
    S.traceShown = 0;
    $("trace").replaceChildren();
    S.eventIndex = 0;
    if (!r.ok) {
      S.loaded = false; S.started = null;
      showDiagnostics(r.errors || [r.error]);
      status("not started: fix the errors above");
      renderNone();
      renderExample();
      PG.saveSoon();
      return false;
    }
    S.loaded = true; S.started = s;
    showDiagnostics([], "the program type-checks; the agents are created");
    status("started " + new Date().toLocaleTimeString());
    say("", "");
    render(r, true);
    return true;
  }
  PG.start_session = start;

  function say(text, kind) {
    const m = $("message");
    m.textContent = text || "";
    m.className = "message " + (kind || "");
    S.message = text || ""; S.messageKind = kind || "";
    PG.explain(m);
  }
  PG.say = say;

  function act(fn, ...args) {
    if (!S.loaded) { say("start a program first (Check and start)", "error"); return null; }
    const r = call(fn, ...args);
    if (!r.ok) { say(r.error, "error"); return r; }
    let msg = r.error || "";
    if (!msg && r.outcome === "idle") msg = "every agent is idle: notify a percept or send a message";
    if (!msg && r.outcome === "limit") msg = "the step limit is reached";
    if (!msg && fn === "runIdle") msg = r.outcome === "stepped"
      ? `${r.taken} rules taken; stopped: the agent is not idle after ${r.taken} rules (the printed loop never idles, D4)`
      : `${r.taken} rules taken`;
    if (!msg && fn === "back") msg = r.undone ? "undone" : "nothing to undo";
    say(msg, r.error ? "error" : "info");
    render(r, fn === "back");
    return r;
  }
  PG.act = act;

  const host = (h) => act("host", JSON.stringify(h));

  // ------------------------------------------------------------- render

  function chip(kind, html, data) {
    const c = el("span", { class: "chip " + kind, "data-entry": data });
    c.innerHTML = html;
    return c;
  }
  const esc = (s) => String(s).replace(/&/g, "&amp;").replace(/</g, "&lt;");
  function perceptChip(e) {
    return chip("percept", `${esc(e.percept)} <span class="prio">${e.priority}</span> <span class="seq">#${e.seq}</span>`,
      `${e.percept}|${e.priority}|${e.seq}`);
  }
  function itemChip(x) {
    if (x.kind === "object") return chip("object", esc(x.object), `object|${x.object}`);
    if (x.kind === "message") return chip("message", `${esc(x.performative)} ${esc(x.content)} <span class="seq">m${x.seq} from ${esc(x.from)}</span>`,
      `${x.performative}|${x.content}|${x.from}|${x.seq}`);
    return perceptChip(x);
  }
  function queue(title, key, items, mk, emptyText) {
    const chips = el("div", { class: "chips" });
    if (items.length === 0) chips.append(el("span", { class: "empty", text: emptyText || "empty" }));
    for (const x of items) chips.append(mk(x));
    return el("div", { class: "queue", "data-queue": key }, el("h4", { text: title }), chips);
  }

  // One agent's card; [where]: goes to a line of the program (null: the
  // source links are plain text, as in Side by side).
  function agentCard(a, where) {
    const behName = {};
    for (const b of a.active) behName[b.instance] = b.behaviour;
    const readyRow = el("div", { class: "ready", "data-list": "ready" });
    if (a.ready.length === 0) readyRow.append(el("span", { class: "empty", text: "no behaviour ready" }));
    a.ready.forEach((id, k) => readyRow.append(el("span", {
      class: "slot" + (k + 1 === a.pos ? " pos" : ""), "data-instance": id,
      title: k + 1 === a.pos ? "JADE's position: runs at the next behaviour step" : "",
      text: (k + 1 === a.pos ? "▶ " : "") + `${behName[id] || "?"} #${id}` })));
    const behBox = el("div", { class: "box", "data-box": "behaviours" },
      el("h4", { text: "Active behaviours (activation order)" }),
      el("div", { class: "chips", "data-list": "active" }, ...(a.active.length ? a.active.map((b) =>
        el("span", { class: "chip", "data-instance": b.instance, text: `${b.behaviour} #${b.instance}` })) : [el("span", { class: "empty", text: "none" })])),
      el("h4", { text: `Ready list (position ${a.pos})` }), readyRow,
      el("h4", { text: "Blocked" }),
      el("div", { class: "chips", "data-list": "blocked" }, ...(a.blocked.length ? a.blocked.map((id) =>
        el("span", { class: "chip", text: `${behName[id] || "?"} #${id}` })) : [el("span", { class: "empty", text: "none" })])));

    let curBox;
    if (a.cur) {
      const todo = el("ol", { class: "todo", "data-list": "todo" });
      a.cur.todo.forEach((h, k) => {
        const m = /^(.*):(\d+)$/.exec(h.at);
        const src = where && m
          ? el("a", { class: "src", href: "#", "data-at": h.at, title: "show this line in the editor",
            onclick: (e) => { e.preventDefault(); where(m[1], +m[2]); }, text: `${h.at}: ${h.source}` })
          : el("span", { class: "src", text: `${h.at}: ${h.source}` });
        todo.append(el("li", {
          class: (k === 0 ? "first" : "") + (h.active ? "" : " gone"),
          "data-handler": `${h.instance}.${h.handler}`,
          title: h.active ? "" : "its behaviour was deactivated: it will be skipped (R4b)",
        }, `${h.behaviour} #${h.instance}, handler ${h.handler} `, src));
      });
      curBox = el("div", { class: "box", "data-box": "dispatch" },
        el("h4", { text: "Dispatch in progress" }),
        el("div", { class: "chips" }, perceptChip(a.cur.entry),
          el("span", { class: "hint", text: a.cur.applied ? " a handler ran" : " no handler ran yet" })),
        el("h4", { text: a.cur.todo.length ? "Handlers still to try (the snapshot, R4a, R4b)" : "No handler left: EndDispatch next" }), todo);
    } else {
      curBox = el("div", { class: "box", "data-box": "dispatch" }, el("h4", { text: "Dispatch in progress" }),
        el("span", { class: "empty", text: "none" }));
    }
    const props = el("table", { class: "props", "data-box": "props" });
    for (const p of a.props) props.append(el("tr", { "data-prop": p.name }, el("td", { text: p.name }), el("td", { text: p.value })));
    if (a.props.length === 0) props.append(el("tr", {}, el("td", { class: "empty", text: "no properties" })));
    const waits = a.waits.filter((w) => w.inversions > 0);
    const ghost = el("div", { class: "box", "data-box": "ghosts" }, el("h4", { text: "Counters (the spec's ghosts)" }),
      el("div", { class: "hint", text: `dispatched this iteration: ${a.dispatched} · percepts done: ${a.done}` }),
      el("div", { class: "hint", text: waits.length ? "waiting behind lower-priority dispatches: " +
        waits.map((w) => `#${w.seq} (priority ${w.priority}) ${w.inversions}`).join(", ") : "no percept waits behind a lower-priority dispatch" }),
      el("div", { class: "hint", text: "BoundedInversion bounds the waits; DispatchesWithinBudget bounds the dispatches of an iteration." }));
    const card = el("div", { class: "agent" + (a.next ? " current" : ""), "data-agent": a.name },
      el("div", { class: "agent-head" }, el("h2", { text: `${a.name} : ${a.type}` }),
        el("span", { class: "badge phase-" + a.phase, "data-phase": a.phase, text: "phase " + a.phase }),
        a.next ? el("span", { class: "badge", text: "runs next" }) : null),
      el("div", { class: "last", "data-last": a.last_action, text: "last rule: " + a.last }),
      el("div", { class: "queues" },
        queue("O2A queue (arrival order)", "o2a", a.o2a, itemChip),
        queue("Priority queue (dispatch order)", "pq", a.pq, perceptChip),
        queue("Message queue", "msgq", a.msgq, itemChip)),
      el("div", { class: "boxes" }, curBox, behBox,
        el("div", { class: "box" }, el("h4", { text: "Agent properties" }), props), ghost));
    PG.explain(card);
    return card;
  }
  PG.agentCard = agentCard;

  function renderNone() {
    $("agents-view").replaceChildren();
    $("next-rule").textContent = "no program running";
    $("counters").textContent = "";
    $("output").textContent = "";
    S.view = null;
    runAt = null; renderGutter();
    setButtons(false);
    renderEvents();
  }
  function setButtons(on) {
    for (const id of ["step", "iteration", "run", "back", "notify", "put", "send", "next-event"]) $(id).disabled = !on;
  }

  function render(r, full) {
    const v = r.view;
    if (!v) return;
    S.view = v;
    setButtons(true);
    $("counters").textContent = `${v.steps} rules · ${v.history} commands · ${v.variant}, ${v.tie}` +
      (v.variant === "budgeted" ? `, budget ${v.budget}` : "");
    // the next rule, and a choice when several are enabled
    const nr = $("next-rule");
    nr.replaceChildren();
    const cur = v.agents.find((a) => a.next);
    if (!cur) nr.append("next: nothing, every agent is idle (R3e)");
    else if (cur.rules.length <= 1) nr.append(`next (${cur.name}): ${cur.rules[0] || "?"}`);
    else {
      nr.append(`next (${cur.name}), choose: `);
      cur.rules.forEach((t, k) => nr.append(el("button", { "data-choice": k, text: t, onclick: () => act("step", k) })));
    }
    runAt = cur && cur.run_at ? cur.run_at : null;
    if (runAt) {
      const at = `${runAt.file}:${runAt.line}`;
      nr.append(" ", el("a", { href: "#", class: "src", "data-run-at": at, title: "show this line in the editor",
        onclick: (e) => { e.preventDefault(); gotoLine(runAt.file, runAt.line, 1); }, text: "▶ " + at }));
      // the line that runs next: shown, unless the student is typing
      if (document.activeElement !== $("source")) {
        if (runAt.file !== fileName() && S.files.some((f) => f.name === runAt.file)) { saveFile(); S.file = S.files.findIndex((f) => f.name === runAt.file); showFile(); }
        if (runAt.file === fileName()) scrollToLine(runAt.line);
      }
    }
    PG.explain(nr);
    renderGutter();
    // host agent list
    const sel = $("host-agent");
    const names = v.agents.map((a) => a.name);
    if ([...sel.options].map((o) => o.value).join() !== names.join()) {
      sel.replaceChildren(...names.map((n) => el("option", { value: n, text: n })));
    }
    $("agents-view").replaceChildren(...v.agents.map((a) => agentCard(a, (f, l) => gotoLine(f, l, 1))));
    renderTrace(full);
    const out = call("output");
    $("output").textContent = Array.isArray(out) ? out.join("\n") : out.error;
    renderExample();
    renderEvents();
    for (const f of PG.onRender) f(r);
    PG.saveSoon();
  }
  PG.render = render; PG.renderNone = renderNone;

  function renderTrace(full) {
    const box = $("trace");
    if (full) { box.replaceChildren(); S.traceShown = 0; }
    const t = call("trace", S.traceShown);
    for (const l of box.querySelectorAll(".fresh")) l.classList.remove("fresh");
    for (const line of t.lines || []) {
      box.append(el("div", { class: "line" + (S.traceShown === 0 ? " header" : " fresh"), text: line }));
      S.traceShown++;
    }
    box.scrollTop = box.scrollHeight;
  }

  // ------------------------------------------------------------- events

  function renderEvents() {
    const box = $("events-box");
    const offered = eventsOffered();
    box.hidden = !(S.mode === "play" || S.mode === "exercise") || offered.length === 0;
    $("events-title").firstChild.textContent = S.mode === "exercise" ? "The exercise's events " : "The example's events ";
    const ol = $("events");
    ol.replaceChildren(...offered.map((e, k) => el("li", {
      class: k < S.eventIndex ? "done" : k === S.eventIndex ? "next" : "", text: e,
      onclick: () => { S.eventIndex = k; doEvent(); } })));
  }
  // One line of an events file, done as run does it.
  function doEventLine(line) {
    const e = JSON.parse(line);
    if (e.notify !== undefined) return host({ kind: "notify", agent: e.agent, text: e.notify, priority: e.priority });
    if (e.put !== undefined) return host({ kind: "put", agent: e.agent, text: e.put });
    if (e.message !== undefined) return host({ kind: "message", agent: e.agent, text: e.message, performative: e.performative || "inform", during: e.during || "" });
    if (e.run === "idle") return act("runIdle", 100000);
    if (typeof e.run === "number") return act("rounds", e.run);
    if (e.run && typeof e.run.rules === "number") return act("rules", e.run.rules);
    return null;
  }
  function doEvent() {
    if (eventsOffered().length === 0) { say("no events for these agents", "error"); return; }
    if (S.eventIndex >= S.events.length) { say("no event left", "info"); return; }
    const line = S.events[S.eventIndex];
    S.eventIndex++;
    doEventLine(line);
    renderEvents();
    PG.saveSoon();
  }
  PG.doEventLine = doEventLine;

  // ------------------------------------------------------------ replays

  function loadReplay(id) {
    const r = S.replays.find((x) => x.id === id);
    if (!r) return;
    S.replay = r; S.replayStep = 0; S.replayOk = [];
    S.example = null;
    $("replay").value = id;
    S.files = r.files.map((f) => ({ name: f.name, text: f.text })); S.file = 0;
    $("example-about").textContent = "The program of the replay " + r.id + ": the model's percepts, priorities and handlers in Jadescript.";
    PG.explain($("example-about"));
    setSettings(r);
    showFile();
    S.events = [];
    start();
    renderReplay();
  }
  function renderReplay() {
    const r = S.replay;
    if (!r) return;
    $("replay-finding").textContent = r.finding;
    $("replay-command").textContent = r.command;
    const ol = $("replay-steps");
    ol.replaceChildren(...r.steps.map((st, k) => el("li", {
      class: k < S.replayStep ? "done" : k === S.replayStep ? "current" : "", "data-step": k },
      el("span", { class: "tla", text: st.tla + (k < S.replayStep ? (S.replayOk[k] ? " ✓" : " ✗") : "") }), st.say)));
    const cur = ol.querySelector(".current");
    if (cur) cur.scrollIntoView({ block: "nearest" });
    const fin = $("replay-final");
    // TLC prints a state only when it finds a property violated; in a model
    // where every property holds (MCBudgeted) the state is the one these
    // steps reach, checked all the same.
    const whose = r.violated ? "TLC's last state" : "The state these steps reach (TLC prints none for " + r.id + ": every property holds)";
    if (S.replayStep < r.steps.length) {
      fin.className = "final pending";
      fin.textContent = whose + ": " + r.final;
    } else {
      const c = call("replayCheck", r.id);
      fin.className = "final " + (c.ok ? "ok" : "bad");
      fin.textContent = r.violated
        ? (c.ok ? "✓ reached the state TLC printed: " : "✗ not TLC's state: " + c.error + ". TLC: ") + r.final
        : (c.ok ? "✓ reached the state these steps reach in " + r.id + " (TLC prints no state: nothing is violated): "
          : "✗ not the state these steps reach: " + c.error + ". Expected: ") + r.final;
    }
    $("replay-next").disabled = S.replayStep >= r.steps.length;
    PG.explain($("replay-panel"));
  }
  function replayNext() {
    const r = S.replay;
    if (!r || S.replayStep >= r.steps.length) return;
    const res = act("replayStep", r.id, S.replayStep);
    const last = res && res.view && res.view.agents[0] ? res.view.agents[0].last_action : "";
    S.replayOk[S.replayStep] = !!res && res.ok && !res.error && last === r.steps[S.replayStep].tla;
    S.replayStep++;
    say(r.steps[S.replayStep - 1].tla + ": " + r.steps[S.replayStep - 1].say, "info");
    renderReplay();
    PG.saveSoon();
  }
  PG.loadReplay = loadReplay; PG.replayNext = replayNext; PG.renderReplay = renderReplay;

  // ------------------------------------------------------- workspaces

  // What a tab keeps while another is shown: the program, the settings,
  // the events, the message, and its session (in its own slot of jsref).
  function saveWs() {
    const name = S.wsName;
    if (!name) return;
    saveFile();
    S.ws[name] = {
      slot: name, files: S.files, file: S.file, example: S.example, events: S.events, eventIndex: S.eventIndex,
      loaded: S.loaded, started: S.started, message: S.message, messageKind: S.messageKind,
      settings: Object.assign({ agents: agentLines() }, readSettings()),
      status: $("load-status").textContent,
    };
  }
  function loadWs(name) {
    S.wsName = name;
    const w = S.ws[name];
    use(name);
    if (!w) { S.files = []; S.file = 0; S.example = null; S.events = []; S.eventIndex = 0; S.loaded = false; S.started = null; showFile(); renderNone(); return false; }
    S.files = w.files; S.file = w.file; S.example = w.example; S.events = w.events; S.eventIndex = w.eventIndex;
    S.loaded = w.loaded; S.started = w.started;
    setSettings(w.settings);
    showFile();
    status(w.status || "");
    checkNow();
    S.traceShown = 0;
    const r = S.loaded ? call("view") : null;
    if (r && r.ok) render(r, true); else { S.loaded = false; renderNone(); }
    say(w.message, w.messageKind);
    return true;
  }
  PG.saveWs = saveWs; PG.loadWs = loadWs;

  // -------------------------------------------------------------- modes

  PG.modes.play = {
    ws: "play", panels: [],
    enter(fresh) { if (fresh) loadExample("robome"); },
  };
  PG.modes.replay = {
    ws: "replay", panels: ["replay-panel"],
    // fresh: the tab is new, or comes back from storage or a link with the
    // step it had reached (S.replayPending): the steps are done again
    enter(fresh) {
      if (!fresh && S.replay) { renderReplay(); return; }
      loadReplay($("replay").value || S.replays[0].id);
      const n = S.replayPending || 0;
      S.replayPending = 0;
      for (let k = 0; k < n; k++) replayNext();
    },
  };
  PG.modes.corridor = {
    ws: null, panels: ["corridor-panel"],
    enter() { if (window.corridorView) window.corridorView.show(); },
  };

  function setMode(m) {
    const mode = PG.modes[m];
    if (!mode) return;
    if (S.mode !== m && PG.modes[S.mode] && PG.modes[S.mode].ws && S.wsName === PG.modes[S.mode].ws) saveWs();
    if (PG.modes[S.mode] && PG.modes[S.mode].leave) PG.modes[S.mode].leave();
    S.mode = m;
    document.body.className = "mode-" + m;
    for (const b of document.querySelectorAll("button.mode[data-mode]")) b.classList.toggle("active", b.dataset.mode === m);
    const all = new Set(Object.values(PG.modes).flatMap((x) => x.panels || []));
    for (const p of all) $(p).hidden = !(mode.panels || []).includes(p);
    let fresh = false;
    if (mode.ws) fresh = !loadWs(mode.ws);
    mode.enter(fresh);
    renderEvents();
    PG.saveSoon();
  }
  PG.setMode = setMode;

  // --------------------------------------------------------------- init

  function init() {
    if (!window.jsref) { document.body.prepend(el("p", { class: "message error", text: "jsref.js did not load: run make playground" })); return false; }
    S.examples = call("examples");
    S.replays = call("replays");
    const sel = $("example");
    const group = (label, xs) => el("optgroup", { label }, ...xs.map((x) => el("option", { value: x.id, text: x.title, title: x.about })));
    sel.append(group("The paper", S.examples.slice(0, 2)), group("Conformance vectors (conformance/)", S.examples.slice(2)));
    $("replay").replaceChildren(...S.replays.map((r) => el("option", { value: r.id, text: `${r.title} (${r.id})` })));

    sel.addEventListener("change", () => { if (sel.value) loadExample(sel.value); });
    $("replay").addEventListener("change", () => loadReplay($("replay").value));
    $("source").addEventListener("input", () => { renderGutter(); checkSoon(); });
    $("source").addEventListener("scroll", syncScroll);
    window.addEventListener("resize", renderGutter);
    $("source").addEventListener("keydown", (e) => {
      if (e.key === "Tab") {   // a tab is the layout's indentation
        e.preventDefault();
        const ta = e.target, a = ta.selectionStart;
        ta.setRangeText("\t", a, ta.selectionEnd, "end");
        renderGutter(); checkSoon();
      }
    });
    for (const id of ["variant", "tie"]) $(id).addEventListener("change", settingsChanged);
    for (const id of ["budget", "capacity", "seed"]) $(id).addEventListener("change", settingsChanged);
    $("agents").addEventListener("input", () => { if (S.loaded) status("edited: Check and start creates these agents"); PG.saveSoon(); });
    $("load").addEventListener("click", () => { S.eventIndex = 0; start(); });
    $("step").addEventListener("click", () => act("step", 0));
    $("iteration").addEventListener("click", () => act("iteration"));
    $("run").addEventListener("click", () => act("runIdle", 5000));
    $("back").addEventListener("click", () => {
      const r = act("back");
      if (r && r.undone && S.mode === "replay" && S.replay && S.replayStep > 0) { S.replayStep--; renderReplay(); }
    });
    const agentName = () => $("host-agent").value;
    const prio = () => { const v = $("notify-priority").value.trim(); return v === "" ? undefined : parseInt(v, 10); };
    $("notify").addEventListener("click", () => host({ kind: "notify", agent: agentName(), text: $("notify-text").value, priority: prio() }));
    $("put").addEventListener("click", () => host({ kind: "put", agent: agentName(), text: $("put-text").value }));
    $("send").addEventListener("click", () => host({ kind: "message", agent: agentName(), text: $("msg-text").value, performative: $("perf").value }));
    for (const [input, button] of [["notify-text", "notify"], ["notify-priority", "notify"], ["put-text", "put"], ["msg-text", "send"]])
      $(input).addEventListener("keydown", (e) => { if (e.key === "Enter") $(button).click(); });
    $("next-event").addEventListener("click", doEvent);
    $("replay-next").addEventListener("click", replayNext);
    $("replay-all").addEventListener("click", () => { while (S.replay && S.replayStep < S.replay.steps.length) replayNext(); });
    $("replay-restart").addEventListener("click", () => loadReplay(S.replay ? S.replay.id : $("replay").value));
    for (const b of document.querySelectorAll("button.mode[data-mode]")) b.addEventListener("click", () => setMode(b.dataset.mode));
    const toggle = (box) => () => { for (const id of ["help", "glossary", "share"]) if (id !== box) $(id).hidden = true; $(box).hidden = !$(box).hidden; };
    $("help-toggle").addEventListener("click", toggle("help"));
    $("glossary-toggle").addEventListener("click", toggle("glossary"));
    $("share-toggle").addEventListener("click", () => { toggle("share")(); if (!$("share").hidden) PG.showLink(); });
    document.addEventListener("keydown", (e) => {
      const t = e.target.tagName;
      if (t === "TEXTAREA" || t === "INPUT" || t === "SELECT" || e.ctrlKey || e.metaKey || e.altKey) return;
      const keys = (PG.modes[S.mode] && PG.modes[S.mode].keys) || { s: "step", i: "iteration", r: "run", b: "back", n: "replay-next" };
      const k = keys[e.key];
      if (k && !$(k).disabled && !$(k).closest("[hidden]") && (k !== "replay-next" || S.mode === "replay")) { e.preventDefault(); $(k).click(); }
    });
    return true;
  }

  // Runs once every script of the page is loaded: the parts initialise,
  // then the session is restored (a link, or this browser's storage) or the
  // page opens on the RoboMe example.
  PG.start = function () {
    if (!init()) return;
    for (const f of PG.onInit) f();
    const restored = PG.restoreSaved ? PG.restoreSaved() : false;
    if (!restored) { S.mode = "play"; setMode("play"); }
    for (const f of PG.onStart) f();
    document.body.dataset.ready = "yes";
  };
  PG.saveSoon = PG.saveSoon || (() => {});
  PG.explain = PG.explain || (() => {});
  PG.gotoLine = gotoLine; PG.showFile = showFile; PG.checkNow = checkNow; PG.renderEvents = renderEvents;
  PG.showDiagnostics = showDiagnostics; PG.status = status; PG.sameFiles = sameFiles;
})();
