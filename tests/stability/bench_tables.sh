#!/bin/sh
# Every bench table is trustworthy in form: it prints a drift check and writes CSV whose first
# columns are scene,lighting,size,path,ms,gpu (tiny sizes on llvmpipe; times are not judged).
# Usage: bench_tables.sh SDFVJ OUTDIR
set -eu
sdfvj=$1; out=$2; mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
"$sdfvj" bench --scenes midi,character --sizes 32x24,48x32 --tests none --paths fragment --frames 2 --warmup 1 \
  --csv "$out/bench.csv" > "$out/bench.txt"
grep -q '^drift check: midi none 32x24 fragment [0-9.]* ms at the start, [0-9.]* ms at the end' "$out/bench.txt" || fail "bench: no drift check"
[ "$(head -1 "$out/bench.csv")" = "scene,lighting,size,path,ms,gpu" ] || fail "bench: CSV header $(head -1 "$out/bench.csv")"
[ "$(wc -l < "$out/bench.csv")" -eq 5 ] || fail "bench: expected 4 rows (2 scenes x 2 sizes)"
grep -q '^character,none,48x32,fragment,[0-9.]*,' "$out/bench.csv" || fail "bench: no character 48x32 row"
"$sdfvj" bench effects --scene midi --size 32x24 --path fragment --frames 2 --warmup 1 --csv "$out/effects.csv" > "$out/effects.txt"
grep -q '^drift check: midi no effects 32x24 fragment' "$out/effects.txt" || fail "effects: no drift check"
[ "$(head -1 "$out/effects.csv")" = "scene,lighting,size,path,ms,gpu,effect,variant" ] || fail "effects: CSV header"
[ "$(wc -l < "$out/effects.csv")" -eq 17 ] || fail "effects: expected 16 rows (baseline + 5 effects x 3)"
"$sdfvj" bench accuracy --scene midi --size 32x24 --sweep tiny --frames 1 --warmup 1 --path fragment \
  --out "$out/accuracy" --csv "$out/accuracy.csv" > "$out/accuracy.txt"
grep -q '^drift check: midi sdfvj default' "$out/accuracy.txt" || fail "accuracy: no drift check"
head -1 "$out/accuracy.csv" | grep -q '^scene,lighting,size,path,ms,gpu,knob,' || fail "accuracy: CSV header"
echo "bench tables ok"
