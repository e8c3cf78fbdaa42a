#!/bin/sh
# ctest fixture: start JACK's dummy server for the MIDI tests, and stop it again.
#   jackd_fixture.sh start STATE_PREFIX SERVER_NAME   (writes STATE_PREFIX.pid and .log)
#   jackd_fixture.sh stop  STATE_PREFIX SERVER_NAME
# The server runs under its own name (jackd -n; clients find it through JACK_DEFAULT_SERVER),
# so it never collides with another test run or a performer's default server. If a server of
# that name already answers (a run that was interrupted), it is used.
set -u
cmd=$1
state=$2
export JACK_DEFAULT_SERVER=${3:-default}
case $cmd in
start)
    rm -f "$state.pid"
    if jack_lsp >/dev/null 2>&1; then
        echo "jackd \"$JACK_DEFAULT_SERVER\" already running; using it"
        exit 0
    fi
    setsid jackd -n "$JACK_DEFAULT_SERVER" --no-realtime -d dummy -r 48000 -p 256 >"$state.log" 2>&1 </dev/null &
    echo $! >"$state.pid"
    i=0
    until jack_lsp >/dev/null 2>&1; do
        i=$((i + 1))
        if [ $i -gt 1000 ]; then
            echo "jackd did not come up in 10 s:"; cat "$state.log"; exit 1
        fi
        sleep 0.01
    done
    echo "jackd \"$JACK_DEFAULT_SERVER\" ready (pid $(cat "$state.pid"))"
    ;;
stop)
    [ -f "$state.pid" ] || { echo "no jackd of ours to stop"; exit 0; }
    pid=$(cat "$state.pid")
    kill "$pid" 2>/dev/null
    i=0
    while kill -0 "$pid" 2>/dev/null; do
        i=$((i + 1))
        if [ $i -gt 500 ]; then kill -9 "$pid" 2>/dev/null; break; fi
        sleep 0.01
    done
    rm -f "$state.pid"
    # Late cycles (a client that did not finish in time) lose MIDI on the way: say how many.
    late=$(grep -c 'XRun' "$state.log" 2>/dev/null)   # prints 0 (and fails) when there is none
    echo "jackd stopped; it reported ${late:-0} late cycle(s)"
    ;;
*)
    echo "usage: $0 start|stop STATE_PREFIX"; exit 2
    ;;
esac
