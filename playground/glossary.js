// The terms the page uses, explained where they appear: every ruling (R1a
// ... R8), decision (D1 ...), property of the TLA+ spec (NoLoss,
// BoundedInversion, ...), the spec's ghosts and the TLC models become links
// with the docs' one line as their tooltip; a click opens the glossary at
// the term, whose entry links to the docs (docs/rulings.md, docs/spec.md,
// relative to this page: out/playground/ is two folders below the
// repository's root). The lines come from the docs at build time
// (playground/gen/glossary.ml), so the page and the docs say the same.
"use strict";

(function () {
  const PG = window.PG;
  if (!PG) return;
  const { $, el, call } = PG;
  const DOCS = "../../docs/";
  let entries = [], byTerm = new Map(), pattern = null;

  const docLink = (e) => DOCS + e.doc;

  // Wraps every term in the text nodes under [root] (not in form controls,
  // links, the trace or the output, which are the program's own words).
  function explain(root) {
    if (!root || !pattern) return;
    const skip = (n) => n.closest("a, textarea, input, select, option, #trace, #output, .chip, .cmp-trace, script, style, svg");
    const walker = document.createTreeWalker(root, NodeFilter.SHOW_TEXT, {
      acceptNode: (n) => (pattern.test(n.data) && !skip(n.parentElement) ? NodeFilter.FILTER_ACCEPT : NodeFilter.FILTER_REJECT),
    });
    const nodes = [];
    for (let n = walker.nextNode(); n; n = walker.nextNode()) nodes.push(n);
    for (const n of nodes) {
      const frag = document.createDocumentFragment();
      let last = 0;
      const text = n.data;
      const re = new RegExp(pattern.source, "g");
      for (let m = re.exec(text); m; m = re.exec(text)) {
        const e = byTerm.get(m[0]);
        if (!e) continue;
        frag.append(text.slice(last, m.index), term(e, m[0]));
        last = m.index + m[0].length;
      }
      frag.append(text.slice(last));
      n.replaceWith(frag);
    }
  }
  function term(e, shown) {
    return el("a", {
      class: "term", href: docLink(e), "data-term": e.term, title: `${e.term} (${e.kind}): ${e.text}`, text: shown,
      onclick: (ev) => { if (ev.ctrlKey || ev.metaKey || ev.shiftKey) return; ev.preventDefault(); openAt(e.term); },
    });
  }
  function renderList(filter) {
    const f = (filter || "").trim().toLowerCase();
    const dl = $("glossary-list");
    const shown = entries.filter((e) => !f || e.term.toLowerCase().startsWith(f) || e.text.toLowerCase().includes(f) || e.kind.toLowerCase().includes(f));
    dl.replaceChildren(...shown.flatMap((e) => [
      el("dt", { id: "glossary-" + e.term, "data-term": e.term }, el("b", { text: e.term }), el("span", { class: "hint", text: " " + e.kind })),
      el("dd", { "data-term": e.term }, e.text + " ", el("a", { href: docLink(e), target: "_blank", rel: "noopener", class: "doc", text: "docs/" + e.doc })),
    ]));
  }
  function openAt(t) {
    for (const id of ["help", "share"]) $(id).hidden = true;
    $("glossary").hidden = false;
    $("glossary-filter").value = t;
    renderList(t);
    const dt = document.getElementById("glossary-" + t);
    if (dt) { dt.classList.add("hit"); dt.scrollIntoView({ block: "nearest" }); }
  }

  PG.explain = explain;
  PG.glossaryOpen = openAt;
  PG.onInit.push(() => {
    const g = call("glossary");
    entries = Array.isArray(g) ? g : [];
    byTerm = new Map(entries.map((e) => [e.term, e]));
    const words = entries.map((e) => e.term).sort((a, b) => b.length - a.length)
      .map((t) => t.replace(/[.*+?^${}()|[\]\\]/g, "\\$&"));
    pattern = words.length ? new RegExp("\\b(?:" + words.join("|") + ")\\b") : null;
    renderList("");
    $("glossary-filter").addEventListener("input", () => renderList($("glossary-filter").value));
    // the example titles in the menu cannot hold links: their tooltip says what they cite
    for (const o of document.querySelectorAll("#example option")) {
      const cited = (o.textContent.match(pattern ? new RegExp(pattern.source, "g") : /$^/) || []).map((t) => byTerm.get(t)).filter((e) => e);
      if (cited.length) o.title = (o.title ? o.title + "\n" : "") + cited.map((e) => `${e.term}: ${e.text}`).join("\n");
    }
    explain($("help"));
    explain(document.querySelector("header .tagline"));
    explain(document.querySelector("footer"));
  });
})();
