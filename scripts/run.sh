#!/usr/bin/env bash
# Installs what is missing, builds, and runs the show: a live window when a display is present,
# otherwise a headless render of the demo preset (its take drives the parameters) into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
  exec ./build/src/app/sdfvj live --preset demo "$@"
fi
echo "run: no display; rendering the demo preset headless into out/"
exec ./build/src/app/sdfvj render --preset demo --replay presets/demo_take.mid --size 640x360 --fps 30 --out out "$@"
