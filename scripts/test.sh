#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite through ctest.
# GL tests run on Mesa llvmpipe through EGL (no display, no GPU); MIDI tests start JACK's dummy
# server themselves; OSC tests use loopback UDP.
#
#   scripts/test.sh                 # the suite (extra args go to ctest)
#   scripts/test.sh --sanitize      # then the ASan + UBSan pass (scripts/test_sanitize.sh)
# In CI (CI=true) the sanitizer pass always runs after the suite.
set -euo pipefail
cd "$(dirname "$0")/.."
sanitize=0
[ "${CI:-}" = "true" ] && sanitize=1
args=()
for a in "$@"; do
  if [ "$a" = "--sanitize" ]; then sanitize=1; else args+=("$a"); fi
done
bash scripts/setup.sh
bash scripts/build.sh
status=0
(cd build && ctest --output-on-failure -j2 --timeout 600 "${args[@]}") || status=$?
if [ "$sanitize" = 1 ]; then
  # Runs even when the suite failed: its reports are about other bugs.
  bash scripts/test_sanitize.sh || status=$((status == 0 ? 1 : status))
fi
exit $status
