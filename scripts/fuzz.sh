#!/usr/bin/env bash
# Bounded libFuzzer runs (clang, AddressSanitizer + UndefinedBehaviorSanitizer):
#   fuzz_core          random meshes and parameters through run_filter (every adapter's path)
#   fuzz_mesh_readers  random files through the command-line tool's PLY/OBJ/OFF/STL readers
#   scripts/fuzz.sh [SECONDS_PER_TARGET]      (default 120)
# A crash is copied into tests/fuzz/regressions/<core|readers>/ (the unit tests replay those
# from then on) and the script exits non-zero.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-120}
build="$top/build-fuzz"
command -v clang++ >/dev/null || { echo "fuzz: clang++ missing: apt-get install clang libclang-rt-14-dev" >&2; exit 1; }
CXX=clang++ cmake -S "$top" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGEOFILTER_FUZZ=ON \
    -DGEOFILTER_BUILD_PLUGIN=OFF -DGEOFILTER_BUILD_TESTS=OFF -DGEOFILTER_BUILD_BENCHMARK=OFF -DGEOFILTER_BUILD_CLI=ON >/dev/null
cmake --build "$build" -j"$(nproc)" --target fuzz_core fuzz_mesh_readers
status=0
for target in core mesh_readers; do
    regressions="$top/tests/fuzz/regressions/${target#mesh_}"
    corpus="$build/corpus-$target"
    crashes="$build/crashes-$target"
    mkdir -p "$corpus" "$crashes"
    cp -n "$regressions"/* "$corpus/" 2>/dev/null || true
    echo "fuzz: fuzz_$target for $seconds s"
    (cd "$crashes" && "$build/tests/fuzz/fuzz_$target" "$corpus" -max_total_time="$seconds" -max_len=4096 \
        -timeout=20 -print_final_stats=1 2>&1 | grep -v '^#' | tail -8) || true  # crashes are judged by their files
    for crash in "$crashes"/crash-* "$crashes"/timeout-* "$crashes"/leak-* "$crashes"/oom-*; do
        [ -f "$crash" ] || continue
        cp "$crash" "$regressions/"
        echo "fuzz: saved $(basename "$crash") into ${regressions#$top/}" >&2
        status=1
    done
done
exit $status
