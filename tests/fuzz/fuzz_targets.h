/* tests/fuzz/fuzz_targets.h -- the code paths the fuzzers drive, shared by the libFuzzer harnesses
 * (tests/fuzz/fuzz_import.c, fuzz_mesh.c) and the cmocka replay of the regression inputs
 * (tests/test_fuzz_regressions.c), which runs them in-process without libFuzzer.
 *
 * Each function runs one input through instess and checks the invariants of docs/design.md, section 6 (an error
 * with a message naming the input, or a valid mesh whose 32x32 render has only finite pixels in range).  It
 * returns 0 when every invariant held and -1 with the broken one described in why[] otherwise; the harnesses
 * turn -1 into abort() so that libFuzzer keeps the input.  Crashes (sanitizer reports) are found by the
 * sanitizers themselves. */
#ifndef INSTESS_FUZZ_TARGETS_H
#define INSTESS_FUZZ_TARGETS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Arbitrary bytes as a mesh file: the format hint is sniffed from the content (ply, OFF, solid / binary STL,
 * IDP2 = md2, glTF, else obj), as a file's extension would name it; imported in this process
 * (sandboxed = false: assimp's crashes crash the caller) or in the forked child of meshes/import.c
 * (sandboxed = true: the program's own path, where they become errors, the child stopped after timeout_ms;
 * 0: 10 s), then validated and rendered. */
int fuzz_import_input(const uint8_t *data, size_t size, bool sandboxed, int timeout_ms, char *why, size_t whylen);

/* Arbitrary bytes as raw mesh arrays (layout in fuzz_targets.c) into mesh_create, then instances,
 * tessellation and a 32x32 render with the patch, level, grid, path, fill and camera the bytes choose. */
int fuzz_mesh_input(const uint8_t *data, size_t size, char *why, size_t whylen);

/* The format hint fuzz_import_input uses for these bytes ("ply", "off", "stl", "md2", "glb", "gltf", "obj"). */
const char *fuzz_sniff_format(const uint8_t *data, size_t size);

#endif
