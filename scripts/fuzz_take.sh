#!/usr/bin/env bash
# Fuzzes the take reader (ParseTake) with libFuzzer for a while (default 60 s).
#   scripts/fuzz_take.sh [seconds] [extra libFuzzer args...]
# Same as scripts/fuzz.sh --only take (build in build-fuzz/, crashes in build-fuzz/crashes/take/).
exec "$(dirname "$0")/fuzz.sh" --only take "$@"
