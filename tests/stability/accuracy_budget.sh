#!/bin/sh
# The accuracy report on the compute path, for a scene that once missed its image budget there:
#  - at most 0.1 % of pixels more than 8/255 off the scene's 4096-step render (issue 6's budget).
#    primitives read 0.135 % at 640x360 (0.168 % at 1080p on the H200): with the cone pre-pass its
#    rays stopped elsewhere within eps on the floor, and the checker's edges moved;
#  - floor hits on the plane (shaders/render/march.glsl onGround): the median geometry error
#    (t err p50) under 0.005 px; it read 0.015-0.021 px while floor hits stopped up to eps short.
# Usage: accuracy_budget.sh SDFVJ OUTDIR
set -eu
bin="$1"; out="$2"
status=0
for scene in primitives; do
  log="$out/$scene.txt"
  mkdir -p "$out"
  "$bin" bench accuracy --scene "$scene" --size 640x360 --ref-size 320x180 --path compute --sweep tiny \
    --frames 1 --warmup 1 --out "$out/$scene" > "$log" 2>&1
  row=$(grep "^$scene | sdfvj default " "$log" || true)
  pct=$(printf '%s\n' "$row" | sed -n 's/.*| *\([0-9.]*\)% >8\/255.*/\1/p')
  p50=$(printf '%s\n' "$row" | sed -n 's/.*t err p50 \([0-9.e-]*\) .*/\1/p')
  if [ -z "$pct" ] || [ -z "$p50" ]; then echo "$scene: no default row in the report:"; cat "$log"; status=1; continue; fi
  if awk -v p="$pct" 'BEGIN { exit !(p <= 0.1) }'; then
    echo "$scene: default $pct % of pixels > 8/255 off: within the 0.1 % budget"
  else
    echo "$scene: default $pct % of pixels > 8/255 off: past the 0.1 % budget"; echo "$row"; status=1
  fi
  if awk -v p="$p50" 'BEGIN { exit !(p <= 0.005) }'; then
    echo "$scene: t err p50 $p50 px: floor hits on the plane"
  else
    echo "$scene: t err p50 $p50 px, expected at most 0.005 px (floor hits on the plane)"; echo "$row"; status=1
  fi
done
exit $status
