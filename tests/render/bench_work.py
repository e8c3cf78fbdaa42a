#!/usr/bin/env python3
"""`sdfvj bench work` counts every map() call where it happens (render.glsl DEBUG_VIEW 6 and 7).

    bench_work.py SDFVJ OUT_DIR

Checked on llvmpipe at 96x54 against what the renderer must do, not against recorded numbers:
- mandelbulb (no floor, so every probe calls map(); AO's farthest-first early out is off there):
  each hit pixel takes exactly 6 calls for its central-difference normal and exactly 5 for AO
  (u_aoSamples), so normal = 6 x and AO = 5 x the share of pixels hit;
- the primary march does not depend on the lighting: the same count under none, full and show;
- none takes no shadow or AO call, full and none no reflection call, show's reflections march;
- a shadow ray or AO costs something wherever the scene has them.
And the `work` effect (DEBUG_VIEW 8, the same counts as a log-scale heatmap) draws mandelbulb's sky,
where no ray enters the bound, at 0 calls (blue) and its surface hot (red above blue), hotter still
with a reflection.
"""
import csv
import os
import subprocess
import sys

sdfvj, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
path = os.path.join(out, "work.csv")
run = subprocess.run([sdfvj, "bench", "work", "--scenes", "mandelbulb,midi,field50", "--tests", "none,full,show",
                      "--size", "96x54", "--csv", path], capture_output=True, text=True, timeout=600)
print(run.stdout)
print(run.stderr, file=sys.stderr)
if run.returncode != 0:
    sys.exit(f"bench work exited {run.returncode}")

rows = {(r["scene"], r["lighting"]): r for r in csv.DictReader(open(path))}
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def v(scene, test, col):
    return float(rows[(scene, test)][col])


refl = ["reflection_march", "reflection_normal", "reflection_shadow", "reflection_ao"]
for scene in ["mandelbulb", "midi", "field50"]:
    for test in ["none", "full", "show"]:
        check((scene, test) in rows, f"{scene} {test}: a row")
    hit = v(scene, "full", "pixels_hit")
    check(0.05 < hit < 1.0, f"{scene}: some pixels hit and some miss ({hit:.3f})")
    march = [v(scene, t, "primary_march") for t in ["none", "full", "show"]]
    check(march[0] > 1.0 and abs(march[0] - march[1]) < 1e-3,
          f"{scene}: the primary march is the same with and without shadows and AO ({march})")
    check(abs(march[2] - march[1]) < 1e-3, f"{scene}: the primary march is the same with reflections ({march})")
    check(v(scene, "none", "primary_shadow") == 0 and v(scene, "none", "primary_ao") == 0,
          f"{scene}: none takes no shadow or AO call")
    check(all(v(scene, t, c) == 0 for t in ["none", "full"] for c in refl), f"{scene}: no reflection call without reflections")
    check(v(scene, "full", "primary_shadow") > 0 and v(scene, "full", "primary_ao") > 0, f"{scene}: full's shadows and AO are counted")
    check(v(scene, "show", "reflection_march") > 0, f"{scene}: show's reflections march")
    total = sum(v(scene, "show", c) for c in ["primary_march", "primary_normal", "primary_shadow", "primary_ao"] + refl)
    check(abs(total - v(scene, "show", "total")) < 1e-2, f"{scene}: total is the sum of the phases")
    for test in ["none", "full", "show"]:
        # a warp (8x4 pixels) pays each phase's busiest lane: at least the mean, at most the block's sum
        t_, wt = v(scene, test, "total"), v(scene, test, "warp_total")
        check(t_ - 1e-3 <= wt <= 32 * t_ + 1e-3, f"{scene} {test}: the warp's cost {wt:.2f} lies between the mean {t_:.2f} and 32x it")
    check(v(scene, "none", "warp_total") < v(scene, "full", "warp_total") < v(scene, "show", "warp_total"),
          f"{scene}: the warp's cost grows with the lighting")

hit = v("mandelbulb", "full", "pixels_hit")
check(abs(v("mandelbulb", "full", "primary_normal") - 6 * hit) < 1e-3,
      f"mandelbulb: 6 calls per hit for central normals ({v('mandelbulb', 'full', 'primary_normal'):.4f} vs {6 * hit:.4f})")
check(abs(v("mandelbulb", "full", "primary_ao") - 5 * hit) < 1e-3,
      f"mandelbulb: 5 AO calls per hit ({v('mandelbulb', 'full', 'primary_ao'):.4f} vs {5 * hit:.4f})")

# The work effect: one frame at 96x54, read with png_slack.py's decoder.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
load = {}
exec(open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "png_slack.py")).read().split("w,h,bpp,A=load")[0], load)


def frame(effects, name):
    folder = os.path.join(out, name)
    r = subprocess.run([sdfvj, "render", "--scene", "mandelbulb", "--effects", effects, "--size", "96x54", "--path", "compute",
                        "--out", folder], capture_output=True, text=True, timeout=300)
    check(r.returncode == 0, f"render --effects {effects}: exit 0 ({r.stderr.strip()[-300:]})")
    w, h, bpp, rows_ = load["load"](os.path.join(folder, "frame_00000.png"))
    return lambda x, y: tuple(rows_[h - 1 - y][x * bpp + k] for k in range(3))   # y up, as fragCoord


full = frame("work", "work_full")
show = frame("pbr,reflections=1,work", "work_show")
sky, centre = full(2, 2), full(48, 27)
check(sky[2] > 100 and sky[0] == 0 and sky[1] == 0, f"the sky's pixel is the heatmap's 0 (dark blue): {sky}")
check(centre[0] > centre[2], f"the fractal's centre pixel is hot (red above blue): {centre}")
# In the heatmap's hot half (red above blue) green falls as the count rises (yellow, orange, red).
ring = [(x, y) for x in range(30, 66, 3) for y in range(15, 40, 3) if full(x, y)[0] > full(x, y)[2] and show(x, y)[0] > show(x, y)[2]]
green = lambda f: sum(f(x, y)[1] for x, y in ring) / max(len(ring), 1)
check(len(ring) > 20 and green(show) < green(full) - 10,
      f"with a reflection the fractal is hotter: mean green {green(show):.1f} against {green(full):.1f} over {len(ring)} pixels")
sys.exit(1 if failures else 0)
