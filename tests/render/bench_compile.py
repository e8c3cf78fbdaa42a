#!/usr/bin/env python3
"""`sdfvj bench compile` (issue 12: where a driver's build time goes) on llvmpipe.

Not a timing test: the times go to docs/performance.md from the GPU machine. What is checked is that
each cut builds the program it says: every cut has its medians row and its CSV row; the @sphere cut's
source has the scene's map() replaced (shorter, and it still builds); a #define cut reaches the
program (one that redefines what the effects define fails to compile, is said as failed, and the
bench exits 1); a cut it cannot read exits 2 saying what it expected.

usage: bench_compile.py SDFVJ WORKDIR
"""
import csv
import os
import re
import subprocess
import sys


def run(binary, *args):
    p = subprocess.run([binary, "bench", "compile", *args], capture_output=True, text=True, timeout=240)
    return p.returncode, p.stdout + p.stderr


def medians(out):
    """The medians table: cut -> its row's cells."""
    rows = {}
    section = out.split("## medians", 1)
    if len(section) < 2:
        return rows
    for line in section[1].splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 3 and cells[0] not in ("cut", "---"):
            rows[cells[0]] = cells
    return rows


def main():
    binary, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    table = os.path.join(work, "compile.csv")
    cuts = ["quick", "quick@sphere", "quick/none", "optimized/-ao+CONE_PREPASS=0"]
    rc, out = run(binary, "--scene", "midi", "--rounds", "1", "--csv", table, "--cuts", *cuts)
    print(out)
    failures = []
    if rc != 0:
        failures.append(f"bench compile exited {rc} with cuts that all build")
    rows = medians(out)
    for cut in cuts:
        cells = rows.get(cut)
        if not cells or len(cells) < 8:
            failures.append(f"no medians row for cut '{cut}'")
            continue
        total = float(cells[6].strip("*"))
        if not total > 0:
            failures.append(f"cut '{cut}': total {total} ms, expected > 0")
    if "quick/none" in rows and rows["quick/none"][1] != "none":
        failures.append(f"cut 'quick/none' built with effects '{rows['quick/none'][1]}', expected none")
    if "optimized/-ao+CONE_PREPASS=0" in rows and "ao" in rows["optimized/-ao+CONE_PREPASS=0"][1].split(","):
        failures.append("cut 'optimized/-ao..' still has ao among its effects")
    if "quick" in rows and "quick@sphere" in rows:
        scene_chars, sphere_chars = int(rows["quick"][2]), int(rows["quick@sphere"][2])
        if not sphere_chars < scene_chars:
            failures.append(f"@sphere source {sphere_chars} chars, not shorter than the scene's {scene_chars}: map() not replaced")
    with open(table, newline="") as f:
        read = list(csv.DictReader(f))
    head = ["scene", "lighting", "size", "path", "ms", "gpu", "cut", "compile_ms", "link_ms", "use_ms", "source_chars"]
    if not read or list(read[0].keys()) != head:
        failures.append(f"CSV columns {list(read[0].keys()) if read else 'none'}, expected {head}")
    elif sorted(r["cut"] for r in read) != sorted(cuts):
        failures.append(f"CSV cuts {[r['cut'] for r in read]}, expected {cuts}")

    # A define that clashes with the effects' own (#define SHADOWS twice) fails to compile: said, exit 1.
    rc, out = run(binary, "--scene", "midi", "--rounds", "1", "--cuts", "quick", "quick+SHADOWS=0")
    print(out)
    if rc != 1 or not re.search(r"\| quick\+SHADOWS=0 \| .*failed: compile", out):
        failures.append(f"a cut that does not compile: exit {rc} (expected 1) and no 'failed: compile' row")

    for bad, expected in (("fast", "expected optimized or quick"), ("quick@cube", "expected @sphere"),
                          ("quick+9X=1", "expected +NAME=VALUE"), ("quick/glow", "unknown effect"),
                          ("quick!Inline_None", "expected !WORDS-JOINED-BY-DASHES")):
        rc, out = run(binary, "--scene", "midi", "--rounds", "1", "--cuts", bad)
        if rc != 2 or expected not in out or bad.split("!")[0].split("+")[0].split("@")[0].split("/")[0] not in out:
            failures.append(f"bad cut '{bad}': exit {rc}, output {out.strip()[:200]!r}; expected exit 2 saying '{expected}'")

    for f in failures:
        print("bench_compile:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
