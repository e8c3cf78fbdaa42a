#!/bin/sh
# The fields' cell table (lib/field_scene.glsl FIELD_CELL_TABLE: each cell's lift, turn and kind
# computed once per work-group into shared memory, and the skip test's height slab it allows) is
# exact: field50 and field150 on the compute path render the same bytes as copies that compute
# every cell in map() (FIELD_CELL_TABLE 0), with the default knobs and at the knobs' ends.
# Usage: field_cells.sh SDFVJ SOURCE OUTDIR
exec sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3" "FIELD_CELL_TABLE 0" compute "field50 field150" \
  "" "--param wave=1.5 --param size=1 --param blend=0.35 --param spin=3 --param speed=4" "--param wave=0 --param size=0.3 --param blend=0"
