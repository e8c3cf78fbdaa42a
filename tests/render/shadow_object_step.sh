#!/bin/sh
# Soft shadows that step past the floor by the objects' distance (render.glsl SHADOW_OBJECT_STEP, on
# for character and the fields) read the same field at other points of the same ray. The frames
# against copies without it (SHADOW_OBJECT_STEP 0) differ only in the penumbrae's sampling: at most
# 600 pixels of 14,400 per frame, by at most 16/255 (seen: up to 327 pixels, by up to 9/255). Both
# paths. (A step past the sphere the improved shadow's estimate expected once darkened the floor
# round character's feet by 81/255.) The numeric bound is `stability: soft shadows that step past
# the floor...`.
# Usage: shadow_object_step.sh SDFVJ SOURCE OUTDIR
set -e
SLACK="600 16" sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3/compute" "SHADOW_OBJECT_STEP 0" compute \
  "character field50 field150" "" "--param wave=1.5 --param blend=0.35 --param floorBlend=0.3"
SLACK="600 16" exec sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3/fragment" "SHADOW_OBJECT_STEP 0" fragment \
  "character field150" ""
