#!/usr/bin/env bash
# check_glsl.sh - assemble every scene like the host does (scripts/assemble_shader.py) and
# validate it with glslangValidator, as fragment and as compute shader, for the scene's own
# effects and for each effect switched one at a time (SHADOWS 0..3, AO, SPECULAR, PBR,
# REFLECTIONS 0..2, FOG, MARCH_FIXED), DEBUG_VIEW 1..3 and NORMALS 0..2, plus all-off and
# all-on, over-relaxation on and off, supersampling, and the reflections' BOUNCE_LIGHT /
# BOUNCE_STEPS. Usage: scripts/check_glsl.sh [scene ...]   (exit status 1 if any variant fails)
set -u
cd "$(dirname "$0")/.."
command -v glslangValidator >/dev/null || { echo "glslangValidator missing: apt-get install -y glslang-tools"; exit 2; }
scenes=("$@")
[ ${#scenes[@]} -eq 0 ] && scenes=(shaders/scenes/*.glsl)
variants=(
  ""
  "NORMALS=0" "NORMALS=1" "NORMALS=2"
  "DEBUG_VIEW=1" "DEBUG_VIEW=2" "DEBUG_VIEW=3"
  "SHADOWS=0" "SHADOWS=1" "SHADOWS=2" "SHADOWS=3"
  "AO=0" "AO=1" "SPECULAR=0" "SPECULAR=1" "PBR=1" "PBR=0"
  "REFLECTIONS=0" "REFLECTIONS=1" "REFLECTIONS=2" "FOG=0" "FOG=1" "MARCH_FIXED=1"
  "SHADOWS=0 AO=0 SPECULAR=0 PBR=0 REFLECTIONS=0 FOG=0"
  "SHADOWS=3 AO=1 SPECULAR=1 PBR=1 REFLECTIONS=2 FOG=1 NORMALS=2"
  "OVERRELAX=0" "OVERRELAX=1" "SUPERSAMPLE=1" "SUPERSAMPLE=2"
  "REFLECTIONS=1 BOUNCE_LIGHT=1" "REFLECTIONS=1 BOUNCE_LIGHT=2 BOUNCE_STEPS=48"
)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0; count=0
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .glsl)
  for stage in frag comp; do
    for v in "${variants[@]}"; do
      src="$tmp/$name.$stage"
      # shellcheck disable=SC2086
      python3 scripts/assemble_shader.py "$scene" "$stage" $v > "$src" || { fail=1; continue; }
      count=$((count + 1))
      if ! log=$(glslangValidator -S "$stage" "$src" 2>&1); then
        echo "FAIL $name $stage [${v:-header effects}]"; echo "$log" | grep -v "^$src$" | head -20
        fail=1
      fi
    done
  done
done
[ $fail -eq 0 ] && echo "check_glsl: $count programs OK" || echo "check_glsl: FAILURES"
exit $fail
