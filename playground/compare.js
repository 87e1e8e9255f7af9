// Side by side: the Playground's program and host events on two loops (or
// two tie policies, or two budgets), in two columns that step together:
// each command is done on both sides (one rule each, an iteration each,
// until idle, a host action on both, a step back on both). Each side is a
// session of its own (jsref's slots "left" and "right"). The two traces are
// compared event by event, the header aside (it names the loop); the first
// event where they differ is marked in the picture (one box per event, a
// row per side) and in both traces.
"use strict";

(function () {
  const PG = window.PG;
  if (!PG) return;
  const { $, el, call, use, S } = PG;
  const SIDES = ["left", "right"];
  const PRESETS = {
    "reference|budgeted": [{ variant: "reference" }, { variant: "budgeted", budget: 1 }],
    "reference|printed": [{ variant: "reference" }, { variant: "printed" }],
    "reference|native": [{ variant: "reference" }, { variant: "native" }],
    "stable|unstable": [{ variant: "reference", tie: "stable" }, { variant: "reference", tie: "unstable" }],
    "budget1|budget2": [{ variant: "budgeted", budget: 1 }, { variant: "budgeted", budget: 2 }],
  };
  const C = {
    preset: "reference|budgeted", left: null, right: null, program: null, events: [], eventIndex: 0,
    loaded: false, views: {}, diff: null, pending: null,
  };
  PG.compare = C;
  const norm = (x) => ({ variant: x.variant || "reference", tie: x.tie || "stable", budget: x.budget || 1 });
  const describe = (x) => x.variant + (x.variant === "budgeted" ? ` (budget ${x.budget})` : "") + (x.tie === "unstable" ? ", unstable ties" : "");

  // The Playground's program: the one it started, else the one in its editor.
  function playProgram() {
    const w = S.ws.play;
    if (!w) return null;
    const s = w.started || { files: w.files, agents: w.settings.agents, o2a_capacity: w.settings.o2a_capacity, seed: w.settings.seed };
    return { files: s.files.map((f) => ({ name: f.name, text: f.text })), agents: s.agents,
      o2a_capacity: s.o2a_capacity == null ? null : s.o2a_capacity, seed: s.seed == null ? null : s.seed,
      fuel: s.fuel || null, max_steps: s.max_steps || null, example: w.example ? w.example.id : null };
  }
  const key = (p) => JSON.stringify(p && [p.files, p.agents, p.o2a_capacity, p.seed]);
  const setupOf = (side) => Object.assign({}, C.program, norm(C[side]));

  // Starts both sides afresh; [hostActions]: done again on both.
  function restart(hostActions) {
    const out = {};
    for (const side of SIDES) {
      use(side);
      out[side] = call("restore", JSON.stringify(setupOf(side)), JSON.stringify(hostActions || []));
    }
    C.loaded = SIDES.every((s) => out[s].ok);
    if (!hostActions) C.eventIndex = 0;
    render(out, "");
  }
  function hostActions() {
    use("left");
    const h = call("export");
    return Array.isArray(h) ? h.filter((x) => x.agent !== undefined) : [];
  }

  function both(fn, ...args) {
    if (!C.loaded) return;
    const out = {};
    for (const side of SIDES) { use(side); out[side] = call(fn, ...args); }
    const said = SIDES.map((s) => {
      const r = out[s];
      if (!r.ok) return `${s}: ${r.error}`;
      if (r.error) return `${s}: ${r.error}`;
      if (r.outcome === "idle") return `${s}: idle`;
      if (fn === "runIdle") return `${s}: ${r.taken} rules` + (r.outcome === "stepped" ? " (not idle: the printed loop never idles, D4)" : "");
      if (fn === "back") return `${s}: ${r.undone ? "undone" : "nothing to undo"}`;
      return null;
    }).filter((x) => x);
    render(out, said.join(" · "));
  }

  // -------------------------------------------------------------- render

  const KIND = {
    notify: ["N", "notify"], refused: ["R", "notify"], put: ["P", "notify"], deliver: ["M", "notify"],
    transfer: ["T", "transfer"], transfer_one: ["T", "transfer"], transfer_spin: ["T", "transfer"], transfer_end: ["T", "transfer"],
    dequeue: ["D", "dequeue"], handle: ["H", "handle"], skip: ["S", "skip"], end_dispatch: ["E", "end"], discard: ["X", "discard"],
    behaviour_step: ["B", "step"], next_iteration: ["n", "step"], idle: ["I", "idle"],
  };
  const kindOf = (ev) => KIND[ev] || ["·", "body"];
  function summary(line) {
    if (line == null) return "nothing more (idle)";
    let e;
    try { e = JSON.parse(line); } catch (_) { return line; }
    const entry = e.percept !== undefined ? `${e.percept} (priority ${e.priority}, #${e.seq})` : "";
    switch (e.event) {
      case "dequeue": return "dequeue " + entry;
      case "notify": return "notify " + entry;
      case "handle": return `handle ${e.percept} #${e.seq} by ${e.behaviour} handler ${e.handler}`;
      case "skip": return `skip ${e.behaviour} handler ${e.handler}`;
      case "end_dispatch": return `end of the dispatch of #${e.seq}`;
      case "discard": return `discard #${e.seq}`;
      case "transfer": return `transfer (${e.moved} moved)`;
      case "behaviour_step": return `behaviour step of ${e.behaviour}` + (e.message ? " taking " + (e.message.percept || e.message.content) : "");
      case "log": return `log "${e.text}"`;
      default: return e.event + (entry ? " " + entry : "");
    }
  }
  const body = (lines) => lines.slice(1);   // the header names the loop: it always differs

  function firstDifference(L, R, idle) {
    const n = Math.min(L.length, R.length);
    for (let k = 0; k < n; k++) if (L[k] !== R[k]) return k;
    if (L.length !== R.length && (L.length < R.length ? idle.left : idle.right)) return n;
    return null;
  }

  function render(out, said) {
    const traces = {}, idle = {};
    for (const side of SIDES) {
      const r = out[side];
      if (r && r.view) C.views[side] = r.view;
      use(side);
      const t = C.loaded ? call("trace", 0) : { lines: [] };
      traces[side] = body(t.lines || []);
      idle[side] = C.views[side] ? C.views[side].all_idle : true;
    }
    const k = C.loaded ? firstDifference(traces.left, traces.right, idle) : null;
    C.diff = k;
    const d = $("cmp-diff");
    d.dataset.index = k == null ? "" : String(k);
    if (!C.loaded) {
      const errs = SIDES.flatMap((s) => (out[s] && !out[s].ok ? out[s].errors || [out[s].error] : []));
      d.textContent = "Not started: " + (errs.join("; ") || "the Playground tab has no program");
      d.className = "diff bad";
    } else if (k == null) {
      d.className = "diff same";
      d.textContent = `No difference so far: the ${Math.min(traces.left.length, traces.right.length)} events of both traces are the same.`;
    } else {
      d.className = "diff differ";
      d.textContent = `The traces differ first at event ${k + 1} (line ${k + 2} of each trace): ` +
        `left, ${describe(C.left)}: ${summary(traces.left[k])}; right, ${describe(C.right)}: ${summary(traces.right[k])}.`;
    }
    if (said) d.append(el("div", { class: "hint", text: said }));
    PG.explain(d);
    timeline(traces, k);
    for (const side of SIDES) column(side, traces[side], k);
    renderEvents();
    const names = C.views.left ? C.views.left.agents.map((a) => a.name) : [];
    const sel = $("cmp-host-agent");
    if ([...sel.options].map((o) => o.value).join() !== names.join()) sel.replaceChildren(...names.map((n) => el("option", { value: n, text: n })));
    for (const id of ["cmp-step", "cmp-iteration", "cmp-run", "cmp-back", "cmp-notify", "cmp-next-event"]) $(id).disabled = !C.loaded;
    const p = C.program;
    $("compare-program").textContent = p ? `Program: ${p.files.map((f) => f.name).join(", ")}, agents ${p.agents.join(", ")}: the Playground tab's (change it there).` : "";
    PG.saveSoon();
  }

  const NS = "http://www.w3.org/2000/svg";
  const svg = (tag, attrs, text) => {
    const e = document.createElementNS(NS, tag);
    for (const [a, v] of Object.entries(attrs || {})) e.setAttribute(a, v);
    if (text != null) e.textContent = text;
    return e;
  };
  // One row of boxes per side, one box per event, the first difference marked.
  function timeline(traces, k) {
    const s = $("cmp-timeline");
    const W = 22, G = 2, X0 = 90;
    const n = Math.max(traces.left.length, traces.right.length, 1);
    const width = X0 + n * (W + G) + 10;
    s.setAttribute("viewBox", `0 0 ${width} 86`);
    s.setAttribute("width", width);
    s.setAttribute("height", 86);
    s.replaceChildren();
    SIDES.forEach((side, row) => {
      const y = 8 + row * 38;
      s.append(svg("text", { x: 4, y: y + 16, class: "row-label" }, side));
      s.append(svg("text", { x: 4, y: y + 28, class: "row-sub" }, describe(C[side]).split(" (")[0]));
      traces[side].forEach((line, i) => {
        let ev = "";
        try { ev = JSON.parse(line).event; } catch (_) { ev = ""; }
        const [letter, cls] = kindOf(ev);
        const g = svg("g", { class: "ev k-" + cls + (k != null && i === k ? " first-diff" : k != null && i > k ? " after" : ""), "data-index": i });
        g.append(svg("title", {}, `event ${i + 1}: ${summary(line)}\n${line}`));
        g.append(svg("rect", { x: X0 + i * (W + G), y, width: W, height: 30, rx: 4 }));
        g.append(svg("text", { x: X0 + i * (W + G) + W / 2, y: y + 20 }, letter));
        s.append(g);
      });
    });
    if (k != null) {
      const x = X0 + k * (W + G) - 1;
      s.append(svg("rect", { x, y: 3, width: W + 2, height: 80, rx: 5, class: "diff-mark" }));
      const wrap = s.parentElement;
      if (wrap && wrap.scrollWidth > wrap.clientWidth) wrap.scrollLeft = Math.max(0, x - wrap.clientWidth / 2);
    }
  }

  function column(side, lines, k) {
    const col = $("cmp-" + side);
    const v = C.views[side];
    const x = C[side];
    const sel = (id, opts, value) => {
      const e = el("select", { id, "data-setting": id.split("-").pop() }, ...opts.map(([val, text]) => el("option", { value: val, text })));
      e.value = value;
      return e;
    };
    const head = el("div", { class: "cmp-head" },
      el("h3", { text: side === "left" ? "Left" : "Right" }),
      el("label", { for: `cmp-${side}-variant`, text: "loop" }),
      sel(`cmp-${side}-variant`, [["reference", "reference"], ["printed", "printed"], ["budgeted", "budgeted"], ["native", "native"]], x.variant),
      el("label", { for: `cmp-${side}-tie`, text: "ties" }),
      sel(`cmp-${side}-tie`, [["stable", "stable"], ["unstable", "unstable"]], x.tie),
      el("label", { for: `cmp-${side}-budget`, text: "budget" }),
      el("input", { id: `cmp-${side}-budget`, type: "number", min: "1", value: String(x.budget) }));
    for (const e of head.querySelectorAll("select, input")) e.addEventListener("change", () => {
      C[side] = norm({ variant: $(`cmp-${side}-variant`).value, tie: $(`cmp-${side}-tie`).value, budget: Math.max(1, parseInt($(`cmp-${side}-budget`).value, 10) || 1) });
      C.preset = "custom"; $("compare-preset").value = "custom";
      restart(hostActions());
    });
    const cur = v && v.agents.find((a) => a.next);
    const next = el("div", { class: "next-rule", "data-next": side },
      !v ? "not started" : cur ? `next (${cur.name}): ${cur.rules.join(" | ") || "?"}` : "next: nothing, every agent is idle (R3e)");
    const trace = el("div", { class: "cmp-trace", "data-trace": side }, ...lines.map((l, i) =>
      el("div", { class: "line" + (k != null && i === k ? " differ" : ""), "data-index": i, text: l })));
    col.replaceChildren(head, next, ...(v ? v.agents.map((a) => PG.agentCard(a, null)) : []),
      el("h4", { text: `Trace (${lines.length} events after the header)` }), trace);
    PG.explain(next);
    const mark = trace.querySelector(".differ");
    if (mark) trace.scrollTop = Math.max(0, mark.offsetTop - trace.offsetTop - 60);
    else trace.scrollTop = trace.scrollHeight;
  }

  function renderEvents() {
    const ol = $("cmp-events");
    ol.replaceChildren(...C.events.map((e, i) => el("li", { class: i < C.eventIndex ? "done" : i === C.eventIndex ? "next" : "", text: e })));
    ol.hidden = C.events.length === 0;
    $("cmp-next-event").hidden = C.events.length === 0;
  }

  function nextEvent() {
    if (C.eventIndex >= C.events.length) return;
    const e = JSON.parse(C.events[C.eventIndex++]);
    if (e.notify !== undefined) both("host", JSON.stringify({ kind: "notify", agent: e.agent, text: e.notify, priority: e.priority }));
    else if (e.put !== undefined) both("host", JSON.stringify({ kind: "put", agent: e.agent, text: e.put }));
    else if (e.message !== undefined) both("host", JSON.stringify({ kind: "message", agent: e.agent, text: e.message, performative: e.performative || "inform", during: e.during || "" }));
    else if (e.run === "idle") both("runIdle", 100000);
    else if (typeof e.run === "number") both("rounds", e.run);
    else if (e.run && typeof e.run.rules === "number") both("rules", e.run.rules);
  }

  function applyPreset(p) {
    C.preset = p;
    if (PRESETS[p]) { C.left = norm(PRESETS[p][0]); C.right = norm(PRESETS[p][1]); }
  }

  PG.modes.compare = {
    ws: null, panels: ["compare-panel"],
    keys: { s: "cmp-step", i: "cmp-iteration", r: "cmp-run", b: "cmp-back" },
    enter() {
      const p = playProgram();
      if (!C.left) applyPreset(C.preset);
      $("compare-preset").value = C.preset;
      const ex = p && p.example ? S.examples.find((x) => x.id === p.example) : null;
      const names = p ? p.agents.map((a) => a.split(":")[0].trim()) : [];
      const evs = ex ? ex.events || [] : [];
      const offered = evs.every((e) => { try { const a = JSON.parse(e).agent; return a === undefined || names.includes(a); } catch (_) { return false; } }) ? evs : [];
      if (!C.loaded || key(p) !== key(C.program)) {
        C.program = p; C.events = offered;
        if (C.pending && key(p) === key(C.pending.program)) {
          // restored from storage or a link: each side's commands done again
          const out = {};
          for (const side of SIDES) { use(side); out[side] = call("restore", JSON.stringify(setupOf(side)), JSON.stringify(C.pending[side] || [])); }
          C.loaded = SIDES.every((s) => out[s].ok);
          C.eventIndex = C.pending.eventIndex || 0;
          C.pending = null;
          render(out, "");
        } else { C.pending = null; restart(null); }
      } else render({}, "");
    },
  };

  PG.compareState = () => {
    if (!C.left) return null;
    const h = {};
    if (C.loaded) for (const side of SIDES) h[side] = PG.inSlot(side, () => call("export"));
    const play = playProgram();
    return { preset: C.preset, left: C.left, right: C.right, eventIndex: C.eventIndex,
      program: C.program && key(C.program) === key(play) ? "play" : C.program, left_history: h.left || [], right_history: h.right || [] };
  };
  PG.compareRestore = (st) => {
    if (!st) return;
    C.preset = st.preset || "custom"; C.left = norm(st.left || {}); C.right = norm(st.right || {});
    C.pending = { program: st.program === "play" ? playProgram() : st.program, left: st.left_history, right: st.right_history, eventIndex: st.eventIndex };
  };

  PG.onInit.push(() => {
    $("compare-preset").addEventListener("change", () => {
      const p = $("compare-preset").value;
      if (p === "custom") { C.preset = p; return; }
      applyPreset(p);
      restart(hostActions());
    });
    $("cmp-step").addEventListener("click", () => both("step", 0));
    $("cmp-iteration").addEventListener("click", () => both("iteration"));
    $("cmp-run").addEventListener("click", () => both("runIdle", 5000));
    $("cmp-back").addEventListener("click", () => both("back"));
    $("cmp-restart").addEventListener("click", () => restart(null));
    const prio = () => { const v = $("cmp-notify-priority").value.trim(); return v === "" ? undefined : parseInt(v, 10); };
    $("cmp-notify").addEventListener("click", () => both("host", JSON.stringify({ kind: "notify", agent: $("cmp-host-agent").value, text: $("cmp-notify-text").value, priority: prio() })));
    for (const id of ["cmp-notify-text", "cmp-notify-priority"]) $(id).addEventListener("keydown", (e) => { if (e.key === "Enter") $("cmp-notify").click(); });
    $("cmp-next-event").addEventListener("click", nextEvent);
  });
})();
