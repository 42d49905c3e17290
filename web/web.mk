# web/web.mk -- `make web`: the tutorial in the browser (README, "The tutorial in a browser"), included by the
# Makefile.  out/web/index.html is one file: the page, its JavaScript and the WebAssembly module (base64), so it
# opens from the disk without a server.
#
#   make web                              build out/web/index.html (installs the toolchain: setup.sh --web)
#   make test-web                         the browser test (tests/web_test.sh): the page in headless Chromium
#                                         against build/instess, pixel for pixel, and its controls
#   make web WEB_TOOLCHAIN=emscripten     the same page with Debian's emscripten instead (apt-get install
#                                         emscripten): the measurement of the README compares the two
#
# What is compiled: the library (core/ raster/ vs/ tess/, meshes/ without the assimp import) with RS_NO_KERNELS
# (raster/raster_internal.h: the reference path, no x86 kernels) and without -fopenmp (web/compat/omp.h: one
# thread), the program's scene layer (cli/run/scene.c, lighting.c, options.c: the one way a view is rendered and
# the option table, so that a frame is `instess`'s command line) and web/: the front end (web.c), the OBJ reader
# (obj.c), meshoptimizer's welding (meshopt.c), the native C library's trigonometry at the page's angles
# (libm.c, with the table web/trig_table.c makes natively).  Same -O2 -ffp-contract=off as the program.

WEB_TOOLCHAIN ?= wasi
WEB_OUT  ?= out/web
WEB_B     = $(B)/web-$(WEB_TOOLCHAIN)
WEB_LIB_SRC = $(filter-out raster/span.c raster/span_wide.c raster/setup_simd.c,$(wildcard core/*.c raster/*.c vs/*.c tess/*.c)) \
              meshes/mesh.c meshes/builtin.c meshes/normals_check.c image/image.c
WEB_APP_SRC = cli/run/scene.c cli/run/lighting.c cli/run/options.c cli/run/displace.c cli/run/inspect.c \
              cli/run/shading.c $(wildcard web/*.c)
WEB_SRC   = $(WEB_LIB_SRC) $(filter-out web/trig_table.c,$(WEB_APP_SRC))
WEB_OBJ   = $(WEB_SRC:%.c=$(WEB_B)/%.o)
WEB_WARN  = -Wall -Wextra -Wno-unused-parameter -Wshadow -Wstrict-prototypes -Werror=switch -Wno-source-uses-openmp
WEB_CFLAGS = -std=c17 -O2 -ffp-contract=off $(WEB_WARN) -D_POSIX_C_SOURCE=200809L -DRS_NO_KERNELS -Iweb/compat \
             -I$(WEB_B)/web
WEB_SETUP = $(B)/.setup-web-done

# wasi: clang 14 for wasm32-wasi with Debian's wasi-libc (only its headers: not /usr/include), a reactor module
# (no main: the page calls its exports), 4 MiB of stack.
ifeq ($(WEB_TOOLCHAIN),wasi)
WEB_CC      = clang --target=wasm32-wasi
WEB_SYSINC  = -nostdlibinc -isystem /usr/include/wasm32-wasi
WEB_LDFLAGS = -mexec-model=reactor -Wl,-z,stack-size=4194304 -Wl,--strip-debug
WEB_BUILD_INFO = WebAssembly: clang $(shell clang -dumpversion 2>/dev/null), wasm32-wasi
else ifeq ($(WEB_TOOLCHAIN),emscripten)
# emscripten: a standalone module (it imports the same WASI calls, so the page is the same), memory that grows.
# The node of the machine may not see Debian's node modules (acorn): NODE_PATH points there.
WEB_CC      = NODE_PATH=/usr/share/nodejs emcc
WEB_LDFLAGS = -sSTANDALONE_WASM --no-entry -sALLOW_MEMORY_GROWTH=1 -sTOTAL_STACK=4194304
WEB_BUILD_INFO = WebAssembly: emscripten $(shell NODE_PATH=/usr/share/nodejs emcc -dumpversion 2>/dev/null)
else
$(error WEB_TOOLCHAIN must be wasi or emscripten)
endif

.PHONY: web test-web
web: $(WEB_OUT)/index.html

$(WEB_SETUP): scripts/setup.sh
	@bash scripts/setup.sh --web
	@mkdir -p $(B) && touch $@

$(WEB_B)/%.o: %.c $(WEB_SETUP)
	@mkdir -p $(dir $@)
	$(WEB_CC) $(WEB_SYSINC) $(WEB_CFLAGS) -MMD -MP -c $< -o $@

# raster/tri.c and raster/target.c with WebAssembly's 128-bit SIMD: the 4-sample walk's vectors (tri_tile_msaa4)
# and target.c's loops (the 4-sample resolve, the fills) become SIMD instructions, the same IEEE and integer
# operations per lane (tests/web_test.mjs compares the page with build/instess pixel for pixel).  The page's
# default 4-sample cube: 7.6-7.8 -> 6.8-6.9 ms a frame (`ROUNDS=15 node web/measure.mjs`, two alternated runs; the
# same as the whole module with -msimd128; tri.c alone gave nothing; the 1-sample cube 4.0 -> 4.1-4.2 ms).
# Browsers without SIMD (before Chrome 91, Firefox 89, Safari 16.4) cannot load the module.
$(WEB_B)/raster/tri.o $(WEB_B)/raster/target.o: WEB_CFLAGS += -msimd128

# The native C library's trigonometry at the page's angles (web/trig_table.c says why); -fno-builtin: computed by
# the library at run time, as the program computes them, never folded by the compiler.
$(B)/web-tools/trig_table: web/trig_table.c $(SETUP)
	@mkdir -p $(dir $@)
	$(CC) -std=c17 -O2 -ffp-contract=off -fno-builtin $< -lm -o $@
$(WEB_B)/web/trig_table.h: $(B)/web-tools/trig_table
	@mkdir -p $(dir $@)
	$< > $@.tmp && mv $@.tmp $@
$(WEB_B)/web/libm.o: $(WEB_B)/web/trig_table.h

$(WEB_B)/instess.wasm: $(WEB_OBJ)
	$(WEB_CC) $(WEB_CFLAGS) $^ $(WEB_LDFLAGS) -o $@

# The page: web/page.html with its script (web/wasi.js, web/page.js) and the module (base64) put in, written to a
# temporary file and renamed (never half a page).
$(WEB_OUT)/index.html: web/page.html web/wasi.js web/page.js web/assemble.sh $(WEB_B)/instess.wasm
	@mkdir -p $(WEB_OUT)
	WEB_BUILD_INFO='$(WEB_BUILD_INFO)' bash web/assemble.sh web/page.html $(WEB_B)/instess.wasm $@ web/wasi.js web/page.js

test-web: $(B)/instess
	@bash tests/web_test.sh

# The page's OBJ reader (web/obj.c) is also compiled natively for tests/test_web_obj.c, which compares it with
# the program's import.
$(B)/tests/test_web_obj: $(B)/web/obj.o
