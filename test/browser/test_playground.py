#!/usr/bin/env python3
"""The playground in a real browser: headless Chromium loads
out/playground/index.html from the file system, and the tests drive the page
as a student does (pick an example, edit, notify, put, send, step, step back,
replay a counterexample, watch the corridor). What the page shows is compared
with the command line: the trace lines must be exactly those of
`jadescript-ref run --trace` for the same events, the queues those the trace
implies, the diagnostics those of `jadescript-ref check`. Screenshots for
docs/tutorial.md are taken on the way (--shots). The last line printed is
"N passed, M failed".

    test_playground.py --page out/playground/index.html --cli PATH/main.exe [--shots DIR]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from webdriver import Browser  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
ARGS = None
B = None
RESULTS = []
TESTS = []


def test(f):
    TESTS.append(f)
    return f


class Failed(Exception):
    pass


def check(cond, msg):
    if not cond:
        raise Failed(msg)


def equal(got, want, what):
    if got != want:
        raise Failed("%s:\n  page: %r\n  want: %r" % (what, got, want))


# ---------------------------------------------------------------- the CLI

def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def cli_trace(files, agents, events, extra=()):
    """Runs `jadescript-ref run` on the program and events; returns the trace
    lines up to the end of the run (the destroy events of finish are not
    something the page does)."""
    d = tempfile.mkdtemp(prefix="jsref-cli-")
    names = []
    for name, text in files:
        with open(os.path.join(d, name), "w", encoding="utf-8") as f:
            f.write(text)
        names.append(name)
    with open(os.path.join(d, "events.jsonl"), "w") as f:
        for e in events:
            f.write(json.dumps(e) + "\n")
    cmd = [ARGS.cli, "run"] + names + sum((["--agent", a] for a in agents), []) + \
        ["--events", "events.jsonl", "--trace", "trace.jsonl"] + list(extra)
    subprocess.run(cmd, cwd=d, capture_output=True, text=True, timeout=60)
    lines = [l for l in read(os.path.join(d, "trace.jsonl")).split("\n") if l.strip()]
    out = []
    for l in lines:
        if json.loads(l).get("event") == "destroy":
            break
        out.append(l)
    return out


def cli_check(files):
    d = tempfile.mkdtemp(prefix="jsref-check-")
    for name, text in files:
        with open(os.path.join(d, name), "w", encoding="utf-8") as f:
            f.write(text)
    r = subprocess.run([ARGS.cli, "check"] + [n for n, _ in files], cwd=d, capture_output=True, text=True, timeout=60)
    return [l for l in r.stderr.split("\n") if l.strip()]


def queues_of(trace, variant="reference"):
    """The queues a trace implies, per agent, as the page shows them
    (data-entry of each chip): an oracle independent of the page."""
    q = {}

    def agent(a):
        return q.setdefault(a, {"o2a": [], "pq": [], "msgq": []})
    for l in trace[1:]:
        e = json.loads(l)
        a = agent(e["agent"])
        ev = e["event"]
        if ev == "notify":
            a["o2a"].append(("p", e["percept"], e["priority"], e["seq"]))
        elif ev == "put":
            a["o2a"].append(("o", e["object"]))
        elif ev == "deliver":
            a["msgq"].append(("m", e["performative"], e["content"], e["from"], e["seq"]))
        elif ev == "transfer":
            moved = [x for x in a["o2a"] if x[0] == "p"]
            a["o2a"] = [x for x in a["o2a"] if x[0] != "p"]
            if variant == "native":
                a["msgq"] += moved
            else:
                a["pq"] += moved
        elif ev == "transfer_one":
            a["pq"].append(a["o2a"].pop(0))
        elif ev == "dequeue":
            a["pq"].remove(("p", e["percept"], e["priority"], e["seq"]))
        elif ev == "behaviour_step" and e.get("message"):
            m = e["message"]
            if "percept" in m:
                a["msgq"].remove(("p", m["percept"], m["priority"], m["seq"]))
            else:
                a["msgq"].remove(("m", m["performative"], m["content"], m["from"], m["seq"]))

    def entry(x):
        if x[0] == "p":
            return "%s|%d|%d" % (x[1], x[2], x[3])
        if x[0] == "o":
            return "object|" + x[1]
        return "%s|%s|%s|%d" % x[1:]
    return {n: {"o2a": [entry(x) for x in a["o2a"]],
                "pq": [entry(x) for x in sorted(a["pq"], key=lambda x: (-x[2], x[3]))],
                "msgq": [entry(x) for x in a["msgq"]]} for n, a in q.items()}


# --------------------------------------------------------------- the page

def page_url():
    return "file://" + os.path.abspath(ARGS.page)


def open_page():
    t0 = time.time()
    B.get(page_url())
    while B.js("return document.body && document.body.dataset.ready || ''") != "yes":
        if time.time() - t0 > 10:
            raise Failed("the page did not become ready in 10 s")
        time.sleep(0.02)
    return time.time() - t0


def shown_trace():
    return B.js("return [...document.querySelectorAll('#trace .line')].map(e => e.textContent)")


def shown_queues():
    return B.js("""
      const r = {};
      for (const a of document.querySelectorAll('[data-agent]')) {
        const q = (k) => [...a.querySelectorAll('[data-queue=' + k + '] [data-entry]')].map(e => e.dataset.entry);
        r[a.dataset.agent] = { o2a: q('o2a'), pq: q('pq'), msgq: q('msgq') };
      }
      return r;""")


def click(id_):
    B.js("document.getElementById(arguments[0]).click()", id_)


def set_value(id_, value, event="input"):
    B.js("""const e = document.getElementById(arguments[0]); e.value = arguments[1];
            e.dispatchEvent(new Event(arguments[2], {bubbles: true}));""", id_, value, event)


def pick_example(id_):
    set_value("example", id_, "change")


def settings(variant="reference", tie="stable", budget=1, capacity="", seed=""):
    set_value("variant", variant, "change")
    set_value("tie", tie, "change")
    set_value("budget", str(budget))
    set_value("capacity", str(capacity))
    set_value("seed", str(seed))
    click("load")


def message():
    return B.js("return document.getElementById('message').textContent")


def notify(agent, percept, priority=None):
    set_value("host-agent", agent, "change")
    set_value("notify-text", percept)
    set_value("notify-priority", "" if priority is None else str(priority))
    click("notify")


def put(agent, obj):
    set_value("host-agent", agent, "change")
    set_value("put-text", obj)
    click("put")


def send(agent, content, perf="inform"):
    set_value("host-agent", agent, "change")
    set_value("perf", perf, "change")
    set_value("msg-text", content)
    click("send")


def all_idle():
    return "every agent is idle" in B.js("return document.getElementById('next-rule').textContent")


def example_program(id_):
    return [(f["name"], f["text"]) for f in B.js(
        "return window.playground.examples.find(x => x.id === arguments[0]).files", id_)]


def compare_stepwise(cli, variant="reference", limit=400, what=""):
    """Steps the page rule by rule; after each rule the trace shown must be a
    prefix of the command line's and the queues those that prefix implies.
    Ends with the whole trace."""
    n = 0
    while not all_idle() and n < limit:
        tr = shown_trace()
        equal(tr, cli[:len(tr)], "%s: the trace after %d rules" % (what, n))
        want = queues_of(tr, variant)
        got = shown_queues()
        for a in want:
            equal(got.get(a), want[a], "%s: the queues of %s after %d rules" % (what, a, n))
        click("step")
        n += 1
    return n


# ------------------------------------------------------------------ tests

@test
def page_loads_from_file_fast_and_small():
    t = open_page()
    check(t < 2.0, "the page took %.2f s to be usable (at most 2 s)" % t)
    size = sum(os.path.getsize(os.path.join(os.path.dirname(ARGS.page), f))
               for f in os.listdir(os.path.dirname(ARGS.page)))
    check(size < 3_000_000, "the playground is %d bytes (a few MB at most)" % size)
    errors = [e for e in B.browser_log() if e.get("level") == "SEVERE"]
    equal(errors, [], "console errors")
    check(B.js("return performance.getEntriesByType('resource').every(r => r.name.startsWith('file:'))"),
          "something was fetched from the network")


@test
def robome_step_by_step_matches_run():
    open_page()
    pick_example("robome")
    settings()
    notify("r", "position(0, 1)")
    notify("r", 'qrCodeRead("A7")')
    notify("r", "obstacle")
    notify("r", "position(0, 2)", priority=9)
    send("r", 'qrCodeRead("X")')
    files = example_program("robome")
    cli = cli_trace(files, ["r:RoboMe:@robome"], [
        {"agent": "r", "notify": "position(0, 1)"}, {"agent": "r", "notify": 'qrCodeRead("A7")'},
        {"agent": "r", "notify": "obstacle"}, {"agent": "r", "notify": "position(0, 2)", "priority": 9},
        {"agent": "r", "message": 'qrCodeRead("X")'}])
    # a screenshot in the middle of a dispatch, for the tutorial
    for _ in range(4):
        click("step")
    if ARGS.shots:
        B.screenshot(os.path.join(ARGS.shots, "playground-dispatch.png"))
    B.js("document.getElementById('back').click(); document.getElementById('back').click();"
         "document.getElementById('back').click(); document.getElementById('back').click();")
    n = compare_stepwise(cli, what="RoboMe")
    check(n > 10, "only %d rules were taken" % n)
    equal(shown_trace(), cli, "the whole trace")


@test
def step_back_restores_trace_and_queues():
    open_page()
    pick_example("robome")
    settings()
    notify("r", "position(0, 1)")
    notify("r", "falling")
    before = []
    for _ in range(6):
        before.append((shown_trace(), shown_queues(), B.js("return document.getElementById('agents-view').innerText")))
        click("step")
    for k in range(5, -1, -1):
        click("back")
        now = (shown_trace(), shown_queues(), B.js("return document.getElementById('agents-view').innerText"))
        equal(now, before[k], "the page after stepping back to rule %d" % k)


@test
def iteration_and_run_to_idle_match_run():
    open_page()
    pick_example("robome")
    settings()
    notify("r", "position(0, 1)")
    notify("r", "obstacle")
    click("iteration")
    tr = shown_trace()
    check(json.loads(tr[-1])["event"] == "behaviour_step", "an iteration ends with the behaviour step")
    notify("r", "falling")
    click("run")
    files = example_program("robome")
    cli = cli_trace(files, ["r:RoboMe:@robome"], [
        {"agent": "r", "notify": "position(0, 1)"}, {"agent": "r", "notify": "obstacle"}, {"run": 1},
        {"agent": "r", "notify": "falling"}, {"run": "idle"}])
    equal(shown_trace(), cli, "the trace")
    check("r: falling: stopped and backing off" in B.js("return document.getElementById('output').textContent"),
          "the log line is in the output")


@test
def shapes_two_agents_and_messages_match_run():
    open_page()
    pick_example("shapes")
    settings()
    files = example_program("shapes")
    agents = B.js("return document.getElementById('agents').value").split("\n")
    cli = cli_trace(files, agents, [])
    n = compare_stepwise(cli, what="Shapes")
    check(n > 3, "only %d rules were taken" % n)
    equal(shown_trace(), cli, "the whole trace")
    if ARGS.shots:
        B.screenshot(os.path.join(ARGS.shots, "playground-shapes.png"))


@test
def printed_loop_spins_on_an_object_as_run_does():
    open_page()
    pick_example("robome")
    settings(variant="printed")
    put("r", '"obj"')
    notify("r", "obstacle")
    for _ in range(12):
        click("step")
    files = example_program("robome")
    cli = cli_trace(files, ["r:RoboMe:@robome"], [{"agent": "r", "put": '"obj"'}, {"agent": "r", "notify": "obstacle"}],
                    ["--variant", "printed", "--max-steps", "12"])
    equal(shown_trace(), cli, "the trace")
    equal(shown_queues()["r"], queues_of(cli, "printed")["r"], "the queues")
    equal(B.js("return document.querySelector('[data-agent=r] [data-last]').dataset.last"), "TransferSpin", "the last rule")


@test
def budgeted_and_native_loops_match_run():
    for variant in ("budgeted", "native"):
        open_page()
        pick_example("robome")
        settings(variant=variant, budget=1)
        events = [{"agent": "r", "notify": p} for p in ("position(0, 1)", "position(0, 2)", "obstacle", "falling")]
        for e in events:
            notify("r", e["notify"])
        files = example_program("robome")
        cli = cli_trace(files, ["r:RoboMe:@robome"], events, ["--variant", variant])
        compare_stepwise(cli, variant=variant, what=variant)
        equal(shown_trace(), cli, "the %s trace" % variant)


@test
def conformance_vector_events_match_expected():
    # every vector: its events done one by one with "Next event", as a student does
    # 083 builds a text of 1,000,000 bytes and a map of 1,000,000 entries
    # (D21): in the page that outlasts WebDriver's script timeout. The same
    # engine runs it natively in test/browser/test_playground_engine.ml.
    heavy = {"083-r7-value-too-large"}
    vectors = sorted(d for d in os.listdir(os.path.join(ROOT, "conformance"))
                     if os.path.isfile(os.path.join(ROOT, "conformance", d, "expected.jsonl"))
                     and d not in heavy)
    check(len(vectors) >= 60, "only %d vectors" % len(vectors))
    open_page()
    for vid in vectors:
        pick_example(vid)
        count = B.js("return window.playground.events.length")
        for _ in range(count):
            click("next-event")
        click("run")
        want = [l for l in read(os.path.join(ROOT, "conformance", vid, "expected.jsonl")).split("\n") if l.strip()]
        want = want[:next((i for i, l in enumerate(want) if json.loads(l).get("event") == "destroy"), len(want))]
        equal(shown_trace(), want, "the trace of %s" % vid)


@test
def unstable_ties_offer_a_choice():
    open_page()
    pick_example("robome")
    settings(tie="unstable")
    notify("r", "position(0, 1)")
    notify("r", "position(0, 2)")
    click("step")   # Transfer
    choices = B.js("return [...document.querySelectorAll('#next-rule [data-choice]')].map(b => b.textContent)")
    equal(len(choices), 2, "the Dequeue choices")
    k = [i for i, c in enumerate(choices) if "#2)" in c][0]
    B.js("document.querySelector('#next-rule [data-choice=\"' + arguments[0] + '\"]').click()", k)
    last = json.loads(shown_trace()[-1])
    equal((last["event"], last["seq"]), ("dequeue", 2), "the entry dequeued")
    equal(shown_queues()["r"]["pq"], ["position(0.0, 1.0)|2|1"], "what is left in the priority queue")


@test
def syntax_and_type_errors_are_shown_as_check_reports_them():
    open_page()
    pick_example("robome")
    text = B.js("return document.getElementById('source').value")
    cases = [
        text.replace("\tprocedure stop do\n", "\tprocedure stop\n", 1),          # a missing do
        text.replace("currentPosition = position(x, y)", "currentPosition = posit(x, y)", 1),   # a type error
        text.replace("with priority = 8", "with priority = ", 1),
    ]
    for k, bad in enumerate(cases):
        check(bad != text, "case %d changed nothing" % k)
        set_value("source", bad)
        want = cli_check([("robome.jade", bad)])
        deadline = time.time() + 5   # the page checks 250 ms after the last key
        while True:
            shown = B.js("return [...document.querySelectorAll('#diagnostics li')].map(e => e.textContent)")
            if shown == want or time.time() > deadline:
                break
            time.sleep(0.05)
        check(len(want) > 0, "case %d: the command line found no error" % k)
        equal(shown, want, "case %d: the diagnostics" % k)
        marked = B.js("return [...document.querySelectorAll('#gutter .err')].map(e => e.textContent)")
        lines = sorted({w.split(":")[1] for w in want})
        equal(sorted(marked), lines, "case %d: the lines marked in the gutter" % k)
        if k == 1:
            # a click on the diagnostic puts the cursor at its line and column
            B.js("document.querySelector('#diagnostics li').click()")
            line, col = int(want[0].split(":")[1]), int(want[0].split(":")[2])
            caret = B.js("const t = document.getElementById('source'); return t.value.slice(0, t.selectionStart).split('\\n')")
            equal((len(caret), len(caret[-1]) + 1), (line, col), "the cursor after a click on the diagnostic")
            if ARGS.shots:
                B.js("window.scrollTo(0, 0)")
                B.screenshot(os.path.join(ARGS.shots, "playground-type-error.png"))
    click("load")
    check(B.js("return document.querySelectorAll('[data-agent]').length") == 0, "a program with errors does not start")
    check("fix the errors" in B.js("return document.getElementById('load-status').textContent"), "the status says why")


@test
def bad_host_input_never_breaks_the_page():
    open_page()
    pick_example("robome")
    settings()
    for p in ("position((", "nothing", "position(\"a\", 1)", "obstacle(1)", ""):
        notify("r", p)
        check("error" in message(), "notify %r: an error is shown (got %r)" % (p, message()))
    notify("r", "obstacle", priority=-3)
    check("error" in message() or "negative" in message() or "not" in message(), "a negative priority is refused")
    put("r", "1 +")
    check(message().startswith("put:1:"), "a bad object is located: %r" % message())
    send("r", "))")
    check(message().startswith("message:1:"), "bad content is located: %r" % message())
    equal(len(shown_trace()), 5, "nothing was recorded")   # the header and create's four lines
    notify("r", "obstacle")
    click("run")
    check(all_idle(), "the page still runs")
    # bad agents and settings
    set_value("agents", "r:Nobody")
    click("load")
    equal(B.js("return [...document.querySelectorAll('#diagnostics li')].map(e => e.textContent)"),
          ["--agent r:Nobody: error: there is no agent type Nobody"], "an unknown agent type")
    set_value("agents", "")
    click("load")
    check("no agent" in B.js("return document.getElementById('diagnostics').textContent"), "no agent at all")
    # programs that never end: endless recursion and an endless loop are
    # run-time errors (R7) that stop the block they happen in; the page goes on
    prog = ("agent A\n\tfunction f(n as integer) as integer do\n\t\treturn f(n + 1)\n\n"
            "\ton create do\n\t\tlog f(1)\n\t\tlog \"after\"\n")
    set_value("source", prog)
    set_value("agents", "a:A")
    click("load")
    d = tempfile.mkdtemp(prefix="jsref-rec-")
    with open(os.path.join(d, "robome.jade"), "w") as f:
        f.write(prog)
    r = subprocess.run([ARGS.cli, "run", "robome.jade", "--agent", "a:A"], cwd=d, capture_output=True, text=True, timeout=60)
    equal(r.stderr.strip(),
          "robome.jade:3:10: error: exhaustion: recursion too deep: more than 200 nested calls of functions and procedures",
          "endless recursion: an exhaustion error at the call (run)")
    equal(B.js("return document.getElementById('output').textContent"), r.stderr.strip(),
          "endless recursion, as run reports it")
    prog = "agent A\n\ton create do\n\t\tlog \"before\"\n\t\twhile true do\n\t\t\tx = 1\n"
    set_value("source", prog)
    click("load")
    d = tempfile.mkdtemp(prefix="jsref-loop-")
    with open(os.path.join(d, "robome.jade"), "w") as f:
        f.write(prog)
    r = subprocess.run([ARGS.cli, "run", "robome.jade", "--agent", "a:A"], cwd=d, capture_output=True, text=True, timeout=60)
    equal(B.js("return document.getElementById('output').textContent").split("\n"),
          [l for l in (r.stdout + r.stderr).split("\n") if l], "an endless loop, as run reports it")
    click("run")
    check(all_idle(), "the page still runs")
    errors = [e for e in B.browser_log() if e.get("level") == "SEVERE"]
    equal(errors, [], "console errors")


REPLAY_STATES = {
    # what TLC printed, as the page must show it after the replay's last step
    "MCPrintedObject": {"o2a": ['object|"obj"', "position|2|1"], "pq": [], "last": "TransferSpin"},
    "MCInversion": {"o2a": ["obstacle|8|3"], "pq": [], "last": "Dequeue", "waits": "#3 (priority 8) 2", "dispatched": "dispatched this iteration: 2"},
    "MCBudgeted": {"o2a": [], "pq": ["position|2|2"], "last": "Dequeue", "dispatched": "dispatched this iteration: 1"},
    "MCTiesUnstable": {"pq": ["a|1|1"], "last": "Dequeue"},
    "MCNative": {"msgq": ["noise|1|3"], "last": "Idle"},
    "MCFloodNative": {"msgq": ["inform|hello|host|1"], "last": "BehaviourStep"},
    "MCFloodPrinted": {"msgq": ["inform|hello|host|1"], "last": "TransferOne"},
}


@test
def counterexample_replays_reach_tlcs_states():
    open_page()
    click("mode-replay")
    ids = B.js("return window.playground.replays.map(r => r.id)")
    equal(sorted(ids), sorted(REPLAY_STATES), "the replays offered")
    for rid in ids:
        set_value("replay", rid, "change")
        n = B.js("return window.playground.replay.steps.length")
        for k in range(n):
            click("replay-next")
        labels = B.js("return [...document.querySelectorAll('#replay-steps .tla')].map(e => e.textContent)")
        check(all(l.endswith("✓") for l in labels), "%s: every step took TLC's action: %r" % (rid, labels))
        final = B.js("return document.getElementById('replay-final').className + ' ' + document.getElementById('replay-final').textContent")
        check("ok" in final.split()[1] and "reached the state TLC printed" in final, "%s: %s" % (rid, final))
        want = REPLAY_STATES[rid]
        q = shown_queues()["r"]
        for k in ("o2a", "pq", "msgq"):
            if k in want:
                equal(q[k], want[k], "%s: %s" % (rid, k))
        equal(B.js("return document.querySelector('[data-agent=r] [data-last]').dataset.last"), want["last"], rid + ": the last action")
        ghosts = B.js("return document.querySelector('[data-agent=r] [data-box=ghosts]').textContent")
        for k in ("waits", "dispatched"):
            if k in want:
                check(want[k] in ghosts, "%s: %r not in %r" % (rid, want[k], ghosts))
        if ARGS.shots and rid in ("MCPrintedObject", "MCInversion", "MCNative"):
            B.js("window.scrollTo(0, 0)")
            B.screenshot(os.path.join(ARGS.shots, "replay-%s.png" % rid))
        # step back through the replay: the first step undone leaves the start state
        for _ in range(n):
            click("back")
        equal(B.js("return document.querySelectorAll('#replay-steps li.done').length"), 0, rid + ": all steps undone")


@test
def corridor_animation_builds_the_map():
    open_page()
    click("mode-corridor")
    total = B.js("return window.CORRIDOR.map.length")
    check(total > 0, "the recorded run built a map")
    equal(B.js("return document.querySelectorAll('#corridor circle').length >= 1"), True, "the robot is drawn")
    B.js("window.corridorView.at(0)")
    at0 = B.js("return document.getElementById('corridor-clock').textContent")
    check("map entries: 0" in at0, "no map at t = 0: " + at0)
    for _ in range(30):
        click("corridor-step")
    B.js("window.corridorView.at(window.CORRIDOR.end / 2)")
    if ARGS.shots:
        B.screenshot(os.path.join(ARGS.shots, "corridor.png"))
    B.js("window.corridorView.at(window.CORRIDOR.end)")
    end = B.js("return document.getElementById('corridor-clock').textContent")
    check(("map entries: %d" % total) in end, "the whole map at the end: " + end)


def main():
    global ARGS, B
    p = argparse.ArgumentParser()
    p.add_argument("--page", default=os.path.join(ROOT, "out", "playground", "index.html"))
    p.add_argument("--cli", required=True)
    p.add_argument("--shots", default=None)
    p.add_argument("-k", default=None, help="only the tests whose name contains this")
    ARGS = p.parse_args()
    ARGS.cli = os.path.abspath(ARGS.cli)
    if ARGS.shots:
        os.makedirs(ARGS.shots, exist_ok=True)
    passed = failed = 0
    B = Browser()
    try:
        for t in TESTS:
            if ARGS.k and ARGS.k not in t.__name__:
                continue
            t0 = time.time()
            try:
                t()
                passed += 1
                print("  ok    %-58s %5.1f s" % (t.__name__, time.time() - t0))
            except Exception as e:   # a failure, or the page or the browser went wrong
                failed += 1
                print("  FAIL  %-58s %5.1f s" % (t.__name__, time.time() - t0))
                msg = str(e) if isinstance(e, Failed) else traceback.format_exc()
                print("        " + msg.replace("\n", "\n        ")[:3000])
            sys.stdout.flush()
    finally:
        B.close()
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
