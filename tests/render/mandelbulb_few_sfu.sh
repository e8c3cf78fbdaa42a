#!/bin/sh
# mandelbulb's power-8 step takes rho and 1 / rho from one inversesqrt and r^7 by squarings
# (MANDELBULB_FEW_SFU, on by default) instead of length(), a division by rho and r^8 / r
# (MANDELBULB_FEW_SFU 0, the copy): the same orbit in real
# arithmetic, rounded apart in the last bits, so a frame may differ in a few pixels by a level or
# two. Both paths, default knobs and the knobs' ends (iterations 16 lengthens the orbit the
# rounding builds up in). Usage: mandelbulb_few_sfu.sh SDFVJ SOURCE OUTDIR
set -e
SLACK="${MANDELBULB_SLACK:-40 8}" sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3/compute" "MANDELBULB_FEW_SFU 0" compute mandelbulb \
  "" "--param iterations=16 --param spin=1" "--param iterations=3 --param hue=0.9 --param colorSpread=3"
SLACK="${MANDELBULB_SLACK:-40 8}" exec sh "$(dirname "$0")/define_exact.sh" "$1" "$2" "$3/fragment" "MANDELBULB_FEW_SFU 0" fragment mandelbulb \
  "" "--param iterations=16 --param spin=1"
