#!/bin/sh
# The primary ray steps past the floor by the objects' distance (render/march.glsl MARCH_OBJECT_STEP,
# on for character and the fields): it stops within the hit epsilon of the same surfaces as copies
# that step by the field (MARCH_OBJECT_STEP 0), so the frames differ only where a hit moved within
# that epsilon: at most 100 pixels of 14,400 per frame, by at most 32/255. Seen: up to 59 pixels
# (field50 at the widest blends), by up to 5/255, and once one silhouette pixel by 18/255 (its
# hit on the other side of an edge). A ray stepping through a surface would draw what lies behind
# it; that none does is `stability: ... hits agree with quarter-length steps` (an unsafe bound
# fails it). Both paths.
# Usage: march_object_step.sh SDFVJ SOURCE OUTDIR
set -e
SLACK="100 32" sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3/compute" "MARCH_OBJECT_STEP 0" compute \
  "character field50 field150" "" "--param wave=1.5 --param blend=0.35 --param floorBlend=0.3"
SLACK="100 32" exec sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3/fragment" "MARCH_OBJECT_STEP 0" fragment \
  "character field150" ""
