/* web/compat/meshoptimizer.h -- the one meshoptimizer function the browser build uses (meshes/mesh.c's
 * welding), implemented in web/meshopt.c: Debian's meshoptimizer is an x86-64 library, and the importer that
 * uses the rest of it (meshes/import.c, through assimp) is not part of the page. */
#ifndef INSTESS_WEB_MESHOPTIMIZER_H
#define INSTESS_WEB_MESHOPTIMIZER_H

#include <stddef.h>

/* destination[i] = the first index in index order whose vertex has the same vertex_size bytes as that of
 * indices[i] (meshoptimizer 0.18's meshopt_generateShadowIndexBuffer, the same result). */
void meshopt_generateShadowIndexBuffer(unsigned int *destination, const unsigned int *indices, size_t index_count,
                                       const void *vertices, size_t vertex_count, size_t vertex_size,
                                       size_t vertex_stride);

#endif
