#!/bin/sh
# character's capsules read 1 / |b - a|^2 from the frame's setup (CHARACTER_CAPSULE_INV, fCapsuleInv)
# instead of dividing in every map() call: the same field in real arithmetic; x * (1 / y) and x / y
# round apart in the last bit, so a frame may differ in a few pixels by 1/255 (llvmpipe: 1-2 of
# 14,400 seen). Both paths, default knobs and the knobs' ends. Usage: capsule_inv.sh SDFVJ SOURCE OUTDIR
set -e
SLACK="8 1" sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3/compute" "CHARACTER_CAPSULE_INV 0" compute character \
  "" "--param wave=1 --param blend=0.25 --param floorBlend=0.5 --param speed=2" "--param blend=0 --param wave=0"
SLACK="8 1" exec sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3/fragment" "CHARACTER_CAPSULE_INV 0" fragment character \
  "" "--param wave=1 --param blend=0.25 --param floorBlend=0.5 --param speed=2"
