#!/usr/bin/python3
"""The largest source files and functions of patlab, against the size limits of docs/contributing.md.

    /usr/bin/python3 scripts/code_size.py [--top N]

Files: lines of every tracked .h/.cpp under src/. Functions: clang-tidy's readability-function-size
line count (including whitespace and comments) of every function of at least 30 lines, read from
a run over the translation units of build/compile_commands.json (scripts/build.sh writes
it; scripts/tidy_units.py).
"""
import argparse
import os
import re
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def tracked_sources():
    out = subprocess.run(["git", "ls-files", "src/*.cpp", "src/*.h"], cwd=ROOT, check=True,
                         capture_output=True, text=True).stdout
    return [line for line in out.splitlines() if line]


def function_sizes(sources):
    config = "{CheckOptions: [{key: readability-function-size.LineThreshold, value: 30}]}"
    cpp = [os.path.join(ROOT, s) for s in sources if s.endswith(".cpp")]
    # The translation units that compile them (a room's unity build: scripts/tidy_units.py).
    cpp = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "tidy_units.py")] + cpp,
                         cwd=ROOT, check=True, capture_output=True, text=True).stdout.split()
    proc = subprocess.run(["run-clang-tidy", "-quiet", "-p", os.path.join(ROOT, "build"),
                           "-checks=-*,readability-function-size", "-config=" + config,
                           "-header-filter=src/(patlab|cli|python)/"] + cpp,
                          cwd=ROOT, capture_output=True, text=True)
    sizes, name = {}, None
    for line in proc.stdout.splitlines():
        line = re.sub(r"\x1b\[[0-9;]*m", "", line)  # run-clang-tidy colours its output
        m = re.search(r"(src/[^:]+):(\d+):\d+: (?:warning|error): function '([^']+)' exceeds", line)
        if m:
            name = (m.group(1), int(m.group(2)), m.group(3))
            continue
        m = re.search(r"note: (\d+) lines including", line)
        if m and name:
            sizes[name] = int(m.group(1))
            name = None
    return sorted(sizes.items(), key=lambda kv: -kv[1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--top", type=int, default=10)
    args = parser.parse_args()
    sources = tracked_sources()
    lines = []
    for s in sources:
        with open(os.path.join(ROOT, s), encoding="utf-8") as f:
            lines.append((sum(1 for _ in f), s))
    print(f"largest files (of {len(sources)} under src/):")
    for n, s in sorted(lines, reverse=True)[:args.top]:
        print(f"  {n:5d}  {s}")
    print("largest functions (lines including whitespace and comments):")
    for (path, line, func), n in function_sizes(sources)[:args.top]:
        print(f"  {n:5d}  {func}  ({path}:{line})")


if __name__ == "__main__":
    main()
