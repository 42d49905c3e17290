#!/usr/bin/env bash
# tests/install_check.sh -- `make install-check`, a stage of `make test`: instess as a user installs and uses it.
#   - make install into a temporary DESTDIR (PREFIX /usr/local): every file, the soname and its links;
#   - each installed header compiles alone as C17 (-Wall -Wextra -Wpedantic -Werror);
#   - examples/npatch_diff.c built with pkg-config against the staged copy alone, from a folder outside the
#     repository: the headers it includes and the library it loads are the staged ones (checked with cc -H and
#     ldd); it matches examples/npatch_diff.png and fails (exit 1, diff image written) on another image;
#   - the same example linked with the static archive: a PNG needs no module (libpng is in the library); for an
#     EXR it finds the codec module through the folder compiled in from LIBDIR (named in its message), or
#     $INSTESS_CODEC_DIR;
#   - the staged program renders (finding its module in ../lib/instess) and compares;
#   - man -l renders the staged page, which names every option `instess --help` prints;
#   - the Python package: staged where Debian's python3 looks, it renders and compares with the staged
#     library; installed into a PREFIX of its own, it finds the library there by itself;
#   - a PREFIX of its own is compiled into the module's folder (the man page's FILES names it);
#   - make uninstall leaves no file behind.
# Prints "install: N passed, M failed"; exit status 1 when M > 0.
set -u
make=${MAKE:-make}
root=$(cd "$(dirname "$0")/.." && pwd)
B=${B:-build}
tmp=$(mktemp -d /tmp/instess-install-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
stage=$tmp/stage
prefix=/usr/local
pass=0; fail=0

# check NAME COMMAND...: run it quietly (output kept in $tmp/last.log); count and report.
check() {
  local name=$1; shift
  if ( "$@" ) >"$tmp/last.log" 2>&1; then pass=$((pass + 1)); echo "ok   $name"
  else fail=$((fail + 1)); echo "FAIL $name"; sed 's/^/    /' "$tmp/last.log" | head -n 20; fi
}

cd "$root" || exit 2
# The builds run here (not counted); what they produced is checked below.
$make --no-print-directory install DESTDIR="$stage" PREFIX=$prefix >"$tmp/install.log" 2>&1 ||
  { cat "$tmp/install.log"; echo "install: 0 passed, 1 failed"; exit 1; }

S=$stage$prefix
files_installed() {
  for f in bin/instess share/man/man1/instess.1 lib/libinstess.so.0.1.0 lib/libinstess.a \
           lib/instess/libinstess_codec.so lib/instess/libinstess_view.so lib/instess/libinstess_run.so \
           lib/pkgconfig/instess.pc \
           include/instess/core/core.h \
           include/instess/core/api.h include/instess/core/math.h include/instess/core/device.h \
           include/instess/core/texture.h \
           include/instess/core/grid.h include/instess/image/image.h include/instess/tess/tess.h \
           include/instess/raster/raster.h include/instess/vs/vs.h include/instess/meshes/meshes.h; do
    [ -f "$S/$f" ] || { echo "missing $S/$f"; return 1; }
  done
  [ "$(readlink "$S/lib/libinstess.so")" = libinstess.so.0 ] && [ "$(readlink "$S/lib/libinstess.so.0")" = libinstess.so.0.1.0 ] &&
    readelf -d "$S/lib/libinstess.so.0.1.0" | grep -q 'SONAME.*\[libinstess.so.0\]'
}
check "install: files, soname libinstess.so.0 and its links" files_installed

header_alone() {
  printf '#include <instess/%s>\nint main(void) { return 0; }\n' "$1" |
    cc -std=c17 -Wall -Wextra -Wpedantic -Werror -I"$S/include" -x c - -c -o /dev/null
}
for h in core/core.h core/api.h core/math.h core/device.h core/texture.h core/grid.h image/image.h raster/raster.h \
         vs/vs.h meshes/meshes.h tess/tess.h; do check "header alone as C17: $h" header_alone "$h"; done

# Export control: the shared library exports exactly the INSTESS_API names of the installed headers (built with
# -fvisibility=hidden: a helper shared between the library's files stays inside it).
exports_equal_api() {
  local hdrs
  hdrs=$(cd "$S/include/instess" && find . -name '*.h' | sed 's#^\./##' | sort)
  (cd "$S/include/instess" && python3 "$root/tests/api_names.py" $hdrs) > "$tmp/api.txt" || return 1
  nm -D --defined-only "$S/lib/libinstess.so.0.1.0" | awk '$2 ~ /^[TDRBV]$/ {print $3}' | sort > "$tmp/exports.txt"
  diff "$tmp/api.txt" "$tmp/exports.txt" >"$tmp/exports.diff" ||
    { echo "< declared INSTESS_API, not exported; > exported, not declared:"; cat "$tmp/exports.diff"; return 1; }
  [ -s "$tmp/api.txt" ]
}
check "exports: nm -D of libinstess.so equals the INSTESS_API names of the installed headers" exports_equal_api

# pkg-config finds the staged copy alone: its .pc through PKG_CONFIG_PATH (the build tree has none), moved
# to the stage by redefining prefix.
pc() { PKG_CONFIG_PATH="$S/lib/pkgconfig" PKG_CONFIG_LIBDIR=/usr/lib/x86_64-linux-gnu/pkgconfig:/usr/share/pkgconfig \
       pkg-config --define-variable=prefix="$S" "$@" instess; }
pc_flags() {
  local c l s
  c=$(pc --cflags) && l=$(pc --libs) && s=$(pc --static --libs) || return 1
  c=${c% }; l=${l% }   # pkg-config ends its output with a space
  echo "cflags: $c; libs: $l; static: $s"
  [ "$c" = "-I$S/include" ] && [ "$l" = "-L$S/lib -linstess" ] &&
    [[ "$s" == *-rdynamic* && "$s" == *-lmeshoptimizer* && "$s" == *-lassimp* && "$s" == *-lpng16* ]]
}
check "pkg-config: flags of the staged copy only (Requires.private, Libs.private)" pc_flags

ex=$tmp/example; mkdir -p "$ex"
cp examples/npatch_diff.png "$ex/ref.png"
build_example() {
  cd "$ex" && cc -std=c17 -Wall -Wextra -Werror -H "$root/examples/npatch_diff.c" $(pc --cflags) $(pc --libs) \
       -Wl,-rpath,"$(pc --variable=libdir)" -o npatch_diff 2>headers.txt || { cat headers.txt; return 1; }
  # every instess header it read is the staged one
  local ours
  ours=$(grep -E 'instess|core\.h|raster\.h|vs\.h|meshes\.h' headers.txt | sed 's/^\.* //')
  echo "$ours"
  [ -n "$ours" ] && ! echo "$ours" | grep -v "^$S/include/instess/" &&
    ldd ./npatch_diff | grep -q "libinstess.so.0 => $S/lib/libinstess.so.0"
}
check "example: built as the README says (pkg-config, the rpath of --variable=libdir) against the stage" build_example

run_example() { cd "$ex" && ./npatch_diff ref.png && [ ! -e ref.png.diff.png ]; }
check "example: renders the N-Patch and matches examples/npatch_diff.png (exit 0)" run_example

# another image of the same size: the staged program's cube
other_reference() {
  cd "$ex" && "$S/bin/instess" --size 128x128 -q -o other.png && { ./npatch_diff other.png; [ $? -eq 1 ]; } &&
    [ -f other.png.diff.png ]
}
check "example: a different reference fails (exit 1, diff image written)" other_reference

# tess/: a program of the user's draws adaptive LOD the instancing way against the stage: more than one level,
# more than one bucket (draw), a valid image.
adaptive_example() {
  cd "$ex" && cc -std=c17 -Wall -Wextra -Werror "$root/examples/adaptive_lod.c" $(pc --cflags) $(pc --libs) \
       -Wl,-rpath,"$(pc --variable=libdir)" -o adaptive_lod || return 1
  local out
  out=$(./adaptive_lod lod.png) || return 1
  echo "$out"
  [[ $out =~ levels\ ([0-9]+)\.\.([0-9]+)\;\ draws:\ ([0-9]+)\ buckets\ of\ [0-9]+\ patterns,\ ([0-9]+)\ triangles ]] &&
    [ "${BASH_REMATCH[1]}" -lt "${BASH_REMATCH[2]}" ] && [ "${BASH_REMATCH[3]}" -gt 1 ] &&
    [ "${BASH_REMATCH[4]}" -gt 0 ] && "$S/bin/instess" compare lod.png lod.png >/dev/null
}
check "example: adaptive LOD through tess/ (per-edge levels, one draw per bucket) built against the stage" adaptive_example

# docs/api.md's complete program, taken from the page as it is, built and run against the stage.
api_doc_program() {
  cd "$ex" && sed -n '/^```c$/,/^```$/p' "$root/docs/api.md" | sed '1d;$d' > api_prog.c && [ -s api_prog.c ] &&
    cc -std=c17 -Wall -Wextra -Werror api_prog.c $(pc --cflags) $(pc --libs) -Wl,-rpath,"$(pc --variable=libdir)" \
       -o api_prog && ./api_prog && [ -s cube.png ] && "$S/bin/instess" compare cube.png cube.png >/dev/null
}
check "docs/api.md: its complete program builds against the stage and writes its image" api_doc_program

# The installed viewer finds its window module (LIBDIR/instess) and draws a frame headless.
installed_viewer() {
  cd "$ex" && SDL_VIDEODRIVER=dummy "$S/bin/instess" view -q --no-hud --size 96x72 --frames 1 --capture view.png &&
    "$S/bin/instess" --size 96x72 -q -o cli.png && "$S/bin/instess" compare view.png cli.png >/dev/null
}
check "the installed instess view loads its window module and draws the frame -o draws (dummy display)" installed_viewer

# A module planted in the folder above the program or in the current folder is never loaded: its constructor
# would run inside instess.  (-o x.exr: a PNG would not look for the codec module at all.)
planted_modules() {
  local p="$tmp/plant" marker="$tmp/plant/ran"
  mkdir -p "$p/bin" "$p/cwd" && cp "$S/bin/instess" "$p/bin/" || return 1
  printf '#include <stdio.h>\n__attribute__((constructor)) static void c(void) { FILE *f = fopen("%s", "w"); if (f) fclose(f); }\n' \
    "$marker" > "$p/m.c" && cc -shared -fPIC "$p/m.c" -o "$p/libinstess_codec.so" || return 1
  cp "$p/libinstess_codec.so" "$p/libinstess_view.so" && cp "$p/libinstess_codec.so" "$p/cwd/" &&
    cp "$p/libinstess_view.so" "$p/cwd/" || return 1
  (cd "$p/cwd" && "$p/bin/instess" --size 16x16 -q -o x.exr 2>/dev/null; SDL_VIDEODRIVER=dummy "$p/bin/instess" view \
     -q --frames 1 --size 16x16 2>/dev/null; true)
  [ ! -e "$marker" ] || { echo "a planted module ran"; return 1; }
}
check "modules are never loaded from the folder above the program or the current folder" planted_modules

# The library opened with RTLD_LOCAL (Python's ctypes default, plugin hosts): its symbols are not global, and the
# codec module it loads on the first image call must still work (it gets the library's functions handed over).
# An EXR: PNGs are read by the library itself (libpng) and would not load the module.
rtld_local() {
  cd "$ex" && "$S/bin/instess" --size 32x32 -q -o local.exr &&
    python3 - "$S/lib/libinstess.so.0" local.exr <<'PY'
import ctypes, os, sys
lib = ctypes.CDLL(sys.argv[1], mode=os.RTLD_LOCAL)
img = ctypes.create_string_buffer(4096)          # an is_image (smaller than this)
err = ctypes.create_string_buffer(1024)
rc = lib.image_read(img, sys.argv[2].encode(), err, ctypes.c_size_t(len(err)))
if rc != 0:
    sys.exit("image_read: %s" % err.value.decode())
w, h, ch = ctypes.cast(img, ctypes.POINTER(ctypes.c_int))[0:3]
lib.image_free(img)
if (w, h) != (32, 32):
    sys.exit("read %dx%d" % (w, h))
PY
}
check "the shared library opened with RTLD_LOCAL (Python ctypes) reads an image through its codec module" rtld_local

static_example() {
  cd "$ex" && cc -std=c17 "$root/examples/npatch_diff.c" $(pc --cflags) "$S/lib/libinstess.a" \
       $(pc --static --libs | sed 's/-linstess//') -o npatch_static || return 1
  ! readelf -d npatch_static | grep -q libinstess || { echo "linked the shared library"; return 1; }
  if [ ! -e "$prefix/lib/instess/libinstess_codec.so" ]; then   # not installed for real: no module to find
    ./npatch_static ref.png || { echo "a PNG needed the module (libpng is in the library)"; return 1; }
    ./npatch_static --write ref.exr 2>err.txt && { echo "found a module without one installed"; return 1; }
    grep -q "$prefix/lib/instess" err.txt || { cat err.txt; return 1; }
  fi
  INSTESS_CODEC_DIR="$S/lib/instess" ./npatch_static --write ref.exr && [ -s ref.exr ]
}
check "example: static archive: PNG without the module, EXR with it (compiled-in LIBDIR or INSTESS_CODEC_DIR)" static_example

staged_program() {
  cd "$ex" && "$S/bin/instess" --mesh octahedron --size 64x64 -q -o a.png && "$S/bin/instess" compare a.png a.png
}
check "program: the staged instess renders (module in ../lib/instess) and compares" staged_program

man_page() {
  local text
  text=$(MANWIDTH=120 man -l "$S/share/man/man1/instess.1" 2>&1) || return 1
  for sec in NAME SYNOPSIS OPTIONS SUBCOMMANDS "EXIT STATUS" EXAMPLES FILES; do
    grep -q "^$sec" <<<"$text" || { echo "no section $sec"; return 1; }
  done
  local opts
  opts=$("$S/bin/instess" --help | grep -oE -- '^  (-[a-zA-Z], )?--[a-z][a-z0-9-]*' | grep -oE -- '--[a-z0-9-]+' | sort -u)
  [ "$(echo "$opts" | wc -l)" -gt 20 ] || { echo "too few options in --help: $opts"; return 1; }
  local section   # the OPTIONS section: each option has its own tag line there ("       -o, --output FILE")
  section=$(sed -n '/^OPTIONS/,/^SUBCOMMANDS/p' <<<"$text")
  for o in $opts; do
    grep -qE -- "^ {7}(-[a-zA-Z], )?$o( |\$)" <<<"$section" || { echo "the man page's OPTIONS lack $o"; return 1; }
  done
  grep -qe "--failpercent P" <<<"$text" && grep -q "$prefix/lib/instess/libinstess_codec.so" <<<"$text"
}
check "man -l renders the page; it names every option of --help" man_page

# The Python package: installed where Debian's python3 finds it (PREFIX/lib/python3.X/dist-packages, on its
# path for /usr/local), and, imported from the stage, it renders and compares with the staged library.
py=${PYTHON:-/usr/bin/python3}
pydir=$("$py" -c 'import sys; print("lib/python%d.%d/dist-packages" % sys.version_info[:2])' 2>/dev/null)
python_staged() {
  [ -f "$S/$pydir/instess/__init__.py" ] && [ -f "$S/$pydir/instess/_paths.py" ] || { echo "no package in $S/$pydir"; return 1; }
  "$py" -c "import sys; sys.exit('$prefix/$pydir' not in sys.path)" || { echo "$prefix/$pydir: not on $py's path"; return 1; }
  cd "$ex" && "$S/bin/instess" --size 48x32 -q -o py.png &&
    INSTESS_LIBDIR="$S/lib" PYTHONPATH="$S/$pydir" PYTHONDONTWRITEBYTECODE=1 "$py" - "$S" <<'PY'
import sys, instess
assert instess._lib._name.startswith(sys.argv[1] + "/lib/"), instess._lib._name
assert instess._run._name == sys.argv[1] + "/lib/instess/libinstess_run.so", instess._run._name
r = instess.compare(instess.render("--size", "48x32"), "py.png")
assert r, r
PY
}
check "python: the staged package renders and compares with the staged library (INSTESS_LIBDIR)" python_staged

# Installed for real into a PREFIX of its own: the package finds the library where make install put it, alone.
python_prefix() {
  local o="$tmp/py" rc
  $make --no-print-directory install PREFIX="$o" >"$tmp/install3.log" 2>&1 || { cat "$tmp/install3.log"; return 1; }
  (cd "$ex" && env -u INSTESS_LIBDIR -u INSTESS_CODEC_DIR PYTHONPATH="$o/$pydir" PYTHONDONTWRITEBYTECODE=1 "$py" - "$o" <<'PY'
import sys, instess
assert instess._lib._name.startswith(sys.argv[1] + "/lib/"), instess._lib._name
img = instess.render("--size", "32x24", "--aov", "depth", format="exr")   # the EXR through the installed codec
assert "depth" in img.channels, img
PY
  )
  rc=$?
  $make --no-print-directory uninstall PREFIX="$o" >/dev/null 2>&1
  local left
  left=$(find "$o" -type f -o -type l 2>/dev/null)
  [ -z "$left" ] || { echo "left behind: $left"; return 1; }
  return $rc
}
check "python: installed into a PREFIX, the package finds its library there (_paths.py); uninstall removes it" python_prefix

other_prefix() {
  local o=/opt/instess-check
  $make --no-print-directory install DESTDIR="$tmp/stage2" PREFIX=$o >"$tmp/install2.log" 2>&1 || { cat "$tmp/install2.log"; return 1; }
  MANWIDTH=120 man -l "$tmp/stage2$o/share/man/man1/instess.1" 2>/dev/null | grep -q "$o/lib/instess/libinstess_codec.so" &&
    grep -q "^prefix=$o" "$tmp/stage2$o/lib/pkgconfig/instess.pc" &&
    [ -f "$tmp/stage2$o/lib/instess/libinstess_codec.so" ]
}
check "PREFIX=/opt/instess-check: compiled into the module's folder and instess.pc" other_prefix
# the build tree back to the default PREFIX (only the module's folder is recompiled)
$make --no-print-directory "$B/instess" >/dev/null 2>&1

uninstalled() {
  $make --no-print-directory uninstall DESTDIR="$stage" PREFIX=$prefix >/dev/null 2>&1 || return 1
  local left
  left=$(find "$stage" -type f -o -type l)
  [ -z "$left" ] || { echo "left behind: $left"; return 1; }
}
check "make uninstall removes every installed file" uninstalled

echo "install: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
