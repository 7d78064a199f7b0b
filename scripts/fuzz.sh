#!/usr/bin/env bash
# Fuzzes the model loader: builds the libFuzzer targets (tests/fuzz) with clang, ASan and UBSan into
# build-fuzz/, seeds each format's corpus with assimp's test models of that format (the
# assimp-testmodels package) and runs each target for SECONDS (default 60). Crashes, timeouts and
# memory blow-ups are kept as build-fuzz/findings/FORMAT/crash-* (timeout-*, oom-*) and the run goes
# on (fork mode); the corpora grow in build-fuzz/corpus/FORMAT and are reused by the next run.
#   scripts/fuzz.sh [SECONDS] [FORMAT...]      formats: ply obj off stl gltf glb (default: all)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
shift || true
formats=("$@")
[ ${#formats[@]} -gt 0 ] || formats=(ply obj off stl gltf glb)
dir=$root/build-fuzz
models=/usr/share/assimp/models

CC=clang-15 CXX=clang++-15 cmake -S "$root" -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCLRASTER_FUZZ=ON \
  -DCLRASTER_BUILD_TESTS=OFF -DCLRASTER_BUILD_CLI=OFF -DCLRASTER_BUILD_EXAMPLES=OFF >/dev/null
cmake --build "$dir" -j "$(nproc)" --target "${formats[@]/#/fuzz_model_}"

for format in "${formats[@]}"; do
  corpus=$dir/corpus/$format findings=$dir/findings/$format
  mkdir -p "$corpus" "$findings"
  # Seeds: the test models of this format up to 64 KiB (libFuzzer's inputs stay small).
  find "$models" -iname "*.$format" -size -64k -type f -print0 | while IFS= read -r -d '' file; do
    cp "$file" "$corpus/seed-$(sha1sum <"$file" | cut -c1-16)"
  done
  echo "fuzz: $format, ${seconds}s, $(ls "$corpus" | wc -l) inputs in the corpus"
  # assimp itself is not instrumented, and crashes, spins and allocates without bound on inputs it
  # was never meant to see; those are what the isolated loader is for, so the run records and goes on.
  (cd "$findings" && LSAN_OPTIONS=suppressions=$root/tests/fuzz/lsan.supp \
    "$dir/tests/fuzz/fuzz_model_$format" "$corpus" -fork="$(nproc)" -ignore_crashes=1 \
    -ignore_timeouts=1 -ignore_ooms=1 -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -max_total_time="$seconds" -print_final_stats=1 >"$findings/log.txt" 2>&1) || true
  echo "fuzz: $format: $(grep -c '' <(ls "$findings" | grep -E '^(crash|timeout|oom|leak)-' || true)) findings in $findings"
done
