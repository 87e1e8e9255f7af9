// The playground page: the user interface only. Everything about Jadescript
// (parsing, type checking, the agent loop, evaluation, the trace) is done by
// window.jsref, the project's OCaml libraries compiled with js_of_ocaml
// (playground/js/jsref.ml); this script shows what they answer.
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

  const S = {
    examples: [], replays: [], example: null, files: [], file: 0,
    loaded: false, traceShown: 0, events: [], eventIndex: 0,
    mode: "play", replay: null, replayStep: 0, replayOk: [], view: null,
  };
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
  let diagLines = {};
  function renderGutter() {
    const n = $("source").value.split("\n").length;
    const g = $("gutter");
    g.replaceChildren();
    const name = S.files[S.file] ? S.files[S.file].name : "";
    for (let i = 1; i <= n; i++) {
      const msg = (diagLines[name] || {})[i];
      g.append(msg ? el("span", { class: "err", title: msg, text: String(i) }) : String(i), "\n");
    }
    g.scrollTop = $("source").scrollTop;
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
  function gotoLine(file, line, col) {
    const i = S.files.findIndex((f) => f.name === file);
    if (i < 0) return;
    saveFile(); S.file = i; showFile();
    const ta = $("source");
    const lines = ta.value.split("\n");
    let pos = 0;
    for (let k = 0; k < line - 1 && k < lines.length; k++) pos += lines[k].length + 1;
    pos += Math.max(0, col - 1);
    ta.focus(); ta.setSelectionRange(pos, pos);
    ta.scrollTop = Math.max(0, (line - 5) * 18);
  }
  let checkTimer = null;
  function checkSoon() {
    clearTimeout(checkTimer);
    if (S.loaded) $("load-status").textContent = "edited: Check and start runs the new text";
    checkTimer = setTimeout(() => {
      saveFile();
      const ds = call("check", JSON.stringify({ files: S.files }));
      showDiagnostics(Array.isArray(ds) ? ds : [ds.error], "the program type-checks");
    }, 250);
  }

  // ---------------------------------------------------------- examples

  function setSettings(x) {
    $("agents").value = (x.agents || []).join("\n");
    $("variant").value = x.variant || "reference";
    $("tie").value = x.tie || "stable";
    $("budget").value = x.budget || 1;
    $("capacity").value = x.o2a_capacity == null ? "" : x.o2a_capacity;
    $("seed").value = x.seed == null ? "" : x.seed;
    $("budget").disabled = $("variant").value !== "budgeted";
  }
  function loadExample(id) {
    const x = S.examples.find((e) => e.id === id);
    if (!x) return;
    S.example = x;
    S.files = x.files.map((f) => ({ name: f.name, text: f.text }));
    S.file = 0;
    $("example").value = id;
    $("example-about").textContent = x.about;
    setSettings(x);
    showFile();
    S.events = x.events || [];
    start();
  }

  function setup() {
    saveFile();
    const num = (v) => (v.trim() === "" ? null : parseInt(v, 10));
    return {
      files: S.files,
      agents: $("agents").value.split("\n").map((s) => s.trim()).filter((s) => s !== ""),
      variant: $("variant").value, tie: $("tie").value,
      budget: Math.max(1, num($("budget").value) || 1),
      o2a_capacity: num($("capacity").value), seed: num($("seed").value),
      fuel: S.example && S.example.fuel ? S.example.fuel : null,
      max_steps: S.example && S.example.max_steps ? S.example.max_steps : null,
    };
  }

  // ------------------------------------------------------------ session

  function start() {
    const r = call("create", JSON.stringify(setup()));
    S.traceShown = 0;
    $("trace").replaceChildren();
    S.eventIndex = 0;
    if (!r.ok) {
      S.loaded = false;
      showDiagnostics(r.errors || [r.error]);
      $("load-status").textContent = "not started: fix the errors above";
      renderNone();
      return false;
    }
    S.loaded = true;
    showDiagnostics([], "the program type-checks; the agents are created");
    $("load-status").textContent = "started " + new Date().toLocaleTimeString();
    render(r, true);
    return true;
  }

  function say(text, kind) { const m = $("message"); m.textContent = text || ""; m.className = "message " + (kind || ""); }

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

  function agentCard(a) {
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
      a.cur.todo.forEach((h, k) => todo.append(el("li", {
        class: (k === 0 ? "first" : "") + (h.active ? "" : " gone"),
        "data-handler": `${h.instance}.${h.handler}`,
        title: h.active ? "" : "its behaviour was deactivated: it will be skipped (R4b)",
      }, `${h.behaviour} #${h.instance}, handler ${h.handler} `, el("span", { class: "src", text: `${h.at}: ${h.source}` }))));
      curBox = el("div", { class: "box", "data-box": "dispatch" },
        el("h4", { text: "Dispatch in progress" }),
        el("div", { class: "chips" }, perceptChip(a.cur.entry),
          el("span", { class: "hint", text: a.cur.applied ? " a handler ran" : " no handler ran yet" })),
        el("h4", { text: a.cur.todo.length ? "Handlers still to try (the snapshot, R4a)" : "No handler left: EndDispatch next" }), todo);
    } else {
      curBox = el("div", { class: "box", "data-box": "dispatch" }, el("h4", { text: "Dispatch in progress" }),
        el("span", { class: "empty", text: "none" }));
    }
    const props = el("table", { class: "props", "data-box": "props" });
    for (const p of a.props) props.append(el("tr", {}, el("td", { text: p.name }), el("td", { text: p.value })));
    if (a.props.length === 0) props.append(el("tr", {}, el("td", { class: "empty", text: "no properties" })));
    const waits = a.waits.filter((w) => w.inversions > 0);
    const ghost = el("div", { class: "box", "data-box": "ghosts" }, el("h4", { text: "Counters (the spec's ghosts)" }),
      el("div", { class: "hint", text: `dispatched this iteration: ${a.dispatched} · percepts done: ${a.done}` }),
      el("div", { class: "hint", text: waits.length ? "waiting behind lower-priority dispatches: " +
        waits.map((w) => `#${w.seq} (priority ${w.priority}) ${w.inversions}`).join(", ") : "no percept waits behind a lower-priority dispatch" }));
    const card = el("div", { class: "agent" + (a.next ? " current" : ""), "data-agent": a.name },
      el("div", { class: "agent-head" }, el("h2", { text: `${a.name} : ${a.type}` }),
        el("span", { class: "badge phase-" + a.phase, "data-phase": a.phase, text: "phase " + a.phase }),
        a.next ? el("span", { class: "badge", text: "runs next" }) : null),
      el("div", { class: "last", "data-last": a.last_action, text: "last rule: " + a.last }),
      el("div", { class: "queues" },
        queue("O2A queue (arrival order)", "o2a", a.o2a, itemChip),
        queue("Priority queue (dispatch order)", "pq", a.pq, perceptChip, a.phase === "idle" ? "empty" : "empty"),
        queue("Message queue", "msgq", a.msgq, itemChip)),
      el("div", { class: "boxes" }, curBox, behBox,
        el("div", { class: "box" }, el("h4", { text: "Agent properties" }), props), ghost));
    return card;
  }

  function renderNone() {
    $("agents-view").replaceChildren();
    $("next-rule").textContent = "no program running";
    $("counters").textContent = "";
    $("output").textContent = "";
    setButtons(false);
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
    // host agent list
    const sel = $("host-agent");
    const names = v.agents.map((a) => a.name);
    if ([...sel.options].map((o) => o.value).join() !== names.join()) {
      sel.replaceChildren(...names.map((n) => el("option", { value: n, text: n })));
    }
    $("agents-view").replaceChildren(...v.agents.map(agentCard));
    renderTrace(full);
    const out = call("output");
    $("output").textContent = Array.isArray(out) ? out.join("\n") : out.error;
    renderEvents();
  }

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
    box.hidden = S.mode !== "play" || S.events.length === 0;
    const ol = $("events");
    ol.replaceChildren(...S.events.map((e, k) => el("li", {
      class: k < S.eventIndex ? "done" : k === S.eventIndex ? "next" : "", text: e,
      onclick: () => { S.eventIndex = k; doEvent(); } })));
  }
  function doEvent() {
    if (S.eventIndex >= S.events.length) { say("no event left", "info"); return; }
    const e = JSON.parse(S.events[S.eventIndex]);
    S.eventIndex++;
    if (e.notify !== undefined) host({ kind: "notify", agent: e.agent, text: e.notify, priority: e.priority });
    else if (e.put !== undefined) host({ kind: "put", agent: e.agent, text: e.put });
    else if (e.message !== undefined) host({ kind: "message", agent: e.agent, text: e.message, performative: e.performative || "inform" });
    else if (e.run === "idle") act("runIdle", 100000);
    else if (typeof e.run === "number") act("rounds", e.run);
    else if (e.run && typeof e.run.rules === "number") act("rules", e.run.rules);
    renderEvents();
  }

  // ------------------------------------------------------------ replays

  function loadReplay(id) {
    const r = S.replays.find((x) => x.id === id);
    if (!r) return;
    S.replay = r; S.replayStep = 0; S.replayOk = [];
    S.example = null;
    $("replay").value = id;
    S.files = r.files.map((f) => ({ name: f.name, text: f.text })); S.file = 0;
    $("example-about").textContent = "The program of the replay " + r.id + ": the model's percepts, priorities and handlers in Jadescript.";
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
    if (S.replayStep < r.steps.length) {
      fin.className = "final pending";
      fin.textContent = "TLC's last state: " + r.final;
    } else {
      const c = call("replayCheck", r.id);
      fin.className = "final " + (c.ok ? "ok" : "bad");
      fin.textContent = (c.ok ? "✓ reached the state TLC printed: " : "✗ not TLC's state: " + c.error + ". TLC: ") + r.final;
    }
    $("replay-next").disabled = S.replayStep >= r.steps.length;
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
  }

  // -------------------------------------------------------------- modes

  function setMode(m) {
    S.mode = m;
    document.body.className = "mode-" + m;
    for (const b of document.querySelectorAll("button.mode[data-mode]")) b.classList.toggle("active", b.dataset.mode === m);
    $("replay-panel").hidden = m !== "replay";
    $("corridor-panel").hidden = m !== "corridor";
    if (m === "replay" && (!S.replay || !S.loaded)) loadReplay($("replay").value || S.replays[0].id);
    if (m === "play" && S.replay) { S.replay = null; loadExample($("example").value); }
    if (m === "corridor" && window.corridorView) window.corridorView.show();
    renderEvents();
  }

  // --------------------------------------------------------------- init

  function init() {
    if (!window.jsref) { document.body.prepend(el("p", { class: "message error", text: "jsref.js did not load: run make playground" })); return; }
    S.examples = call("examples");
    S.replays = call("replays");
    const sel = $("example");
    const group = (label, xs) => el("optgroup", { label }, ...xs.map((x) => el("option", { value: x.id, text: x.title })));
    sel.append(group("The paper", S.examples.slice(0, 2)), group("Conformance vectors (conformance/)", S.examples.slice(2)));
    $("replay").replaceChildren(...S.replays.map((r) => el("option", { value: r.id, text: `${r.title} (${r.id})` })));

    sel.addEventListener("change", () => loadExample(sel.value));
    $("replay").addEventListener("change", () => loadReplay($("replay").value));
    $("source").addEventListener("input", () => { renderGutter(); checkSoon(); });
    $("source").addEventListener("scroll", () => { $("gutter").scrollTop = $("source").scrollTop; });
    $("source").addEventListener("keydown", (e) => {
      if (e.key === "Tab") {   // a tab is the layout's indentation
        e.preventDefault();
        const ta = e.target, a = ta.selectionStart;
        ta.setRangeText("\t", a, ta.selectionEnd, "end");
        renderGutter(); checkSoon();
      }
    });
    $("variant").addEventListener("change", () => { $("budget").disabled = $("variant").value !== "budgeted"; });
    $("load").addEventListener("click", () => { S.eventIndex = 0; start(); });
    $("step").addEventListener("click", () => act("step", 0));
    $("iteration").addEventListener("click", () => act("iteration"));
    $("run").addEventListener("click", () => act("runIdle", 5000));
    $("back").addEventListener("click", () => {
      const r = act("back");
      if (r && r.undone) {
        if (S.replay && S.replayStep > 0) { S.replayStep--; renderReplay(); }
        else if (S.eventIndex > 0 && S.events.length) { /* the events list stays where it is */ }
      }
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
    $("help-toggle").addEventListener("click", () => { $("help").hidden = !$("help").hidden; });
    document.addEventListener("keydown", (e) => {
      const t = e.target.tagName;
      if (t === "TEXTAREA" || t === "INPUT" || t === "SELECT" || e.ctrlKey || e.metaKey || e.altKey) return;
      const k = { s: "step", i: "iteration", r: "run", b: "back", n: "replay-next" }[e.key];
      if (k && !$(k).disabled && (k !== "replay-next" || S.mode === "replay")) { e.preventDefault(); $(k).click(); }
    });
    setMode("play");
    loadExample("robome");
    document.body.dataset.ready = "yes";
  }

  init();
})();
