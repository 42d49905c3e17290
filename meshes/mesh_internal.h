/* meshes/mesh_internal.h -- helpers shared by the files of meshes/ (not part of the public header). */
#ifndef INSTESS_MESH_INTERNAL_H
#define INSTESS_MESH_INTERNAL_H

#include <stddef.h>

/* Write a formatted message into err (if any). */
void mesh_set_err(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

#endif
