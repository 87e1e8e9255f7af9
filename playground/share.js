// Programs that travel: the page's state (each tab's program, agents,
// settings and session; the replay and its step; the exercise; the two
// columns of Side by side) is kept in this browser's local storage after
// every change, and written into a link (after "#", so that it works from
// a file:// address too) that reproduces the session in any browser. A
// session is saved as the commands done (jsref's export: host actions as
// the lines of an events file say them, runs of rules counted) and
// restored by doing them again; programs that are an example's (or an
// exercise's) unchanged are saved by name.
"use strict";

(function () {
  const PG = window.PG;
  if (!PG) return;
  const { $, call, S } = PG;
  const KEY = "jadescript-playground";
  const VERSION = 1;
  let saving = true;

  // base64url of UTF-8 text, and back
  const enc = (s) => btoa(unescape(encodeURIComponent(s))).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
  const dec = (s) => decodeURIComponent(escape(atob(s.replace(/-/g, "+").replace(/_/g, "/"))));

  // The files of a workspace's program, unless they are its base's (the
  // example's or the exercise's) unchanged.
  const filesOrBase = (files, base) => (base && PG.sameFiles(files, base) ? undefined : files);

  function wsSnapshot(name, w) {
    if (!w) return null;
    const base = name === "exercise" ? PG.exerciseBase && PG.exerciseBase() : w.example && w.example.files;
    const history = w.loaded ? PG.inSlot(name, () => call("export")) : null;
    const started = w.started ? {
      files: filesOrBase(w.started.files, base), agents: w.started.agents,
      variant: w.started.variant, tie: w.started.tie, budget: w.started.budget,
      o2a_capacity: w.started.o2a_capacity, seed: w.started.seed, interleave: w.started.interleave,
    } : null;
    const sameAsStarted = w.started && PG.sameFiles(w.files, w.started.files);
    return {
      example: w.example ? w.example.id : null,
      files: sameAsStarted ? "started" : filesOrBase(w.files, base), file: w.file,
      settings: w.settings, eventIndex: w.eventIndex, message: w.message, messageKind: w.messageKind,
      started, history: Array.isArray(history) ? history : null,
    };
  }

  // Everything, as one object.
  function snapshot() {
    if (S.mode && PG.modes[S.mode] && PG.modes[S.mode].ws === S.wsName) PG.saveWs();
    const ws = {};
    // the replay tab is kept as its model and step (its steps are done again)
    for (const name of Object.keys(S.ws)) if (name !== "replay") ws[name] = wsSnapshot(name, S.ws[name]);
    return {
      v: VERSION, mode: S.mode, ws,
      replay: S.replay ? { id: S.replay.id, step: S.replayStep } : null,
      exercise: PG.exerciseState ? PG.exerciseState() : null,
      compare: PG.compareState ? PG.compareState() : null,
    };
  }

  // Puts a saved workspace back: its session restored in its slot.
  function wsRestore(name, w) {
    if (!w) return;
    const ex = w.example ? S.examples.find((x) => x.id === w.example) : null;
    const base = name === "exercise" ? PG.exerciseBase && PG.exerciseBase() : ex && ex.files;
    const copy = (fs) => (fs || []).map((f) => ({ name: f.name, text: f.text }));
    let started = null;
    if (w.started) started = Object.assign({}, w.started, { files: copy(w.started.files || base),
      fuel: ex && ex.fuel ? ex.fuel : null, max_steps: ex && ex.max_steps ? ex.max_steps : null });
    const files = w.files === "started" && started ? copy(started.files) : copy(w.files || base);
    // an example or exercise this build no longer has: the tab opens as new
    if (files.length === 0) return;
    let loaded = false;
    if (started && w.history) {
      const r = PG.inSlot(name, () => call("restore", JSON.stringify(started), JSON.stringify(w.history)));
      loaded = !!r.ok;
    }
    S.ws[name] = {
      slot: name, files, file: Math.min(w.file || 0, Math.max(0, files.length - 1)), example: ex,
      events: name === "exercise" ? (PG.exerciseEvents ? PG.exerciseEvents() : []) : ex ? ex.events || [] : [],
      eventIndex: w.eventIndex || 0, loaded, started: loaded ? started : null,
      message: w.message || "", messageKind: w.messageKind || "",
      settings: w.settings || {}, status: loaded ? "restored" : "",
    };
  }

  function restore(snap) {
    if (!snap || snap.v !== VERSION || !snap.ws) return false;
    if (PG.exerciseRestore) PG.exerciseRestore(snap.exercise);
    for (const name of Object.keys(snap.ws)) wsRestore(name, snap.ws[name]);
    if (snap.replay) {
      const r = S.replays.find((x) => x.id === snap.replay.id);
      if (r) { $("replay").value = r.id; S.replayPending = snap.replay.step; }
    }
    if (PG.compareRestore) PG.compareRestore(snap.compare);
    S.mode = "corridor";   // no workspace: setMode then loads the one of snap.mode
    S.wsName = null;
    PG.setMode(PG.modes[snap.mode] ? snap.mode : "play");
    return true;
  }

  function save() {
    if (!saving) return;
    try { localStorage.setItem(KEY, JSON.stringify(snapshot())); } catch (_) { /* storage full or refused: the link still works */ }
  }
  let timer = null;
  // a burst of actions (Run to idle, the tests) is saved once, when it pauses;
  // leaving the page saves at once (pagehide)
  PG.saveSoon = () => { clearTimeout(timer); timer = setTimeout(save, 400); };
  PG.saveNow = save;
  window.addEventListener("pagehide", save);
  // a link pasted into the address bar of a page already open changes only
  // the part after "#": the page starts again to read it
  window.addEventListener("hashchange", () => { if (location.hash.startsWith("#s=")) location.reload(); });

  function link() {
    const base = location.href.split("#")[0];
    return base + "#s=" + enc(JSON.stringify(snapshot()));
  }
  PG.showLink = () => {
    const l = link();
    $("share-link").value = l;
    $("share-status").textContent = `${l.length.toLocaleString("en")} characters`;
  };

  // At start: a link's session first (then the address is cleaned, so that
  // a reload shows the work done since), else this browser's.
  PG.restoreSaved = () => {
    const h = location.hash;
    if (h.startsWith("#s=")) {
      let snap = null;
      try { snap = JSON.parse(dec(h.slice(3))); } catch (_) { snap = null; }
      try { history.replaceState(null, "", location.href.split("#")[0]); } catch (_) { /* a browser that refuses: the hash stays */ }
      if (restore(snap)) { PG.say("this session comes from a link", "info"); save(); return true; }
      PG.onStart.push(() => PG.say("the link could not be read: it is cut or it is not a playground link", "error"));
    }
    let saved = null;
    try { saved = JSON.parse(localStorage.getItem(KEY) || "null"); } catch (_) { saved = null; }
    return saved ? restore(saved) : false;
  };

  PG.onInit.push(() => {
    $("share-copy").addEventListener("click", () => {
      PG.showLink();
      const l = $("share-link").value;
      const done = () => { $("share-status").textContent = "copied: paste it anywhere"; };
      const fallback = () => {
        $("share-link").select();
        try { document.execCommand("copy"); done(); } catch (_) { $("share-status").textContent = "select the link and copy it"; }
      };
      if (navigator.clipboard && navigator.clipboard.writeText) navigator.clipboard.writeText(l).then(done, fallback);
      else fallback();
    });
    $("forget").addEventListener("click", () => {
      saving = false;
      try { localStorage.removeItem(KEY); } catch (_) { /* nothing to forget */ }
      document.body.dataset.ready = "no";
      location.reload();
    });
  });
})();
