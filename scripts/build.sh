#!/usr/bin/env bash
# Configures and builds into build/ (optimized, with line tables). Extra args go to cmake.
# -g1, not RelWithDebInfo's -g: file:line in backtraces and sanitizer reports, and on CI's 2
# cores a quarter less compile time (cmd_live.cpp 7.1 -> 5.0 s, live_state_test.cpp 4.9 -> 3.5 s).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" "$@" >/dev/null
cmake --build build -j"$(nproc)"
