#!/usr/bin/env bash
# GPU-machine runs in one command each.
#
#   scripts/gpu.sh prepare        here: build the headless renderer (EGL + libepoxy only) into
#                                 .devbuild/ and fetch the GL loader .debs into .gl/ (both ignored)
#   scripts/gpu.sh remote ARGS..  there (the device tool runs it in the repo root, carrying .gl and
#                                 .devbuild): unpack the loaders, point EGL at NVIDIA's vendor file,
#                                 run `sdfvj-headless ARGS..` and leave its output in $OUT
#   scripts/gpu.sh prepare-ab REV here: .devbuild/ab/, every scene now and as of REV (NAME_before)
#   scripts/gpu.sh prepare-rev REV here: .devbuild/rev/, shaders/ presets/ mappings/ as of REV (`measure loops`)
#   scripts/gpu.sh prepare-roots  here: .devbuild/revs/NAME, trees of shaders as of a commit plus a patch
#                                 (ROOTS="NAME=REV+PATCH ..."), each scene with and without QUAD_SHADE
#                                 (`measure roots`: the show drawn by each tree in turn)
#   scripts/gpu.sh measure PART   there: the figures docs/ quotes, into $OUT (a part per call: the
#                                 timeouts of several add up past one 600 s call). Each part's comment
#                                 below says what it measures. Issue 12 (reloads): reload, retune,
#                                 adopt, toggle, launch, fresh, handover, stage, s16 (render processes),
#                                 spirv (GLSL against SPIR-V builds), compile (where a build's
#                                 time goes: `bench compile`'s cuts, and the one-site renderer's frames),
#                                 onesite (the one-site renderer as a save's quick tier), swap (a new
#                                 server's first frame asked for with its answer or after its import), split
#                                 (the quick tier's build: field against renderer), s43 (swap + split + knobs
#                                 of the quick tier's link, one call), ahead (effect pad hits through
#                                 render processes, cold against built ahead), eval (a save drawn
#                                 by the scene's evaluator program against the quick tier).
#                                 Issue 13 (frames): frames, field, cone, lit, ab (against `prepare-ab
#                                 REV`), loops (and compiles, against `prepare-rev REV`), ssaa, wg,
#                                 overrelax, s13 (needs `AB_RENDER_OK=1 prepare-ab REV`), final13, s22 (normals),
#                                 s15b, s15c, define (DEFINE="NAME VALUE": every scene against a copy
#                                 with it, frames and compiles), copies (VARIANTS="SCENE/SUFFIX/
#                                 NAME=VALUE,..." copies, one interleaved run), scales (the budget's
#                                 render-scale rows), s27 (scales + session 27's copies, one call),
#                                 s29 (CONE_PAST_FLOOR, CONE_MIRROR, MANDELBULB_FEW_SFU: one call),
#                                 s29b (the defaults: frames, the 7680x4320 show, scales);
#                                 post (issue 12: a post effect's save, `bench post`), s31 (post + s29b);
#                                 resize (a render-scale change's frame, `bench resize`), s33 (resize + post;
#                                 many files: OUT=/tmp/o ... measure s33, then tar /tmp/o into $OUT);
#                                 postservers (issue 12: a post effect's save drawn by the render
#                                 processes, `bench reload --post`, without and with a standby;
#                                 many files as s33);
#                                 qrefl (issue 13: the 7680x4320 show with quad_reflections, its
#                                 time (qrefl_time) and its image (qrefl_image)); qrefl2 (the
#                                 pixels that trace their own bounce: QREFL2_VARIANTS copies);
#                                 pending = adopt + field + cone.
#
# Example (device tool): carry [".gl", ".devbuild"], command
#   bash scripts/gpu.sh remote bench --markdown $OUT/bench.md
set -euo pipefail
cd "$(dirname "$0")/.."
# variant ROOT SCENE SUFFIX "NAME VALUE"...: ROOT/shaders/scenes/SCENE_SUFFIX.glsl, the scene (from
# VARIANT_SRC, ./shaders by default) renamed, each #define right after its header (a scene copy for
# an interleaved A/B through SDFVJ_ROOT_OVERRIDE)
variant() { local root=$1 s=$2 v=$3 d; shift 3
  sed -e "s/\"NAME\": \"$s\"/\"NAME\": \"${s}_$v\"/" "${VARIANT_SRC:-shaders}/scenes/$s.glsl" > "$root/shaders/scenes/${s}_$v.glsl"
  for d in "$@"; do sed -i "/^}\*\//a #define $d" "$root/shaders/scenes/${s}_$v.glsl"; done; }
case "${1:-}" in
  prepare)
    mkdir -p .gl /tmp/amd64/partial .devbuild/lib
    o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
    if ! ls .gl/libegl1_*.deb >/dev/null 2>&1; then
      apt-get $o update -qq
      (cd .gl && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
    fi
    # `measure spirv`: Debian's glslangValidator (one static binary) beside sdfvj-headless
    if command -v glslangValidator >/dev/null; then cp "$(command -v glslangValidator)" .devbuild/; fi
    if ! ls .devbuild/lib/libepoxy.so.0* >/dev/null 2>&1; then
      (cd /tmp && apt-get download libepoxy0 && dpkg -x libepoxy0_*.deb /tmp/epoxy-x)
      cp -a /tmp/epoxy-x/usr/lib/x86_64-linux-gnu/libepoxy.so.0* .devbuild/lib/
    fi
    # The build folder stays outside .devbuild (not carried), so the next prepare rebuilds only what changed.
    b="${DEVBUILD_CMAKE:-/tmp/sdfvj-devbuild-cmake}"
    rm -rf .devbuild/cmake
    cmake -S . -B "$b" -DSDFVJ_HEADLESS_ONLY=ON -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$b" -j"$(nproc)" --target sdfvj-headless
    cp "$b/src/app/sdfvj-headless" .devbuild/
    du -sh .gl .devbuild
    ;;
  prepare-ab)
    # here: .devbuild/ab/ = shaders/, presets/, mappings/ as now, plus every scene as of git
    # revision $2 under the name NAME_before (its NAME, and its includes of every lib/ file
    # that changed since, renamed to the old copies lib/X_before.glsl), for `measure ab`.
    rev="${2:?usage: scripts/gpu.sh prepare-ab REV}"
    ab=.devbuild/ab; rm -rf "$ab"; mkdir -p "$ab"; cp -r shaders presets mappings "$ab/"
    changed=$(git diff --name-only "$rev" -- shaders/lib | sed 's#^shaders/lib/##; s#\.glsl$##')
    # AB_RENDER_OK=1: shaders/render changed in a way the old scenes never reach (a new #if branch)
    if [ "${AB_RENDER_OK:-0}" != 1 ] && ! git diff --quiet "$rev" -- shaders/render; then
      echo "shaders/render changed since $rev: not per scene (AB_RENDER_OK=1 if the old scenes cannot reach the change)" >&2; exit 1
    fi
    # a lib that includes a changed one is old too (field_scene.glsl includes field.glsl)
    for _ in 1 2 3; do
      for f in shaders/lib/*.glsl; do
        l=$(basename "$f" .glsl)
        for c in $changed; do git show "$rev:$f" 2>/dev/null | grep -q "\"lib/$c.glsl\"" && changed="$changed $l"; done
      done
      changed=$(echo $changed | tr ' ' '\n' | sort -u)
    done
    rename() { local e=(-e ''); for l in $changed; do e+=(-e "s#\"lib/$l.glsl\"#\"lib/${l}_before.glsl\"#"); done; sed "${e[@]}"; }
    for l in $changed; do git show "$rev:shaders/lib/$l.glsl" | rename > "$ab/shaders/lib/${l}_before.glsl"; done
    for f in shaders/scenes/*.glsl; do
      n=$(basename "$f" .glsl)
      git show "$rev:$f" | rename | sed "s/\"NAME\": \"$n\"/\"NAME\": \"${n}_before\"/" > "$ab/shaders/scenes/${n}_before.glsl"
    done
    echo "changed libs: ${changed:-none}"
    ;;
  prepare-roots)
    # here: .devbuild/revs/NAME for each ROOTS entry NAME=REV or NAME=REV+PATCH (shaders, presets and
    # mappings as of REV, with docs/performance/nvidia-h100-s50/variants/PATCH.patch applied), each
    # scene also as SCENE_qs0 and SCENE_qs7 (QUAD_SHADE 0 / 7; a no-op before session 49), for
    # `measure roots`. Session 50: the show with quad_reflections got slower with session 49's code
    # (character 2.55 -> 5.08 ms with QUAD_SHADE 0 on an H100, the same picture); the defaults are the
    # variants that would tell which change: session 48's shaders, with only the texel's float depth,
    # now, and now with quadFind returning, the bounce's look-up inline, and that plus the old shading.
    roots="${ROOTS:-s48=07e4006 s48depth=07e4006+s48_float_depth now=HEAD return=HEAD+return inline=HEAD+inline oldshade=HEAD+inline_oldshade}"
    rm -rf .devbuild/revs && mkdir -p .devbuild/revs
    for e in $roots; do
      name="${e%%=*}"; spec="${e#*=}"; rev="${spec%%+*}"; patchName=""; [ "$spec" != "$rev" ] && patchName="${spec#*+}"
      d=.devbuild/revs/$name; mkdir -p "$d"; git archive "$rev" shaders presets mappings | tar x -C "$d"
      [ -n "$patchName" ] && (cd "$d" && patch -s -p1 < "$OLDPWD/docs/performance/nvidia-h100-s50/variants/$patchName.patch")
      for f in "$d"/shaders/scenes/*.glsl; do
        for q in 0 7; do VARIANT_SRC="$d/shaders" variant "$d" "$(basename "$f" .glsl)" "qs$q" "QUAD_SHADE $q"; done
      done
      echo ".devbuild/revs/$name: $rev${patchName:+ + $patchName}"
    done
    ;;
  prepare-rev)
    rev="${2:?usage: scripts/gpu.sh prepare-rev REV}"
    rm -rf .devbuild/rev && mkdir -p .devbuild/rev && git archive "$rev" shaders presets mappings | tar x -C .devbuild/rev
    echo ".devbuild/rev: shaders, presets, mappings as of $(git rev-parse --short "$rev")"
    ;;
  measure)
    # `measure reload` (issue 12), `measure frames` and `measure field` (issue 13) each fit one
    # device call; `measure` alone runs them all.
    out="${OUT:?set OUT to the folder for the results}"
    part="${2:-all}"
    if [ "$part" = pending ]; then bash "$0" measure adopt; bash "$0" measure field; bash "$0" measure cone; exit; fi
    run() { bash "$0" remote "$@"; }
    all="midi primitives character mandelbulb field50 field150"   # every shipped scene
    if [ "$part" = reload ] || [ "$part" = all ]; then
    for s in midi character; do
      timeout 100 bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute --rounds 3 > "$out/reload_$s.txt" 2>&1 || true
    done
    # The compile process (issue 12: `sdfvj compile-server` compiles, the render thread loads its
    # binary), the same with the loader (`warm`: a shared-context thread loads the binary and uses
    # it once before the hand-over) and the driver's parallel compile, rounds interleaved in one run.
    timeout 75 bash "$0" remote bench reload --scene midi --size 1920x1080 --path compute --modes process,warm,driver \
      --rounds 3 > "$out/reload_midi_process.txt" 2>&1 || true
    timeout 120 bash "$0" remote bench reload --scene character --size 1920x1080 --path compute --modes process,warm,driver \
      --rounds 3 > "$out/reload_character_process.txt" 2>&1 || true
    # Reload (issue 12): the rows above have the drivers' disk caches off and a new program every
    # save, tiered on NVIDIA; below: without the quick tier, the warm-cache row, and a second
    # launch served by the program cache (first launch compiles into an empty cache folder).
    for s in midi character; do
      timeout 80 bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute --modes driver --rounds 3 \
        --tiered off > "$out/reload_${s}_untiered.txt" 2>&1 || true
      timeout 40 bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute --modes driver --rounds 3 \
        --warm-cache > "$out/reload_${s}_warm.txt" 2>&1 || true
      rm -rf /tmp/sdfvj-launch-cache
      for launch in first second; do
        XDG_CACHE_HOME=/tmp/sdfvj-launch-cache timeout 60 bash "$0" remote bench reload --scene $s --size 1920x1080 \
          --path compute --first-frame > "$out/launch_${s}_$launch.txt" 2>&1 || true
      done
      # Second launch again, the cached binary loaded and used once on the loader thread first.
      XDG_CACHE_HOME=/tmp/sdfvj-launch-cache timeout 60 bash "$0" remote bench reload --scene $s --size 1920x1080 \
        --path compute --first-frame --modes warm > "$out/launch_${s}_second_warm.txt" 2>&1 || true
    done
    fi
    if [ "$part" = frames ] || [ "$part" = all ]; then
    timeout 100 bash "$0" remote bench --scenes midi primitives character mandelbulb field50 field150 --sizes 3840x2160 --tests full --paths compute \
      --frames 20 --warmup 5 --markdown "$out/bench_4k.md" --csv "$out/bench_4k.csv" > "$out/bench_4k.txt" 2>&1 || true
    timeout 200 bash "$0" remote bench accuracy --scene all --size 1920x1080 --ref-size 960x540 --path compute --frames 15 --warmup 5 \
      --out "$out/accuracy" --markdown "$out/accuracy.md" --csv "$out/accuracy_bench.csv" > "$out/accuracy.txt" 2>&1 || true
    timeout 60 bash "$0" remote bench effects --scene midi --size 1920x1080 --path compute --csv "$out/effects_midi.csv" > "$out/effects_midi.txt" 2>&1 || true
    # Scaling (issue 13), every cell interleaved in one run: cost against resolution for every
    # scene, against primitive count (midi 5, character 15, field50, field150), and the effects
    # table of the 150-shape field; CSV for docs/performance/.
    timeout 150 bash "$0" remote bench --sizes 640x480 1280x720 1920x1080 3840x2160 7680x4320 --tests full --paths compute \
      --frames 10 --warmup 3 --markdown "$out/scaling_resolution.md" --csv "$out/scaling_resolution.csv" \
      > "$out/scaling_resolution.txt" 2>&1 || true
    timeout 100 bash "$0" remote bench --scenes midi character field50 field150 --sizes 640x360 1920x1080 3840x2160 \
      --tests full none --paths compute --frames 15 --warmup 3 --markdown "$out/scaling_primitives.md" \
      --csv "$out/scaling_primitives.csv" > "$out/scaling_primitives.txt" 2>&1 || true
    timeout 60 bash "$0" remote bench effects --scene field150 --size 1920x1080 --path compute --csv "$out/effects_field150.csv" \
      > "$out/effects_field150.txt" 2>&1 || true
    fi
    if [ "$part" = adopt ] || [ "$part" = all ]; then
    # Issue 12's lever: NVIDIA finishes a loaded program once per context, so the program is drawn on
    # the context whose thread loaded and used it (adopt-process; adopt: compiled on that thread),
    # presented on the render context; against the compile process's hand-over, untiered, interleaved.
    for s in midi character; do
      timeout 120 bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute --modes process,adopt-process,adopt \
        --tiered off --rounds 3 > "$out/reload_${s}_adopt.txt" 2>&1 || true
    done
    fi
    if [ "$part" = cone ] || [ "$part" = all ]; then
    # The compute path's cone pre-pass (issue 13) against every primary ray from the eye: the tiny
    # sweep's `default` and `no cone pre-pass` rows are timed interleaved, with their geometry error.
    for size in 1920x1080 3840x2160; do
      timeout 140 bash "$0" remote bench accuracy --scene all --size $size --ref-size 960x540 --path compute --sweep tiny \
        --frames 15 --warmup 5 --out "$out/cone_$size" --csv "$out/cone_$size.csv" > "$out/cone_$size.txt" 2>&1 || true
    done
    fi
    if [ "$part" = retune ] || [ "$part" = all ]; then
    # Issue 12: a save that only retunes a number (--edit retune): the literal tier (the scene's
    # literals as uniforms, built and used once before the saves) shows it, the optimized program
    # follows; against the structural edit (--edit nudge) of the same mode and tiers, in one call.
    for s in midi character; do
      for e in retune nudge; do
        timeout 90 bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute --modes process --rounds 3 \
          --edit $e > "$out/reload_${s}_$e.txt" 2>&1 || true
      done
    done
    # What the literal tier costs per frame while it is on screen (NAME:literals), interleaved with NAME.
    timeout 90 bash "$0" remote bench --scenes midi midi:literals primitives primitives:literals character character:literals \
      mandelbulb mandelbulb:literals --sizes 1920x1080 3840x2160 --tests full --paths compute --frames 15 --warmup 3 \
      --markdown "$out/literal_tier_frames.md" --csv "$out/literal_tier_frames.csv" > "$out/literal_tier_frames.txt" 2>&1 || true
    fi
    if [ "$part" = variants ]; then
    # Issue 13 experiments, whole bench runs alternating (base, fastmath, setup, twice): NVIDIA's
    # `#pragma optionNV(fastmath on)` / `(fastprecision on)`; character with its skeleton (sin/cos of
    # the walk, per frame) computed once per invocation (sceneSetup() from main) instead of per map().
    # $SETUP_SCENE: the character with the setup split out (made here by the caller).
    base="$(mktemp -d)"; fast="$(mktemp -d)"; setup="$(mktemp -d)"
    for d in "$base" "$fast" "$setup"; do cp -r shaders presets mappings "$d/"; done
    sed -i '1i #pragma optionNV(fastmath on)\n#pragma optionNV(fastprecision on)' "$fast/shaders/render/uniforms.glsl"
    cp "${SETUP_SCENE:?}" "$setup/shaders/scenes/character.glsl"
    sed -i 's/^void main() {$/void main() {\n#if defined(SCENE_SETUP)\n    sceneSetup();\n#endif/' "$setup/shaders/render/main_comp.glsl"
    for i in 1 2; do
      for v in base fast setup; do
        eval root=\$$v
        sc="midi primitives character mandelbulb"; [ $v = setup ] && sc=character
        SDFVJ_ROOT_OVERRIDE="$root" timeout 70 bash "$0" remote bench --scenes $sc --sizes 1920x1080 3840x2160 --tests full \
          --paths compute --frames 15 --warmup 3 --csv "$out/var_${v}_$i.csv" > "$out/var_${v}_$i.txt" 2>&1 || true
      done
    done
    fi
    if [ "$part" = ab ]; then
    # Issue 13, session 9: cheaper map() calls (mandelbulb's power 8 without trigonometry, the
    # fields' poses by angle addition) against the scenes as of a revision, in one interleaved
    # run (.devbuild/ab, made here by `scripts/gpu.sh prepare-ab REV`); then issue 13's heaviest
    # target, the `show` lighting (soft shadows, AO, PBR, one reflection bounce) at 4K and at
    # 7680x4320 (4K with 4 samples a pixel), against `full`; then the changed scenes' accuracy.
    # $AB_SCENES: the scenes compared (default: those session 9 changed); $AB_SHOW: also at 8K show.
    ab=""; for s in ${AB_SCENES:-mandelbulb field50 field150}; do ab="$ab $s ${s}_before"; done
    case " $ab " in *" character "*) ;; *) ab="character $ab" ;; esac   # the reference row of every table
    SDFVJ_ROOT_OVERRIDE="$PWD/.devbuild/ab" timeout 150 bash "$0" remote bench --scenes $ab \
      --sizes 1920x1080 3840x2160 --tests full --paths compute --frames 15 \
      --warmup 3 --markdown "$out/ab.md" --csv "$out/ab.csv" > "$out/ab.txt" 2>&1 || true
    show=""; for s in ${AB_SHOW:-}; do show="$show $s ${s}_before"; done
    [ -z "$show" ] || SDFVJ_ROOT_OVERRIDE="$PWD/.devbuild/ab" timeout 150 bash "$0" remote bench --scenes $show \
      --sizes 7680x4320 --tests show --paths compute --frames 10 --warmup 3 \
      --markdown "$out/ab_show.md" --csv "$out/ab_show.csv" > "$out/ab_show.txt" 2>&1 || true
    [ -n "${AB_SCENES:-}" ] || timeout 200 bash "$0" remote bench --sizes 3840x2160 7680x4320 --tests full show --paths compute \
      --frames 10 --warmup 3 --markdown "$out/show.md" --csv "$out/show.csv" > "$out/show.txt" 2>&1 || true
    acc=$(echo ${AB_SCENES:-mandelbulb field150} | tr ' ' ,)
    timeout 150 bash "$0" remote bench accuracy --scene "$acc" --size 1920x1080 --ref-size 960x540 --path compute \
      --frames 15 --warmup 5 --out "$out/accuracy_ab" --csv "$out/accuracy_ab.csv" > "$out/accuracy_ab.txt" 2>&1 || true
    fi
    if [ "$part" = ssaa ]; then
    # Issue 13's 4x supersampled 4K: the show lighting at 7680x4320 (every sample shaded, then a
    # downsample not timed) against 4 samples a pixel at 3840x2160, each sample shaded
    # (show_ssaa_exact) or each surface the samples see shaded once (show_ssaa), one interleaved
    # run (its 7680x4320 rows of show_ssaa* are 16 samples a 4K pixel, there only to interleave).
    timeout 300 bash "$0" remote bench --scenes $all --sizes 3840x2160 7680x4320 --tests show show_ssaa show_ssaa_exact \
      --paths compute --frames 8 --warmup 3 --markdown "$out/ssaa.md" --csv "$out/ssaa.csv" > "$out/ssaa.txt" 2>&1 || true
    fi
    if [ "$part" = wg ]; then
    # Issue 13: the compute path's work-group shape (main_comp.glsl WORKGROUP_X/Y, 8x8 unless the
    # scene declares another), scene copies that define another shape (NAME_wgXxY), one interleaved
    # run at 1080p and 4K, then the show lighting at 7680x4320 for the scenes given in $WG_SHOW.
    wg="$(mktemp -d)"; cp -r shaders presets mappings "$wg/"; sc=""; show=""
    for s in ${WG_SCENES:-$all}; do
      sc="$sc $s"
      case " ${WG_SHOW:-} " in *" $s "*) show="$show $s" ;; esac
      for v in ${WG_SHAPES:-8x8 8x4 16x8 8x16 16x16}; do
        variant "$wg" $s wg$v "WORKGROUP_X ${v%x*}" "WORKGROUP_Y ${v#*x}"
        sc="$sc ${s}_wg$v"
        case " ${WG_SHOW:-} " in *" $s "*) show="$show ${s}_wg$v" ;; esac
      done
    done
    SDFVJ_ROOT_OVERRIDE="$wg" timeout 300 bash "$0" remote bench --scenes $sc --sizes 1920x1080 3840x2160 --tests full \
      --paths compute --frames 12 --warmup 3 --markdown "$out/wg.md" --csv "$out/wg.csv" > "$out/wg.txt" 2>&1 || true
    [ -z "$show" ] || SDFVJ_ROOT_OVERRIDE="$wg" timeout 200 bash "$0" remote bench --scenes $show --sizes 7680x4320 --tests show \
      --paths compute --frames 6 --warmup 2 --markdown "$out/wg_show.md" --csv "$out/wg_show.csv" > "$out/wg_show.txt" 2>&1 || true
    rm -rf "$wg"
    fi
    if [ "$part" = fresh ]; then
    # Issue 12: reloads with the drivers' disk caches on but empty at the start (`--driver-cache
    # fresh`, the folder shared with the compile process), every save a program no cache has seen:
    # does the compile process's priming use leave NVIDIA's finished code where the show finds it?
    # (Session 12: no, the first draw of the loaded binary still took 175-245 ms; nor with the
    # compile server making a new context after each job, leaving out its priming use, or running
    # each job in a child process that exits: commit 41045dc, docs/performance.md.)
    for s in midi character; do
      timeout 150 bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute --modes process,driver \
        --driver-cache fresh --rounds 3 > "$out/reload_${s}_fresh.txt" 2>&1 || true
      timeout 150 bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute --modes process \
        --driver-cache off --rounds 3 > "$out/reload_${s}_off.txt" 2>&1 || true
    done
    fi
    if [ "$part" = handover ]; then
    # Issue 12, session 14: the compile process's reply as a sign only (process-source), the
    # render thread compiling the same text for NVIDIA's disk cache (shared with the server) to
    # serve, against loading the server's binary (process) and the driver alone; caches on but
    # empty at the start, every save a new program, tiered as `live` is, rounds interleaved.
    for s in midi character; do
      timeout 200 bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute \
        --modes process,process-source,driver --driver-cache fresh --rounds 3 > "$out/reload_${s}_handover.txt" 2>&1 || true
      grep -A6 'modes side by side' "$out/reload_${s}_handover.txt" || tail -5 "$out/reload_${s}_handover.txt"
      grep -h 'driver disk cache' "$out/reload_${s}_handover.txt" || true
    done
    fi
    if [ "$part" = stage ]; then
    # Issue 12, session 14: each program drawn by a stage (the thread and shared context that
    # loaded the compile process's binary, used it once and drew its first frame while the stage
    # on screen went on drawing) against the process mode (binary loaded and first drawn on the
    # render thread) and warm (a loader thread uses it first, the render thread draws it): does a
    # first use on one thread stall the others? Driver caches off, untiered, rounds interleaved.
    for s in ${STAGE_SCENES:-midi character}; do
      timeout 250 bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute --modes process,stage,warm \
        --tiered off --driver-cache ${STAGE_CACHE:-off} --rounds 3 > "$out/reload_${s}_stage.txt" 2>&1 || true
      grep -h -A1 'median:' "$out/reload_${s}_stage.txt" | cut -c1-240 || true
      grep -h -A3 '^| round' "$out/reload_${s}_stage.txt" | cut -c1-200 || true
    done
    fi
    if [ "$part" = s16 ]; then
    # Session 16 (issue 12): each program compiled, used and drawn by a render process of its own, its
    # frames handed over on the GPU (render-process; -sync: every frame a round trip) or by shared memory (-shm), against the compile
    # process (binary loaded and first drawn here); caches off, untiered, rounds interleaved. (`sdfvj
    # info` there, session 15's part of this name, is in docs/performance/nvidia-h200/s15/.)
    for s in ${S16_SCENES:-midi character}; do
      # S16_TIERED=on S16_MODES=process,render-process: the quick tier too (in a second server)
      # S16_TAG=NAME: the file's name ends _NAME (a second run with another environment, say
      # SDFVJ_CONTEXT_PRIORITY=high for the show's own context, keeps the first's file)
      f="$out/reload_${s}_render_process${S16_TIERED:+_tiered_$S16_TIERED}${S16_TAG:+_$S16_TAG}.txt"
      timeout ${S16_TIMEOUT:-200} bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute --tiered ${S16_TIERED:-off} \
        --modes ${S16_MODES:-process,render-process,render-process-sync,render-process-shm} --driver-cache off --rounds ${S16_ROUNDS:-3} > "$f" 2>&1 || true
      grep -h -A6 'modes side by side' "$f" || tail -5 "$f"
      grep -h -E '^render processes|^longest frame before|^median' "$f" | cut -c1-300 || true
    done
    fi
    if [ "$part" = ahead ]; then
    # Session 18 (issue 12): effect pad hits as live --render-process takes them, each hit's variant
    # compiled by its spare against built ahead into the program cache by a server of their own
    # (ServerShow::BuildAhead), rounds interleaved; the drivers' disk caches off, then on in empty
    # folders of each way's own (as a performer's machine has them).
    for s in ${AHEAD_SCENES:-midi character}; do
      for c in ${AHEAD_CACHES:-off fresh}; do
        timeout 240 bash "$0" remote bench reload --edit toggle --modes render-process --scene $s --size 1920x1080 --path compute \
          --rounds ${AHEAD_ROUNDS:-6} --driver-cache $c > "$out/ahead_${s}_$c.txt" 2>&1 || true
        grep -h -E '^\| render-process|never reached' "$out/ahead_${s}_$c.txt" | cut -c1-300 || tail -5 "$out/ahead_${s}_$c.txt"
      done
    done
    fi
    if [ "$part" = spirv ]; then
    # Session 17 (issue 12): each scene's compute program built from GLSL and from SPIR-V (prepare
    # copies Debian's glslangValidator beside the binary), interleaved, caches off, to its first use.
    for s in ${SPIRV_SCENES:-midi character}; do
      timeout 200 bash "$0" remote bench spirv --scene $s --rounds ${SPIRV_ROUNDS:-5} > "$out/spirv_$s.txt" 2>&1 || true
      grep -h -E '^\| [0-9]|^medians|takes no SPIR-V|failed' "$out/spirv_$s.txt" | cut -c1-300 || tail -5 "$out/spirv_$s.txt"
    done
    fi
    if [ "$part" = compile ]; then
    # Session 40 (issue 12): where the driver's build time of a scene's program goes (`bench compile`):
    # the quick tier and the optimized program, the renderer alone (map() a sphere), lighting cut
    # away; cuts interleaved, caches off, each build to its first use. COMPILE_CUTS replaces the cuts.
    for s in ${COMPILE_SCENES:-midi character}; do
      # shellcheck disable=SC2086
      timeout 280 bash "$0" remote bench compile --scene $s --rounds ${COMPILE_ROUNDS:-5} --csv "$out/compile_$s.csv" \
        --cuts ${COMPILE_CUTS:-quick optimized quick@sphere optimized@sphere quick/none quick/-soft_shadows quick/-ao quick+ONE_SITE=1 optimized+ONE_SITE=1 quick@sphere+ONE_SITE=1} \
        > "$out/compile_$s.txt" 2>&1 || true
      sed -n '/^## medians/,$p' "$out/compile_$s.txt" | cut -c1-300; tail -2 "$out/compile_$s.txt"
    done
    # The one-site renderer's frames (render/one_site.glsl, ONE_SITE 1) against each scene as shipped.
    root=/tmp/sdfvj-onesite; rm -rf "$root"; mkdir -p "$root"; cp -r shaders presets mappings "$root/"
    names=""
    for s in ${COMPILE_SCENES:-midi character}; do variant "$root" "$s" os "ONE_SITE 1"; names="$names $s ${s}_os"; done
    # shellcheck disable=SC2086
    SDFVJ_ROOT_OVERRIDE=$root timeout 250 bash "$0" remote bench --scenes $names --sizes 1920x1080 3840x2160 --tests full \
      --paths compute --frames 10 --warmup 3 --markdown "$out/frames_onesite.md" > "$out/frames_onesite.txt" 2>&1 || true
    grep -E '^\| |drift' "$out/frames_onesite.txt" | head -40
    fi
    if [ "$part" = onesite ]; then
    # Session 40 (issue 12): the one-site renderer (render/one_site.glsl) as the quick tier of a
    # save (SDFVJ_QUICK_ONE_SITE=1 in the render servers' environment) against `inline none` alone:
    # save -> quick tier, its frames, the optimized program after; rounds interleaved, caches off.
    # First its builds with NVIDIA's hints or none (bench compile; ONESITE_COMPILE=0 skips them), then
    # saves: the quick tier as shipped (one site, `unroll none`), one site with no hint, and the
    # quick tier before session 40 (SDFVJ_QUICK_ONE_SITE=0: the usual renderer, `inline none`).
    [ "${ONESITE_COMPILE:-1}" = 1 ] && for s in ${ONESITE_SCENES:-midi character}; do
      timeout 150 bash "$0" remote bench compile --scene $s --rounds 3 --csv "$out/compile_onesite_$s.csv" --cuts quick \
        optimized+ONE_SITE=1 'optimized+ONE_SITE=1!unroll-none' quick+ONE_SITE=1 > "$out/compile_onesite_$s.txt" 2>&1 || true
      sed -n '/^## medians/,$p' "$out/compile_onesite_$s.txt" | cut -c1-300
    done
    for s in ${ONESITE_SCENES:-midi character}; do
      timeout 280 bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute --tiered on --rounds ${ONESITE_ROUNDS:-4} \
        --modes render-process,render-process+SDFVJ_QUICK_OPTIONS=none,render-process+SDFVJ_QUICK_ONE_SITE=0 \
        > "$out/reload_onesite_$s.txt" 2>&1 || true
      grep -h -A4 'modes side by side' "$out/reload_onesite_$s.txt" | cut -c1-300 || tail -5 "$out/reload_onesite_$s.txt"
      grep -h -E '^median' "$out/reload_onesite_$s.txt" | cut -c1-300
    done
    fi
    if [ "$part" = swap ]; then
    # Session 41 (issue 12): a new render server's first frame asked for with its answer, drawn while
    # its images are imported (as shipped), against asked for once they are (before session 41:
    # render-process-first-after-import, which makes no images ahead either); session 42, as shipped: a
    # spare's images made and imported ahead and the first frame drawn with the streamed inputs, shown
    # with the answer, against session 41's (SDFVJ_SERVER_PREPARE_IMAGES=0). Structural saves, tiered,
    # caches off, rounds interleaved.
    for s in ${SWAP_SCENES:-midi character}; do
      timeout 280 bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute --tiered on --rounds ${SWAP_ROUNDS:-5} \
        --modes ${SWAP_MODES:-render-process,render-process+SDFVJ_SERVER_PREPARE_IMAGES=0,render-process-first-after-import} > "$out/reload_swap_$s.txt" 2>&1 || true
      grep -h -A4 'modes side by side' "$out/reload_swap_$s.txt" | cut -c1-300 || tail -5 "$out/reload_swap_$s.txt"
      grep -h -E '^median' "$out/reload_swap_$s.txt" | cut -c1-300
    done
    fi
    if [ "$part" = s43 ]; then
    # Session 43 (issue 12), one call: the swap (sessions 41-42 on NVIDIA), the split, then knobs that
    # might shorten the quick tier's link (a scene's own #ifndef switches, an optionNV hint, the
    # fragment path). Each step's files land in $OUT as it ends, so a call cut short keeps them.
    SWAP_ROUNDS=${SWAP_ROUNDS:-4} SWAP_SCENES=midi bash "$0" measure swap
    SPLIT_ROUNDS=${SPLIT_ROUNDS:-3} bash "$0" measure split
    knobs() {   # SCENE PATH CUTS..
      local s=$1 p=$2; shift 2
      timeout 100 bash "$0" remote bench compile --scene "$s" --path "$p" --rounds 3 --csv "$out/knobs_${s}_$p.csv" --cuts "$@" \
        > "$out/knobs_${s}_$p.txt" 2>&1 || true
      sed -n '/^## medians/,$p' "$out/knobs_${s}_$p.txt" | cut -c1-220
    }
    knobs character compute quick quick+CHARACTER_SKIP=0 quick+CHARACTER_CAPSULE_INV=0 'quick!ifcvt-none' quick+MARCH_OBJECT_STEP=0
    knobs midi compute quick 'quick!ifcvt-none' quick+OVERRELAX=0 quick+BOUNDS=0
    knobs midi fragment quick optimized
    SWAP_ROUNDS=${SWAP_ROUNDS_CHARACTER:-3} SWAP_SCENES=character bash "$0" measure swap
    fi
    if [ "$part" = eval ]; then
    # Session 44 (issue 12): a structural save drawn by the scene's evaluator program (built ahead;
    # the save translated on the CPU, no driver build) against the compile process with its quick
    # tier, rounds interleaved, caches off. The table's "frame ms on the quick tier" column is the
    # evaluator program's frame while it is on screen.
    # EVAL_RUNS: SCENE:SIZE:ROUNDS each (the 4K run: the interpreter's frame where pixels cost most).
    for run in ${EVAL_RUNS:-midi:1920x1080:5 character:1920x1080:5 midi:3840x2160:3}; do
      IFS=: read -r s size rounds <<< "$run"
      timeout 170 bash "$0" remote bench reload --scene $s --size $size --path compute --tiered on --rounds $rounds \
        --modes ${EVAL_MODES:-process,process-evaluator} > "$out/reload_eval_${s}_$size.txt" 2>&1 || true
      echo "== $s $size"
      grep -h -A4 'modes side by side' "$out/reload_eval_${s}_$size.txt" | cut -c1-300 || tail -5 "$out/reload_eval_${s}_$size.txt"
      grep -h -E '^evaluator tier|evaluator tier:|^median' "$out/reload_eval_${s}_$size.txt" | cut -c1-300
    done
    fi
    if [ "$part" = split ]; then
    # Session 42 (issue 12): where the quick tier's build goes on NVIDIA: the scene's field against the
    # renderer around it, with the scene's effects and with none (`bench compile`, caches off, cuts
    # interleaved). SPLIT_CUTS replaces the cuts.
    for s in ${SPLIT_SCENES:-midi character}; do
      # shellcheck disable=SC2086
      timeout 200 bash "$0" remote bench compile --scene $s --rounds ${SPLIT_ROUNDS:-3} --csv "$out/split_$s.csv" \
        --cuts ${SPLIT_CUTS:-quick quick@sphere quick/none quick/none@sphere optimized@sphere optimized/none@sphere} \
        > "$out/split_$s.txt" 2>&1 || true
      sed -n '/^## medians/,$p' "$out/split_$s.txt" | cut -c1-300; tail -2 "$out/split_$s.txt"
    done
    fi
    if [ "$part" = define ]; then
    # A render lever against the shaders before it: every scene (or DEFINE_SCENES) against a copy with
    # DEFINE="NAME VALUE" (_off), 1080p and 4K full lighting interleaved, and midi's and character's
    # compile (untiered; DEFINE_RELOAD=0: not).
    root="$(mktemp -d)"; cp -r shaders presets mappings "$root/"; sc=""
    for s in ${DEFINE_SCENES:-$all}; do variant "$root" $s off "${DEFINE:?DEFINE=NAME VALUE}"; sc="$sc $s ${s}_off"; done
    SDFVJ_ROOT_OVERRIDE="$root" timeout 150 bash "$0" remote bench --scenes $sc --sizes 1920x1080 3840x2160 --tests full \
      --paths compute --frames 20 --warmup 5 --markdown "$out/define_frames.md" --csv "$out/define_frames.csv" > "$out/define_frames.txt" 2>&1 || true
    cat "$out/define_frames.md" 2>/dev/null; grep -h drift "$out/define_frames.txt" || true
    [ "${DEFINE_RELOAD:-1}" = 0 ] || for s in midi character midi_off character_off; do SDFVJ_ROOT_OVERRIDE="$root" timeout 60 bash "$0" remote bench reload --scene $s \
      --size 1920x1080 --path compute --modes driver --tiered off --rounds 3 > "$out/define_reload_$s.txt" 2>&1 || true; { grep -h "^median" "$out/define_reload_$s.txt" || true; } | cut -c1-200; done
    rm -rf "$root"
    fi
    if [ "$part" = s27 ]; then
    # Session 27's pending GPU figures in one call (no GPU was lent then): the budget's render-scale
    # rows; mandelbulb's MANDELBULB_FEW_SFU (off) against as shipped; the knobs as literals (the most
    # folding a per-frame setup could buy) for mandelbulb and field50; full lighting at 1080p and 4K,
    # then the 7680x4320 show.
    v="mandelbulb/few/MANDELBULB_FEW_SFU=1 mandelbulb/lit/u_power=8.0f,u_iterations=8.0f,u_hue=0.5f,u_colorSpread=0.8f,u_spin=0.15f"
    v="$v field50/lit/u_blend=0.3f,u_size=0.95f,u_wave=0.5f,u_speed=1.0f,u_spin=0.6f,u_floorBlend=0.1f"
    mkdir -p "$out/scales" "$out/frames" "$out/show"
    OUT="$out/scales" bash "$0" measure scales
    OUT="$out/frames" VARIANTS="$v" VARIANT_TIMEOUT=200 bash "$0" measure copies
    OUT="$out/show" VARIANTS="$v" VARIANT_SIZES=7680x4320 VARIANT_TESTS=show VARIANT_TIMEOUT=150 bash "$0" measure copies
    fi
    if [ "$part" = s29 ]; then
    # Session 29 (issue 13) in one call: the cone past the floor and its mirror images (march.glsl
    # CONE_PAST_FLOOR, CONE_MIRROR, both on) against copies with the mirror off (_nm) and with both
    # off (_old, the cone as before), in the show at 3840x2160 and 7680x4320, beside mandelbulb's
    # MANDELBULB_FEW_SFU (_few: on); then the same copies (less _nm: no reflection, no mirror) in full
    # lighting at 1080p and 4K. (The budget's render-scale rows: `measure scales`, a call of its own.)
    mkdir -p "$out/show" "$out/full"
    v=""; for s in character field50 field150; do v="$v $s/old/CONE_PAST_FLOOR=0 $s/nm/CONE_MIRROR=0"; done
    OUT="$out/show" VARIANTS="$v mandelbulb/few/MANDELBULB_FEW_SFU=1" \
      VARIANT_SIZES="3840x2160 7680x4320" VARIANT_TESTS=show VARIANT_TIMEOUT=280 bash "$0" measure copies
    v=""; for s in character field50 field150; do v="$v $s/old/CONE_PAST_FLOOR=0"; done
    OUT="$out/full" VARIANTS="$v mandelbulb/few/MANDELBULB_FEW_SFU=1" VARIANT_TIMEOUT=240 bash "$0" measure copies
    fi
    if [ "$part" = s29b ]; then
    # Session 29's defaults as shipped: every scene in full lighting at 1080p and 4K, the 7680x4320 show,
    # then the budget's render-scale rows (`scales`).
    timeout 150 bash "$0" remote bench --scenes $all --sizes 1920x1080 3840x2160 --tests full --paths compute --frames 20 --warmup 5 \
      --markdown "$out/frames.md" --csv "$out/frames.csv" > "$out/frames.txt" 2>&1 || true
    cat "$out/frames.md" 2>/dev/null; grep -h drift "$out/frames.txt" || tail -5 "$out/frames.txt"
    timeout 100 bash "$0" remote bench --scenes $all --sizes 7680x4320 --tests show --paths compute --frames 8 --warmup 2 \
      --markdown "$out/show.md" --csv "$out/show.csv" > "$out/show.txt" 2>&1 || true
    cat "$out/show.md" 2>/dev/null; grep -h drift "$out/show.txt" || tail -5 "$out/show.txt"
    mkdir -p "$out/scales"; OUT="$out/scales" bash "$0" measure scales
    fi
    if [ "$part" = post ] || [ "$part" = s31 ]; then
    # Issue 12: a post effect's save, the chain in contexts of its own (IsfHost, as live draws it)
    # against the window's context: save -> screen, the longest frame, the steady frame (`bench post`).
    for size in 1920x1080 3840x2160; do
      timeout 80 bash "$0" remote bench post --size $size --rounds 5 --csv "$out/post_$size.csv" > "$out/post_$size.txt" 2>&1 || true
      cat "$out/post_$size.txt"
    done
    fi
    if [ "$part" = s31 ]; then
    mkdir -p "$out/s29b"; OUT="$out/s29b" bash "$0" measure s29b
    fi
    if [ "$part" = resize ] || [ "$part" = s33 ]; then
    # A change of the render scale (the resolution slider, `live --frame-budget`): the frame that makes
    # it, with other sizes' targets kept against new targets each time (`bench resize`), the scene alone
    # and under a post chain.
    for args in "--size 3840x2160" "--size 3840x2160 --post bloom" "--size 1920x1080 --post feedback_trails"; do
      n=$(echo "$args" | tr -d ' -' | tr ',' '_')
      timeout 90 bash "$0" remote bench resize --scene character $args --scales 1,0.7,0.5,0.85,2 --rounds 4 \
        --csv "$out/resize_$n.csv" > "$out/resize_$n.txt" 2>&1 || true
      cat "$out/resize_$n.txt"
    done
    fi
    if [ "$part" = s33 ]; then
    # A post effect's first save with and without the first build's spare set, interleaved in one run
    # (`bench post`'s second way; each save's longest frame in order), as `measure post` runs it.
    mkdir -p "$out/post"; OUT="$out/post" bash "$0" measure post
    fi
    if [ "$part" = postservers ]; then
    # Issue 12: a post effect's save with the chain drawn by the render processes (`live --render-process`
    # since session 34: a spare builds the scene and the chain, then goes on screen), and with a standby
    # holding the scene's program ready (only the chain built), interleaved. `measure post` is the same
    # effects' save with the chain in the show's process (session 33's figures), a call of its own.
    # POSTSERVERS="SIZE:EFFECT ..." picks the rows (live keeps a chain with feedback in its own process
    # since session 35, so feedback_trails there is the bench's alone).
    for args in ${POSTSERVERS:-3840x2160:bloom 3840x2160:feedback_trails 1920x1080:bloom}; do
      size=${args%%:*}; fx=${args#*:}
      timeout 180 bash "$0" remote bench reload --scene midi --size $size --path compute --modes render-process,render-process-standby --post $fx \
        --rounds 4 > "$out/servers_${fx}_$size.txt" 2>&1 || true
      grep -h "^##\|^|\|median\|standby\|missed" "$out/servers_${fx}_$size.txt" | cut -c1-300 || tail -5 "$out/servers_${fx}_$size.txt"
    done
    fi
    if [ "$part" = scales ]; then
    # The frame budget's resolution term (issue 13): every scene's default at render scales 0.25..1
    # and 2x2 supersampled, resampled as `live --render-scale` shows them, against the supersampled
    # truth (`bench accuracy --sweep scale`); its accuracy.csv rows replace docs/accuracy/accuracy.csv's
    # scale rows (measured on llvmpipe in session 27).
    timeout 200 bash "$0" remote bench accuracy --scene all --size 1920x1080 --ref-size 96x54 --sweep scale --path compute \
      --frames 15 --warmup 5 --out "$out/scales" --csv "$out/scales_bench.csv" > "$out/scales.txt" 2>&1 || true
    grep -h "scale=\|supersampled\|drift" "$out/scales.txt" || tail -5 "$out/scales.txt"
    fi
    if [ "$part" = copies ]; then
    # Several render levers in one interleaved run: VARIANTS="SCENE/SUFFIX/NAME=VALUE,NAME=VALUE ..."
    # (each a copy of SCENE, SCENE_SUFFIX, with those #defines), every SCENE named there as it ships
    # too; VARIANT_SIZES (1920x1080 3840x2160), VARIANT_TESTS (full).
    root="$(mktemp -d)"; cp -r shaders presets mappings "$root/"; sc=""
    for v in ${VARIANTS:?VARIANTS=SCENE/SUFFIX/NAME=VALUE,...}; do
      s="${v%%/*}"; rest="${v#*/}"; suf="${rest%%/*}"; defs="${rest#*/}"
      case " $sc " in *" $s "*) ;; *) sc="$sc $s" ;; esac
      IFS=, read -r -a dl <<< "${defs//=/ }"; variant "$root" "$s" "$suf" "${dl[@]}"; sc="$sc ${s}_$suf"
    done
    SDFVJ_ROOT_OVERRIDE="$root" timeout ${VARIANT_TIMEOUT:-300} bash "$0" remote bench --scenes $sc --sizes ${VARIANT_SIZES:-1920x1080 3840x2160} \
      --tests ${VARIANT_TESTS:-full} --paths compute --frames 20 --warmup 5 --markdown "$out/copies.md" --csv "$out/copies.csv" > "$out/copies.txt" 2>&1 || true
    cat "$out/copies.md" 2>/dev/null; grep -h drift "$out/copies.txt" || tail -5 "$out/copies.txt"
    rm -rf "$root"
    fi
    if [ "$part" = qrefl ] || [ "$part" = qrefl_time ]; then
    # Session 46, issue 13: the 7680x4320 show (4x supersampled 4K) with its bounce traced once per
    # 2x2 pixels (`quad_reflections`, show_quad_reflections), against the show as shipped and with
    # direct_reflections; QREFL_OWN0 scenes also as copies whose pixels never trace their own bounce
    # (_own0: QUAD_REFLECTIONS_OWN 0, no fallback where a pixel's surface is not the quad centre's).
    root="$(mktemp -d)"; cp -r shaders presets mappings "$root/"; sc="$all"
    for s in ${QREFL_OWN0-mandelbulb field50 field150}; do variant "$root" "$s" own0 "QUAD_REFLECTIONS_OWN 0"; sc="$sc ${s}_own0"; done
    SDFVJ_ROOT_OVERRIDE="$root" timeout ${QREFL_TIMEOUT:-300} bash "$0" remote bench --scenes $sc --sizes 7680x4320 \
      --tests show show_quad_reflections show_direct --paths compute --frames 15 --warmup 3 \
      --markdown "$out/qrefl_show.md" --csv "$out/qrefl_show.csv" > "$out/qrefl_show.txt" 2>&1 || true
    cat "$out/qrefl_show.md" 2>/dev/null; grep -h drift "$out/qrefl_show.txt" || tail -5 "$out/qrefl_show.txt"
    rm -rf "$root"
    fi
    if [ "$part" = qrefl ] || [ "$part" = qrefl_image ]; then
    # What it draws: `bench ssaa` at 3840x2160 with the show's effects; its last column is the
    # 7680x4320 frame with quad_reflections averaged 2x2 against the same frame without.
    timeout ${QREFL_IMAGE_TIMEOUT:-240} bash "$0" remote bench ssaa --size 3840x2160 --effects none,soft_shadows,ao,specular,pbr,reflections=1 \
      --markdown "$out/qrefl_image.md" > "$out/qrefl_image.txt" 2>&1 || true
    cat "$out/qrefl_image.txt"
    fi
    if [ "$part" = roots ]; then
    # Session 50, issue 13: the 7680x4320 show with quad_reflections drawn by each tree of
    # `prepare-roots` in turn (not interleaved across trees: each is its own bench run), twice;
    # ROOT_SCENES (character and field150, each lending nothing and all).
    for pass in 1 2; do
      for d in .devbuild/revs/*/; do
        n="$(basename "$d")"
        SDFVJ_ROOT_OVERRIDE="$PWD/$d" timeout ${ROOT_TIMEOUT:-60} bash "$0" remote bench --scenes ${ROOT_SCENES:-character_qs0 character_qs7 field150_qs0 field150_qs7} \
          --sizes 7680x4320 --tests show_quad_reflections --paths compute --frames 10 --warmup 3 \
          --markdown "$out/roots_${n}_$pass.md" --csv "$out/roots_${n}_$pass.csv" > "$out/roots_${n}_$pass.txt" 2>&1 || true
        echo "$pass $n: $(grep -h '^| [a-z]' "$out/roots_${n}_$pass.md" 2>/dev/null | awk -F'|' '{printf "%s%s ", $2, $5}')"
      done
    done
    # Then every shipped scene as its tree ships it, for the trees in ROOT_SHOW_TREES (session 51).
    for n in ${ROOT_SHOW_TREES-now return inline}; do
      [ -d ".devbuild/revs/$n" ] || continue
      SDFVJ_ROOT_OVERRIDE="$PWD/.devbuild/revs/$n" timeout ${ROOT_SHOW_TIMEOUT:-80} bash "$0" remote bench --scenes $all \
        --sizes 7680x4320 --tests show_quad_reflections --paths compute --frames 10 --warmup 3 \
        --markdown "$out/roots_show_$n.md" --csv "$out/roots_show_$n.csv" > "$out/roots_show_$n.txt" 2>&1 || true
      echo "show $n: $(grep -h '^| [a-z]' "$out/roots_show_$n.md" 2>/dev/null | awk -F'|' '{printf "%s%s ", $2, $5}')"
    done
    fi
    if [ "$part" = qrefl2 ]; then
    # Session 47, issue 13: what the pixels that trace their own bounce cost and draw. Every scene
    # in QREFL2_SCENES as shipped, and copies of those in QREFL2_COPIED, one per QREFL2_VARIANTS entry
    # "SUFFIX/NAME=VALUE,NAME=VALUE": near0 (no quad beside asked first: session 46's), own0 (never
    # their own bounce), cos95 and cos90 (their own only where the normals part by more than about
    # 18 or 26 degrees, not 8); session 48: defer0 (QUAD_REFLECTIONS_DEFER 0: their own bounce in
    # the frame, not listed for a dispatch of its own); session 49: qs7, qs1, qs3 (QUAD_SHADE: the
    # quads lend their centres' AO and shadows, all, the AO alone, AO and "lit"). Session 47's first call also had own2 (their own without its
    # shadow ray and AO: QUAD_REFLECTIONS_OWN 2, commit 8e46934, since removed). The 7680x4320 show with and without quad_reflections, then
    # `bench ssaa` at 3840x2160 (its last column: what each draws).
    root="$(mktemp -d)"; cp -r shaders presets mappings "$root/"; sc="${QREFL2_SCENES:-$all}"
    for s in ${QREFL2_COPIED:-mandelbulb field150}; do
      for v in ${QREFL2_VARIANTS:-near0/QUAD_REFLECTIONS_NEAR=0 own0/QUAD_REFLECTIONS_OWN=0 cos95/QUAD_REFLECTIONS_COS=0.95f cos90/QUAD_REFLECTIONS_COS=0.90f}; do
        suf="${v%%/*}"; defs="${v#*/}"; IFS=, read -r -a dl <<< "${defs//=/ }"
        variant "$root" "$s" "$suf" "${dl[@]}"; sc="$sc ${s}_$suf"
      done
    done
    SDFVJ_ROOT_OVERRIDE="$root" timeout ${QREFL_TIMEOUT:-300} bash "$0" remote bench --scenes $sc --sizes 7680x4320 \
      --tests ${QREFL2_TESTS:-show show_quad_reflections} --paths compute --frames 15 --warmup 3 \
      --markdown "$out/qrefl2_show.md" --csv "$out/qrefl2_show.csv" > "$out/qrefl2_show.txt" 2>&1 || true
    cat "$out/qrefl2_show.md" 2>/dev/null; grep -h drift "$out/qrefl2_show.txt" || tail -5 "$out/qrefl2_show.txt"
    if [ "${QREFL2_IMAGE:-1}" = 1 ]; then   # QREFL2_IMAGE=0: copies that draw the same picture, time only
    SDFVJ_ROOT_OVERRIDE="$root" timeout ${QREFL_IMAGE_TIMEOUT:-240} bash "$0" remote bench ssaa --scenes "$(echo $sc | tr ' ' ,)" --size 3840x2160 \
      --effects none,soft_shadows,ao,specular,pbr,reflections=1 --markdown "$out/qrefl2_image.md" > "$out/qrefl2_image.txt" 2>&1 || true
    cat "$out/qrefl2_image.txt"
    fi
    rm -rf "$root"
    fi
    if [ "$part" = s22 ]; then
    # Session 22, issue 13: normals by forward differences from the march's own value at the hit (3 map()
    # calls) against the tetrahedron (4, the shipped scenes' choice) and central differences (6), every
    # bounded scene (S22_SCENES) at 1080p and 4K full lighting, interleaved: copies whose header asks for
    # "forward" (_forward) and "central" (_central).
    root="$(mktemp -d)"; cp -r shaders presets mappings "$root/"; sc=""
    for s in ${S22_SCENES:-midi primitives character field50 field150}; do
      for n in forward central; do
        sed -e "s/\"NAME\": \"$s\"/\"NAME\": \"${s}_$n\"/" -e "s/\"NORMALS\": \"tetrahedron\"/\"NORMALS\": \"$n\"/" \
          "shaders/scenes/$s.glsl" > "$root/shaders/scenes/${s}_$n.glsl"
      done
      sc="$sc $s ${s}_forward ${s}_central"
    done
    SDFVJ_ROOT_OVERRIDE="$root" timeout 280 bash "$0" remote bench --scenes $sc --sizes 1920x1080 3840x2160 --tests full \
      --paths compute --frames 20 --warmup 5 --markdown "$out/s22_normals.md" --csv "$out/s22_normals.csv" > "$out/s22_normals.txt" 2>&1 || true
    cat "$out/s22_normals.md" 2>/dev/null; grep -h drift "$out/s22_normals.txt" || true
    rm -rf "$root"
    fi
    if [ "$part" = s15b ]; then
    # Session 15, floor hits on the plane (render/march.glsl onGround): every scene as it ships against
    # a copy without it (_nosnap, GROUND_SNAP 0) at 1080p and 4K full lighting, interleaved; the
    # 7680x4320 show as shipped; the accuracy report for docs/accuracy.md (its command line).
    # (more than the 8 files a device call brings back: all in one archive, s15b.tgz)
    w="$(mktemp -d)"; root="$(mktemp -d)"; cp -r shaders presets mappings "$root/"; sc=""
    for s in $all; do variant "$root" $s nosnap "GROUND_SNAP 0"; sc="$sc $s ${s}_nosnap"; done
    SDFVJ_ROOT_OVERRIDE="$root" timeout 150 bash "$0" remote bench --scenes $sc --sizes 1920x1080 3840x2160 --tests full \
      --paths compute --frames 20 --warmup 5 --markdown "$w/s15b_frames.md" --csv "$w/s15b_frames.csv" > "$w/s15b_frames.txt" 2>&1 || true
    rm -rf "$root"
    cat "$w/s15b_frames.md" 2>/dev/null || true
    timeout 100 bash "$0" remote bench --scenes $all --sizes 7680x4320 --tests show --paths compute --frames 8 --warmup 2 \
      --markdown "$w/s15b_show.md" --csv "$w/s15b_show.csv" > "$w/s15b_show.txt" 2>&1 || true
    cat "$w/s15b_show.md" 2>/dev/null || true
    timeout 200 bash "$0" remote bench accuracy --scene all --size 1920x1080 --ref-size 960x540 --path compute --frames 15 \
      --warmup 5 --out "$w/s15b_accuracy" --markdown "$w/s15b_accuracy.md" > "$w/s15b_accuracy.txt" 2>&1 || true
    grep -h -E 'drift|\| sdfvj default' "$w"/s15b*.txt | cut -c1-220 || true
    tar czf "$out/s15b.tgz" -C "$w" . && rm -rf "$w"
    fi
    if [ "$part" = s15c ]; then
    # Session 15: character's part skip (a limb whose bounding sphere is more than the blend radius
    # beyond the body so far is not evaluated; exact) against a copy without it (_noskip,
    # CHARACTER_SKIP 0): 1080p and 4K full lighting, its effects at 4K, the 7680x4320 show,
    # interleaved; its accuracy rows.
    root="$(mktemp -d)"; cp -r shaders presets mappings "$root/"
    variant "$root" character noskip "CHARACTER_SKIP 0"
    SDFVJ_ROOT_OVERRIDE="$root" timeout 100 bash "$0" remote bench --scenes character character_noskip \
      --sizes 1920x1080 3840x2160 --tests full show --paths compute --frames 30 --warmup 5 --markdown "$out/s15c_frames.md" \
      --csv "$out/s15c_frames.csv" > "$out/s15c_frames.txt" 2>&1 || true
    SDFVJ_ROOT_OVERRIDE="$root" timeout 80 bash "$0" remote bench --scenes character character_noskip --sizes 7680x4320 \
      --tests show --paths compute --frames 8 --warmup 2 --markdown "$out/s15c_show.md" --csv "$out/s15c_show.csv" \
      > "$out/s15c_show.txt" 2>&1 || true
    timeout 60 bash "$0" remote bench effects --scene character --size 3840x2160 --path compute --csv "$out/s15c_effects.csv" \
      > "$out/s15c_effects.txt" 2>&1 || true
    timeout 90 bash "$0" remote bench accuracy --scene character --size 1920x1080 --ref-size 960x540 --path compute \
      --sweep tiny --frames 12 --warmup 4 --out "$out/s15c_accuracy" > "$out/s15c_accuracy.txt" 2>&1 || true
    rm -rf "$root" "$out/s15c_accuracy"
    cat "$out/s15c_frames.md" "$out/s15c_show.md" 2>/dev/null || true
    grep -h '^|' "$out/s15c_effects.txt" || true
    grep -h -E 'drift|\| sdfvj default' "$out"/s15c*.txt | cut -c1-220 || true
    fi
    if [ "$part" = s13 ]; then
    # Issue 13, session 13, one call: (1) every scene as it ships against copies (NAME_SUFFIX, each
    # a #define after the header) at 1080p and 4K, full lighting, interleaved: _or over-relaxed
    # and _plain plainly stepping sphere tracing, and the fields' exact cell skip against the field
    # lib before it (.devbuild/ab from `AB_RENDER_OK=1 prepare-ab REV`: NAME_before); (2) the show
    # lighting at 7680x4320 against cheaper reflections: _l1 no AO where a reflection lands, _l2
    # neither AO nor a shadow ray there, _s48 a reflection marches at most 48 steps, _l1s48 and
    # _l2s48 both; (3) the accuracy sweep (its plain-sphere-tracing row). Session 13 also ran _ct4 /
    # _orct4 copies, the cone pre-pass in 4x4 tiles; that switch was removed (slower at 4K).
    root="$(mktemp -d)"; cp -r .devbuild/ab/. "$root/"
    sc=""
    for s in $all; do
      variant "$root" $s or "OVERRELAX 1"; variant "$root" $s plain "OVERRELAX 0"; sc="$sc $s ${s}_or ${s}_plain"
    done
    for s in field50 field150; do [ -f "$root/shaders/scenes/${s}_before.glsl" ] && sc="$sc ${s}_before"; done
    SDFVJ_ROOT_OVERRIDE="$root" timeout 230 bash "$0" remote bench --scenes $sc --sizes 1920x1080 3840x2160 --tests full \
      --paths compute --frames 12 --warmup 3 --markdown "$out/s13.md" --csv "$out/s13.csv" > "$out/s13.txt" 2>&1 || true
    show=""
    for s in ${S13_SHOW:-character mandelbulb field50 field150}; do
      variant "$root" $s l1 "BOUNCE_LIGHT 1"; variant "$root" $s l2 "BOUNCE_LIGHT 2"; variant "$root" $s s48 "BOUNCE_STEPS 48"
      variant "$root" $s l1s48 "BOUNCE_LIGHT 1" "BOUNCE_STEPS 48"; variant "$root" $s l2s48 "BOUNCE_LIGHT 2" "BOUNCE_STEPS 48"
      show="$show $s ${s}_l1 ${s}_l2 ${s}_s48 ${s}_l1s48 ${s}_l2s48"
    done
    SDFVJ_ROOT_OVERRIDE="$root" timeout 170 bash "$0" remote bench --scenes $show --sizes 7680x4320 --tests show \
      --paths compute --frames 8 --warmup 2 --markdown "$out/s13_show.md" --csv "$out/s13_show.csv" > "$out/s13_show.txt" 2>&1 || true
    timeout 150 bash "$0" remote bench accuracy --scene all --size 1920x1080 --ref-size 960x540 --path compute --frames 12 \
      --warmup 4 --out "$out/s13_accuracy" --csv "$out/s13_accuracy.csv" > "$out/s13_accuracy.txt" 2>&1 || true
    grep -h 'drift' "$out"/s13*.txt || true
    rm -rf "$root"
    fi
    if [ "$part" = final13 ]; then
    # Issue 13, session 13's figures as shipped (over-relaxation on, the fields' cell skip): every
    # scene at 1080p and 4K with its own lighting, the 7680x4320 show with full and with direct
    # reflections, the accuracy sweep (its plain-sphere-tracing row), character's and field150's
    # effects at 4K.
    timeout 100 bash "$0" remote bench --scenes $all --sizes 1920x1080 3840x2160 --tests full --paths compute \
      --frames 20 --warmup 5 --markdown "$out/f13_frames.md" --csv "$out/f13_frames.csv" > "$out/f13_frames.txt" 2>&1 || true
    timeout 150 bash "$0" remote bench --scenes $all --sizes 7680x4320 --tests show show_direct --paths compute \
      --frames 8 --warmup 2 --markdown "$out/f13_show.md" --csv "$out/f13_show.csv" > "$out/f13_show.txt" 2>&1 || true
    timeout 150 bash "$0" remote bench accuracy --scene all --size 1920x1080 --ref-size 960x540 --path compute --frames 12 \
      --warmup 4 --out "$out/f13_accuracy" --csv "$out/f13_accuracy.csv" > "$out/f13_accuracy.txt" 2>&1 || true
    for s in character field150; do
      timeout 60 bash "$0" remote bench effects --scene $s --size 3840x2160 --path compute --csv "$out/f13_effects_$s.csv" \
        > "$out/f13_effects_$s.txt" 2>&1 || true
    done
    grep -h 'drift' "$out"/f13*.txt || true
    fi
    if [ "$part" = overrelax ]; then
    # Issue 13: over-relaxed sphere tracing (render.glsl OVERRELAX, Keinert et al. 2014) against
    # plain sphere tracing, every scene as it ships and copies that define OVERRELAX 1 (NAME_or) and
    # 0 (NAME_plain), one interleaved run at 1080p and 4K.
    orr="$(mktemp -d)"; cp -r shaders presets mappings "$orr/"; sc=""
    for s in $all; do
      variant "$orr" $s or "OVERRELAX 1"; variant "$orr" $s plain "OVERRELAX 0"; sc="$sc $s ${s}_or ${s}_plain"
    done
    SDFVJ_ROOT_OVERRIDE="$orr" timeout 200 bash "$0" remote bench --scenes $sc --sizes 1920x1080 3840x2160 --tests full \
      --paths compute --frames 12 --warmup 3 --markdown "$out/overrelax.md" --csv "$out/overrelax.csv" > "$out/overrelax.txt" 2>&1 || true
    rm -rf "$orr"
    fi
    if [ "$part" = launch ]; then
    # Issue 12: a second launch as a user has it, the driver's own disk cache on (in a folder kept
    # between the two launches) with and without sdfvj's program cache; first launch into empty caches.
    for s in midi character; do
      for pc in on off; do
        rm -rf /tmp/sdfvj-launch; mkdir -p /tmp/sdfvj-launch/nv
        flag=""; [ $pc = off ] && flag="--no-program-cache"
        for launch in first second third; do
          XDG_CACHE_HOME=/tmp/sdfvj-launch __GL_SHADER_DISK_CACHE=1 __GL_SHADER_DISK_CACHE_PATH=/tmp/sdfvj-launch/nv \
            __GL_SHADER_DISK_CACHE_SKIP_CLEANUP=1 timeout 60 bash "$0" remote bench reload --scene $s --size 1920x1080 \
            --path compute --first-frame --driver-cache warm $flag > "$out/launch_${s}_pc${pc}_$launch.txt" 2>&1 || true
        done
      done
    done
    fi
    if [ "$part" = loops ]; then
    # Session 10: the frame tables after one copy of map() per loop (every scene at 1080p and 4K,
    # twice, then the show lighting at 4K and 7680x4320), and the compiles of field150 and
    # character against the shaders of `prepare-rev REV` (.devbuild/rev), driver caches off.
    for i in 1 2; do
      timeout 100 bash "$0" remote bench --scenes $all --sizes 1920x1080 3840x2160 --tests full --paths compute \
        --frames 15 --warmup 3 --markdown "$out/frames_$i.md" --csv "$out/frames_$i.csv" > "$out/frames_$i.txt" 2>&1 || true
    done
    timeout 120 bash "$0" remote bench --scenes $all --sizes 3840x2160 7680x4320 --tests show --paths compute \
      --frames 8 --warmup 3 --markdown "$out/show.md" --csv "$out/show.csv" > "$out/show.txt" 2>&1 || true
    for s in field150 character; do
      for r in rev now; do
        root="$PWD"; [ $r = rev ] && root="$PWD/.devbuild/rev"
        [ -d "$root" ] || continue
        SDFVJ_ROOT_OVERRIDE="$root" timeout 100 bash "$0" remote bench reload --scene $s --size 1920x1080 --path compute \
          --rounds 3 --modes driver > "$out/reload_${s}_$r.txt" 2>&1 || true
      done
    done
    fi
    if [ "$part" = toggle ] || [ "$part" = all ]; then
    # Issue 12: effect pad hits (the six one-effect variants) cold, built ahead (live's prefetch)
    # and built ahead + used once on the render context, rounds interleaved, driver caches off.
    for s in midi character; do
      timeout 240 bash "$0" remote bench reload --edit toggle --scene $s --size 1920x1080 --path compute --rounds 6 \
        > "$out/toggle_$s.txt" 2>&1 || true
    done
    fi
    if [ "$part" = lit ] || [ "$part" = all ]; then
    # Issue 13: no shadow ray for a surface turned away from the light (render.glsl facesLight; every
    # direct term carries max(n.l, 0), so no pixel changes) against a copy of shaders/ without it;
    # whole runs alternate (after, before, after, before), each warmed after its compiles.
    before="$(mktemp -d)"
    cp -r shaders presets mappings "$before/"
    sed -i 's/if (facesLight \&\& /if (/' "$before/shaders/render/render.glsl"
    for i in 1 2; do
      for v in after before; do
        root="$PWD"; [ $v = before ] && root="$before"
        SDFVJ_ROOT_OVERRIDE="$root" timeout 70 bash "$0" remote bench --scenes midi primitives character mandelbulb field50 field150 \
          --sizes 1920x1080 3840x2160 --tests full --paths compute --frames 15 --warmup 3 \
          --csv "$out/lit_${v}_$i.csv" > "$out/lit_${v}_$i.txt" 2>&1 || true
      done
    done
    rm -rf "$before"
    fi
    if [ "$part" = field ] || [ "$part" = all ]; then
    # The field scenes' box bound (issue 13, SCENE_BOX in render.glsl) on and off in one interleaved
    # run: a copy of shaders/ adds field150_nobox, the same scene with only its bounding sphere;
    # then the fields' accuracy rows (geometry against the CPU double reference).
    nobox="$(mktemp -d)"
    cp -r shaders presets mappings "$nobox/"
    sed '/^#define SCENE_BOX 1$/d' shaders/lib/field_scene.glsl > "$nobox/shaders/lib/field_scene_nobox.glsl"
    sed -e 's#lib/field_scene.glsl#lib/field_scene_nobox.glsl#' -e 's/"NAME": "field150"/"NAME": "field150_nobox"/' \
      shaders/scenes/field150.glsl > "$nobox/shaders/scenes/field150_nobox.glsl"
    SDFVJ_ROOT_OVERRIDE="$nobox" timeout 80 bash "$0" remote bench --scenes character field150 field150_nobox \
      --sizes 1920x1080 3840x2160 --tests full --paths compute --frames 15 --warmup 3 --markdown "$out/field_box.md" \
      --csv "$out/field_box.csv" > "$out/field_box.txt" 2>&1 || true
    rm -rf "$nobox"
    timeout 120 bash "$0" remote bench accuracy --scene character,field150 --size 1920x1080 --ref-size 960x540 --path compute \
      --frames 15 --warmup 5 --out "$out/accuracy_fields" --csv "$out/accuracy_fields.csv" > "$out/accuracy_fields.txt" 2>&1 || true
    fi
    ;;
  remote)
    shift
    for f in .gl/*.deb; do dpkg -x "$f" /; done
    ldconfig
    export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
    vk=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; [ -f $vk ] && export VK_DRIVER_FILES=$vk   # render processes' shared image
    export LD_LIBRARY_PATH="$PWD/.devbuild/lib:${LD_LIBRARY_PATH:-}"
    export SDFVJ_ROOT="${SDFVJ_ROOT_OVERRIDE:-$PWD}"
    nvidia-smi --query-gpu=name,driver_version --format=csv,noheader || true
    exec ./.devbuild/sdfvj-headless "$@"
    ;;
  *)
    sed -n '2,/^set -euo/p' "$0" | sed '$d'; exit 2 ;;
esac
