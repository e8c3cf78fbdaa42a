#!/usr/bin/env bash
# Fuzzes the take reader (ParseTake) with libFuzzer for a while (default 60 s).
#   scripts/fuzz_take.sh [seconds] [extra libFuzzer args...]
# Needs clang with compiler-rt (Debian: apt-get install -y clang libclang-rt-14-dev).
# Builds only the fuzz target, in build-fuzz-take/. Crashes land in build-fuzz-take/crashes/.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-60}"
shift || true
build="$root/build-fuzz-take"

command -v clang++ >/dev/null || { echo "fuzz_take: clang++ not found (apt-get install -y clang libclang-rt-14-dev)"; exit 1; }
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DSDFVJ_FUZZ=ON -DSDFVJ_HEADLESS_ONLY=ON >/dev/null
cmake --build "$build" --target fuzz_take -j"$(nproc)"

# Seed corpus: the committed seeds (hand-built edge cases), the demo take, and a working copy
# that libFuzzer grows (kept between runs).
corpus="$build/corpus"
mkdir -p "$corpus" "$build/crashes"
cp -n "$root"/tests/take/corpus/* "$corpus"/ 2>/dev/null || true
cp -n "$root/presets/demo_take.mid" "$corpus"/ 2>/dev/null || true

"$build/src/take/fuzz_take" "$corpus" \
  -max_total_time="$seconds" -max_len=4096 -rss_limit_mb=1024 -malloc_limit_mb=256 \
  -dict="$root/tests/take/smf.dict" -artifact_prefix="$build/crashes/" -print_final_stats=1 "$@"
echo "fuzz_take: no crash in ${seconds} s"
