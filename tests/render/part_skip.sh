#!/bin/sh
# character's part skip (shaders/scenes/character.glsl CHARACTER_SKIP) leaves the field as it is: the
# scene renders the same bytes as a copy that evaluates every limb (CHARACTER_SKIP 0), over a walk
# cycle, with the default knobs and at the blend's and the wave's ends. Usage: part_skip.sh SDFVJ SOURCE OUTDIR
exec sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3" "CHARACTER_SKIP 0" fragment character \
  "" "--param wave=1 --param blend=0.25 --param floorBlend=0.5" "--param blend=0 --param speed=2"
