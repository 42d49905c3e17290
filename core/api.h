/* core/api.h -- INSTESS_API, the mark of every function the shared library exports.
 *
 * Conventions: libinstess.so is built with -fvisibility=hidden, so a function is visible to its users only when
 * its prototype in an installed header carries INSTESS_API; everything else (helpers shared between the
 * library's files, internal headers) stays inside the library.  tests/install_check.sh compares `nm -D` of the
 * shared library with the INSTESS_API prototypes of the installed headers: the two lists must be equal.
 */
#ifndef INSTESS_API_H
#define INSTESS_API_H

#define INSTESS_API __attribute__((visibility("default")))

#define INSTESS_VERSION "0.1.0"

#endif
