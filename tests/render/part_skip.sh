#!/bin/sh
# character's part skip (shaders/scenes/character.glsl CHARACTER_SKIP) leaves the field as it is: the
# scene renders the same bytes as a copy that evaluates every limb (CHARACTER_SKIP 0), over a walk
# cycle, with the default knobs and at the blend's and the wave's ends. Usage: part_skip.sh SDFVJ SOURCE OUTDIR
# The skip is exact in real arithmetic; the two programs are compiled differently, and llvmpipe may
# round a limb's union in its last bit: a frame may differ in 2 pixels by 1/255 (seen once: 1 pixel).
SLACK="2 1" exec sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3" "CHARACTER_SKIP 0" fragment character \
  "" "--param wave=1 --param blend=0.25 --param floorBlend=0.5" "--param blend=0 --param speed=2"
