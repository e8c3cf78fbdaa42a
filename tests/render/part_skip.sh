#!/bin/sh
# character's part skip (shaders/scenes/character.glsl CHARACTER_SKIP) leaves the field as it is: the
# scene renders the same bytes as a copy that evaluates every limb (CHARACTER_SKIP 0), over a walk
# cycle, with the default knobs and at the blend's and the wave's ends. Usage: part_skip.sh SDFVJ SOURCE OUTDIR
set -eu
bin="$1"; src="$2"; out="$3"
rm -rf "$out"; mkdir -p "$out/root"
cp -r "$src/shaders" "$src/presets" "$src/mappings" "$out/root/"
scenes="$out/root/shaders/scenes"
sed -e 's/"NAME": "character"/"NAME": "character_noskip"/' "$scenes/character.glsl" > "$scenes/character_noskip.glsl"
sed -i '/^}\*\//a #define CHARACTER_SKIP 0' "$scenes/character_noskip.glsl"
status=0
n=0
for knobs in "" "--param wave=1 --param blend=0.25 --param floorBlend=0.5" "--param blend=0 --param speed=2"; do
  n=$((n + 1)); mkdir -p "$out/$n"
  for s in character character_noskip; do
    # shellcheck disable=SC2086
    SDFVJ_ROOT="$out/root" "$bin" render --scene $s --size 160x90 --frames 6 --fps 4 --path fragment $knobs \
      --out "$out/$n/$s" > "$out/$n/$s.log" 2>&1 || { echo "render $s $knobs failed:"; cat "$out/$n/$s.log"; exit 1; }
  done
  for f in "$out/$n/character"/*.png; do
    if ! cmp -s "$f" "$out/$n/character_noskip/$(basename "$f")"; then
      echo "knobs [$knobs]: $(basename "$f") differs with the part skip"; status=1
    fi
  done
  [ $status = 0 ] && echo "knobs [$knobs]: 6 frames, the same bytes with and without the part skip"
done
exit $status
