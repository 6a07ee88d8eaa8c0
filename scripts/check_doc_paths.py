#!/usr/bin/env python3
"""Every source path that docs/*.md and README.md mention exists.

The forms checked: `src/...` (a file or a folder), `patlab/<room>/x.h` and `<room>/x.h` (a header
or source of a room of scripts/rooms.txt, or of the command line, cli/), with brace lists
expanded (`sim/track.{h,cpp}`). Paths with a wildcard or a placeholder (`*`, `<`) are skipped.
A missing one is reported as `docs/x.md:LINE: 'path' does not exist; expected ...` and the exit
status is 1. Run by scripts/check_style.sh and the ctest doc_paths.

usage: scripts/check_doc_paths.py [--root DIR] [FILE.md...]
"""
import argparse
import pathlib
import re
import sys


# Other projects' sources that the docs cite (a paper's or a renderer's code), not ours.
FOREIGN = ("src/pbrt/",)


def rooms(root):
    names = []
    for line in (root / "scripts" / "rooms.txt").read_text().splitlines():
        match = re.match(r"^(\w+):", line)
        if match:
            names.append(match.group(1))
    return names


def expand(path):
    """`a.{h,cpp}` -> [`a.h`, `a.cpp`]; one brace list at most."""
    match = re.search(r"\{([^{}]*)\}", path)
    if not match:
        return [path]
    return [path[:match.start()] + item + path[match.end():] for item in match.group(1).split(",")]


def mentions(line, room_names):
    """(text as written, the path under the root) for every source path in `line`."""
    found = []
    lead = r"(?<![\w/.$~-])"
    for match in re.finditer(lead + r"src/[\w./{},-]*", line):
        found.append((match.group(0), match.group(0)))
    rooms_alt = "|".join(room_names + ["cli"])
    header = lead + r"(patlab/)?(" + rooms_alt + r")/[\w./-]*?\.(?:h|cpp|\{[\w,]+\})(?![\w])"
    for match in re.finditer(header, line):
        text = match.group(0)
        if line[max(0, match.start() - 4):match.start()].endswith("src/"):
            continue
        inner = text[len("patlab/"):] if match.group(1) else text
        base = "src/" if match.group(2) == "cli" else "src/patlab/"
        found.append((text, base + inner))
    return found


def check(root, files):
    room_names = rooms(root)
    problems = []
    for md in files:
        shown = md.relative_to(root) if md.is_relative_to(root) else md
        for number, line in enumerate(md.read_text().splitlines(), 1):
            for text, path in mentions(line, room_names):
                path = path.rstrip(".,")
                text = text.rstrip(".,")
                if ("*" in path or "<" in path or path in ("src", "src/")
                        or path.startswith(FOREIGN)):
                    continue
                for one in expand(path):
                    if not (root / one).exists():
                        problems.append(f"{shown}:{number}: '{text}' does not exist; expected "
                                        f"a path in the source tree ({one} is not)")
    return problems


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--root", default=pathlib.Path(__file__).resolve().parent.parent,
                        type=pathlib.Path)
    parser.add_argument("files", nargs="*", type=pathlib.Path)
    args = parser.parse_args()
    root = args.root.resolve()
    files = [f.resolve() for f in args.files] or (
        sorted((root / "docs").glob("*.md")) + [root / "README.md"])
    problems = check(root, files)
    for problem in problems:
        print(problem, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
