#!/usr/bin/env bash
# web/assemble.sh TEMPLATE WASM OUT JS... -- the page as one file: TEMPLATE with the line holding
# <!-- INSTESS_SCRIPTS --> replaced by the JS files (inline, in order) and the line holding <!-- INSTESS_WASM -->
# by the module in base64, in a <script type="application/octet-stream" id="instess-wasm"> element the page
# decodes; the line holding <!-- INSTESS_BUILD --> by <meta name="instess-build" content="$WEB_BUILD_INFO"> (the
# toolchain, shown by the page).  Written to OUT.tmp, then renamed onto OUT: never half a page.
set -euo pipefail
template=$1 wasm=$2 out=$3
shift 3
tmp="$out.tmp"
trap 'rm -f "$tmp"' EXIT
{
  while IFS= read -r line || [ -n "$line" ]; do
    case $line in
      *'<!-- INSTESS_SCRIPTS -->'*)
        for js in "$@"; do printf '<script>\n'; cat "$js"; printf '</script>\n'; done ;;
      *'<!-- INSTESS_BUILD -->'*)
        printf '<meta name="instess-build" content="%s">\n' "${WEB_BUILD_INFO:-WebAssembly}" ;;
      *'<!-- INSTESS_WASM -->'*)
        printf '<script type="application/octet-stream" id="instess-wasm">'
        base64 -w0 "$wasm"
        printf '</script>\n' ;;
      *) printf '%s\n' "$line" ;;
    esac
  done < "$template"
} > "$tmp"
grep -q 'id="instess-wasm"' "$tmp" || { echo "assemble: $template has no <!-- INSTESS_WASM --> line" >&2; exit 1; }
mv "$tmp" "$out"
trap - EXIT
