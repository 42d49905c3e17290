# tests/fuzz/fuzz.mk -- libFuzzer harnesses (included by the Makefile).
#
#   make fuzz FUZZ_SECONDS=N    build the harnesses into build-fuzz/ (clang, -fsanitize=fuzzer,address,undefined
#                               with float-cast-overflow and float-divide-by-zero) and run each for N seconds
#                               (default 60), one after the other, under nice -n 19.  Seeds: tests/fuzz/corpus/;
#                               the growing corpus and the crash artifacts stay in build-fuzz/.
#   make fuzz-build             only build them.
# A crashing input found this way is copied into tests/fuzz/regressions/ (see tests/fuzz/README.md) once fixed; make test
# replays them all through tests/test_fuzz_regressions.c without libFuzzer.

FUZZ_B       = build-fuzz
FUZZ_SECONDS ?= 60
FUZZ_NAMES   = import mesh
FUZZ_SAN     = -fsanitize=address,undefined,float-cast-overflow,float-divide-by-zero -fno-sanitize-recover=all \
               -fno-omit-frame-pointer
# fuzz_replay replays fuzz_import's artifacts through the forked import child (run.sh: contained or not).
FUZZ_BINS    = $(FUZZ_NAMES:%=$(FUZZ_B)/fuzz/fuzz_%) $(FUZZ_B)/fuzz/fuzz_replay

.PHONY: fuzz-build

fuzz: fuzz-build
	@FUZZ_B=$(FUZZ_B) bash tests/fuzz/run.sh $(FUZZ_SECONDS) $(FUZZ_NAMES)

# The library and the scene layer built with -fsanitize=fuzzer-no-link (coverage without libFuzzer's main),
# then each harness linked with -fsanitize=fuzzer.
fuzz-build: $(SETUP)
	@bash scripts/setup.sh --sanitize
	@nice -n 19 $(MAKE) --no-print-directory B=$(FUZZ_B) CC=clang CXX=clang++ OPT=-O1 \
	    CFLAGS="$(CFLAGS_BASE) $(FUZZ_SAN) -fsanitize=fuzzer-no-link -Wno-unknown-warning-option" \
	    CXXFLAGS="-std=c++17 -O1 -g $(ARCH) -ffp-contract=off $(FUZZ_SAN) -fno-sanitize=vptr" \
	    LDFLAGS="-fopenmp -Wl,--as-needed $(FUZZ_SAN)" $(FUZZ_BINS)

# Only meaningful with B=$(FUZZ_B) and the flags above (fuzz-build passes them).
$(B)/fuzz/fuzz_%: tests/fuzz/fuzz_%.c tests/fuzz/fuzz_targets.c tests/fuzz/fuzz_targets.h $(B)/libinstess_app.a \
                  $(B)/libinstess.a
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -fsanitize=fuzzer $< tests/fuzz/fuzz_targets.c $(B)/libinstess_app.a $(B)/libinstess.a \
	    $(LDFLAGS) -fsanitize=fuzzer $(LDLIBS) -o $@
