#!/bin/sh
# AO's farthest probe first (lib/shading.glsl AO_FARTHEST_FIRST) is exact: scenes that ship with
# it (the fields) render the same bytes without it, and scenes that ship without it the same
# bytes with it (mandelbulb's field is a distance estimate: its Lipschitz bound is the one the
# early return relies on). Usage: ao_farthest.sh SDFVJ SOURCE OUTDIR
set -eu
here="$(dirname "$0")"
status=0
sh "$here/define_exact.sh" "$1" "$2" "$3/on" "AO_FARTHEST_FIRST 0" compute "field50" || status=1
sh "$here/define_exact.sh" "$1" "$2" "$3/off" "AO_FARTHEST_FIRST 1" compute "midi character mandelbulb" || status=1
exit $status
