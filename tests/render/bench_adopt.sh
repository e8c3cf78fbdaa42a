#!/bin/sh
# Issue 12's lever, on llvmpipe: a new program drawn on the context that compiled and used it
# (`bench reload --modes adopt`) does not stall the first frame that shows it, where the
# shared-context worker's program does. With Mesa's disk cache off llvmpipe JITs a shader once per
# context, as NVIDIA finishes a program once per context: the worker's program is JITted again at
# its first draw on the render context (400+ ms at 160x90), the adopted one is not. A ratio of the
# two modes' longest frames in one interleaved run, not a time, so a slow machine does not fail it.
# $2 = stage: the same for `--modes stage`, the program compiled, first used and drawn by a thread
# of its own (with no compile process here, Mesa giving no binaries with its cache off), which
# then draws every frame of it. $2 = render-process: each program compiled, used and drawn by a
# process of its own (shared memory here: llvmpipe cannot export a dma-buf, so the fallback runs).
bin=$1
mode=${2:-adopt}
out=$("$bin" bench reload --scene midi --size 160x90 --path fragment --driver-cache off --modes worker,$mode --rounds 3 \
    --no-program-cache 2>&1) || { echo "$out"; exit 1; }
echo "$out" | sed -n '/modes side by side/,$p'
worker=$(echo "$out" | awk -F'|' '$2 == " worker " { gsub(/ /, "", $5); print $5 }')
adopt=$(echo "$out" | awk -F'|' -v m=" $mode " '$2 == m { gsub(/ /, "", $5); print $5 }')
# What a 60 Hz display shows (frames paced as a display's, the bench's default): the worker's stall
# repeats the frame before for many refreshes (a 400 ms frame: 24), the mode's frames for a quarter
# of that at most (0 here alone).
wmiss=$(echo "$out" | awk -F'|' '$2 == " worker " { gsub(/ /, "", $10); print $10 }')
amiss=$(echo "$out" | awk -F'|' -v m=" $mode " '$2 == m { gsub(/ /, "", $10); print $10 }')
# Each mode says what its saves waited for past the build (save -> screen less the compile).
past=$(echo "$out" | sed -n 's/^past the build.*median \([0-9.]*\) ms$/\1/p' | head -1)
awk -v p="$past" 'BEGIN { if (p == "" || p + 0 <= 0) { print "bench_adopt: no \"past the build\" median"; exit 1 } }' || exit 1
awk -v w="$worker" -v a="$adopt" -v m="$mode" -v wm="$wmiss" -v am="$amiss" 'BEGIN {
    if (w == "" || a == "" || wm == "" || am == "") { print "bench_adopt: no side-by-side table"; exit 1 }
    r = a / w
    printf "longest frame during a reload: %s %s ms / worker %s ms = %.3f (expected < 0.25)\n", m, a, w, r
    printf "display refreshes missed a save at 60 Hz: %s %s, worker %s (expected worker >= 8, %s <= a quarter of it)\n", m, am, wm, m
    exit !(r < 0.25 && wm >= 8 && am <= wm / 4) }'
