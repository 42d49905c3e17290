#!/usr/bin/env bash
# scripts/setup.sh [--bench|--sanitize|--web] -- install what instess needs from Debian's packages, only when
# missing.  Checks pkg-config (and a few files) first; runs apt-get through sudo when not root.  Idempotent and
# quiet when everything is there.  --bench also installs what `make bench` needs (Mesa's llvmpipe, EGL, GLES/GL);
# --sanitize clang, its runtimes and valgrind; --web what `make web` and its browser test need (clang and lld
# for wasm32-wasi, wasi-libc, compiler-rt's wasm32 builtins; Chromium and node to drive it).
set -euo pipefail

need=()
have_pc() { pkg-config --exists "$1" 2>/dev/null; }
command -v pkg-config >/dev/null 2>&1 || need+=(pkg-config)
command -v g++ >/dev/null 2>&1 || need+=(g++)
command -v make >/dev/null 2>&1 || need+=(make)
have_pc OpenImageIO || need+=(libopenimageio-dev)
have_pc libpng || need+=(libpng-dev)
command -v oiiotool >/dev/null 2>&1 || need+=(openimageio-tools)
have_pc cmocka || need+=(libcmocka-dev)
have_pc assimp || need+=(libassimp-dev)
have_pc sdl2 || need+=(libsdl2-dev)
have_pc SDL2_ttf || need+=(libsdl2-ttf-dev)
[ -f /usr/include/meshoptimizer.h ] || need+=(libmeshoptimizer-dev)
[ -f /usr/share/assimp/models/MD2/faerie.md2 ] || need+=(assimp-testmodels)
[ -f /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf ] && [ -f /usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf ] ||
  need+=(fonts-dejavu-core)
# make test's install stage renders the man page (man -l) and reads the library's soname (readelf)
command -v man >/dev/null 2>&1 || need+=(man-db)
command -v groff >/dev/null 2>&1 || need+=(groff-base)
command -v readelf >/dev/null 2>&1 || need+=(binutils)
# the Python package (python/instess) and its tests run on Debian's python3 with its numpy and pytest
/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1 || need+=(python3-numpy)
/usr/bin/python3 -c 'import pytest' >/dev/null 2>&1 || need+=(python3-pytest)
if [ "${1:-}" = "--bench" ]; then
  have_pc egl || need+=(libegl-dev)
  have_pc gl || need+=(libgl-dev)
  [ -e /usr/lib/x86_64-linux-gnu/dri/swrast_dri.so ] || need+=(libgl1-mesa-dri)
  [ -e /usr/lib/x86_64-linux-gnu/libEGL_mesa.so.0 ] || need+=(libegl-mesa0)
fi
if [ "${1:-}" = "--sanitize" ]; then
  command -v clang >/dev/null 2>&1 || need+=(clang)
  command -v valgrind >/dev/null 2>&1 || need+=(valgrind)
  [ -e /usr/lib/llvm-14/lib/libomp.so ] || need+=(libomp-dev)
  # clang's sanitizer and libFuzzer runtimes are a separate package on Debian 12
  compgen -G '/usr/lib/llvm-14/lib/clang/*/lib/linux/libclang_rt.asan-x86_64.a' >/dev/null || need+=(libclang-rt-14-dev)
fi

if [ "${1:-}" = "--web" ]; then
  command -v clang >/dev/null 2>&1 || need+=(clang)
  command -v wasm-ld >/dev/null 2>&1 || need+=(lld)
  [ -f /usr/include/wasm32-wasi/stdio.h ] || need+=(wasi-libc)
  compgen -G '/usr/lib/llvm-14/lib/clang/*/lib/wasi/libclang_rt.builtins-wasm32.a' >/dev/null || need+=(libclang-rt-14-dev-wasm32)
  command -v chromium >/dev/null 2>&1 || need+=(chromium)
  command -v node >/dev/null 2>&1 || need+=(nodejs)
fi

[ ${#need[@]} -eq 0 ] && exit 0

echo "setup: installing ${need[*]}" >&2
sudo=""
if [ "$(id -u)" != 0 ]; then
  command -v sudo >/dev/null 2>&1 || { echo "setup: need root or sudo to install: ${need[*]}" >&2; exit 1; }
  sudo=sudo
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
echo "setup: done" >&2
