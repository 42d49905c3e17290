/* core/core.h -- the core of instess, one include: the HLSL-like math (core/math.h), the Direct3D 9-style
 * device (core/device.h), its textures and samplers (core/texture.h), its pixel shaders (core/pixel.h), the
 * tessellation grids (core/grid.h) and the pipeline inspector (core/inspect.h).
 * Each of those headers states its own conventions; images are the module image/ (image/image.h).
 */
#ifndef INSTESS_CORE_H
#define INSTESS_CORE_H

#include "api.h"
#include "math.h"
#include "device.h"
#include "texture.h"
#include "grid.h"
#include "inspect.h"
#include "pixel.h"

#endif
