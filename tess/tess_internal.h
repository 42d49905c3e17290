/* tess/tess_internal.h -- what tess/'s files share.  Private to tess/. */
#ifndef INSTESS_TESS_INTERNAL_H
#define INSTESS_TESS_INTERNAL_H

#include "tess.h"
#include "../core/hlsl.h"
#include "../vs/vs.h"

/* Whether p renumbers three corners (0, 1, 2 each once): tess_permute_instance and
 * tess_permute_adjacent_normals read anything else as the identity (a NULL p too). */
static inline bool tess_is_permutation(const uint8_t *p)
{
    return p && p[0] < 3 && p[1] < 3 && p[2] < 3 && p[0] != p[1] && p[1] != p[2] && p[0] != p[2];
}

#endif
