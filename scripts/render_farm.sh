#!/usr/bin/env bash
# Splits one `sdfvj render` into N slices (render --frame-range A:B), runs them with GNU parallel
# on this machine or on others (--sshlogin), and joins the result: PNG frames into one folder
# (their names keep the absolute frame index, so the join is a move), or H.264 segments into one
# video with ffmpeg's concat demuxer (no re-encode). The PNGs are byte-identical to a one-machine
# render; docs/farm.md has the same job as a Slurm array and a Kubernetes Indexed Job.
#
#   scripts/render_farm.sh TAKE.mid --preset demo --slices 4 --out out/frames
#   scripts/render_farm.sh --preset cue_tour --frames 900 --slices 8 --video show.mp4
#   scripts/render_farm.sh take.mid --slices 16 --sshlogin 4/gpu1,4/gpu2 --out /nfs/show -- --size 3840x2160
#
# Options (all others, and everything after `--`, go to every `sdfvj render` as they are):
#   TAKE            a .mid take (render --replay TAKE); without one, --preset P runs its script
#   --slices N      how many slices (jobs); default 4
#   --jobs J        slices at once per host (parallel -j); default: N on this machine, 1 per host with --sshlogin
#   --sshlogin L    hosts for GNU parallel (repeatable; "4/host" = 4 jobs there). The hosts must see
#                   the same paths (a shared file system) and have sdfvj at the same path
#   --out DIR       PNG frames (default out/farm);  --video FILE  one .mp4 instead
#   --bin PATH      the sdfvj binary (default: $SDFVJ_BIN, else build/src/app/sdfvj)
#   --keep          keep the slices' work folder (DIR.slices / FILE.slices)
# Exit status: 0 joined; 1 a slice or the join failed (its log is printed); 2 bad usage.
set -euo pipefail

die() { echo "render_farm: $*" >&2; exit 2; }

root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${SDFVJ_BIN:-$root/build/src/app/sdfvj}"
slices=4 jobs="" out="" video="" take="" keep=0
sshlogins=() pass=()
while [ $# -gt 0 ]; do
  case "$1" in
    --slices) slices="${2:?--slices needs N}"; shift 2 ;;
    --jobs) jobs="${2:?--jobs needs J}"; shift 2 ;;
    --sshlogin|-S) sshlogins+=("${2:?--sshlogin needs a host list}"); shift 2 ;;
    --out) out="${2:?--out needs a folder}"; shift 2 ;;
    --video) video="${2:?--video needs a file}"; shift 2 ;;
    --bin) bin="${2:?--bin needs a path}"; shift 2 ;;
    --keep) keep=1; shift ;;
    --frame-range|--count-frames) die "$1 is the farm's to set: it gives every slice its own range" ;;
    --) shift; pass+=("$@"); break ;;
    *.mid|*.midi) [ -z "$take" ] || die "two takes: $take and $1, expected one"; take="$1"; shift ;;
    *) pass+=("$1"); shift ;;
  esac
done
[[ "$slices" =~ ^[1-9][0-9]*$ ]] || die "--slices $slices: expected a whole number >= 1"
[ -z "$jobs" ] || [[ "$jobs" =~ ^[1-9][0-9]*$ ]] || die "--jobs $jobs: expected a whole number >= 1"
[ -z "$out" ] || [ -z "$video" ] || die "--out and --video: expected one of them"
[ -n "$out$video" ] || out="out/farm"
[ -x "$bin" ] || die "no sdfvj at $bin (build it, or give --bin / SDFVJ_BIN)"
command -v parallel >/dev/null || die "needs GNU parallel (apt-get install parallel; scripts/setup.sh installs it)"
[ -z "$video" ] || command -v ffmpeg >/dev/null || die "--video needs ffmpeg (apt-get install ffmpeg)"
[ -z "$take" ] || pass=(--replay "$take" "${pass[@]}")

# The whole render's length, from the same options (no GL).
total="$("$bin" render "${pass[@]}" --count-frames)" || die "sdfvj render ${pass[*]} --count-frames failed (above)"
[[ "$total" =~ ^[0-9]+$ ]] || die "sdfvj render --count-frames printed '$total', expected a frame count"
[ "$slices" -le "$total" ] || slices="$total"

target="${video:-$out}"
work="$target.slices"
rm -rf "$work"
mkdir -p "$work"
work="$(cd "$work" && pwd)"   # absolute: remote hosts start in their home folder

# One command line per slice, quoted for the shell parallel runs it in (here or over ssh).
# Slice k gets frames [k*total/N, (k+1)*total/N): sizes differ by one frame at most.
jobfile="$work/jobs.txt"
: > "$jobfile"
for ((k = 0; k < slices; ++k)); do
  a=$((k * total / slices)); b=$(((k + 1) * total / slices - 1))
  if [ -n "$video" ]; then dest=(--video "$work/segment_$k.mp4"); else dest=(--out "$work/slice_$k"); fi
  printf '%q ' "$bin" render "${pass[@]}" --quiet --frame-range "$a:$b" "${dest[@]}" >> "$jobfile"
  printf '> %q 2>&1\n' "$work/slice_$k.log" >> "$jobfile"
done

popts=(--halt now,fail=1 --joblog "$work/joblog.txt")
if [ ${#sshlogins[@]} -gt 0 ]; then
  for s in "${sshlogins[@]}"; do popts+=(--sshlogin "$s"); done
  popts+=(-j "${jobs:-1}")
else
  popts+=(-j "${jobs:-$slices}")
fi
echo "render_farm: $total frames in $slices slices -> $target" >&2
if ! parallel "${popts[@]}" < "$jobfile"; then
  for log in "$work"/slice_*.log; do [ -s "$log" ] && { echo "--- $log" >&2; cat "$log" >&2; }; done
  echo "render_farm: a slice failed (logs above, jobs in $work/joblog.txt); nothing joined" >&2
  exit 1
fi

if [ -n "$video" ]; then
  : > "$work/concat.txt"
  for ((k = 0; k < slices; ++k)); do printf "file '%s'\n" "$work/segment_$k.mp4" >> "$work/concat.txt"; done
  mkdir -p "$(dirname "$video")"
  if ! ffmpeg -hide_banner -loglevel error -y -f concat -safe 0 -i "$work/concat.txt" -c copy "file:$video"; then
    echo "render_farm: ffmpeg could not join the segments in $work; expected $video" >&2
    exit 1
  fi
else
  mkdir -p "$out"
  missing=0
  for ((i = 0; i < total; ++i)); do
    name=$(printf 'frame_%05d.png' "$i")
    found=("$work"/slice_*/"$name")
    if [ ! -e "${found[0]}" ]; then missing=$((missing + 1)); continue; fi
    mv -f "${found[0]}" "$out/$name"
  done
  if [ "$missing" -gt 0 ]; then
    echo "render_farm: $missing of $total frames missing after the slices ran, expected frame_00000..$(printf '%05d' $((total - 1))).png" >&2
    exit 1
  fi
fi
[ "$keep" -eq 1 ] || rm -rf "$work"
echo "render_farm: joined $total frames into $target" >&2
