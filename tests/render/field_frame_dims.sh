#!/bin/sh
# The fields' dimensions at the frame's size and the shapes' top computed once per frame (lib/field_scene.glsl
# FIELD_FRAME_DIMS: FieldDims in the frame state) draw what the same values computed in every map() call
# draw (FIELD_FRAME_DIMS 0), at the default knobs and at the size's and the wave's ends, both paths. The
# two programs may fuse a product into an FMA differently: a frame may differ in 8 of 14,400 pixels by
# 1/255. Usage: field_frame_dims.sh SDFVJ SOURCE OUTDIR
set -e
SLACK="8 1" sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3/compute" "FIELD_FRAME_DIMS 0" compute "field50 field150" \
  "" "--param size=0.3 --param wave=0" "--param size=1 --param wave=1.5 --param blend=0.35"
SLACK="8 1" exec sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3/fragment" "FIELD_FRAME_DIMS 0" fragment "field150" \
  "" "--param size=0.3 --param wave=0"
