#!/usr/bin/env bash
# Extracts the real meshes the project uses from Debian's libcgal-demo into meshes/
# (see meshes/README.md for where they come from). Idempotent.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
archive=/usr/share/doc/libcgal-demo/data.tar.gz
names=(bunny00 diplodocus man refined_elephant fandisk_large)
[ -f "$archive" ] || { echo "fetch-meshes: $archive missing: apt-get install libcgal-demo" >&2; exit 1; }
todo=()
for n in "${names[@]}"; do [ -s "$top/meshes/$n.off" ] || todo+=("data/meshes/$n.off"); done
[ ${#todo[@]} -eq 0 ] && exit 0
tar -xzf "$archive" -C "$top/meshes" --strip-components=2 "${todo[@]}"
echo "fetch-meshes: extracted ${todo[*]} into meshes/"
