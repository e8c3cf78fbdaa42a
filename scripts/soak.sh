#!/usr/bin/env bash
# The stage soak: `sdfvj live` must survive everything a stage throws at it, all at once.
#
#   scripts/soak.sh [--quick] [--minutes N] [--bin PATH] [--driver PATH] [--keep]
#                   [--only osc|midi|saves] [--rss-limit-mb N] [--rss-late-limit-mb N] [--gap-limit-ms N] [--seed N]
#                   [--render-process] [--post CHAIN] [--live-arg ARG ...] [--driver-cache cold|as-set]
#
#   --quick        at most 45 s in all (CI, `ctest -L soak`): a 15 s storm
#   --minutes N    length of the storm (default 10)
#   --bin PATH     the sdfvj to soak (default: build-asan/src/app/sdfvj when it exists, else
#                  build/src/app/sdfvj)
#   --driver PATH  tests/soak's soak_driver (default: next to --bin's build, else built here with g++)
#   --keep         keep the work folder (it is always kept when the soak fails)
#   --only KIND    one source alone (osc, midi or saves), to tell which one causes a finding
#   --render-process  the show runs `live --render-process`: every save builds in a render process
#   --post CHAIN   the show's post chain (default bloom,feedback_trails). A chain with feedback stays
#                  in the show's process under --render-process; `--post bloom` with
#                  SDFVJ_POST_IN_SERVER=1 has the render processes build and draw it (and its saves)
#   --live-arg ARG one more argument for `sdfvj live` (repeatable), e.g. the frame budget moving
#                  the render scale under the storm: --live-arg --frame-budget --live-arg 20
#   --driver-cache cold (default): Mesa's shader disk cache in an empty folder of the work folder
#                  (MESA_SHADER_CACHE_DIR), so llvmpipe compiles every program's pixel code during the
#                  soak, as at a first show on a new machine; as-set: the cache as the environment has it
#                  (warmed by earlier runs, it hides a first draw that compiles on the show's thread)
#
# It runs `sdfvj live --preset demo --post bloom,feedback_trails (--post) --audio system:capture_1` at 320x180 in an Xvfb display on Mesa llvmpipe, with
# SDFVJ_ROOT at a temporary COPY of shaders/, presets/ and mappings/ (the repository's files are
# never touched), --log-params, --record take.mid, an OSC port liblo picks free, and a private
# JACK dummy server (JACK_DEFAULT_SERVER=sdfvj-soak-$$). soak_driver then floods it with hostile
# OSC, MIDI from a controller port that is unplugged and plugged back, and valid/broken saves of
# scenes, library files, presets, mappings and the post chain's ISF files (see tests/soak/soak_driver.cpp).
#
# Passes when: sdfvj is still running at the end and then exits by itself (--seconds) with code 0;
# no gap between logged frames is longer than --gap-limit-ms (default 250; the first second is
# start-up and not counted); the last OSC value sent after the storm is in the last frame; VmRSS
# grew by at most --rss-limit-mb from the baseline (taken 2 s after the first frame) and by at most
# --rss-late-limit-mb over the second half of the storm (not with --quick: too short to be past the
# warm-up); stderr holds
# no sanitizer report; the recorded take renders again (`sdfvj render --replay take.mid`), reading
# the audio the show recorded beside it (take.mid.wav, from JACK's dummy capture port).
# Exit code 0 on pass, 1 on fail, 2 on bad usage or a missing tool.
set -u

repo=$(cd "$(dirname "$0")/.." && pwd)
quick=0 minutes=10 bin="" driver="" keep=0 only="" rssLimit="" rssLateLimit="" gapLimit=250 seed=$$ liveExtra=() post=bloom,feedback_trails
driverCache=cold
while [ $# -gt 0 ]; do
    case $1 in
    --quick) quick=1 ;;
    --minutes) minutes=${2:?--minutes needs a number}; shift ;;
    --bin) bin=${2:?--bin needs a path}; shift ;;
    --driver) driver=${2:?--driver needs a path}; shift ;;
    --keep) keep=1 ;;
    --only) only=${2:?--only needs osc, midi or saves}; shift ;;
    --rss-limit-mb) rssLimit=${2:?}; shift ;;
    --rss-late-limit-mb) rssLateLimit=${2:?}; shift ;;
    --gap-limit-ms) gapLimit=${2:?}; shift ;;
    --seed) seed=${2:?}; shift ;;
    --render-process) liveExtra+=(--render-process) ;;
    --post) post=${2:?--post needs a chain, e.g. bloom}; shift ;;
    --live-arg) liveExtra+=("${2?--live-arg needs an argument}"); shift ;;
    --driver-cache) driverCache=${2:?--driver-cache needs cold or as-set}; shift ;;
    -h|--help) sed -n '2,/^set -u/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "soak: unknown argument '$1' (see --help)"; exit 2 ;;
    esac
    shift
done
case $minutes in ''|*[!0-9.]*) echo "soak: --minutes wants a number"; exit 2 ;; esac
case $driverCache in cold|as-set) ;; *) echo "soak: --driver-cache wants cold or as-set, not '$driverCache'"; exit 2 ;; esac

if [ $quick = 1 ]; then storm=15; else storm=$(awk -v m="$minutes" 'BEGIN { printf "%d", m * 60 }'); fi
[ "$storm" -ge 5 ] || storm=5
warm=2                        # seconds of calm after the first frame: the RSS baseline
finalPhase=6                  # the driver's calm end: restore files, preset, the final value (5.5 s)
liveSeconds=$((warm + storm + finalPhase + 4))   # sdfvj quits by itself after this (live clock)
finalValue=1.2345
osc_rate=2000

for tool in Xvfb jackd jack_lsp awk; do
    command -v $tool >/dev/null 2>&1 || { echo "soak: $tool is not installed (scripts/setup.sh installs it)"; exit 2; }
done

if [ -z "$bin" ]; then
    if [ -x "$repo/build-asan/src/app/sdfvj" ]; then bin=$repo/build-asan/src/app/sdfvj; else bin=$repo/build/src/app/sdfvj; fi
fi
[ -x "$bin" ] || { echo "soak: no sdfvj at $bin (build it, or pass --bin)"; exit 2; }
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
sanitized=0
grep -q -a -m1 "__asan_init\|__ubsan_handle" "$bin" && sanitized=1
# Memory: the first seconds of the storm fill caches (a program per scene and effect variant,
# Mesa's JIT code), so growth is bounded twice: baseline -> end (--rss-limit-mb) and over the
# second half of the storm (--rss-late-limit-mb), where a leak shows and warm-up does not.
if [ -z "$rssLimit" ]; then if [ $sanitized = 1 ]; then rssLimit=384; else rssLimit=192; fi; fi
if [ -z "$rssLateLimit" ]; then if [ $sanitized = 1 ]; then rssLateLimit=64; else rssLateLimit=32; fi; fi

work=$(mktemp -d /tmp/sdfvj-soak.XXXXXX)
XVFB_PID="" JACK_PID="" LIVE_PID="" DRIVER_PID="" STAMP_PID=""
failures=()
fail() { failures+=("$1"); echo "soak: FAIL: $1"; }

stop_pid() {   # stop_pid PID: TERM, up to 5 s, then KILL; only processes this script started
    local pid=$1 i=0
    [ -n "$pid" ] || return 0
    kill "$pid" 2>/dev/null || return 0
    while kill -0 "$pid" 2>/dev/null && [ $i -lt 50 ]; do sleep 0.1; i=$((i + 1)); done
    kill -9 "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    return 0
}
cleanup() {
    stop_pid "$DRIVER_PID"; DRIVER_PID=""
    stop_pid "$LIVE_PID"; LIVE_PID=""
    stop_pid "$STAMP_PID"; STAMP_PID=""   # its tail ends with sdfvj (--pid)
    stop_pid "$JACK_PID"; JACK_PID=""
    stop_pid "$XVFB_PID"; XVFB_PID=""
    if [ $keep = 0 ] && [ ${#failures[@]} = 0 ] && [ -n "${work:-}" ]; then rm -rf "$work"; fi
}
trap cleanup EXIT
trap 'fail "interrupted"; exit 1' INT TERM

t0=$(date +%s.%N)
loadStart=$(cut -d' ' -f1-3 /proc/loadavg)
elapsed() { awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }'; }
rss_kb() { awk '/^VmRSS:/ { print $2 }' "/proc/$1/status" 2>/dev/null || echo 0; }
# wait_for SECONDS COMMAND...: polls every 50 ms
wait_for() {
    local n=$(awk -v s="$1" 'BEGIN { printf "%d", s * 20 }') i=0
    shift
    until "$@"; do
        i=$((i + 1)); [ $i -gt "$n" ] && return 1
        sleep 0.05
    done
}

# --- the driver ---------------------------------------------------------------------------
if [ -z "$driver" ]; then
    for d in "$(dirname "$bin")/../../tests/soak/soak_driver" "$repo/build-soak/tests/soak/soak_driver" "$repo/build/tests/soak/soak_driver"; do
        [ -x "$d" ] && { driver=$d; break; }
    done
fi
if [ -z "$driver" ]; then
    echo "soak: building soak_driver with g++ (no build folder has it)"
    g++ -O1 -std=c++20 "$repo/tests/soak/soak_driver.cpp" $(pkg-config --cflags --libs liblo rtmidi) -pthread \
        -o "$work/soak_driver" || { echo "soak: cannot build soak_driver"; exit 2; }
    driver=$work/soak_driver
fi

# --- the stage: a copy of the data, a display, a JACK server --------------------------------
mkdir -p "$work/root"
cp -r "$repo/shaders" "$repo/presets" "$repo/mappings" "$work/root/"
# --frame-budget (--live-arg) reads the accuracy sweep from the data root; without it the budget did not start
mkdir -p "$work/root/docs/accuracy" && cp "$repo/docs/accuracy/accuracy.csv" "$work/root/docs/accuracy/"

setsid Xvfb -displayfd 3 -screen 0 640x360x24 -nolisten tcp 3>"$work/xvfb.display" >"$work/xvfb.log" 2>&1 </dev/null &
XVFB_PID=$!
wait_for 10 test -s "$work/xvfb.display" || { fail "Xvfb did not start: $(tail -3 "$work/xvfb.log")"; exit 1; }
display=:$(tr -d ' \n' <"$work/xvfb.display")

export JACK_DEFAULT_SERVER=sdfvj-soak-$$
export JACK_NO_AUDIO_RESERVATION=1
setsid jackd -n "$JACK_DEFAULT_SERVER" --no-realtime -d dummy -r 48000 -p 256 >"$work/jackd.log" 2>&1 </dev/null &
JACK_PID=$!
wait_for 10 jack_lsp >/dev/null 2>&1
jack_lsp >/dev/null 2>&1 || { fail "jackd did not start: $(tail -3 "$work/jackd.log")"; exit 1; }

# --- the show -------------------------------------------------------------------------------
: "${ASAN_OPTIONS:=detect_leaks=1:halt_on_error=1:quarantine_size_mb=64:malloc_context_size=15}"
: "${UBSAN_OPTIONS:=print_stacktrace=1}"
# Third-party leaks (Mesa, fontconfig, JACK) are suppressed as in scripts/test_sanitize.sh.
if [ -z "${LSAN_OPTIONS:-}" ] && [ -f "$repo/scripts/lsan.supp" ]; then LSAN_OPTIONS=suppressions=$repo/scripts/lsan.supp:print_suppressions=0; fi
# A sanitizer build keeps Mesa's swrast_dri.so mapped to the end (as scripts/test_sanitize.sh
# does): libEGL/libGLX unload it at exit, and memory its globals hold would look leaked.
sdfvj_preload=""
if [ "$sanitized" = 1 ]; then
  sdfvj_preload=$(ls /usr/lib/*/dri/swrast_dri.so 2>/dev/null | head -n1 || true)
  ASAN_OPTIONS="verify_asan_link_order=0:$ASAN_OPTIONS"
fi
export ASAN_OPTIONS UBSAN_OPTIONS LSAN_OPTIONS
export SDFVJ_ROOT=$work/root
export LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=llvmpipe
if [ $driverCache = cold ]; then
  mkdir -p "$work/mesa-cache"
  export MESA_SHADER_CACHE_DIR=$work/mesa-cache
fi
echo "soak: Mesa's shader disk cache: ${MESA_SHADER_CACHE_DIR:-as set} ($driverCache)"
echo "soak: $bin (sanitizer build: $([ $sanitized = 1 ] && echo yes || echo no)), storm ${storm} s, display $display, JACK $JACK_DEFAULT_SERVER, work $work"
(cd "$work" && DISPLAY=$display LD_PRELOAD=$sdfvj_preload exec "$bin" live --preset demo --post "$post" --audio system:capture_1 --size 320x180 --path fragment --midi soak-controller \
    --osc-port 0 --log-params "$work/params.log" --record "$work/take.mid" --seconds "$liveSeconds" "${liveExtra[@]}") \
    >"$work/live.out" 2>"$work/live.err" </dev/null &
LIVE_PID=$!
# A copy of stderr with wall-clock stamps, to tell what happened around the longest frame gaps.
stamp_stderr() {
    local line
    while IFS= read -r line; do printf '%s %s\n' "$EPOCHREALTIME" "${line:0:300}"; done
}
tail --pid=$LIVE_PID -s 0.05 -n +1 -F "$work/live.err" 2>/dev/null | stamp_stderr >"$work/live.err.stamped" &
STAMP_PID=$!

oscPort=""
first_frame() { [ -s "$work/params.log" ] || ! kill -0 $LIVE_PID 2>/dev/null; }
wait_for 90 first_frame
oscPort=$(sed -n 's/.*OSC: listening on UDP port \([0-9]*\).*/\1/p' "$work/live.err" | head -1)
if ! kill -0 $LIVE_PID 2>/dev/null || [ ! -s "$work/params.log" ] || [ -z "$oscPort" ]; then
    fail "sdfvj live did not come up (no frame or no OSC port); stderr tail:"
    tail -20 "$work/live.err"
    exit 1
fi
# Live clock -> wall clock: the live time of the newest frame now (one frame of error at most).
clockOffset=$(awk -v now="$EPOCHREALTIME" '{ t = $1 } END { printf "%.3f", now - t }' "$work/params.log")
rssFirst=$(rss_kb $LIVE_PID)
sleep $warm
rssStart=$(rss_kb $LIVE_PID)
rssPeak=$rssStart
echo "soak: first frame at $(elapsed) s, OSC port $oscPort, VmRSS $((rssFirst / 1024)) MB at the first frame, $((rssStart / 1024)) MB after ${warm} s (baseline)"

# --- the storm ------------------------------------------------------------------------------
# The driver stands for the outside world (a tablet, a controller, an editor), so it yields the
# CPU to the show: on a 2-core machine it would otherwise take a core from llvmpipe.
nice -n 10 "$driver" ${only:+--only "$only"} --osc-port "$oscPort" --root "$work/root" --seconds "$storm" --midi-name soak-controller \
    --osc-rate $osc_rate --save-ms 300 --replug-s 3 --final-preset demo --final-param twist \
    --final-value $finalValue --seed "$seed" >"$work/driver.out" 2>"$work/driver.err" &
DRIVER_PID=$!
limit=$((storm + finalPhase + 20)) i=0 died=0 nextReport=60
while kill -0 $DRIVER_PID 2>/dev/null; do
    sleep 1; i=$((i + 1))
    if ! kill -0 $LIVE_PID 2>/dev/null; then died=1; break; fi
    r=$(rss_kb $LIVE_PID); [ "${r:-0}" -gt "$rssPeak" ] && rssPeak=$r
    echo "$i $r" >>"$work/rss.log"
    if [ $i -ge $nextReport ]; then
        echo "soak: $((i / 60)) min: alive, VmRSS $((r / 1024)) MB, $(wc -l <"$work/params.log") frames"
        nextReport=$((nextReport + 60))
    fi
    [ $i -gt $limit ] && { fail "soak_driver did not finish in ${limit} s"; break; }
done
stop_pid "$DRIVER_PID" >/dev/null; DRIVER_PID=""   # on TERM it restores the files and prints its counts
sleep 0.5

aliveAtEnd=0 rssEnd=0
if [ $died = 0 ] && kill -0 $LIVE_PID 2>/dev/null; then
    aliveAtEnd=1
    rssEnd=$(rss_kb $LIVE_PID)
    [ "$rssEnd" -gt "$rssPeak" ] && rssPeak=$rssEnd
fi
lastLine=$(tail -n 2 "$work/params.log" | head -n 1)   # the last line may be half-written
diedAt=$(elapsed)
[ $aliveAtEnd = 1 ] || fail "sdfvj live died during the storm (noticed at $diedAt s of the soak, live clock $(tail -n 2 "$work/params.log" | head -n 1 | awk '{ print $1 }') s)"

# sdfvj quits by itself at --seconds; wait for that (bounded), then stop it.
wait_for $((liveSeconds + 30)) sh -c "! kill -0 $LIVE_PID 2>/dev/null"
if kill -0 $LIVE_PID 2>/dev/null; then
    fail "sdfvj live did not quit at --seconds $liveSeconds; stopped with SIGTERM"
    stop_pid $LIVE_PID
fi
wait $LIVE_PID 2>/dev/null; liveRc=$?
LIVE_PID=""
if [ $aliveAtEnd = 1 ] && [ $liveRc != 0 ]; then fail "sdfvj live exited with code $liveRc"; fi
[ $died = 1 ] && [ $liveRc -ge 128 ] && echo "soak: sdfvj live was killed by signal $((liveRc - 128))"

# --- the checks -----------------------------------------------------------------------------
read -r frames maxGap gapAt < <(awk '$1 >= 1.0 { if (n++) { g = $1 - p; if (g > m) { m = g; at = p } } p = $1 }
    END { printf "%d %.0f %.2f\n", n, m * 1000, at }' "$work/params.log")
# The five longest gaps, and how many passed 100 ms: one stall, or a slow machine throughout?
gaps=$(awk '$1 >= 1.0 { if (n++) printf "%.0f %.2f\n", ($1 - p) * 1000, p; p = $1 }' "$work/params.log" | sort -rn |
    awk '$1 > 100 { over++ } NR <= 5 { printf "%s%d ms @%ss", sep, $1, $2; sep = ", " } END { printf "; %d gaps over 100 ms", over }')
liveTime=$(tail -n 2 "$work/params.log" | head -n 1 | awk '{ print $1 }')
[ "${maxGap:-0}" -le "$gapLimit" ] || fail "a ${maxGap} ms gap between frames at live time ${gapAt} s (limit ${gapLimit} ms)"
# With --render-process a late server's frame is not waited for: the loop goes on showing its last
# image, and says so ("render process late: ... up to N ms"). What the audience sees is that image
# standing still, so it has the gap's limit too.
lateMax=$(grep -a -o 'render process late: .* up to [0-9]* ms' "$work/live.err" | awk '{ v = $(NF - 1) + 0; if (v > m) m = v } END { printf "%d", m }')
lateLines=$(grep -a -c '^render process late' "$work/live.err" || true)
[ "${lateMax:-0}" -le "$gapLimit" ] || fail "a render process's image stood still for ${lateMax} ms (said as 'render process late'; limit ${gapLimit} ms)"

finalSeen=$(echo "$lastLine" | awk -v want=$finalValue '{ for (i = 2; i <= NF; ++i) if ($i ~ /^twist=/) {
    v = substr($i, 7) + 0; d = v - want; if (d < 0) d = -d; print (d < 1e-3 ? "yes" : "no (" v ")"); exit } print "no (no twist)" }')
[ "$finalSeen" = yes ] || fail "the last OSC value /sdfvj/raw/twist $finalValue is not in the last frame: $finalSeen"

rssGrowth=$(( (rssEnd - rssStart) / 1024 ))
if [ $aliveAtEnd = 1 ] && [ $rssGrowth -gt "$rssLimit" ]; then fail "VmRSS grew by $rssGrowth MB (limit $rssLimit MB)"; fi
# RSS swings by 100 MB within a minute (programs compiled and dropped, Mesa's JIT code, the
# sanitizer's quarantine): the second half compares the median of the minute around the middle
# of the storm with the median of its last minute, so a trend counts and a swing does not.
rssMedian() {  # rssMedian FROM TO -> median VmRSS (kB) of the samples with FROM <= t < TO
    awk -v a="$1" -v b="$2" '$1 >= a && $1 < b { v[n++] = $2 } END {
        if (!n) { print 0; exit } for (i = 0; i < n; ++i) for (j = i + 1; j < n; ++j) if (v[j] < v[i]) { t = v[i]; v[i] = v[j]; v[j] = t }
        print v[int(n / 2)] }' "$work/rss.log" 2>/dev/null
}
rssMid=$(rssMedian $((storm / 2 - 30)) $((storm / 2 + 30)))
rssLateEnd=$(rssMedian $((storm - 60)) $((storm)))
rssLate=$(( (rssLateEnd - rssMid) / 1024 ))
# A 15 s storm is all warm-up (the 10-minute run levels off after 2-3 minutes): --quick reports it only.
if [ $quick = 0 ] && [ $aliveAtEnd = 1 ] && [ "$rssMid" -gt 0 ] && [ $rssLate -gt "$rssLateLimit" ]; then
    fail "VmRSS grew by $rssLate MB over the second half of the storm (limit $rssLateLimit MB): a leak?"
fi

sanReports=$(grep -a -c -E "ERROR: AddressSanitizer|runtime error:|LeakSanitizer|ERROR: ThreadSanitizer" "$work/live.err")
[ "$sanReports" = 0 ] || fail "$sanReports sanitizer report lines in sdfvj's stderr"

recorded=$(sed -n 's/^recorded \([0-9]*\) events to .*/\1/p' "$work/live.err" | tail -1)
takeOk=no
if [ -s "$work/take.mid" ]; then
    # Against the repository's own data (read only): the copy may hold a broken save after a crash.
    (cd "$work" && SDFVJ_ROOT=$repo LD_PRELOAD=$sdfvj_preload "$bin" render --preset demo --replay take.mid --frames 1 --size 64x36 --path fragment \
        --out "$work/replay" --quiet) >"$work/replay.log" 2>&1 && takeOk=yes
fi
[ $takeOk = yes ] || fail "the recorded take does not render again: $(tail -3 "$work/replay.log" 2>/dev/null)"
# The audio the show recorded beside the take (JACK's dummy capture port: silence) reads back in the replay.
wavBytes=$(stat -c %s "$work/take.mid.wav" 2>/dev/null || echo 0)
wavOk=no
if [ "$wavBytes" -gt 44 ] && ! grep -q "rendering without the take's audio" "$work/replay.log"; then wavOk=yes; fi
[ $wavOk = yes ] || fail "the recorded audio does not read back ($wavBytes bytes): $(grep -a "take's audio" "$work/replay.log" | tail -1)"

# The show's MIDI status lines: the controller gone (unplugged), then listened to again.
read -r gone reconnects < <(awk '/soak-controller is gone/ { if (!g) n++; g = 1 }
    /listening to .*soak-controller/ { if (g) b++; g = 0 } /^preset demo.json/ { fn = n; fb = b }
    END { printf "%d %d\n", fn, fb }' "$work/live.err")   # up to the final preset: the driver's exit unplugs too
# The MIDI status when the final preset switch came (the controller is plugged in through the
# calm end; it vanishes for good when the driver exits, which the show then reports too).
lastMidi=$(awk '/^sdfvj: MIDI/ { m = $0 } /^preset demo.json/ { s = m } END { print s }' "$work/live.err")
if [ -z "$only" ] || [ "$only" = midi ]; then
    case $lastMidi in
    *"listening to "*soak-controller*) ;;
    *) fail "the MIDI controller was not listened to again after its last replug: ${lastMidi:-no MIDI status line}" ;;
    esac
fi
count() { awk -v k="$1" '$1 == "COUNT" && $2 == k { print $3; f = 1 } END { if (!f) print 0 }' "$work/driver.out"; }
sumc() { awk -v p="$1" '$1 == "COUNT" && $2 ~ p { s += $3 } END { print s + 0 }' "$work/driver.out"; }

# What sdfvj printed around the three longest gaps (live time; from the stamped stderr copy).
around=$(awk '$1 >= 1.0 { if (n++) printf "%.0f %.3f %.3f\n", ($1 - p) * 1000, p, $1; p = $1 }' "$work/params.log" |
    sort -rn | head -3 | while read -r ms from to; do
        echo "  gap ${ms} ms from ${from} s:"
        win=$(awk -v a="$from" -v b="$to" -v off="$clockOffset" '{ t = $1 - off } t >= a - 0.6 && t <= b {
            m = substr($0, index($0, " ") + 1); k = substr(m, 1, 24)
            if (k == pk) { rep++; next }
            if (rep) printf "             (and %d more like it)\n", rep
            printf "    %7.2f  %s\n", t, m; pk = k; rep = 0 }
            END { if (rep) printf "             (and %d more like it)\n", rep }' "$work/live.err.stamped" 2>/dev/null | tail -8)
        [ -n "$win" ] && echo "$win"
        # The show's own account of that frame: `--hitch-ms` says the longest frame of a second
        # at most once a second, so its line can come up to a second after the gap, past the lines above.
        hitch=$(awk -v b="$to" -v off="$clockOffset" '{ t = $1 - off } t >= b - 0.05 && t <= b + 1.1 &&
            index($0, "sdfvj live: a ") && index($0, " ms frame (--hitch-ms") {
            printf "    %7.2f  %s\n", t, substr($0, index($0, " ") + 1); exit }' "$work/live.err.stamped" 2>/dev/null)
        if [ -n "$hitch" ] && ! grep -qxF -- "$hitch" <<<"$win"; then echo "$hitch" | cut -c1-400; fi
    done)

# The show's own account of its long frames (`live --hitch-ms`, 100 by default: at most one line a
# second, the longest): how much of them its thread ran, waited for a CPU (the machine too loaded)
# or was blocked (the GPU, a render process, a file), and their longest stages.
hitchRe='^sdfvj live: a [0-9]* ms frame'
hitchLines=$(grep -a -c "$hitchRe" "$work/live.err" || true)
hitchShare=$(grep -a "$hitchRe" "$work/live.err" | awk '{ ms += $4; for (i = 1; i < NF; ++i) {
        if ($i == "ran") r += $(i + 1); if ($i == "waited") w += $(i + 1); if ($i == "blocked") b += $(i + 1) } }
    END { if (ms > 0) printf "the show'"'"'s thread ran %.0f %%, waited for a CPU %.0f %%, was blocked %.0f %% of their %.1f s", 100 * r / ms, 100 * w / ms, 100 * b / ms, ms / 1000 }')
hitchTop=$(grep -a "$hitchRe" "$work/live.err" | sort -t' ' -k4,4 -rn | head -3 | cut -c1-260 | sed 's/^/    /')

# --- summary --------------------------------------------------------------------------------
echo
echo "================ sdfvj soak summary ================"
echo "binary          $bin$([ $sanitized = 1 ] && echo ' (sanitizers)')"
echo "commit          $(git -C "$repo" rev-parse --short HEAD 2>/dev/null)$(git -C "$repo" diff --quiet HEAD -- src 2>/dev/null || echo ' + local changes in src/')"
echo "storm           ${storm} s (+${finalPhase} s calm end)${only:+, only $only}, wall $(elapsed) s in all"
sig=""; [ "$liveRc" -gt 128 ] 2>/dev/null && sig=" (killed by SIG$(kill -l $((liveRc - 128)) 2>/dev/null))"
echo "still running   $([ $aliveAtEnd = 1 ] && echo yes || echo "NO (noticed at $diedAt s)"), then exit code $liveRc$sig"
echo "frames          ${frames:-0} logged after the first second, live clock reached ${liveTime:-?} s"
echo "longest gap     ${maxGap:-?} ms at live time ${gapAt:-?} s (limit ${gapLimit} ms); longest: $gaps"
[ -n "$around" ] && echo "around the longest gaps, what sdfvj printed (live time, s):" && echo "$around"
echo "hitches         ${hitchLines:-0} said (frames over --hitch-ms, the longest of each second)${hitchShare:+; $hitchShare}"
[ -n "$hitchTop" ] && echo "$hitchTop"
echo "late images     ${lateLines:-0} 'render process late' lines, the longest ${lateMax:-0} ms (limit ${gapLimit} ms; --render-process only)"
echo "machine load    $loadStart at the start, $(cut -d' ' -f1-3 /proc/loadavg) at the end (1/5/15 min; $(nproc) cores)"
echo "VmRSS           first frame $((rssFirst / 1024)) MB, baseline $((rssStart / 1024)) MB, end $((rssEnd / 1024)) MB, peak $((rssPeak / 1024)) MB; growth ${rssGrowth} MB (limit ${rssLimit} MB), ${rssLate} MB over the second half (median of its last minute against the middle one; $([ $quick = 1 ] && echo "not checked in --quick" || echo "limit ${rssLateLimit} MB"))"
echo "VmRSS timeline  $(awk -v n="$storm" 'BEGIN { step = n / 8 < 1 ? 1 : int(n / 8) } $1 % step == 0 { printf "%s%ds %dMB", sep, $1, $2 / 1024; sep = ", " }' "$work/rss.log" 2>/dev/null)"
echo "final value     /sdfvj/raw/twist $finalValue in the last frame: $finalSeen"
echo "sanitizer       $sanReports report lines"
echo "take            ${recorded:-?} events recorded; renders again: $takeOk"
echo "audio           take.mid.wav $((wavBytes / 1024)) KiB recorded from system:capture_1; reads back in the replay: $wavOk"
echo "OSC sent        $(sumc '^osc_') datagrams: $(count osc_valid_param) param, $(count osc_raw) raw (NaN/inf too), $(count osc_wrong_type) wrong types, $(count osc_unknown_address) unknown addresses, $(count osc_preset) preset, $(count osc_effect_toggle) effect toggles, $(count osc_huge_string) huge strings, $(( $(count osc_garbage) + $(count osc_mangled) + $(count osc_bad_bundle) )) garbage/mangled/bundles"
echo "MIDI sent       $(sumc '^midi_(cc|note|running|sysex|system|other|random)') messages: $(count midi_cc) CC, $(count midi_note) notes, $(count midi_sysex) sysex, $(count midi_running_status) running status, $(( $(count midi_system_or_stray) + $(count midi_random_bytes) )) stray/system/random"
echo "MIDI replugs    $(count midi_replug) (the show said gone $gone times, listening again $reconnects times)"
echo "saves           $(sumc '^save_(valid|broken)$'): $(count save_valid) valid, $(count save_broken) broken; $(count save_rename) rename, $(count save_in_place) in place, $(count save_two_halves) in two halves; $(count save_scene) scene, $(count save_lib) lib, $(count save_preset) preset, $(count save_mapping) mapping, $(count save_isf) ISF"
echo "shader errors   $(grep -a -c -E '\.(glsl|fs):[0-9]' "$work/live.err") lines; reloads $(grep -a -c '^shader reloaded' "$work/live.err") scene, $(grep -a -c '^post reloaded' "$work/live.err") post"
if [ ${#failures[@]} = 0 ]; then
    echo "result          PASS"
else
    echo "result          FAIL"
    for f in "${failures[@]}"; do echo "  - $f"; done
    echo "work folder     $work (kept)"
    echo "---- sdfvj stderr, last 25 lines ----"
    tail -n 25 "$work/live.err"
fi
echo "===================================================="
[ ${#failures[@]} = 0 ]
