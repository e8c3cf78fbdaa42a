#!/usr/bin/env bash
# Fuzzes the input decoders (MIDI bytes, OSC packets, TOML mappings) with libFuzzer, default 60 s.
#   scripts/fuzz_input.sh [seconds] [extra libFuzzer args...]
# Needs clang with compiler-rt (Debian: apt-get install -y clang libclang-rt-14-dev).
# Builds only the fuzz target, in build-fuzz-input/. Crashes land in build-fuzz-input/crashes/.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-60}"
shift || true
build="$root/build-fuzz-input"

command -v clang++ >/dev/null || { echo "fuzz_input: clang++ not found (apt-get install -y clang libclang-rt-14-dev)"; exit 1; }
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DSDFVJ_FUZZ=ON >/dev/null
cmake --build "$build" --target fuzz_input -j"$(nproc)"

# Seeds: first byte picks the decoder (0 MIDI, 1 OSC, 2 TOML). libFuzzer grows the corpus
# in place, so it is kept between runs.
corpus="$build/corpus"
mkdir -p "$corpus" "$build/crashes"
printf '\x00\xb0\x01\x40\x02\x41\xb0\x63\x02\x62\x2c\x06\x64\x26\x05\x90\x24\x64\xe0\x00\x40\xc0\x03' >"$corpus/midi_mix"
printf '\x00\xf0\x7e\x01\xf7\x05\xf8\xb0\x10\x7f\xf2\x01\x02\x80\x24\x00' >"$corpus/midi_sysex"
printf '\x01/sdfvj/param/twist\x00\x00,f\x00\x00\x3f\x00\x00\x00' >"$corpus/osc_param"
printf '\x01/sdfvj/preset\x00\x00\x00,s\x00\x00intro\x00\x00\x00' >"$corpus/osc_preset"
printf '\x01#bundle\x00\x00\x00\x00\x00\x00\x00\x00\x01\x00\x00\x00\x10/fader\x00\x00,i\x00\x00\x00\x00\x00\x01' >"$corpus/osc_bundle"
for f in "$root"/mappings/*.toml; do { printf '\x02'; cat "$f"; } >"$corpus/toml_$(basename "$f")"; done

"$build/src/control/fuzz_input" "$corpus" \
  -max_total_time="$seconds" -max_len=4096 -rss_limit_mb=1024 -malloc_limit_mb=256 \
  -artifact_prefix="$build/crashes/" -print_final_stats=1 "$@"
echo "fuzz_input: no crash in ${seconds} s"
