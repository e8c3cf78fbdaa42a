#!/bin/sh
# Issue 12: effect pad hits (`bench reload --edit toggle`) after the six one-effect variants were
# built ahead (live's prefetch) start no compile and all reach the screen; cold hits compile every
# one. Counts, not times: llvmpipe still JITs a prefetched program at its first draw, and a loaded
# machine must not fail it. The times go to docs/performance.md from the GPU machine.
bin=$1
out=$("$bin" bench reload --edit toggle --scene midi --size 96x54 --path fragment --rounds 3 --fps 0 2>&1) || { echo "$out"; exit 1; }
echo "$out"
echo "$out" | grep -q "never reached the screen" && { echo "bench_toggle: a hit never reached the screen"; exit 1; }
col() { echo "$out" | awk -F'|' -v w=" $1 " '$2 == w { gsub(/ /, "", $6); print $6 }'; }
cold=$(col cold); ahead=$(col prefetch); primed=$(col prefetch+prime)
echo "compiles the hits started: cold $cold, prefetch $ahead, prefetch+prime $primed (expected >= 3, 0, 0)"
[ -n "$cold" ] && [ "$cold" -ge 3 ] && [ "$ahead" = 0 ] && [ "$primed" = 0 ]
