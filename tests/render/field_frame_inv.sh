#!/bin/sh
# The fields' blends with their reciprocals computed once per frame (lib/field_scene.glsl
# FIELD_FRAME_INV, fOpUnionSmoothColorInv: no division and no branch per map() call) draw what the
# division draws: field50 and field150 against copies that divide (FIELD_FRAME_INV 0), both paths,
# at the default knobs, the widest blends, and both blends 0 (the sharp union, reciprocal 0). x / k
# and x * (1 / k) round apart in the last bit: a frame may differ in 8 of 14,400 pixels by 1/255
# (seen: 1 of 129,600 at 480x270). Usage: field_frame_inv.sh SDFVJ SOURCE OUTDIR
set -e
SLACK="8 1" sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3/compute" "FIELD_FRAME_INV 0" compute "field50 field150" \
  "" "--param blend=0.35 --param floorBlend=0.3 --param wave=1.5" "--param blend=0 --param floorBlend=0"
SLACK="8 1" exec sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3/fragment" "FIELD_FRAME_INV 0" fragment "field150" \
  "" "--param blend=0 --param floorBlend=0"
