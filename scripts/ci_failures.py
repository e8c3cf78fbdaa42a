#!/usr/bin/env python3
"""Prints, last, what each failed ctest test printed (the tail of its output), and the warnings of
tests that passed (a retry that saved one says what went wrong the first time).

CI's record keeps the beginning and the end of a run's output; a failure's details sit in the
middle, between the suite's progress lines and the fuzz smoke, and were cut there. .ci/run calls
this at the very end so the reason is in what is kept.

    scripts/ci_failures.py build [build-asan ...]   # ctest's Testing/Temporary/LastTest.log
"""
import os
import re
import subprocess
import sys

TAIL_LINES = 40


def failed_outputs(build):
    log = os.path.join(build, "Testing", "Temporary", "LastTest.log")
    failed = os.path.join(build, "Testing", "Temporary", "LastTestsFailed.log")
    if not os.path.exists(failed) or not os.path.exists(log):
        return []
    names = set()
    with open(failed, encoding="utf-8", errors="replace") as f:
        for line in f:
            _, _, name = line.strip().partition(":")
            if name:
                names.add(name)
    if not names:
        return []
    with open(log, encoding="utf-8", errors="replace") as f:
        text = f.read()
    out = []
    # Each test's record: "N/M Testing: NAME" ... "Output:" dashes, the output, dashes, "Test Failed." / "Test Passed."
    for m in re.finditer(r"^\d+/\d+ Testing: (.*)$", text, re.M):
        name = m.group(1).strip()
        if name not in names:
            continue
        start = text.find("Output:", m.end())
        end = text.find("\n<end of output>", start)
        if start < 0 or end < 0:
            continue
        body = text[start:end].splitlines()[2:]
        out.append((name, body[-TAIL_LINES:]))
    return out


def warned_outputs(build):
    """Tests that passed but printed a Catch2 WARN (a retry that saved them, say): its lines."""
    log = os.path.join(build, "Testing", "Temporary", "LastTest.log")
    if not os.path.exists(log):
        return []
    with open(log, encoding="utf-8", errors="replace") as f:
        text = f.read()
    out = []
    for m in re.finditer(r"^\d+/\d+ Testing: (.*)$", text, re.M):
        start = text.find("Output:", m.end())
        end = text.find("\n<end of output>", start)
        if start < 0 or end < 0:
            continue
        body = text[start:end].splitlines()[2:]
        verdict = text.find("Test Passed.", end, end + 400)
        at = [i for i, line in enumerate(body) if line.rstrip().endswith("warning:")]
        if verdict >= 0 and at:
            out.append((m.group(1).strip(), body[at[0]:at[0] + TAIL_LINES]))
    return out


FRAME = re.compile(r"^\s*(\S+)\(\+(0x[0-9a-f]+)\)\[0x[0-9a-f]+\]\s*$")


def symbolized(line):
    """A crash_trace frame `FILE(+0xOFFSET)[ADDR]` with addr2line's function appended, if it knows."""
    m = FRAME.match(line)
    if not m or not os.path.exists(m.group(1)):
        return line
    try:
        out = subprocess.run(["addr2line", "-f", "-C", "-e", m.group(1), m.group(2)],
                             capture_output=True, text=True, timeout=10).stdout.splitlines()
    except (OSError, subprocess.SubprocessError):
        return line
    return f"{line}  = {out[0]}" if out and out[0] != "??" else line


def main():
    any_failed = False
    for build in sys.argv[1:]:
        for name, tail in failed_outputs(build):
            any_failed = True
            print(f"ci: FAILED in {build}: {name} (last {len(tail)} lines of its output)")
            for line in tail:
                print("    " + symbolized(line)[:300])
        for name, lines in warned_outputs(build):
            print(f"ci: passed with a warning in {build}: {name}")
            for line in lines:
                print("    " + line[:300])
    if not any_failed:
        print("ci: no failed test recorded")


if __name__ == "__main__":
    main()
