#!/usr/bin/env bash
# Builds every libFuzzer target with clang in build-fuzz/ (only those targets) and runs each.
#   scripts/fuzz.sh [--smoke] [--only NAME] [seconds] [extra libFuzzer args...]
#     seconds   per target (default 60; --smoke: 5)
#     --smoke   CI mode: short runs, exit 1 if any target crashes (build + run < 3 min on 2 cores)
#     --only    one target: scene, preset, input, take, isf or wav
# Targets: fuzz_scene (scene headers, structure-aware), fuzz_preset (presets, structure-aware),
# fuzz_input (MIDI bytes, OSC through a real lo_server, TOML mappings), fuzz_take (SMF reader),
# fuzz_isf (ISF .fs files: header, pass-size expressions, parameters, GLSL translation), fuzz_wav
# (the WAV reader `render --replay` reads a take's audio with).
# Needs clang with compiler-rt (Debian: apt-get install -y clang-14 libclang-rt-14-dev).
# Crashes land in build-fuzz/crashes/NAME/; reproduce one with build-fuzz/.../fuzz_NAME FILE.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build-fuzz"
smoke=0
only=""
while [ $# -gt 0 ]; do
  case "$1" in
    --smoke) smoke=1; shift ;;
    --only) only="$2"; shift 2 ;;
    *) break ;;
  esac
done
seconds=$([ "$smoke" = 1 ] && echo 5 || echo 60)
if [ $# -gt 0 ] && [[ "$1" =~ ^[0-9]+$ ]]; then seconds="$1"; shift; fi

names=(scene preset input take isf wav)
[ -n "$only" ] && names=("$only")
declare -A target_dir=([scene]=src/scene [preset]=src/scene [input]=src/control [take]=src/take [isf]=src/isf [wav]=src/audio)
for n in "${names[@]}"; do
  [ -n "${target_dir[$n]:-}" ] || { echo "fuzz: unknown target '$n', expected scene, preset, input, take, isf or wav"; exit 2; }
done

cxx="$(command -v clang++ || command -v clang++-14 || true)"
cc="$(command -v clang || command -v clang-14 || true)"
[ -n "$cxx" ] && [ -n "$cc" ] || { echo "fuzz: clang not found (apt-get install -y clang-14 libclang-rt-14-dev)"; exit 2; }

# -O1 with line tables: about half the compile time of RelWithDebInfo under ASan+UBSan, and
# crash reports still name file:line.
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" \
  -DSDFVJ_FUZZ=ON >/dev/null
targets=()
for n in "${names[@]}"; do targets+=("fuzz_$n"); done
cmake --build "$build" --target "${targets[@]}" -j"$(nproc)"

# Seeds, generated here (nothing big in the repository); libFuzzer grows each corpus in place.
# The first byte of a scene/preset input picks raw text (0) or the structure-aware builder.
seed() {  # seed NAME -> fills build-fuzz/corpus/NAME
  local c="$build/corpus/$1"
  mkdir -p "$c"
  case "$1" in
    scene)
      for f in "$root"/shaders/scenes/*.glsl; do
        { printf '\x00'; sed -n '/\/\*{/,/}\*\//p' "$f" | sed '1s/^.*\/\*{//'; } >"$c/raw_$(basename "$f")"
      done
      printf '\x01' >"$c/built_default"
      printf '\x02\x07\x07\x07\x07\x07\x07\x07\x07\x07\x07\x07\x07\x07\x07\x07\x07' >"$c/built_sevens" ;;
    preset)
      for f in "$root"/presets/*.json; do { printf '\x00'; cat "$f"; } >"$c/raw_$(basename "$f")"; done
      printf '\x01' >"$c/built_default"
      printf '\x02\x05\x05\x05\x05\x05\x05\x05\x05\x05\x05\x05\x05' >"$c/built_fives" ;;
    input)
      printf '\x00\xb0\x01\x40\x02\x41\xb0\x63\x02\x62\x2c\x06\x64\x26\x05\x90\x24\x64\xe0\x00\x40\xc0\x03' >"$c/midi_mix"
      printf '\x00\xf0\x7e\x01\xf7\x05\xf8\xb0\x10\x7f\xf2\x01\x02\x80\x24\x00' >"$c/midi_sysex"
      printf '\x01/sdfvj/param/twist\x00\x00,f\x00\x00\x3f\x00\x00\x00' >"$c/osc_param"
      printf '\x01/sdfvj/preset\x00\x00\x00,s\x00\x00intro\x00\x00\x00' >"$c/osc_preset"
      printf '\x01/sdfvj/preset\x00\x00\x00,i\x00\x00\xff\xff\xff\xff' >"$c/osc_preset_minus1"
      printf '\x01#bundle\x00\x00\x00\x00\x00\x00\x00\x00\x01\x00\x00\x00\x10/fader\x00\x00,i\x00\x00\x00\x00\x00\x01' >"$c/osc_bundle"
      printf '\x01#bundle\x00\xf0\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x10/fader\x00\x00,i\x00\x00\x00\x00\x00\x01' >"$c/osc_bundle_future"
      for f in "$root"/mappings/*.toml; do { printf '\x02'; cat "$f"; } >"$c/toml_$(basename "$f")"; done ;;
    take)
      cp -n "$root"/tests/take/corpus/* "$c"/ 2>/dev/null || true
      cp -n "$root/presets/demo_take.mid" "$c"/ 2>/dev/null || true ;;
    isf)
      cp -n "$root"/shaders/isf/*.fs "$c"/ 2>/dev/null || true
      printf 'void mainImage(out vec4 c, in vec2 p) { c = texture(iChannel1, p / iResolution.xy); }\n' >"$c/shadertoy"
      printf '/*{ "PASSES": [ { "TARGET": "a", "WIDTH": "floor($WIDTH / (1 + $n))", "PERSISTENT": true } ], "INPUTS": [ { "NAME": "n", "TYPE": "long", "VALUES": [0, 1, 2], "LABELS": ["a", "b", "c"], "DEFAULT": 1 } ] }*/\nvoid main() { gl_FragColor = IMG_THIS_PIXEL(a); }\n' >"$c/passes" ;;
    wav)
      python3 - "$c" <<'PY'
import struct, sys
def wav(fmt, ch, rate, bits, frames, extra=b""):
    body = bytes((i * 37) & 0xFF for i in range(frames * ch * bits // 8))
    f = struct.pack("<4sIHHIIHH", b"fmt ", 16, fmt, ch, rate, rate * ch * bits // 8, ch * bits // 8, bits)
    d = struct.pack("<4sI", b"data", len(body)) + body + (b"\0" if len(body) & 1 else b"")
    rest = b"WAVE" + f + extra + d
    return struct.pack("<4sI", b"RIFF", len(rest)) + rest
out = sys.argv[1]
open(out + "/pcm16_mono", "wb").write(wav(1, 1, 48000, 16, 8))
open(out + "/pcm24_stereo", "wb").write(wav(1, 2, 44100, 24, 5))
open(out + "/float32_sdfv", "wb").write(wav(3, 1, 48000, 32, 6, struct.pack("<4sId", b"sdfv", 8, 12.5)))
open(out + "/float64", "wb").write(wav(3, 1, 96000, 64, 3))
PY
      ;;
  esac
}

failed=()
for n in "${names[@]}"; do
  seed "$n"
  mkdir -p "$build/crashes/$n"
  extra=()
  [ "$n" = take ] && extra+=(-dict="$root/tests/take/smf.dict")
  echo "fuzz: fuzz_$n for ${seconds} s"
  log="$build/fuzz_$n.log"
  if "$build/${target_dir[$n]}/fuzz_$n" "$build/corpus/$n" -max_total_time="$seconds" -max_len=4096 -timeout=10 \
       -rss_limit_mb=1024 -malloc_limit_mb=256 -artifact_prefix="$build/crashes/$n/" -print_final_stats=1 \
       "${extra[@]}" "$@" >"$log" 2>&1; then
    grep -E '^Done|stat::number_of_executed_units' "$log" | head -1 | sed "s/^/fuzz: fuzz_$n: /"
  else
    failed+=("$n")
    tail -40 "$log"
    echo "fuzz: fuzz_$n FAILED, see $log and $build/crashes/$n/"
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: crashes in: ${failed[*]}"
  exit 1
fi
echo "fuzz: no crash in ${names[*]} (${seconds} s each)"
