// The corridor view: the recorded run of the corridor simulation
// (corridor_data.js, written at build time by playground/gen/corridor.ml from
// corridor_sim/ running the paper's program on the interpreter), animated or
// stepped: the robot, its path, the cubes, and the map being built.
"use strict";

(function () {
  const D = window.CORRIDOR;
  const $ = (id) => document.getElementById(id);
  const NS = "http://www.w3.org/2000/svg";
  const svg = (tag, attrs) => {
    const e = document.createElementNS(NS, tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    return e;
  };
  if (!D) { window.corridorView = { show() { $("corridor-about").textContent = "corridor_data.js is missing: run make playground"; } }; return; }

  const scale = Math.min(960 / D.length, 220 / D.width);
  const X = (x) => 20 + x * scale;
  const Y = (y) => 240 - y * scale;      // y up, as in the simulation's frame
  // events: the percepts handled (all but most positions) and the commands
  const events = [];
  for (const h of D.handled) events.push({ t: h[1], kind: "percept", text: `${h[2]} (priority ${h[3]}, #${h[4]}) from ${h[6]}: notified at ${h[0].toFixed(2)} s` + (h[5] === 0 ? ", discarded" : "") });
  for (const c of D.commands) events.push({ t: c[0], kind: "command", text: `command ${c[2]} (takes effect at ${c[1].toFixed(2)} s)` });
  for (const c of D.collisions) events.push({ t: c[0], kind: "collision", text: `collision at (${c[1]}, ${c[2]})` });
  for (const f of D.falls) events.push({ t: f[0], kind: "fall", text: `fall at (${f[1]}, ${f[2]})` });
  events.sort((a, b) => a.t - b.t);

  let t = 0, timer = null, built = false, path, robot, heading, mapLayer;
  // Where each map entry's code is printed: the centre of the cube's face
  // (faces in the order east, north, west, south of the cube's frame).
  const faceOf = (code) => {
    for (const c of D.cubes) {
      const k = c.faces.indexOf(code);
      if (k >= 0) { const a = c.yaw + k * Math.PI / 2; return [c.x + c.size / 2 * Math.cos(a), c.y + c.size / 2 * Math.sin(a)]; }
    }
    return null;
  };
  const outside = (m) => m[0] < 0 || m[0] > D.length || m[1] < 0 || m[1] > D.width;
  function build() {
    const s = $("corridor");
    s.replaceChildren();
    s.append(svg("rect", { x: X(0), y: Y(D.width), width: D.length * scale, height: D.width * scale, fill: "#fff", stroke: "#1d2330", "stroke-width": 3 }));
    for (const d of D.dropoffs) s.append(svg("rect", { x: X(d[0]), y: Y(d[3]), width: (d[2] - d[0]) * scale, height: (d[3] - d[1]) * scale, fill: "#fdeceb", stroke: "#b3261e" }));
    for (const c of D.cubes) {
      const g = svg("g", { transform: `translate(${X(c.x)} ${Y(c.y)}) rotate(${-c.yaw * 180 / Math.PI})` });
      const k = c.size * scale;
      g.append(svg("rect", { x: -k / 2, y: -k / 2, width: k, height: k, fill: "#fdebd3", stroke: "#8a5a12" }));
      s.append(g);
      const label = svg("text", { x: X(c.x), y: Y(c.y) - k, "text-anchor": "middle", "font-size": 12, fill: "#8a5a12" });
      label.textContent = c.id;
      s.append(label);
    }
    path = svg("polyline", { fill: "none", stroke: "#2458c7", "stroke-width": 2, "stroke-opacity": 0.7 });
    mapLayer = svg("g", {});
    robot = svg("circle", { r: 0.15 * scale, fill: "#2458c7", "fill-opacity": 0.35, stroke: "#2458c7" });
    heading = svg("line", { stroke: "#2458c7", "stroke-width": 3 });
    s.append(path, mapLayer, robot, heading);
    const slider = $("corridor-time");
    slider.max = Math.round(D.end * 10);
    $("corridor-about").textContent = `The paper's RoboMe agent (examples/robome/robome.jade on the interpreter, reference loop) ` +
      `driving the simulated robot through the "${D.scenario}" corridor (seed ${D.seed}, ${D.end} s): ` +
      `the same run as jadescript-ref sim ${D.scenario} --seed ${D.seed}. Blue: the path; orange: cubes; green dots: ` +
      `the map entries (worldMap[currentPosition] = qrCode) as the agent builds them. ${D.positions_handled} position percepts were handled (one in five seconds is listed).`;
    const far = D.map.filter(outside).length;
    $("corridor-lesson").textContent = `What the map believes. The QR code handler files each code under currentPosition: ` +
      `the robot's own position as the agent last handled it, not the cube's. A dashed line joins each map entry to the cube face ` +
      `where its code is printed. Three things pull them apart: the distance from which the camera reads a code; the noise of the ` +
      `UWB positions` + (far ? ` (${far} of the ${D.map.length} entries, in red, even lie outside the corridor's walls)` : "") +
      `; and the order of dispatch, since priorities reorder what the map believes: a QR code (priority 4) is dispatched before ` +
      `the positions (priority 2) that arrived in the same iteration, and is filed under an older one. The Playground's RoboMe ` +
      `example shows the last with four events, and exercise 7 asks you to fix it (docs/simulation.md: the map error).`;
    if (window.PG && window.PG.explain) window.PG.explain($("corridor-lesson"));
    built = true;
  }
  function poseAt(time) {
    const tr = D.trajectory;
    let lo = 0, hi = tr.length - 1;
    while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (tr[mid][0] <= time) lo = mid; else hi = mid - 1; }
    return { k: lo, p: tr[lo] };
  }
  function draw() {
    const { k, p } = poseAt(t);
    path.setAttribute("points", D.trajectory.slice(0, k + 1).map((q) => `${X(q[1]).toFixed(1)},${Y(q[2]).toFixed(1)}`).join(" "));
    robot.setAttribute("cx", X(p[1])); robot.setAttribute("cy", Y(p[2]));
    heading.setAttribute("x1", X(p[1])); heading.setAttribute("y1", Y(p[2]));
    heading.setAttribute("x2", X(p[1] + 0.25 * Math.cos(p[3]))); heading.setAttribute("y2", Y(p[2] + 0.25 * Math.sin(p[3])));
    mapLayer.replaceChildren();
    let entries = 0;
    for (const m of D.map) {
      if (m[3] > t) continue;   // the time the agent made this entry
      entries++;
      // the belief: a thin line from where the map files the code to where it is printed
      const f = faceOf(m[2]);
      if (f) mapLayer.append(svg("line", { x1: X(m[0]), y1: Y(m[1]), x2: X(f[0]), y2: Y(f[1]), class: "belief", stroke: "#1d7a3a", "stroke-width": 1, "stroke-dasharray": "3 3", "stroke-opacity": 0.7 }));
      const out = outside(m);
      mapLayer.append(svg("circle", { cx: X(m[0]), cy: Y(m[1]), r: 5, fill: out ? "#b3261e" : "#1d7a3a", class: "entry" + (out ? " outside" : "") }));
      const lb = svg("text", { x: X(m[0]) + 7, y: Y(m[1]) + 4, "font-size": 11, fill: out ? "#b3261e" : "#1d7a3a" });
      lb.textContent = m[2];
      mapLayer.append(lb);
    }
    $("corridor-time").value = Math.round(t * 10);
    const seen = events.filter((e) => e.t <= t);
    $("corridor-clock").textContent = `t = ${t.toFixed(1)} s · ${seen.length} events · map entries: ${entries}`;
    const ol = $("corridor-log");
    ol.replaceChildren(...seen.slice(-60).map((e, i, a) => {
      const li = document.createElement("li");
      li.textContent = `${e.t.toFixed(2)} s  ${e.text}`;
      if (i === a.length - 1) li.className = "now";
      return li;
    }));
    ol.scrollTop = ol.scrollHeight;
  }
  function stop() { clearInterval(timer); timer = null; $("corridor-play").textContent = "Play"; }
  function play() {
    if (timer) { stop(); return; }
    $("corridor-play").textContent = "Pause";
    timer = setInterval(() => { t = Math.min(D.end, t + 0.5); draw(); if (t >= D.end) stop(); }, 50);
  }
  window.corridorView = {
    show() { if (!built) build(); draw(); },
    at(time) { if (!built) build(); t = time; draw(); },
  };
  $("corridor-play").addEventListener("click", play);
  $("corridor-step").addEventListener("click", () => { stop(); const e = events.find((x) => x.t > t + 1e-6); t = e ? e.t : D.end; draw(); });
  $("corridor-reset").addEventListener("click", () => { stop(); t = 0; draw(); });
  $("corridor-time").addEventListener("input", (e) => { stop(); t = e.target.value / 10; draw(); });
})();
