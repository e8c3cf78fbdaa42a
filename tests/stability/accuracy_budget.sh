#!/bin/sh
# The accuracy report's image budget (issue 6: at most 0.1 % of pixels more than 8/255 off the
# scene's 4096-step render) on the compute path, for scenes that once missed it there: primitives
# read 0.135 % at 640x360 with the cone pre-pass (0.168 % at 1080p on the H200) and declares it off
# now (shaders/scenes/primitives.glsl). Usage: accuracy_budget.sh SDFVJ OUTDIR
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
  if [ -z "$pct" ]; then echo "$scene: no default row in the report:"; cat "$log"; status=1; continue; fi
  if awk -v p="$pct" 'BEGIN { exit !(p <= 0.1) }'; then
    echo "$scene: default $pct % of pixels > 8/255 off: within the 0.1 % budget"
  else
    echo "$scene: default $pct % of pixels > 8/255 off: past the 0.1 % budget"; echo "$row"; status=1
  fi
done
exit $status
