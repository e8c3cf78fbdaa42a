#!/bin/sh
# Issue 12, `bench reload --modes process,process-source`: in process-source the compile process's
# reply is only a sign, and the render thread compiles the same text itself. With Mesa's disk cache
# on (in empty folders of the run, shared with the server) that compile is the server's program
# served from the cache, so its own time is a small fraction of the server's compile; if the text
# or the hint differed, it would be a compile as long as the server's. (On NVIDIA it is not served:
# the driver reads its cache when a process starts, docs/performance.md, session 14.) A ratio of
# two columns of one run, not a time.
bin=$1
out=$("$bin" bench reload --scene midi --size 160x90 --path fragment --driver-cache fresh --modes process,process-source \
    --rounds 2 --tiered off --no-program-cache 2>&1) || { echo "$out"; exit 1; }
echo "$out" | grep -E '^## |^median:'
server=$(echo "$out" | awk '/^## process:/ { s = 1 } /^## process-source:/ { s = 0 } s && /^median:/ { print $NF == "ms" ? $(NF-1) : "" }')
shown=$(echo "$out" | awk '/^## process-source:/ { s = 1 } s && /^median:/ { print $(NF-1); exit }')
awk -v p="$server" -v s="$shown" 'BEGIN {
    if (p == "" || s == "") { print "bench_handover: no median lines"; exit 1 }
    r = s / p
    printf "compile: the show again from the same text %s ms / the server %s ms = %.3f (expected < 0.25)\n", s, p, r
    exit !(r < 0.25) }'
