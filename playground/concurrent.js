// Concurrency: several agents' rules interleaved by hand or drawn from a
// seed, messages in flight that the student makes arrive (between two
// rules, or during the receiver's behaviour step: SendInStep, R5d revised),
// as R6 revised allows and `run --interleave` draws them (D45). The tab has
// its own workspace (jsref's slot "concurrent"): the program, the agents and
// a session of the finer interleaving. After every command the trace so far
// is judged by the oracle's judge compiled into the page (jsref.judge,
// lib/judge); a trace pasted from another implementation is judged against
// the same program and agents (jsref.judgeText), its first unexplained line
// marked with the judge's message.
"use strict";

(function () {
  const PG = window.PG;
  if (!PG) return;
  const { $, el, call, S } = PG;
  const DEFAULT = "047-r6-ping-pong";   // two agents passing a ball by messages
  const K = { seed: 1, verdict: null, paste: null };
  PG.concurrent = K;
  PG.concurrentSeed = () => K.seed;
  const here = () => S.wsName === "concurrent";

  function say(text, kind) {
    const m = $("conc-message");
    m.textContent = text || "";
    m.className = "message " + (kind || "");
    PG.explain(m);
  }

  function act(fn, ...args) {
    if (!S.loaded) { say("start a program first (Check and start)", "error"); return null; }
    const r = call(fn, ...args);
    if (!r.ok) { say(r.error, "error"); return r; }
    let msg = r.error || r.drawn || "";
    if (!msg && r.outcome === "idle") msg = "this agent is idle: it has no rule to take until a percept or a message arrives (R3e)";
    if (!msg && r.outcome === "limit") msg = "the step limit is reached";
    if (!msg && fn === "back") msg = r.undone ? "undone" : "nothing to undo";
    if (!msg && fn === "finish") msg = r.ended ? "the run has ended: every message in flight arrived, then every agent was destroyed" : "the run had ended already";
    say(msg, r.error ? "error" : "info");
    PG.render(r, fn === "back");
    return r;
  }

  // ------------------------------------------------------------ the judge

  function verdictText(j, what) {
    if (j.accepted) {
      return `✓ Accepted${j.complete ? "" : " so far"}: the program explains every line of ${what} (${j.lines} lines, ${j.level} level)` +
        (j.complete ? "; the run is complete (every agent destroyed, every message delivered, D26)." : "; the run goes on.");
    }
    return `✗ Line ${j.line} is not explained: ${j.message}`;
  }

  function judgeRun() {
    const box = $("conc-verdict");
    for (const l of document.querySelectorAll("#trace .line.unexplained")) l.classList.remove("unexplained");
    if (!S.loaded) { box.className = "final pending"; box.textContent = "no run: start a program"; K.verdict = null; return; }
    const j = call("judge");
    K.verdict = j;
    if (j.accepted === undefined) { box.className = "final bad"; box.textContent = j.error || "the judge did not answer"; return; }
    box.className = "final " + (j.accepted ? "ok" : "bad");
    box.dataset.accepted = j.accepted ? "yes" : "no";
    box.dataset.line = j.accepted ? "" : String(j.line);
    box.textContent = verdictText(j, "this run's trace");
    if (!j.accepted) {
      const line = document.querySelectorAll("#trace .line")[j.line - 1];
      if (line) { line.classList.add("unexplained"); line.scrollIntoView({ block: "nearest" }); }
    }
    PG.explain(box);
  }

  function judgePaste() {
    if (!S.loaded) { say("start a program first (Check and start): a trace is judged against its program and agents", "error"); return; }
    const text = $("conc-paste").value;
    const j = call("judgeText", text.endsWith("\n") || text === "" ? text : text + "\n");
    K.paste = j;
    const box = $("conc-paste-verdict");
    box.hidden = false;
    const lines = $("conc-paste-lines");
    lines.hidden = false;
    lines.replaceChildren();
    if (j.accepted === undefined) { box.className = "final bad"; box.textContent = j.error || "the judge did not answer"; return; }
    box.className = "final " + (j.accepted ? "ok" : "bad");
    box.dataset.accepted = j.accepted ? "yes" : "no";
    box.dataset.line = j.accepted ? "" : String(j.line);
    box.textContent = verdictText(j, "the pasted trace");
    const rows = text.split("\n");
    if (rows.length && rows[rows.length - 1] === "") rows.pop();
    rows.forEach((l, k) => {
      const bad = !j.accepted && j.line === k + 1;
      lines.append(el("div", { class: "line" + (bad ? " unexplained" : ""), "data-line": k + 1, text: `${k + 1}  ${l}` }));
      if (bad) lines.append(el("div", { class: "why", text: "↑ " + j.message }));
    });
    if (!j.accepted && j.line > rows.length) lines.append(el("div", { class: "why", text: `line ${j.line} (missing): ${j.message}` }));
    const mark = lines.querySelector(".unexplained");
    if (mark) lines.scrollTop = Math.max(0, mark.offsetTop - lines.offsetTop - 60);
    PG.explain(box);
  }

  // ------------------------------------------------------------- render

  function renderPanel() {
    if (!here()) return;
    const v = S.loaded ? S.view : null;
    const agents = $("conc-agents");
    agents.replaceChildren();
    if (v && v.interleave != null && v.interleave !== K.seed) K.seed = v.interleave;
    $("conc-seed").value = K.seed;
    if (!v) {
      agents.append(el("span", { class: "empty", text: "no program running" }));
    } else {
      for (const a of v.agents) {
        const what = v.finished ? "destroyed" : a.idle ? "idle (R3e)" : a.rules[0] || "?";
        const b = el("button", {
          id: "conc-rule-" + a.name, "data-agent-rule": a.name,
          title: a.window ? "its last rule was a behaviour step: a message may still arrive during it (R5d)" : "",
          onclick: () => act("ruleOf", a.name),
        }, el("span", { class: "who", text: a.name }), ": " + what + (a.window ? " · in its step's window" : ""));
        b.disabled = v.finished || a.idle;
        agents.append(b);
      }
    }
    const flight = $("conc-flight");
    flight.replaceChildren();
    const seen = new Set();
    for (const m of v ? v.in_flight : []) {
      const first = !seen.has(m.receiver);
      seen.add(m.receiver);
      const li = el("li", { class: first ? "" : "waits", "data-flight": `${m.sender}>${m.receiver}|${m.performative}|${m.content}` },
        `${m.performative} ${m.content}: ${m.sender} → ${m.receiver}`);
      if (first) {
        li.append(el("button", { "data-arrive": m.receiver, text: "arrive now", title: "between two rules of " + m.receiver + " (Send)",
          onclick: () => act("arrive", JSON.stringify({ receiver: m.receiver, during: false })) }));
        const during = el("button", { "data-arrive-step": m.receiver, text: `arrive during ${m.receiver}'s step`,
          title: m.window ? "during the behaviour step just taken, after its handlers looked (SendInStep, R5d)"
            : "only between a behaviour step of " + m.receiver + " and its next rule (R5d)",
          onclick: () => act("arrive", JSON.stringify({ receiver: m.receiver, during: true })) });
        during.disabled = !m.window;
        li.append(during);
      } else li.append(el("span", { class: "hint", text: " (after the older one: R5e)" }));
      flight.append(li);
    }
    if (!flight.children.length) flight.append(el("li", { class: "waits", text: "none" }));
    for (const id of ["conc-random", "conc-random10", "conc-finish"]) $(id).disabled = !v || v.finished;
    $("conc-back").disabled = !v;
    $("conc-counters").textContent = v ? `${v.steps} rules · ${v.history} commands · seed ${v.interleave}` + (v.finished ? " · ended" : "") : "";
    const st = S.started;
    $("conc-program").textContent = st ? `Program: ${st.files.map((f) => f.name).join(", ")}, agents ${st.agents.join(", ")} (change them in the editor on the left, then Check and start).` : "";
    judgeRun();
    PG.explain($("conc-agents"));
  }

  // ----------------------------------------------------------------- mode

  function openDefault() {
    const x = S.examples.find((e) => e.id === DEFAULT);
    if (!x) return;
    S.files = x.files.map((f) => ({ name: f.name, text: f.text }));
    S.file = 0; S.example = x; S.events = [];
    PG.setSettings(x);
    PG.showFile();
    PG.start_session();
  }

  PG.modes.concurrent = {
    ws: "concurrent", panels: ["concurrent-panel"],
    keys: { d: "conc-random", b: "conc-back" },
    enter(fresh) { if (fresh) openDefault(); else renderPanel(); },
  };

  PG.onRender.push(() => renderPanel());

  PG.onInit.push(() => {
    $("conc-random").addEventListener("click", () => act("draw"));
    $("conc-random10").addEventListener("click", () => {
      for (let k = 0; k < 10; k++) { const r = act("draw"); if (!r || !r.ok || r.error) break; }
    });
    $("conc-back").addEventListener("click", () => act("back"));
    $("conc-finish").addEventListener("click", () => act("finish"));
    $("conc-restart").addEventListener("click", () => { if (PG.start_session()) say("the run started again", "info"); });
    $("conc-seed").addEventListener("change", () => {
      const n = parseInt($("conc-seed").value, 10);
      if (!Number.isFinite(n) || n === K.seed) { $("conc-seed").value = K.seed; return; }
      K.seed = n;
      if (S.loaded && PG.start_session()) say(`seed ${n}: the run started again, its draws from this seed`, "info");
    });
    $("conc-judge").addEventListener("click", judgePaste);
    $("conc-paste-own").addEventListener("click", () => {
      if (!S.loaded) return;
      const t = call("trace", 0);
      $("conc-paste").value = (t.lines || []).join("\n") + "\n";
    });
  });
})();
