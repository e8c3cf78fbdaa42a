#!/usr/bin/env bash
# Fuzzes the input decoders (MIDI bytes, OSC through a real lo_server, TOML mappings), default 60 s.
#   scripts/fuzz_input.sh [seconds] [extra libFuzzer args...]
# Same as scripts/fuzz.sh --only input (build in build-fuzz/, crashes in build-fuzz/crashes/input/).
exec "$(dirname "$0")/fuzz.sh" --only input "$@"
