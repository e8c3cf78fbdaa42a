#!/bin/sh
# The compute path's lanes in 8x4 blocks (render/main_comp.glsl WARP_BLOCKS, on for character's 16x16
# groups) draw the same pixels: character renders the same bytes as a copy whose lanes run row by row
# (WARP_BLOCKS 0), at 160x90 (groups cut by the frame's edges), default knobs and the knobs' ends.
# A lane mapped to the wrong pixel leaves one unwritten, or writes it twice. Usage: warp_blocks.sh SDFVJ SOURCE OUTDIR
exec sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3" "WARP_BLOCKS 0" compute character \
  "" "--param wave=1 --param blend=0.25 --param floorBlend=0.5 --param speed=2"
