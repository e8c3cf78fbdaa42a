#!/bin/sh
# A lever that claims to be exact renders the same bytes with and without it: every scene named
# renders against a copy of itself (NAME_alt) with one #define after its header, over 6 frames
# of its animation, once per knob set (each set one argument; "" = the default knobs).
#   define_exact.sh SDFVJ SOURCE OUTDIR "NAME VALUE" PATH "SCENE ..." [KNOBS ...]
# SLACK="PIXELS LEVELS" in the environment: a frame may differ in at most PIXELS pixels, by at most
# LEVELS/255 (png_slack.py), for a lever exact in real arithmetic whose two programs the compiler
# rounds differently.
# Used by render_part_skip_exact (character's CHARACTER_SKIP), render_field_cells_exact and render_ao_farthest_exact
# (lib/shading.glsl AO_FARTHEST_FIRST, both ways).
set -eu
bin="$1"; src="$2"; out="$3"; define="$4"; path="$5"; scenes="$6"; shift 6
[ $# -gt 0 ] || set -- ""
rm -rf "$out"; mkdir -p "$out/root"
cp -r "$src/shaders" "$src/presets" "$src/mappings" "$out/root/"
dir="$out/root/shaders/scenes"
for s in $scenes; do
  sed -e "s/\"NAME\": \"$s\"/\"NAME\": \"${s}_alt\"/" "$dir/$s.glsl" > "$dir/${s}_alt.glsl"
  sed -i "/^}\*\//a #define $define" "$dir/${s}_alt.glsl"
done
status=0
n=0
for knobs in "$@"; do
  n=$((n + 1))
  for s in $scenes; do
    mkdir -p "$out/$n"
    for v in "$s" "${s}_alt"; do
      # shellcheck disable=SC2086
      SDFVJ_ROOT="$out/root" "$bin" render --scene "$v" --size 160x90 --frames 6 --fps 4 --path "$path" $knobs \
        --out "$out/$n/$v" > "$out/$n/$v.log" 2>&1 || { echo "render $v $knobs failed:"; cat "$out/$n/$v.log"; exit 1; }
    done
    bad=0
    for f in "$out/$n/$s"/*.png; do
      g="$out/$n/${s}_alt/$(basename "$f")"
      if cmp -s "$f" "$g"; then continue; fi
      # shellcheck disable=SC2086
      if [ -n "${SLACK:-}" ] && python3 "$(dirname "$0")/png_slack.py" "$f" "$g" $SLACK > "$out/$n/slack.txt"; then
        echo "$s knobs [$knobs]: $(basename "$f") within the slack ($SLACK): $(cat "$out/$n/slack.txt")"
      else
        echo "$s knobs [$knobs]: $(basename "$f") differs with #define $define${SLACK:+ beyond the slack ($SLACK): $(cat "$out/$n/slack.txt" 2>/dev/null)}"; bad=1
      fi
    done
    if [ $bad = 0 ]; then echo "$s knobs [$knobs]: 6 frames, the same${SLACK:+ within the slack} with #define $define"; else status=1; fi
  done
done
exit $status
