#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite through ctest.
# GL tests run on Mesa llvmpipe through EGL (no display, no GPU); MIDI tests start JACK's dummy
# server themselves; OSC tests use loopback UDP.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
cd build
ctest --output-on-failure -j2 --timeout 600 "$@"
