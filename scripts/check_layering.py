#!/usr/bin/python3
"""The rooms' layering and the size of files, checked against scripts/rooms.txt.

    /usr/bin/python3 scripts/check_layering.py [--root DIR]   (scripts/check_layering.sh)

Fails (exit 1), naming file and line, on
  - an include in src/patlab/<room>/ of a room that <room> may not use: one after it (upward),
    one it does not declare, or a private one in a public header;
  - a room linked in src/patlab/<room>/CMakeLists.txt other than the ones rooms.txt declares,
    with the same PUBLIC / PRIVATE split (and a declared one that is not linked);
  - a cycle among the rooms, declared in rooms.txt or made by includes;
  - rooms.txt itself: a use of a room that is not before it, a room without a directory;
  - the room order in CMakeLists.txt and the room table of docs/architecture.md differing from
    rooms.txt;
  - a namespace opened at file scope in src/patlab/<room>/ other than patlab::<room> (or one
    nested in it, such as patlab::<room>::internal); core's files open patlab itself or its
    math namespace patlab::pmath (docs/architecture.md, rule 14); a library's own namespace
    (a forward declaration such as `namespace ceres { class LossFunction; }`) is not patlab's and
    is left alone;
  - a .cpp or .h file under src/, tests/ or examples/ over 500 lines, unless
    scripts/long_files.txt lets it have more (up to the count it gives; an entry for a file that
    is no longer over the limit is a problem too, so the list only shrinks).
A file of the tree that is absent (CMakeLists.txt, the document) is not checked, so that the
checker runs on a small tree of its planted-failure test (tests/scripts/test_check_layering.py).
"""
import argparse
import os
import re
import sys

MAX_FILE_LINES = 500
INCLUDE = re.compile(r'^\s*#\s*include\s*["<](?:patlab/|\.\./)(\w+)/')
NAMESPACE = re.compile(r"\bnamespace\s+([\w:]+)\s*\{")
CORE_NAMESPACES = ("patlab", "patlab::pmath")
ROOMS_LINE = re.compile(r"^(\w+)\s*:\s*([\w\s]*?)\s*(?:;\s*([\w\s]*?)\s*)?$")


class Rooms:
    """rooms.txt: the order, and each room's public and private uses with the line they are on."""

    def __init__(self):
        self.order = []
        self.public = {}
        self.private = {}
        self.line = {}


def read_rooms(path, problems):
    rooms = Rooms()
    with open(path, encoding="utf-8") as f:
        for number, text in enumerate(f, 1):
            text = text.split("#", 1)[0].strip()
            if not text:
                continue
            m = ROOMS_LINE.match(text)
            if not m:
                problems.append(f"{path}:{number}: '{text}'; expected '<room>: <public uses> "
                                "[; <private uses>]'")
                continue
            room = m.group(1)
            rooms.order.append(room)
            rooms.public[room] = m.group(2).split()
            rooms.private[room] = (m.group(3) or "").split()
            rooms.line[room] = number
    return rooms


def check_rooms_file(rooms, path, problems):
    """Every use names a room before the user; no cycle among the declared uses."""
    position = {room: i for i, room in enumerate(rooms.order)}
    for room in rooms.order:
        for used in rooms.public[room] + rooms.private[room]:
            where = f"{path}:{rooms.line[room]}"
            if used not in position:
                problems.append(f"{where}: {room} uses {used}, which is not a room")
            elif position[used] >= position[room]:
                problems.append(f"{where}: {room} uses {used}, which is not before it in the "
                                "order (a room may use only rooms before it)")
    graph = {r: set(rooms.public[r] + rooms.private[r]) & set(position) for r in rooms.order}
    for cycle in find_cycles(graph):
        problems.append(f"{path}:{rooms.line[cycle[0]]}: the declared uses make a cycle: "
                        + " -> ".join(cycle + [cycle[0]]))


def find_cycles(graph):
    """Each elementary cycle found by a depth-first search, once, as a list of rooms."""
    cycles, seen = [], set()
    state = {}

    def visit(node, path):
        state[node] = "open"
        path.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == "open":
                cycle = path[path.index(nxt):]
                key = frozenset(cycle)
                if key not in seen:
                    seen.add(key)
                    cycles.append(cycle)
            elif nxt not in state:
                visit(nxt, path)
        path.pop()
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            visit(node, [])
    return cycles


def source_files(root, top):
    base = os.path.join(root, top)
    for folder, dirs, files in os.walk(base):
        dirs.sort()
        for name in sorted(files):
            if name.endswith((".cpp", ".h")):
                yield os.path.join(folder, name)


def is_public_header(path):
    return path.endswith(".h") and not path.endswith("_internal.h")


def check_includes(root, rooms, problems):
    """Every include of another room is declared; returns the include edges room -> used."""
    position = {room: i for i, room in enumerate(rooms.order)}
    edges = {}
    for room in rooms.order:
        allowed_public = set(rooms.public[room])
        allowed = allowed_public | set(rooms.private[room])
        for path in source_files(root, os.path.join("src", "patlab", room)):
            rel = os.path.relpath(path, root)
            with open(path, encoding="utf-8", errors="replace") as f:
                for number, text in enumerate(f, 1):
                    m = INCLUDE.match(text)
                    if not m or m.group(1) == room:
                        continue
                    used = m.group(1)
                    where = f"{rel}:{number}: {room} includes {used}/"
                    edges.setdefault((room, used), f"{rel}:{number}")
                    if used not in position:
                        problems.append(f"{where}, which is not a room")
                    elif used not in allowed:
                        kind = ("an upward include: " + used + " comes after " + room
                                if position[used] > position[room] else "not declared")
                        problems.append(f"{where}, which {room} may not use ({kind}; "
                                        "scripts/rooms.txt)")
                    elif is_public_header(rel) and used not in allowed_public:
                        problems.append(f"{where} in a public header, but {used} is a private "
                                        f"use of {room} (only sources and *_internal.h may "
                                        "include it; scripts/rooms.txt)")
    return edges


def check_include_cycles(edges, problems):
    graph = {}
    for used_by, used in edges:
        graph.setdefault(used_by, set()).add(used)
    for cycle in find_cycles(graph):
        steps = [f"{a} -> {b} ({edges[(a, b)]})"
                 for a, b in zip(cycle, cycle[1:] + [cycle[0]])]
        problems.append(f"{edges[(cycle[0], cycle[1 % len(cycle)])]}: the includes make a cycle "
                        "of rooms: " + ", ".join(steps))


def code_of(line, in_comment):
    """A line without its comments and string literals; and whether a /* comment stays open."""
    out, i = [], 0
    while i < len(line):
        if in_comment:
            end = line.find("*/", i)
            if end < 0:
                return "".join(out), True
            in_comment, i = False, end + 2
        elif line.startswith("//", i):
            break
        elif line.startswith("/*", i):
            in_comment, i = True, i + 2
        elif line[i] in "\"'":
            quote, i = line[i], i + 1
            while i < len(line) and line[i] != quote:
                i += 2 if line[i] == "\\" else 1
            i += 1
            out.append('""')
        else:
            out.append(line[i])
            i += 1
    return "".join(out), in_comment


def expected_namespaces(room):
    return CORE_NAMESPACES if room == "core" else (f"patlab::{room}",)


def namespace_allowed(name, room):
    """patlab::<room> or a namespace nested in it; in core, patlab itself (not one nested in it,
    which would be a room's name) or patlab::pmath and those nested in it. A namespace outside
    patlab (a library's, opened to forward-declare one of its types) is not checked."""
    if name != "patlab" and not name.startswith("patlab::"):
        return True
    if room == "core":
        return name == "patlab" or name == "patlab::pmath" or name.startswith("patlab::pmath::")
    return name == f"patlab::{room}" or name.startswith(f"patlab::{room}::")


def check_namespaces(root, rooms, problems):
    """Each namespace a room's file opens at file scope is the room's own (or nested in it)."""
    for room in rooms.order:
        allowed = expected_namespaces(room)
        for path in source_files(root, os.path.join("src", "patlab", room)):
            rel = os.path.relpath(path, root)
            depth, in_comment = 0, False
            with open(path, encoding="utf-8", errors="replace") as f:
                for number, text in enumerate(f, 1):
                    if text.lstrip().startswith("#"):
                        continue
                    code, in_comment = code_of(text, in_comment)
                    opened = {m.end() - 1: m.group(1) for m in NAMESPACE.finditer(code)}
                    for i, c in enumerate(code):
                        if c == "{":
                            name = opened.get(i)
                            if depth == 0 and name is not None and not namespace_allowed(
                                    name, room):
                                problems.append(f"{rel}:{number}: namespace {name} in room "
                                                f"{room}; expected {' or '.join(allowed)}")
                            depth += 1
                        elif c == "}":
                            depth = max(depth - 1, 0)


def cmake_calls(text, names):
    """(name, [(token, line)]) for each call of one of `names` in a CMake file."""
    for m in re.finditer(r"\b(" + "|".join(names) + r")\s*\(", text):
        depth, i = 1, m.end()
        while i < len(text) and depth:
            depth += {"(": 1, ")": -1}.get(text[i], 0)
            i += 1
        body_start = m.end()
        body = re.sub(r"#[^\n]*", "", text[body_start:i - 1])
        tokens = []
        for t in re.finditer(r"[^\s()]+", body):
            line = text.count("\n", 0, body_start + t.start()) + 1
            tokens.append((t.group(0), line))
        yield m.group(1), tokens


def linked_rooms(path, room, rooms):
    """{(used, 'PUBLIC'|'PRIVATE'): line} of the rooms that a room's CMakeLists.txt links."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    linked = {}
    for name, tokens in cmake_calls(text, ["patlab_add_module", "target_link_libraries"]):
        mode = "PUBLIC" if name == "patlab_add_module" else "PRIVATE"
        for token, line in tokens[1:]:
            if token in ("PUBLIC", "PRIVATE", "INTERFACE"):
                mode = "PUBLIC" if token == "INTERFACE" else token
                continue
            m = re.fullmatch(r"patlab_(\w+)", token)
            if m and m.group(1) != room and m.group(1) not in ("options", "all"):
                linked.setdefault((m.group(1), mode), line)
    return linked


def check_cmake(root, rooms, problems):
    for room in rooms.order:
        path = os.path.join(root, "src", "patlab", room, "CMakeLists.txt")
        if not os.path.isfile(path):
            continue
        rel = os.path.relpath(path, root)
        linked = linked_rooms(path, room, rooms)
        declared = {(u, "PUBLIC") for u in rooms.public[room]}
        declared |= {(u, "PRIVATE") for u in rooms.private[room]}
        for (used, mode), line in sorted(linked.items(), key=lambda kv: kv[1]):
            if (used, mode) not in declared:
                problems.append(f"{rel}:{line}: {room} links patlab_{used} {mode}, which "
                                f"scripts/rooms.txt does not declare ({room}: "
                                f"{describe_uses(rooms, room)})")
        for used, mode in sorted(declared - set(linked)):
            problems.append(f"{rel}:1: scripts/rooms.txt declares that {room} uses {used} "
                            f"({mode}), but this file does not link patlab_{used} {mode}")


def describe_uses(rooms, room):
    text = " ".join(rooms.public[room]) or "-"
    if rooms.private[room]:
        text += " ; " + " ".join(rooms.private[room])
    return text


def check_room_dirs(root, rooms, problems):
    base = os.path.join(root, "src", "patlab")
    present = sorted(d for d in os.listdir(base) if os.path.isdir(os.path.join(base, d)))
    for d in present:
        if d not in rooms.public:
            problems.append(f"src/patlab/{d}/: a room that scripts/rooms.txt does not list")
    for room in rooms.order:
        if room not in present:
            problems.append(f"scripts/rooms.txt:{rooms.line[room]}: {room} has no directory "
                            f"src/patlab/{room}/")


def check_build_order(root, rooms, problems):
    path = os.path.join(root, "CMakeLists.txt")
    if not os.path.isfile(path):
        return
    with open(path, encoding="utf-8") as f:
        text = f.read()
    m = re.search(r"foreach\(module([^)]*)\)\s*\n\s*add_subdirectory\(src/patlab/\$\{module\}\)",
                  text)
    if not m:
        problems.append("CMakeLists.txt:1: no foreach(module ...) add_subdirectory("
                        "src/patlab/${module}) that lists the rooms")
        return
    order = m.group(1).split()
    if order != rooms.order:
        line = text.count("\n", 0, m.start()) + 1
        problems.append(f"CMakeLists.txt:{line}: the rooms are built in the order "
                        f"{' '.join(order)}; scripts/rooms.txt says {' '.join(rooms.order)}")


def check_document(root, rooms, problems):
    """The table of docs/architecture.md: one row per room, in order, with the same uses."""
    path = os.path.join(root, "docs", "architecture.md")
    if not os.path.isfile(path):
        return
    rows = []
    with open(path, encoding="utf-8") as f:
        for number, text in enumerate(f, 1):
            m = re.match(r"^\|\s*`(\w+)/`\s*\|[^|]*\|([^|]*)\|", text)
            if m and m.group(1) != "cli":
                rows.append((m.group(1), m.group(2).strip(), number))
    if [r[0] for r in rows] != rooms.order:
        line = rows[0][2] if rows else 1
        problems.append(f"docs/architecture.md:{line}: the room table lists "
                        f"{' '.join(r[0] for r in rows) or 'no rooms'}; scripts/rooms.txt "
                        f"says {' '.join(rooms.order)}")
    for room, uses, number in rows:
        if room not in rooms.public:
            continue
        public, _, private = uses.partition(";")
        names = [re.findall(r"\w+", public), re.findall(r"\w+", private)]
        if sorted(names[0]) != sorted(rooms.public[room]) or \
                sorted(names[1]) != sorted(rooms.private[room]):
            problems.append(f"docs/architecture.md:{number}: {room} uses '{uses}'; "
                            f"scripts/rooms.txt:{rooms.line[room]} says "
                            f"'{describe_uses(rooms, room)}'")


def read_long_files(root, problems):
    """scripts/long_files.txt: {path: (most lines, line of the entry)}."""
    path = os.path.join(root, "scripts", "long_files.txt")
    allowed = {}
    if not os.path.isfile(path):
        return allowed
    with open(path, encoding="utf-8") as f:
        for number, text in enumerate(f, 1):
            words = text.split("#", 1)[0].split()
            if not words:
                continue
            if len(words) != 2 or not words[1].isdigit():
                problems.append(f"scripts/long_files.txt:{number}: '{text.strip()}'; expected "
                                "'<path> <most lines>'")
                continue
            allowed[words[0]] = (int(words[1]), number)
    return allowed


def check_file_sizes(root, problems):
    allowed = read_long_files(root, problems)
    count = 0
    for top in ("src", "tests", "examples"):
        for path in source_files(root, top):
            count += 1
            rel = os.path.relpath(path, root)
            with open(path, encoding="utf-8", errors="replace") as f:
                lines = sum(1 for _ in f)
            limit, entry = allowed.pop(rel, (MAX_FILE_LINES, None))
            if entry is not None and lines <= MAX_FILE_LINES:
                problems.append(f"scripts/long_files.txt:{entry}: {rel} has {lines} lines now, "
                                f"within the limit of {MAX_FILE_LINES}; remove its entry")
            elif lines > limit:
                problems.append(f"{rel}:{limit + 1}: {lines} lines; a source file has at most "
                                f"{limit} (split it along its concepts)")
    for rel, (_, entry) in sorted(allowed.items(), key=lambda kv: kv[1][1]):
        problems.append(f"scripts/long_files.txt:{entry}: {rel} does not exist; remove its entry")
    return count


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default=os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))), help="the tree to check (default: this checkout)")
    args = parser.parse_args()
    root = os.path.abspath(args.root)
    rooms_path = os.path.join(root, "scripts", "rooms.txt")
    if not os.path.isfile(rooms_path):
        print(f"check_layering: {rooms_path}: no such file", file=sys.stderr)
        return 1
    problems = []
    rooms = read_rooms(rooms_path, problems)
    check_rooms_file(rooms, "scripts/rooms.txt", problems)
    check_room_dirs(root, rooms, problems)
    check_build_order(root, rooms, problems)
    check_document(root, rooms, problems)
    check_cmake(root, rooms, problems)
    edges = check_includes(root, rooms, problems)
    check_include_cycles(edges, problems)
    check_namespaces(root, rooms, problems)
    files = check_file_sizes(root, problems)
    for problem in problems:
        print(problem)
    if problems:
        print(f"layering: {len(problems)} problem(s)")
        return 1
    print(f"layering ok: {len(rooms.order)} rooms, {len(edges)} room-to-room uses, "
          f"{files} source files of at most {MAX_FILE_LINES} lines")
    return 0


if __name__ == "__main__":
    sys.exit(main())
