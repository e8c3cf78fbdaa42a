#!/bin/sh
# ctest fixture: a virtual X display for the `live` tests.
#   xvfb_fixture.sh start STATE_PREFIX   (writes STATE_PREFIX.pid, .display (the number), .log)
#   xvfb_fixture.sh stop  STATE_PREFIX
# Xvfb picks a free display number itself (-displayfd) and reports it once it accepts clients.
set -u
cmd=$1
state=$2
case $cmd in
start)
    rm -f "$state.pid" "$state.display"
    command -v Xvfb >/dev/null 2>&1 || { echo "Xvfb not installed (apt-get install xvfb)"; exit 1; }
    setsid Xvfb -displayfd 3 -screen 0 640x360x24 -nolisten tcp 3>"$state.display" >"$state.log" 2>&1 </dev/null &
    echo $! >"$state.pid"
    i=0
    until [ -s "$state.display" ]; do
        i=$((i + 1))
        if [ $i -gt 1000 ] || ! kill -0 "$(cat "$state.pid")" 2>/dev/null; then
            echo "Xvfb did not come up in 10 s:"; cat "$state.log"; exit 1
        fi
        sleep 0.01
    done
    echo "Xvfb ready on :$(cat "$state.display") (pid $(cat "$state.pid"))"
    ;;
stop)
    [ -f "$state.pid" ] || { echo "no Xvfb of ours to stop"; exit 0; }
    pid=$(cat "$state.pid")
    kill "$pid" 2>/dev/null
    i=0
    while kill -0 "$pid" 2>/dev/null; do
        i=$((i + 1))
        if [ $i -gt 500 ]; then kill -9 "$pid" 2>/dev/null; break; fi
        sleep 0.01
    done
    rm -f "$state.pid" "$state.display"
    echo "Xvfb stopped"
    ;;
*)
    echo "usage: $0 start|stop STATE_PREFIX"; exit 2
    ;;
esac
