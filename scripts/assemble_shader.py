#!/usr/bin/env python3
"""Assemble a scene into one GLSL program source, the way the host (src/shader) does.

Usage: assemble_shader.py SCENE.glsl frag|comp [NAME=VALUE ...] > program.glsl

Order: #version 450 core, the #defines (effects from the scene's JSON header, overridden
by NAME=VALUE arguments), render/uniforms.glsl, one `uniform float u_<input>;` per header
input, the scene, render/render.glsl, render/supersample.glsl, main_frag.glsl or main_comp.glsl
(src/shader/shader.cpp AssembleProgram). `#include "x"` is
resolved relative to shaders/ and each file is expanded once (the include guards would
skip repeats anyway). Used by scripts/check_glsl.sh.
"""
import json
import os
import re
import sys

SHADERS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "shaders")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"\s*$')
HEADER = re.compile(r"/\*(\{.*?\})\*/", re.S)

EFFECT_DEFINES = {
    "SHADOWS": lambda v: {"none": 0, "hard": 1, "soft": 2, "improved": 3}[v],
    "AO": int, "SPECULAR": int, "PBR": int, "REFLECTIONS": int, "FOG": int,
    "NORMALS": lambda v: {"central": 0, "forward": 1, "tetrahedron": 2, "tetra": 2}[v],
}


def expand(path, seen, out):
    path = os.path.normpath(path)
    if path in seen:
        return
    seen.add(path)
    with open(path) as f:
        for line in f:
            m = INCLUDE.match(line)
            if m:
                expand(os.path.join(SHADERS, m.group(1)), seen, out)
            else:
                out.append(line.rstrip("\n"))


def header(scene_path):
    text = open(scene_path).read()
    m = HEADER.search(text)
    if not m:
        sys.exit(f"{scene_path}: no /*{{...}}*/ JSON header")
    return json.loads(m.group(1))


def main():
    scene, stage = sys.argv[1], sys.argv[2]
    meta = header(scene)
    defines = {"DEBUG_VIEW": 0, "NORMALS": 0, "MARCH_FIXED": 0, "SUPERSAMPLE": 0}
    for k, v in meta.get("EFFECTS", {}).items():
        if k not in EFFECT_DEFINES:
            sys.exit(f"{scene}: EFFECTS.{k} is not an effect this script knows, expected one of {', '.join(EFFECT_DEFINES)}")
        defines[k] = EFFECT_DEFINES[k](v)
    for arg in sys.argv[3:]:
        k, v = arg.split("=", 1)
        defines[k] = int(v)
    out = ["#version 450 core"]
    out += [f"#define {k} {v}" for k, v in defines.items()]
    out.append("#define SDFVJ_COMPUTE 1" if stage == "comp" else "#define SDFVJ_FRAGMENT 1")
    seen = set()
    expand(os.path.join(SHADERS, "render", "uniforms.glsl"), seen, out)
    out += [f"uniform float u_{i['NAME']};" for i in meta.get("INPUTS", [])]
    expand(scene, seen, out)
    for name in ("render.glsl", "supersample.glsl", "main_frag.glsl" if stage == "frag" else "main_comp.glsl"):
        expand(os.path.join(SHADERS, "render", name), seen, out)
    print("\n".join(out))


if __name__ == "__main__":
    main()
