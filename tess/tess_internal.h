/* tess/tess_internal.h -- what tess/'s files share.  Private to tess/. */
#ifndef INSTESS_TESS_INTERNAL_H
#define INSTESS_TESS_INTERNAL_H

#include "tess.h"
#include "../core/hlsl.h"
#include "../vs/vs.h"

#endif
