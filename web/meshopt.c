/* web/meshopt.c -- meshopt_generateShadowIndexBuffer for the browser build (web/compat/meshoptimizer.h says
 * why): every index is replaced by the first index, in index order, whose vertex has the same bytes.  An open
 * hash table keyed by the vertex bytes (FNV-1a), as meshoptimizer does; out of memory aborts, as meshoptimizer's
 * allocator does (the page reports the trap). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "compat/meshoptimizer.h"

/* FNV-1a of n bytes at p. */
static uint32_t hash_bytes(const unsigned char *p, size_t n)
{
    uint32_t h = 2166136261u;
    for (size_t k = 0; k < n; k++) h = (h ^ p[k]) * 16777619u;
    return h;
}

void meshopt_generateShadowIndexBuffer(unsigned int *destination, const unsigned int *indices, size_t index_count,
                                       const void *vertices, size_t vertex_count, size_t vertex_size,
                                       size_t vertex_stride)
{
    const unsigned char *v = vertices;
    size_t size = 16;
    while (size < 2 * vertex_count) size *= 2;
    unsigned int *table = malloc(size * sizeof *table), *first = malloc((vertex_count ? vertex_count : 1) * sizeof *first);
    if (!table || !first) abort();
    memset(table, 0xff, size * sizeof *table);
    memset(first, 0xff, (vertex_count ? vertex_count : 1) * sizeof *first);
    for (size_t i = 0; i < index_count; i++) {
        unsigned int index = indices[i];
        if (first[index] == ~0u) {
            const unsigned char *key = v + (size_t)index * vertex_stride;
            size_t slot = hash_bytes(key, vertex_size) & (size - 1);
            while (table[slot] != ~0u && memcmp(v + (size_t)table[slot] * vertex_stride, key, vertex_size) != 0)
                slot = (slot + 1) & (size - 1);
            if (table[slot] == ~0u) table[slot] = index;
            first[index] = table[slot];
        }
        destination[i] = first[index];
    }
    free(table);
    free(first);
}
