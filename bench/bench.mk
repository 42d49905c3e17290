# bench/bench.mk -- `make bench`: build/bench (instess, in-process) against build/bench-gl (Mesa's llvmpipe).
# Included from the top-level Makefile (include bench/bench.mk); uses its B, CC, CFLAGS, LDFLAGS, LDLIBS and
# pattern rule $(B)/%.o: %.c.  build/bench-gl needs EGL and the GL headers (scripts/setup.sh --bench installs
# them); `make` and `make test` never build it.  The GL entry points are loaded with eglGetProcAddress, so
# bench-gl links libEGL only.
#   make bench                      the whole benchmark (scripts/setup.sh --bench first)
#   make bench BENCH_ARGS='--scenes A --patch npatch --keep out/bench'

BENCH_ARGS ?=
BENCH_GL_CFLAGS = $(shell pkg-config --cflags egl 2>/dev/null)
BENCH_GL_LIBS   = $(shell pkg-config --libs egl 2>/dev/null || echo -lEGL)

# Objects go to $(B)/bench-obj/ (not $(B)/bench/, which would clash with the program $(B)/bench).
BENCH_OBJ = $(B)/bench-obj

$(BENCH_OBJ)/gl_ref.o: bench/gl_ref.c bench/gl_shaders.h bench/bench_scene_file.h
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(BENCH_GL_CFLAGS) -MMD -MP -c $< -o $@

$(BENCH_OBJ)/bench.o: bench/bench.c bench/bench_lod.h bench/bench_scene_file.h $(SETUP)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -MMD -MP -c $< -o $@

$(BENCH_OBJ)/bench_lod.o: bench/bench_lod.c bench/bench_lod.h $(SETUP)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -MMD -MP -c $< -o $@

$(B)/bench-gl: $(BENCH_OBJ)/gl_ref.o
	$(CC) $(LDFLAGS) $^ $(BENCH_GL_LIBS) -o $@

$(B)/bench: $(BENCH_OBJ)/bench.o $(BENCH_OBJ)/bench_lod.o $(B)/libinstess.a
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

.PHONY: bench-setup bench-build
bench-setup:
	@bash scripts/setup.sh --bench

bench-build: bench-setup
	@$(MAKE) --no-print-directory -f $(firstword $(MAKEFILE_LIST)) $(B)/bench $(B)/bench-gl

bench: bench-build
	$(B)/bench $(BENCH_ARGS)
