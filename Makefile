# instess -- tessellation through instancing, on the CPU.
#
#   make            install missing Debian packages (scripts/setup.sh), build the library and build/instess
#   make figures    render every figure of the source documents into out/ with out/index.html
#   make test       build and run every test (tests/run.sh prints "N passed, N failed")
#   make bench      the benchmark of docs/design.md, section 6, against Mesa's llvmpipe
#   make goldens    re-render the golden images under tests/golden/ (only on purpose: commit says why);
#                   make goldens ONLY=ID[,ID...] re-renders just those
#
# The fixed build configuration (goldens are rendered with it; do not change it casually):
#   gcc, -O2 -march=x86-64-v3 -ffp-contract=off.  -ffp-contract=off forbids the compiler from fusing a*b+c
#   into FMA behind our back, so the scalar reference path and the SIMD path round identically and images are
#   the same bytes on every machine of this kind.

# All cores unless the caller chose a -j.
ifeq ($(filter -j%,$(MAKEFLAGS)),)
MAKEFLAGS += -j$(shell nproc)
endif

ifeq ($(origin CC),default)
CC       = gcc
endif
ifeq ($(origin CXX),default)
CXX      = g++
endif
ARCH     ?= -march=x86-64-v3
OPT      ?= -O2
CFLAGS_BASE = -std=c17 $(OPT) -g $(ARCH) -ffp-contract=off -fopenmp -Wall -Wextra -Wno-unused-parameter \
              -Wshadow -Wstrict-prototypes -Werror=switch -D_POSIX_C_SOURCE=200809L
CFLAGS   ?= $(CFLAGS_BASE)
CXXFLAGS ?= -std=c++17 $(OPT) -g $(ARCH) -ffp-contract=off -Wall -Wextra
B        ?= build

PKGS_ALL = OpenImageIO cmocka assimp
LDLIBS_IMG  = $(shell pkg-config --libs OpenImageIO 2>/dev/null) -lstdc++
CXXFLAGS_IMG = $(shell pkg-config --cflags OpenImageIO 2>/dev/null)
LDLIBS_MESH = $(shell pkg-config --libs assimp 2>/dev/null) -lmeshoptimizer -lstdc++
LDLIBS_TEST = $(shell pkg-config --libs cmocka 2>/dev/null)
# --as-needed: link only what is used.  OpenImageIO is not linked into the programs at all: the image codec is
# the module libinstess_codec.so (core/image_oiio.cpp), opened on the first image call (core/image_codec.c);
# programs export their symbols to it (-rdynamic).
LDFLAGS  ?= -fopenmp -Wl,--as-needed
LDLIBS   = $(LDLIBS_MESH) -lm
PROG_LDFLAGS = -rdynamic

LIB_SRC  = $(wildcard core/*.c raster/*.c vs/*.c meshes/*.c)
LIB_OBJ  = $(LIB_SRC:%.c=$(B)/%.o)
IMG_OBJ  = $(B)/core/image_oiio.o
CODEC_SO = $(B)/libinstess_codec.so
TEST_SRC = $(wildcard tests/test_*.c)
TEST_BIN = $(TEST_SRC:tests/%.c=$(B)/tests/%)
TEST_UTIL_SRC = $(wildcard tests/util/*.c)
TEST_UTIL_OBJ = $(TEST_UTIL_SRC:%.c=$(B)/%.o)
# cli/: the program's main (cli/main.c) and the scene layer every program and golden test shares.
APP_SRC  = $(filter-out cli/main.c,$(wildcard cli/*.c))
APP_OBJ  = $(APP_SRC:%.c=$(B)/%.o)
SETUP    = $(B)/.setup-done

.PHONY: all setup test test-unit sanitize valgrind fuzz figures bench goldens clean
.SECONDARY:
.DEFAULT_GOAL := all

all: $(B)/instess

setup: $(SETUP)
$(SETUP): scripts/setup.sh
	@bash scripts/setup.sh
	@mkdir -p $(B) && touch $@

$(B)/%.o: %.c $(SETUP)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(OBJ_DEFS) -MMD -MP -c $< -o $@

# The OpenImageIO version the codec module is built against, for `instess --version` (core/image.c), which
# names it without loading the module.
$(B)/core/image.o: OBJ_DEFS = -DINSTESS_OIIO_VERSION='"$(shell pkg-config --modversion OpenImageIO 2>/dev/null)"'

$(B)/core/image_oiio.o: core/image_oiio.cpp $(SETUP)
	@mkdir -p $(dir $@)
	$(CXX) $(CXXFLAGS) -fPIC $(CXXFLAGS_IMG) -MMD -MP -c $< -o $@

$(CODEC_SO): $(IMG_OBJ)
	$(CXX) -shared $(LDFLAGS) $^ $(LDLIBS_IMG) -o $@

$(B)/libinstess.a: $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(B)/libinstess_app.a: $(APP_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(B)/instess: $(B)/cli/main.o $(B)/libinstess_app.a $(B)/libinstess.a | $(CODEC_SO)
	$(CC) $(LDFLAGS) $(PROG_LDFLAGS) $^ $(LDLIBS) -o $@

$(B)/tests/%: $(B)/tests/%.o $(TEST_UTIL_OBJ) $(B)/libinstess_app.a $(B)/libinstess.a | $(CODEC_SO)
	$(CC) $(LDFLAGS) $(PROG_LDFLAGS) $^ $(LDLIBS_TEST) $(LDLIBS) -o $@

# make test = the unit, numerical and golden tests, then the same tests built with AddressSanitizer and
# UndefinedBehaviorSanitizer (clang), then valgrind on the renderer.  make test-unit runs only the first part.
test:
	@MAKE="$(MAKE)" bash tests/all.sh

test-unit: $(TEST_BIN) $(B)/instess
	@bash tests/check_includes.sh
	@bash tests/run.sh $(TEST_BIN)

# The sanitizer build: every test, clang, ASan + UBSan with float-cast-overflow and float-divide-by-zero,
# halting on the first error (-fno-sanitize-recover=all), leaks checked by LeakSanitizer at exit, and the
# rasterizer's stated preconditions checked (INSTESS_CHECKS turns RS_ASSERT into assert).  Every program loads
# libstdc++ at start: ASan finds the real __cxa_throw only if it is there before the codec module is opened.
SAN      = -fsanitize=address,undefined,float-cast-overflow,float-divide-by-zero -fno-sanitize-recover=all \
           -fno-omit-frame-pointer
SAN_B    = build-asan
sanitize: $(SETUP)
	@bash scripts/setup.sh --sanitize
	@$(MAKE) --no-print-directory B=$(SAN_B) CC=clang CXX=clang++ OPT=-O1 \
	    CFLAGS="$(CFLAGS_BASE) $(SAN) -DINSTESS_CHECKS -Wno-unknown-warning-option" \
	    CXXFLAGS="-std=c++17 -O1 -g $(ARCH) -ffp-contract=off $(SAN) -fno-sanitize=vptr" \
	    LDFLAGS="-fopenmp -Wl,--no-as-needed -lstdc++ -Wl,--as-needed $(SAN)" \
	    $(TEST_BIN:$(B)/%=$(SAN_B)/%) $(SAN_B)/instess
	@ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:halt_on_error=1 \
	 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 LSAN_OPTIONS=suppressions=tests/lsan.supp \
	 INSTESS_BIN=$(SAN_B)/instess TEST_LOG_DIR=$(SAN_B)/test-logs TEST_LABEL=sanitize \
	 bash tests/run.sh $(TEST_BIN:$(B)/%=$(SAN_B)/%)

# valgrind on the renderer: a few scenes, no errors, no definite leaks.  memcheck runs the instess program
# built with tests/valgrind/codec_raw.c in place of the OpenImageIO codec (OpenImageIO's libhwy dies of SIGILL
# under valgrind on CPUs without RDTSCP; see that file): the renderer's code is the same, only the file
# encoding differs, and each image is compared with the same run's image outside valgrind.
VG_BIN   = $(B)/tests/valgrind/instess
$(VG_BIN): $(B)/cli/main.o $(B)/libinstess_app.a $(filter-out $(B)/core/image_codec.o,$(LIB_OBJ)) \
          $(B)/tests/valgrind/codec_raw.o
	$(CC) $(LDFLAGS) $^ $(LDLIBS_MESH) -lm -o $@

valgrind: $(VG_BIN)
	@bash scripts/setup.sh --sanitize
	@bash tests/valgrind.sh $(VG_BIN)

figures: $(B)/instess
	@mkdir -p out
	$(B)/instess figures --out out

# make goldens ONLY=fig-1.1.2,fig-003-5 regenerates just those goldens (the rest are checked as usual).
goldens: $(B)/instess $(TEST_BIN)
	INSTESS_REGENERATE_GOLDENS=1 INSTESS_GOLDENS_ONLY=$(ONLY) bash tests/run.sh $(TEST_BIN)

include bench/bench.mk
-include tests/fuzz/fuzz.mk

# Every build folder: build/, the sanitizer's, the fuzzers' and any other build-*/ (and tests/failures/).
clean:
	rm -rf $(B) build build-* tests/failures

-include $(shell find $(B) -name '*.d' 2>/dev/null)
