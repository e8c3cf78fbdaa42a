#!/usr/bin/env python3
"""Fails when a Catch2 test name has a character ctest cannot carry.

catch_discover_tests cuts a test name at ';' (CMake's list separator), and the shortened name
then matches no test: ctest reports the test as passed without running it. Also reports the
names that are not unique, which Catch2 refuses at start-up.
Usage: check_test_names.py TESTS_DIR
"""
import pathlib
import re
import sys

NAME = re.compile(r'TEST_CASE\s*\(\s*((?:"(?:[^"\\]|\\.)*"\s*)+)', re.S)
bad, seen, dups = [], {}, []
for path in sorted(pathlib.Path(sys.argv[1]).rglob("*.cpp")):
    text = path.read_text(errors="replace")
    for m in NAME.finditer(text):
        name = "".join(re.findall(r'"((?:[^"\\]|\\.)*)"', m.group(1)))
        line = text.count("\n", 0, m.start()) + 1
        where = f"{path}:{line}"
        if ";" in name:
            bad.append(f"{where}: test name has ';' (ctest cuts the name there and runs nothing), expected ',': {name}")
        if name in seen:
            dups.append(f"{where}: test name also used at {seen[name]}: {name}")
        seen[name] = where
for line in bad + dups:
    print(line)
print(f"{len(seen)} test names checked, {len(bad) + len(dups)} problems")
sys.exit(1 if bad or dups else 0)
