#!/usr/bin/env python3
"""The translation units clang-tidy must parse to see every source file of src/ (check_style.sh).

Reads BUILD/compile_commands.json (default build/). A room built as a unity build
(PATLAB_UNITY_BUILD) compiles its sources through generated files that #include them; those
files are listed instead of the sources, and a source listed on its own is listed as itself.
Exits 1, naming them, when a source of SOURCES (the arguments) is in no unit: a clang-tidy run
that skipped it would pass without looking at it.
"""
import json
import os
import re
import sys

INCLUDE = re.compile(r'^#include "([^"]+)"', re.M)


def main(argv):
    build = "build"
    if len(argv) >= 2 and argv[0] == "--build":
        build, argv = argv[1], argv[2:]
    sources = {os.path.abspath(s) for s in argv}
    with open(os.path.join(build, "compile_commands.json"), encoding="utf-8") as f:
        commands = json.load(f)
    units, seen = [], set()
    for entry in commands:
        path = os.path.normpath(os.path.join(entry["directory"], entry["file"]))
        if path in sources:
            units.append(path)
            seen.add(path)
            continue
        if "/Unity/unity_" not in path:
            continue
        with open(path, encoding="utf-8") as f:
            included = {os.path.normpath(p) for p in INCLUDE.findall(f.read())}
        if included & sources:
            units.append(path)
            seen |= included & sources
    missing = sorted(sources - seen)
    if missing:
        for path in missing:
            print(f"{os.path.relpath(path)}: in no translation unit of {build}/"
                  "compile_commands.json; expected every source built", file=sys.stderr)
        return 1
    print("\n".join(units))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
