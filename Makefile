# instess -- tessellation through instancing, on the CPU.
#
#   make            install missing Debian packages (scripts/setup.sh), build the library and build/instess
#   make figures    render every figure of the source documents into out/ with out/index.html
#   make test       build and run every test (tests/run.sh prints "N passed, N failed")
#   make install    install the library, headers, instess.pc, the program and its man page under PREFIX
#                   (default /usr/local; DESTDIR stages it, e.g. make install DESTDIR=/tmp/stage), and the
#                   Python package python/instess where Debian's python3 finds it (PYTHONDIR);
#                   make uninstall removes exactly those files
#   make bench      the benchmark of docs/design.md, section 6, against Mesa's llvmpipe
#   make web        the tutorial in the browser: out/web/index.html, one file (web/web.mk); make test-web tests it
#   make goldens    re-render the golden images under tests/golden/ (only on purpose: commit says why);
#                   make goldens ONLY=ID[,ID...] re-renders just those
#
# The fixed build configuration (goldens are rendered with it; do not change it casually):
#   gcc, -O2 -march=x86-64-v3 -ffp-contract=off.  -ffp-contract=off forbids the compiler from fusing a*b+c
#   into FMA behind our back, so the scalar reference path and the SIMD path round identically and images are
#   the same bytes on every machine of this kind.

# All cores by default.  Only the top-level make sets it: a -j on its command line wins over this default (GNU
# make 4.3 does not show -j or the jobserver in MAKEFLAGS while it reads the makefile, so they cannot be tested
# here), and a nested make (tests/all.sh's stages, the sanitizer build) shares its parent's jobserver -- setting
# -j there too made each of them print "warning: -jN forced in makefile: resetting jobserver mode".
ifeq ($(MAKELEVEL),0)
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
# PNG files are written and read through libpng (image/image_png.c), linked into the library: two small
# libraries instead of OpenImageIO's ~260 for the format every render and golden uses.
LDLIBS_PNG  = $(shell pkg-config --libs libpng 2>/dev/null || echo -lpng16)
# --as-needed: link only what is used.  OpenImageIO is not linked into the programs at all: the image codec is
# the module libinstess_codec.so (image/image_oiio.cpp), opened on the first image call (image/image_codec.c);
# programs export their symbols to it (-rdynamic).
LDFLAGS  ?= -fopenmp -Wl,--as-needed
LDLIBS   = $(LDLIBS_MESH) $(LDLIBS_PNG) -lm
PROG_LDFLAGS = -rdynamic

LIB_SRC  = $(wildcard core/*.c raster/*.c vs/*.c meshes/*.c image/*.c tess/*.c)
# The rasterizer's fast-path kernels are compiled a second time for AVX-512 (raster/raster_internal.h,
# RS_KERNEL): the library picks that copy at run time on CPUs that have it (rs_set_isa), with the same bytes.
KERNEL_SRC = raster/span.c raster/span_wide.c raster/setup_simd.c
KERNEL512  = -march=x86-64-v4 -DRS_KERNEL_AVX512
LIB_OBJ  = $(LIB_SRC:%.c=$(B)/%.o) $(KERNEL_SRC:%.c=$(B)/%.avx512.o)
IMG_OBJ  = $(B)/image/image_oiio.o
CODEC_SO = $(B)/libinstess_codec.so
TEST_SRC = $(wildcard tests/test_*.c)
TEST_BIN = $(TEST_SRC:tests/%.c=$(B)/tests/%)
TEST_UTIL_SRC = $(wildcard tests/util/*.c)
TEST_UTIL_OBJ = $(TEST_UTIL_SRC:%.c=$(B)/%.o)
# cli/: the program, in three folders: run/ (main, the option table, the scene, the files of a run, compare,
# smoothness), figures/ (the gallery) and view/ (the viewer; its SDL2 window is a module of its own).
APP_SRC  = $(filter-out cli/run/main.c cli/view/view.c,$(wildcard cli/*/*.c))
APP_OBJ  = $(APP_SRC:%.c=$(B)/%.o)
# The window of `instess view` (cli/view/view.c, SDL2 and SDL2_ttf) is the module libinstess_view.so, opened by
# cli/view/view_state.c only when `instess view` runs: SDL2 links about fifty libraries, which every start of the
# program would load otherwise.
VIEW_SO  = $(B)/libinstess_view.so
CFLAGS_SDL = $(shell pkg-config --cflags sdl2 SDL2_ttf 2>/dev/null)
LDLIBS_SDL = $(shell pkg-config --libs sdl2 SDL2_ttf 2>/dev/null)
SETUP    = $(B)/.setup-done

.PHONY: all setup test test-unit sanitize faults valgrind fuzz figures bench goldens clean install uninstall \
        install-check python-check FORCE
.SECONDARY:
.DEFAULT_GOAL := all

all: $(B)/instess

setup: $(SETUP)
$(SETUP): scripts/setup.sh
	@bash scripts/setup.sh
	@mkdir -p $(B) && touch $@

$(B)/%.o: %.c $(SETUP)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(DEFS) $(OBJ_DEFS) -MMD -MP -c $< -o $@

$(B)/%.avx512.o: %.c $(SETUP)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(KERNEL512) -MMD -MP -c $< -o $@

# The OpenImageIO version the codec module is built against, for `instess --version` (image/image.c), which
# names it without loading the module.
$(B)/image/image.o: OBJ_DEFS = -DINSTESS_OIIO_VERSION='"$(shell pkg-config --modversion OpenImageIO 2>/dev/null)"'

$(B)/image/image_oiio.o: image/image_oiio.cpp $(SETUP)
	@mkdir -p $(dir $@)
	$(CXX) $(CXXFLAGS) -fPIC $(CXXFLAGS_IMG) -MMD -MP -c $< -o $@

$(CODEC_SO): $(IMG_OBJ)
	$(CXX) -shared $(LDFLAGS) $^ $(LDLIBS_IMG) -o $@

$(B)/cli/view/view.pic.o: cli/view/view.c $(SETUP)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -fPIC $(CFLAGS_SDL) -MMD -MP -c $< -o $@

$(VIEW_SO): $(B)/cli/view/view.pic.o
	$(CC) -shared $(LDFLAGS) $^ $(LDLIBS_SDL) -o $@

$(B)/libinstess.a: $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(B)/libinstess_app.a: $(APP_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(B)/instess: $(B)/cli/run/main.o $(B)/libinstess_app.a $(B)/libinstess.a | $(CODEC_SO) $(VIEW_SO)
	$(CC) $(LDFLAGS) $(PROG_LDFLAGS) $^ $(LDLIBS) -o $@

# The test programs in $(B)/tests/ find the modules beside themselves, as every program does (never one
# folder up): links to the build's modules.
$(B)/tests/libinstess_codec.so: | $(CODEC_SO)
	@mkdir -p $(dir $@)
	ln -sf ../libinstess_codec.so $@
$(B)/tests/libinstess_view.so: | $(VIEW_SO)
	@mkdir -p $(dir $@)
	ln -sf ../libinstess_view.so $@
TEST_MODULES = $(B)/tests/libinstess_codec.so $(B)/tests/libinstess_view.so

# The program with the test hooks (cli/run/output.c, INSTESS_TEST_HOOKS): only tests run it; its output.o is
# linked ahead of the archive, whose own output.o is then never pulled in.
HOOKS_BIN = $(B)/tests/instess-hooks
$(B)/cli/run/output.hooks.o: cli/run/output.c $(SETUP)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -DINSTESS_TEST_HOOKS -MMD -MP -c $< -o $@
$(HOOKS_BIN): $(B)/cli/run/main.o $(B)/cli/run/output.hooks.o $(B)/libinstess_app.a $(B)/libinstess.a | $(CODEC_SO) $(VIEW_SO) \
              $(TEST_MODULES)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $(PROG_LDFLAGS) $^ $(LDLIBS) -o $@

$(B)/tests/%: $(B)/tests/%.o $(TEST_UTIL_OBJ) $(B)/libinstess_app.a $(B)/libinstess.a | $(CODEC_SO) $(TEST_MODULES)
	$(CC) $(LDFLAGS) $(PROG_LDFLAGS) $^ $(LDLIBS_TEST) $(LDLIBS) -o $@

# make test = the unit, numerical and golden tests, the staged install, the Python package's tests, then the same
# tests built with AddressSanitizer and UndefinedBehaviorSanitizer (clang), then allocation failure everywhere
# (make faults), then valgrind on the renderer, then the browser page (make test-web, web/web.mk).  make test-unit
# runs only the first part.
# (+: the nested makes of tests/all.sh share this make's jobserver, so -j passes through without a warning)
test:
	+@MAKE="$(MAKE)" bash tests/all.sh

test-unit: $(TEST_BIN) $(B)/instess $(HOOKS_BIN)
	@bash tests/check_includes.sh
	@bash tests/make_check.sh
	@bash tests/check_api_walkers.sh
	@bash tests/run.sh $(TEST_BIN)

# The sanitizer build: every test, clang, ASan + UBSan with float-cast-overflow and float-divide-by-zero,
# halting on the first error (-fno-sanitize-recover=all), leaks checked by LeakSanitizer at exit, and the
# rasterizer's stated preconditions checked (INSTESS_CHECKS turns RS_ASSERT into assert).  Every program loads
# libstdc++ at start: ASan finds the real __cxa_throw only if it is there before the codec module is opened.
# The codec module (C++) is built without -fsanitize=function: its calls into the library go through the table
# the loader hands it (codec_set_host), and that check needs the C++ UBSan runtime, which the C programs lack.
# allocator_may_return_null: an allocation ASan cannot make (the API walkers ask for SIZE_MAX bytes) returns NULL,
# as malloc does, so the library's out-of-memory paths run instead of ASan's report.
# intercept_tls_get_addr=0: clang 14's LeakSanitizer records each thread's dynamic TLS through __tls_get_addr and,
# at exit, can read a garbage range for a dlopen'd module's block (the codec module's OpenImageIO) and die in its
# tracer ("Tracer caught signal 11", "DTLS 9 at 0x1bb4-0x2c00002cb6"): test_image did so on every run in a shell
# with a few more environment variables and never with `env -i`, i.e. as the addresses fell.  Without the
# interception that range is not scanned; no test reports a leak held only there.
SAN      = -fsanitize=address,undefined,float-cast-overflow,float-divide-by-zero -fno-sanitize-recover=all \
           -fno-omit-frame-pointer
SAN_B    = build-asan
# The make of the sanitizer build (its targets follow), shared by sanitize and faults.
SAN_MAKE = $(MAKE) --no-print-directory B=$(SAN_B) CC=clang CXX=clang++ OPT=-O1 \
	    CFLAGS="$(CFLAGS_BASE) $(SAN) -DINSTESS_CHECKS -Wno-unknown-warning-option" \
	    CXXFLAGS="-std=c++17 -O1 -g $(ARCH) -ffp-contract=off $(SAN) -fno-sanitize=vptr,function" \
	    LDFLAGS="-fopenmp -Wl,--no-as-needed -lstdc++ -Wl,--as-needed $(SAN)"
SAN_ENV  = ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:halt_on_error=1:allocator_may_return_null=1:intercept_tls_get_addr=0 \
	   UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 LSAN_OPTIONS=suppressions=tests/lsan.supp
sanitize: $(SETUP)
	@bash scripts/setup.sh --sanitize
	@$(SAN_MAKE) $(TEST_BIN:$(B)/%=$(SAN_B)/%) $(SAN_B)/instess $(SAN_B)/tests/instess-hooks
	@$(SAN_ENV) \
	 INSTESS_BIN=$(SAN_B)/instess INSTESS_HOOKS_BIN=$(SAN_B)/tests/instess-hooks TEST_LOG_DIR=$(SAN_B)/test-logs TEST_LABEL=sanitize \
	 bash tests/run.sh $(TEST_BIN:$(B)/%=$(SAN_B)/%)

# The fault-injection build (tests/fault/fault.c): the program of the sanitizer build with every malloc, calloc,
# realloc, aligned_alloc and strdup of its own objects wrapped, so that INSTESS_FAULT_AT=N fails the N-th.
# tests/faults.sh runs a render, a compare and an import with N = 1, 2, ... until the operation succeeds: each
# failure must end in an error message and the error's exit code, with no output written, no leak and no
# sanitizer report.  It is never the normal program: only this target links fault.o.
FAULT_WRAP = -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc,--wrap=aligned_alloc,--wrap=strdup
FAULT_BIN  = $(B)/tests/instess-faults
$(FAULT_BIN): $(B)/cli/run/main.o $(B)/tests/fault/fault.o $(B)/libinstess_app.a $(B)/libinstess.a | $(CODEC_SO) \
              $(VIEW_SO) $(TEST_MODULES)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $(PROG_LDFLAGS) $(FAULT_WRAP) $^ $(LDLIBS) -o $@

faults: $(SETUP)
	@bash scripts/setup.sh --sanitize
	@$(SAN_MAKE) $(SAN_B)/tests/instess-faults
	@$(SAN_ENV) bash tests/faults.sh $(SAN_B)/tests/instess-faults

# valgrind on the renderer: a few scenes, no errors, no definite leaks.  memcheck runs the instess program
# built with tests/valgrind/codec_raw.c in place of the OpenImageIO codec (OpenImageIO's libhwy dies of SIGILL
# under valgrind on CPUs without RDTSCP; see that file): the renderer's code is the same, only the file
# encoding differs, and each image is compared with the same run's image outside valgrind.
VG_BIN   = $(B)/tests/valgrind/instess
$(VG_BIN): $(B)/cli/run/main.o $(B)/libinstess_app.a $(filter-out $(B)/image/image_codec.o,$(LIB_OBJ)) \
          $(B)/tests/valgrind/codec_raw.o
	$(CC) $(LDFLAGS) $^ $(LDLIBS_MESH) $(LDLIBS_PNG) -lm -o $@

valgrind: $(VG_BIN)
	@bash scripts/setup.sh --sanitize
	@bash tests/valgrind.sh $(VG_BIN)

# ------------------------------------------------------------------------------------------------------------
# make install / make uninstall.  The version is core.h's INSTESS_VERSION; the soname carries its major number.
#   $(LIBDIR)/libinstess.so.X.Y.Z (soname libinstess.so.X), libinstess.so -> it, libinstess.a
#   $(LIBDIR)/instess/libinstess_codec.so   the OpenImageIO codec module the library opens on its first image call
#   $(LIBDIR)/instess/libinstess_view.so    the SDL2 window of `instess view`, opened only by that command
#   $(INCLUDEDIR)/instess/{core/core.h,raster/raster.h,vs/vs.h,meshes/meshes.h}: the folders' public headers
#     as they are in the tree (their relative includes, "../core/core.h", hold there too)
#   $(PKGCONFIGDIR)/instess.pc, $(BINDIR)/instess, $(MANDIR)/man1/instess.1 (written by `instess --man`)
# The library's objects are built again with -fPIC under $(B)/pic/ (the program and the tests keep the fixed
# configuration's objects).  The module's folder is compiled into image/image_codec.c (INSTESS_CODEC_DIR), so
# changing PREFIX or LIBDIR rebuilds that one object; the shared library finds the module beside itself first,
# which is what a staged (DESTDIR) copy uses.  cli/run/scene.h is the program's layer (option tables, output files)
# and is not installed: a user sets up the device and the instanced draw with core.h, as examples/ shows.
VERSION    := $(shell sed -n 's/^\#define INSTESS_VERSION "\(.*\)"/\1/p' core/api.h)
SOVERSION  := $(firstword $(subst ., ,$(VERSION)))
PREFIX     ?= /usr/local
BINDIR     ?= $(PREFIX)/bin
LIBDIR     ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
MANDIR     ?= $(PREFIX)/share/man
PKGCONFIGDIR ?= $(LIBDIR)/pkgconfig
CODECDIR    = $(LIBDIR)/instess
SO_NAME     = libinstess.so.$(SOVERSION)
SO_REAL     = libinstess.so.$(VERSION)
PIC_OBJ     = $(LIB_SRC:%.c=$(B)/pic/%.o) $(KERNEL_SRC:%.c=$(B)/pic/%.avx512.o)
# The Python package (python/instess) goes where Debian's python3 finds it: PREFIX/lib/python3.X/dist-packages
# (/usr/local/lib/python3.11/dist-packages and /usr/lib/python3.11/dist-packages are both on its path).
PYTHON     ?= /usr/bin/python3
PYTHONDIR  ?= $(PREFIX)/lib/python$(shell $(PYTHON) -c 'import sys; print("%d.%d" % sys.version_info[:2])' 2>/dev/null || echo 3)/dist-packages
PUB_HDR     = core/core.h core/api.h core/math.h core/device.h core/texture.h core/grid.h core/inspect.h core/pixel.h raster/raster.h vs/vs.h \
              meshes/meshes.h image/image.h tess/tess.h
INSTALLED   = $(BINDIR)/instess $(MANDIR)/man1/instess.1 $(LIBDIR)/$(SO_REAL) $(LIBDIR)/$(SO_NAME) \
              $(LIBDIR)/libinstess.so $(LIBDIR)/libinstess.a $(CODECDIR)/libinstess_codec.so $(CODECDIR)/libinstess_view.so \
              $(CODECDIR)/libinstess_run.so $(PKGCONFIGDIR)/instess.pc $(PUB_HDR:%=$(INCLUDEDIR)/instess/%) \
              $(PYTHONDIR)/instess/__init__.py $(PYTHONDIR)/instess/_paths.py

# The module's folder as compiled in: the stamp changes (and image_codec.o is rebuilt) only when it does.
$(B)/.codecdir: FORCE
	@mkdir -p $(B)
	@echo '$(CODECDIR)' | cmp -s - $@ || echo '$(CODECDIR)' > $@
FORCE:
$(B)/image/image_codec.o $(B)/pic/image/image_codec.o $(B)/cli/view/view_state.o: $(B)/.codecdir
$(B)/image/image_codec.o $(B)/pic/image/image_codec.o: DEFS = -DINSTESS_CODEC_DIR='"$(CODECDIR)"'

$(B)/pic/%.avx512.o: %.c $(SETUP)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(KERNEL512) -fPIC -fvisibility=hidden -fno-semantic-interposition -MMD -MP -c $< -o $@

$(B)/pic/%.o: %.c $(SETUP)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -fPIC -fvisibility=hidden -fno-semantic-interposition $(DEFS) -MMD -MP -c $< -o $@

# -z defs: every symbol the library uses is in it or in the libraries named here.
$(B)/$(SO_REAL): $(PIC_OBJ)
	$(CC) -shared -Wl,-soname,$(SO_NAME) -Wl,-z,defs $(LDFLAGS) $^ $(LDLIBS) -ldl -lpthread -o $@

# The program's render as one library call (cli/run/render_call.c, scene_render_args) for the Python package:
# the module libinstess_run.so, cli/run/ built again with -fPIC and hidden symbols (only scene_render_args is
# exported), linked against libinstess.so (DT_NEEDED libinstess.so.0, found beside it: RUNPATH $ORIGIN/..).
RUN_SRC     = $(filter-out cli/run/main.c,$(wildcard cli/run/*.c))
RUN_SO      = $(B)/libinstess_run.so
$(RUN_SO): $(RUN_SRC:%.c=$(B)/pic/%.o) $(B)/$(SO_REAL)
	$(CC) -shared -Wl,-z,defs -Wl,-rpath,'$$ORIGIN/..' $(LDFLAGS) $^ $(LDLIBS) -o $@

# The man page, from the program's own tables (the same that print --help).
$(B)/instess.1: $(B)/instess
	$(B)/instess --man > $@.tmp && mv $@.tmp $@

# instess.pc: the library links assimp (Requires.private), meshoptimizer, libpng, OpenMP and libstdc++
# (Libs.private; libpng there, not in Requires.private, whose Cflags pkg-config would add: no installed header
# includes png.h);
# a static link must also export the library's image functions to the codec module (-rdynamic).  libdir and
# includedir are relative to ${prefix} when under it, so `pkg-config --define-variable=prefix=...` finds a
# staged or moved copy.
$(B)/instess.pc: Makefile core/api.h $(B)/.codecdir
	@printf '%s\n' 'prefix=$(PREFIX)' 'libdir=$(patsubst $(PREFIX)/%,$${prefix}/%,$(LIBDIR))' \
	  'includedir=$(patsubst $(PREFIX)/%,$${prefix}/%,$(INCLUDEDIR))' '' \
	  'Name: instess' 'Description: tessellation through instancing on a CPU Direct3D 9-style device' \
	  'Version: $(VERSION)' 'Requires.private: assimp' 'Cflags: -I$${includedir}' \
	  'Libs: -L$${libdir} -linstess' 'Libs.private: -rdynamic -lmeshoptimizer $(LDLIBS_PNG) -fopenmp -lstdc++ -ldl -lpthread -lm' > $@

install: $(B)/instess $(B)/instess.1 $(B)/$(SO_REAL) $(B)/libinstess.a $(CODEC_SO) $(VIEW_SO) $(RUN_SO) $(B)/instess.pc
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR) $(DESTDIR)$(CODECDIR) $(DESTDIR)$(PKGCONFIGDIR) \
	    $(DESTDIR)$(MANDIR)/man1 $(addprefix $(DESTDIR)$(INCLUDEDIR)/instess/,$(dir $(PUB_HDR))) \
	    $(DESTDIR)$(PYTHONDIR)/instess
	install -m 755 $(B)/instess $(DESTDIR)$(BINDIR)/instess
	install -m 644 $(B)/instess.1 $(DESTDIR)$(MANDIR)/man1/instess.1
	install -m 755 $(B)/$(SO_REAL) $(DESTDIR)$(LIBDIR)/$(SO_REAL)
	ln -sf $(SO_REAL) $(DESTDIR)$(LIBDIR)/$(SO_NAME)
	ln -sf $(SO_NAME) $(DESTDIR)$(LIBDIR)/libinstess.so
	install -m 644 $(B)/libinstess.a $(DESTDIR)$(LIBDIR)/libinstess.a
	install -m 755 $(CODEC_SO) $(DESTDIR)$(CODECDIR)/libinstess_codec.so
	install -m 755 $(VIEW_SO) $(DESTDIR)$(CODECDIR)/libinstess_view.so
	install -m 755 $(RUN_SO) $(DESTDIR)$(CODECDIR)/libinstess_run.so
	install -m 644 python/instess/__init__.py $(DESTDIR)$(PYTHONDIR)/instess/__init__.py
	printf '%s\n' '# Where make install put the libraries (python/instess/__init__.py looks here first).' \
	  "LIBDIR = '$(LIBDIR)'" "MODULEDIR = '$(CODECDIR)'" > $(DESTDIR)$(PYTHONDIR)/instess/_paths.py
	install -m 644 $(B)/instess.pc $(DESTDIR)$(PKGCONFIGDIR)/instess.pc
	for h in $(PUB_HDR); do install -m 644 $$h $(DESTDIR)$(INCLUDEDIR)/instess/$$h || exit 1; done

# Removes the files install writes, then the folders it made if they are empty.
uninstall:
	rm -f $(addprefix $(DESTDIR),$(INSTALLED))
	rm -rf $(DESTDIR)$(PYTHONDIR)/instess/__pycache__
	-rmdir $(addprefix $(DESTDIR)$(INCLUDEDIR)/instess/,$(dir $(PUB_HDR))) $(DESTDIR)$(INCLUDEDIR)/instess \
	    $(DESTDIR)$(CODECDIR) $(DESTDIR)$(PYTHONDIR)/instess 2>/dev/null || true

# The staged install, the example built against it with pkg-config, each installed header alone, the man page.
install-check: $(B)/instess
	@bash tests/install_check.sh

# The Python package's tests (python/tests, pytest with Debian's python3) on this build's library.
python-check: $(B)/$(SO_REAL) $(RUN_SO) $(B)/instess
	@INSTESS_LIBDIR=$(B) INSTESS_BIN=$(B)/instess PYTHON=$(PYTHON) bash tests/python_check.sh

figures: $(B)/instess
	@mkdir -p out
	$(B)/instess figures --out out

# make goldens ONLY=fig-1.1.2,fig-003-5 regenerates just those goldens (the rest are checked as usual).
goldens: $(B)/instess $(TEST_BIN)
	INSTESS_REGENERATE_GOLDENS=1 INSTESS_GOLDENS_ONLY=$(ONLY) bash tests/run.sh $(TEST_BIN)

include bench/bench.mk
include web/web.mk
-include tests/fuzz/fuzz.mk

# Every build folder: build/, the sanitizer's, the fuzzers' and any other build-*/ (and tests/failures/).
clean:
	rm -rf $(B) build build-* tests/failures

-include $(shell find $(B) -name '*.d' 2>/dev/null)
