# jadescript-ref. The two commands a new user needs:
#   make demo    the main job (for now: the paper's programs parsed and formatted)
#   make test    every test suite; last line "N passed, M failed"
# Both run scripts/setup first, which installs what is missing (idempotent).

.PHONY: all setup build demo test bench spec spec-full conformance clean

all: build

setup:
	@bash scripts/setup

build: setup
	@dune build

demo: build
	@bash scripts/demo

test: setup
	@bash scripts/test

bench: build
	@dune exec --no-print-directory bench/bench.exe -- all

# The longer agreement checks: every model (full ones too) against TLC, the
# mutant table, 200 TLC behaviours replayed and 200 OCaml runs validated per
# model, then every suite with 10x the property-test counts.
conformance: build
	@dune exec --no-print-directory -- jadescript-ref explore --all --full --mutants --simulate 200 --validate 200
	@JSREF_LONG=1 bash scripts/test

clean:
	@dune clean
	@rm -rf out

-include spec/spec.mk
