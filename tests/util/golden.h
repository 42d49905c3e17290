/* tests/util/golden.h -- pixel-diff ("golden image") checks for every golden test of the project.
 *
 * A golden is the reviewed, committed image a test's output must match: tests/golden/<name>.png, or .exr when
 * name ends in ".exr" (EXR keeps depth and AOV channels; PNG keeps the first four channels in 8 bits).
 *
 *   // 0.5% of the pixels may differ by more than 2/255 (anti-aliased edges of this scene may move by a bit).
 *   assert_int_equal(golden_check(&img, "raster_cube_l4", 2.0f / 255.0f, 0.5f), 0);
 *
 * golden_check first writes the actual image to the failure directory in the golden's format and reads it back,
 * so the comparison sees exactly what a regeneration would store (8-bit or half rounding included); a
 * threshold of 0 therefore means "the same file content".
 *  - INSTESS_REGENERATE_GOLDENS=1 (set by `make goldens`): (re)writes the golden and passes; with
 *    INSTESS_GOLDENS_ONLY=NAME[,NAME...] (`make goldens ONLY=...`) only those goldens (names without the
 *    extension, e.g. fig-1.1.2), the others are checked as usual.
 *  - Otherwise the golden is compared with image_check (image/image.h), the same pixel-diff test as `instess compare
 *    ACTUAL GOLDEN --fail T --failpercent P`: the check passes when at most fail_percent percent of the pixels
 *    have a channel differing by more than fail_thresh.  A missing golden is a FAILURE.
 *  - On failure it keeps <failures>/<name>.actual.<ext> and writes <failures>/<name>.diff.png (red: failing
 *    pixels), prints the max / mean error and the counts on stderr, and how to regenerate (`make goldens`).
 * Directories (relative to the repository top, where tests run) can be overridden for tests of this helper:
 *   INSTESS_GOLDEN_DIR (default tests/golden), INSTESS_FAILURE_DIR (default tests/failures).
 */
#ifndef INSTESS_TESTS_GOLDEN_H
#define INSTESS_TESTS_GOLDEN_H

#include "../../core/core.h"
#include "../../core/hlsl.h"
#include "../../image/image.h"

/* Returns 0 when actual matches the golden `name` (or the golden was regenerated), -1 otherwise. */
int golden_check(const is_image *actual, const char *name, float fail_thresh, float fail_percent);

/* The directories in use (environment override or default). */
const char *golden_dir(void);
const char *golden_failure_dir(void);

#endif
