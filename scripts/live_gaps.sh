#!/usr/bin/env bash
# What a save costs the frames of `sdfvj live` on this machine: in-process reloads against
# `--render-process` (or, with --post, the chain in contexts of its own against the window's), each mode in
# its own show, one after the other.
#
#   scripts/live_gaps.sh [--scene NAME] [--post NAME] [--size WxH] [--saves N] [--bin PATH]
#
#   --post NAME   the show runs the ISF post effect shaders/isf/NAME.fs over the scene, and the saves
#                 go to that file instead of the scene (what a post effect's reload costs the frames).
#                 The modes are then the chain in contexts of its own (the default) against the chain
#                 in the window's context (SDFVJ_POST_CONTEXTS=0), both in-process, and the chain drawn
#                 by the render processes (--render-process with SDFVJ_POST_IN_SERVER=1, post-render-process).
#
# Each show runs in an Xvfb display with SDFVJ_ROOT at a temporary copy of shaders/, the drivers'
# shader disk caches off (every save is a compile). Every 4 s the scene gets a new constant (a
# program no cache has seen); --log-params gives each frame's time. Per mode it prints the median
# frame interval and, per save, the longest interval in the 3 s after it, with the compile the log
# reports where it does (the render process's "build B ms, first use U ms").
set -eu
repo=$(cd "$(dirname "$0")/.." && pwd)
scene=midi post="" size=320x180 saves=4 bin=$repo/build/src/app/sdfvj
while [ $# -gt 0 ]; do
    case $1 in
    --scene) scene=$2; shift ;;
    --post) post=$2; shift ;;
    --size) size=$2; shift ;;
    --saves) saves=$2; shift ;;
    --bin) bin=$2; shift ;;
    -h|--help) sed -n '2,/^set -eu/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "live_gaps: unknown argument '$1'"; exit 2 ;;
    esac
    shift
done
command -v Xvfb >/dev/null || { echo "live_gaps: needs Xvfb"; exit 2; }
work=$(mktemp -d /tmp/sdfvj-gaps.XXXXXX)
display=:$((90 + RANDOM % 9))
Xvfb "$display" -screen 0 1280x720x24 >/dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb 2>/dev/null; kill $(jobs -p) 2>/dev/null; rm -rf "$work"' EXIT
sleep 1
export MESA_SHADER_CACHE_DISABLE=true __GL_SHADER_DISK_CACHE=0 JACK_NO_START_SERVER=1
modes="in-process render-process"
[ -n "$post" ] && modes="post-own-contexts post-window-context post-render-process"
modes=${LIVE_GAPS_MODES:-$modes}
run_mode() {   # $1: one of $modes
    local mode=$1 root=$work/$1 extra=() contexts=1
    mkdir -p "$root"
    cp -r "$repo/shaders" "$root/"
    [ "$mode" = render-process ] || [ "$mode" = post-render-process ] && extra=(--render-process)
    [ "$mode" = post-window-context ] && contexts=0
    local file=$root/shaders/scenes/$scene.glsl
    if [ -n "$post" ]; then file=$root/shaders/isf/$post.fs; extra+=(--post "$post"); fi
    cp "$file" "$root/original.glsl"
    (DISPLAY=$display SDFVJ_ROOT=$root SDFVJ_POST_CONTEXTS=$contexts SDFVJ_POST_IN_SERVER=1 exec "$bin" live --scene "$scene" --size "$size" --path fragment --midi none \
        --osc-port 0 --hide-overlay --log-params "$root/params.log" --seconds $((6 + 4 * saves)) "${extra[@]}") \
        >"$root/out.log" 2>&1 &
    local pid=$!
    sleep 5
    : >"$root/saves.log"
    for i in $(seq 1 "$saves"); do
        # A new constant in the scene's (or the post effect's) own code: a program no cache has seen.
        { cat "$root/original.glsl"; printf '\nfloat liveGapsSave%d() { return %d.0; }\n' "$i" "$i"; } >"$file.new"
        mv "$file.new" "$file"
        awk -v t="$(date +%s.%N)" 'BEGIN { print t }' >>"$root/saves.log"
        sleep 4
    done
    wait $pid || true
}
for mode in $modes; do run_mode $mode; done
python3 - "$work" "$saves" $modes <<'PY'
import re, statistics, sys, os
work, saves = sys.argv[1], int(sys.argv[2])
for mode in sys.argv[3:]:
    root = os.path.join(work, mode)
    t = [float(l.split()[0]) for l in open(os.path.join(root, "params.log")) if l.strip()]
    gaps = [(t[i] - t[i - 1]) * 1000 for i in range(1, len(t))]
    med = statistics.median(gaps[len(gaps) // 5:]) if gaps else 0
    log = open(os.path.join(root, "out.log")).read()
    builds = re.findall(r"build (\d+) ms, first use (\d+) ms", log)
    # Save k lands about 5 + 4(k-1) s after start on the live clock.
    rows = []
    for k in range(saves):
        at = 5 + 4 * k
        window = [(gaps[i - 1], t[i] - at) for i in range(1, len(t)) if at - 0.2 <= t[i] <= at + 3]
        rows.append(max(window) if window else (float("nan"), 0))
    comp = ", ".join(f"{int(b) + int(u)}" for b, u in builds[1:]) or \
        ", ".join(re.findall(r"post reloaded \(built in (\d+) ms\)", log)) or "not reported"
    print(f"{mode:20s} median frame {med:6.1f} ms; longest frame after each save (when): " +
          " / ".join(f"{r:.0f} (+{a:.2f} s)" for r, a in rows) + f" ms; compiles (build + first use): {comp} ms")
    # The frames drawn while each post build ran (from the save to the build's end, as the log reports it).
    posts = [float(b) for b in re.findall(r"post reloaded \(built in (\d+) ms\)", log)]
    if posts and len(posts) >= saves:
        during = []
        for k, b in enumerate(posts[-saves:]):
            at = 5 + 4 * k
            idx = [i for i in range(1, len(t)) if at <= t[i] <= at + b / 1000 + 0.1]
            if not idx: continue
            w = [gaps[i - 1] for i in idx]
            # as many frames just before the save, with no build running: the machine's own noise
            q = gaps[max(0, idx[0] - 1 - len(w)):idx[0] - 1]
            during.append((statistics.median(w), max(w), len(w), (statistics.median(q), max(q)) if q else (0, 0)))
        print(f"{'':20s} frames during each build (median / longest / count): " +
              " / ".join(f"{m:.0f} / {x:.0f} / {n}" for m, x, n, _ in during) + " ms; longest against the median frame: " +
              " / ".join(f"{x / med:.1f}x" for _, x, _, _ in during) + "; as many frames before the save (median / longest): " +
              " / ".join(f"{q[0]:.0f} / {q[1]:.0f}" for *_, q in during) + " ms")
PY
