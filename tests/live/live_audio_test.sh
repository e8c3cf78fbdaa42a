#!/bin/sh
# live --audio through JACK's dummy server (ctest fixture `jackd`) in a real window (fixture `xvfb`):
# jack_simple_client plays a sine; a mapping entry `audio = "level"` drives twist. With the sine
# connected twist sits well above its range's bottom; with the port left unconnected (silence)
# it sits at the bottom, -3. Usage: live_audio_test.sh SDFVJ_BIN XVFB_STATE OUT_DIR
set -eu
bin=$1 state=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
export DISPLAY=":$(cat "$state.display")"
jack_simple_client > "$out/simple.log" 2>&1 &
sine=$!
trap 'kill $sine 2>/dev/null || true' EXIT
sleep 1
cat > "$out/audio.toml" <<'TOML'
[profile]
name = "live audio test"

[[map]]
audio = "level"
target = "twist"
smoothing = 0
TOML
run() {   # $1 = --audio argument, $2 = log name
  port=$(( 20000 + ($$ + ${#2}) % 20000 ))
  "$bin" live --scene midi --audio "$1" --mapping "$out/audio.toml" --size 160x90 --path fragment --seconds 3 \
    --osc-port "$port" --midi no-such-controller --log-params "$out/$2.txt" --hide-overlay > "$out/$2.log" 2>&1
  cat "$out/$2.log"
}
run jack_simple_client:output1 sine
run in silence
grep -q "connected from jack_simple_client:output1" "$out/sine.log"
# The last second's median twist of each run.
median() { tail -n 30 "$out/$1.txt" | sed -n 's/.* twist=\([^ ]*\).*/\1/p' | sort -g | awk '{v[NR]=$1} END {print v[int((NR+1)/2)]}'; }
sine=$(median sine) quiet=$(median silence)
echo "twist: sine $sine, silence $quiet"
awk -v s="$sine" -v q="$quiet" 'BEGIN { exit !(s > -2.0 && q < -2.9) }' && echo "live-audio-ok"
