# jadescript-ref. The two commands a new user needs:
#   make demo    the main job: the paper's RoboMe agent, type-checked and run on the
#                simulated robot in the paper's corridor (scripts/demo)
#   make test    every test suite, in parallel lanes (one a core, at most 4;
#                JSREF_TEST_JOBS=1: one after another); last line "N passed, M failed"
# Both run scripts/setup first, which installs what is missing (idempotent).

.PHONY: all setup build demo test bench spec spec-full conformance clean playground fuzz proofs

all: build

setup:
	@bash scripts/setup

build: setup
	@dune build

demo: build
	@bash scripts/demo

test: setup
	@bash scripts/test

# The proofs of the agent loop (docs/proofs.md): every proof of proofs/*.v
# checked again by coqc from scratch, with the seconds of each file and its
# lines of specification and of proof. (`make test` checks them too: a
# broken proof fails the build.)
proofs: setup
	@out=$$(mktemp -d) && bash proofs/check.sh --time "$$out"; status=$$?; rm -rf "$$out"; exit $$status

bench: build
	@dune exec --no-print-directory bench/bench.exe -- all

# The longer agreement checks: every model (full ones too) against TLC, the
# mutant table, 200 TLC behaviours replayed and 200 OCaml runs validated per
# model, the three kill counts over the bug catalogue (lib/defects,
# conformance/README.md: the vectors compared exactly, the vectors judged,
# 1000 generated programs judged; each defect's row ends at its first
# killing case), 1,000 generated programs judged on the reference and under
# --interleave, the judge's false rejections over 20 seeds of the finer
# interleaving (scripts/judge-seeds: every vector and 50 generated programs
# per seed), 1,000 generated programs (seeds 1 and 2, 500 each) run freely
# on JADE and judged, and 1,000 more in two containers (seeds 1 and 2;
# docs/jade.md, "Generated programs, running freely"), the same run in lock
# step on JADE and judged (1,000 in one container; in two, the first 600 of
# seed 1 and 400 of seed 2; docs/jade.md, "Generated programs, in lock
# step"), then every
# suite with 10x the property-test counts.
conformance: build
	@dune exec --no-print-directory -- jadescript-ref explore --all --full --mutants --simulate 200 --validate 200
	@dune exec --no-print-directory -- jadescript-ref defects --first
	@dune exec --no-print-directory -- jadescript-ref defects --judge
	@dune exec --no-print-directory -- jadescript-ref defects --generated 1000 --seed 1
	@dune exec --no-print-directory -- jadescript-ref conform --generated 1000 --seed 1 | tail -n 1
	@dune exec --no-print-directory -- jadescript-ref conform --generated 1000 --seed 1 --impl "$$PWD/_build/default/bin/main.exe run --interleave 7" | tail -n 1
	@bash scripts/judge-seeds 20 50 | tail -n 1
	@bash scripts/jade-generated --seed 1 500 | tail -n 25
	@bash scripts/jade-generated --seed 2 500 | tail -n 25
	@bash scripts/jade-generated --split --seed 1 500 | tail -n 25
	@bash scripts/jade-generated --split --seed 2 500 | tail -n 25
	@bash scripts/jade-generated --locked --seed 1 500 | tail -n 25
	@bash scripts/jade-generated --locked --seed 2 500 | tail -n 25
	@bash scripts/jade-generated --split --locked --seed 1 600 | tail -n 25
	@bash scripts/jade-generated --split --locked --seed 2 400 | tail -n 25
	@JSREF_LONG=1 bash scripts/test

# The fuzz campaign (fuzz/README.md): 1,000,000 generated inputs over
# parse, check, run, limits, cli, validate and conform, and the hostile
# classes (hostile: every documented limit in every input format, hostile
# names, big programs, pipes; jade: javac on compile's Java; differential:
# the interpreter against JADE, FUZZ_DIFFERENTIAL programs), each in a child with
# bounded memory and time; a table of counts per target, then
# "fuzz: N inputs, K findings" (exit 1 on any finding). The budget is a
# parameter: make fuzz FUZZ_INPUTS=200000, or FUZZ_SECONDS=600 (then it stops
# starting new inputs after that long); FUZZ_SEED and FUZZ_JOBS too.
FUZZ_INPUTS ?= 1000000
FUZZ_SEED ?= 1
FUZZ_JOBS ?= 2
# programs run on the interpreter and on JADE (the differential target; a JVM each)
FUZZ_DIFFERENTIAL ?= 20
fuzz: build
	@dune exec --no-print-directory ./fuzz/fuzz.exe -- --inputs $(FUZZ_INPUTS) --seed $(FUZZ_SEED) --jobs $(FUZZ_JOBS) --differential $(FUZZ_DIFFERENTIAL) $(if $(FUZZ_SECONDS),--seconds $(FUZZ_SECONDS))

# The students' playground (playground/, docs/tutorial.md): out/playground/,
# index.html and its scripts, compiled from the project's libraries with
# js_of_ocaml in a build context of its own (playground/dune-workspace.playground),
# so that a plain `dune build` never needs js_of_ocaml. Honours DUNE_BUILD_DIR.
PLAY_BUILD = $(or $(DUNE_BUILD_DIR),_build)/playground/playground/js
playground: setup
	@dune build --root . --workspace playground/dune-workspace.playground $(PLAY_BUILD)/jsref.js $(PLAY_BUILD)/corridor_data.js
	@mkdir -p out/playground
	@cp -f $(PLAY_BUILD)/jsref.js $(PLAY_BUILD)/corridor_data.js out/playground/
	@cp -f playground/index.html playground/style.css playground/ui.js playground/glossary.js playground/share.js \
	  playground/exercises.js playground/compare.js playground/corridor.js playground/concurrent.js out/playground/
	@chmod u+w out/playground/*
	@echo "playground: out/playground/index.html ($$(du -ch out/playground/* | tail -n 1 | cut -f1) in all); open it in a browser"

clean:
	@dune clean
	@rm -rf out

-include spec/spec.mk
