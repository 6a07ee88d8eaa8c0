"""scripts/check_layering.sh on small planted trees: a clean tree passes, and each kind of breach
(an upward or undeclared include, a private room in a public header, a link that rooms.txt does
not declare, a cycle, a long file, a build order or document table that disagrees) fails with
its file:line message.

Run by ctest as `layering_planted` (tests/CMakeLists.txt).
"""
import os
import subprocess
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree

import pytest  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECKER = os.path.join(ROOT, "scripts", "check_layering.sh")

# Four rooms: base; side; mid uses base; top uses mid in its headers and base in its sources.
ROOMS = "# room: public uses ; private uses\nbase:\nside:\nmid: base\ntop: mid ; base\n"
DECLARED = {"base": "", "side": "", "mid": "PUBLIC patlab_base",
            "top": "PUBLIC patlab_mid PRIVATE patlab_base"}
TABLE = ("| room | what | uses (PUBLIC; PRIVATE) | external |\n|---|---|---|---|\n"
         "| `base/` | b | — | — |\n| `side/` | s | — | — |\n| `mid/` | m | base | — |\n"
         "| `top/` | t | mid; base | — |\n| `cli/` | the tool | everything | — |\n")


def write(root, rel, text):
    path = os.path.join(root, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


@pytest.fixture
def tree(tmp_path):
    """A tree that passes: every room includes only what rooms.txt lets it use."""
    root = str(tmp_path)
    write(root, "scripts/rooms.txt", ROOMS)
    write(root, "CMakeLists.txt",
          "foreach(module base side mid top)\n  add_subdirectory(src/patlab/${module})\n"
          "endforeach()\n")
    write(root, "docs/architecture.md", "# rooms\n\n" + TABLE)
    for room, deps in DECLARED.items():
        write(root, f"src/patlab/{room}/CMakeLists.txt", f"patlab_add_module({room} {deps})\n")
        write(root, f"src/patlab/{room}/{room}.h", "#pragma once\n")
    write(root, "src/patlab/mid/mid.cpp", '#include "patlab/mid/mid.h"\n#include "patlab/base/base.h"\n')
    write(root, "src/patlab/top/top.h", '#pragma once\n#include "patlab/mid/mid.h"\n')
    write(root, "src/patlab/top/top_internal.h", '#pragma once\n#include "patlab/base/base.h"\n')
    write(root, "src/patlab/top/top.cpp", '#include "patlab/top/top.h"\n#include "patlab/base/base.h"\n')
    write(root, "src/cli/main.cpp", '#include "patlab/top/top.h"\n#include "patlab/side/side.h"\n')
    write(root, "tests/top/top_test.cpp", "\n" * 500)
    return root


def check(root):
    proc = subprocess.run(["bash", CHECKER, "--root", root], capture_output=True, text=True)
    return proc.returncode, proc.stdout.splitlines()


def expect_problems(root, *expected):
    code, lines = check(root)
    assert code == 1, lines
    for problem in expected:
        assert problem in lines, "\n".join(lines)
    assert lines[-1] == f"layering: {len(lines) - 1} problem(s)"


def test_the_clean_tree_passes(tree):
    code, lines = check(tree)
    assert code == 0, lines
    assert lines == ["layering ok: 4 rooms, 3 room-to-room uses, 9 source files of at most 500 "
                     "lines"]


def test_an_upward_include_is_named_with_file_and_line(tree):
    write(tree, "src/patlab/base/base.cpp", "// base\n#include \"patlab/top/top.h\"\n")
    expect_problems(tree, "src/patlab/base/base.cpp:2: base includes top/, which base may not use "
                    "(an upward include: top comes after base; scripts/rooms.txt)")


def test_an_undeclared_include_is_named(tree):
    write(tree, "src/patlab/mid/mid.cpp", '#include "patlab/side/side.h"\n')
    expect_problems(tree, "src/patlab/mid/mid.cpp:1: mid includes side/, which mid may not use "
                    "(not declared; scripts/rooms.txt)")


def test_a_private_room_in_a_public_header_is_named(tree):
    write(tree, "src/patlab/top/top.h", '#pragma once\n#include "patlab/base/base.h"\n')
    expect_problems(tree, "src/patlab/top/top.h:2: top includes base/ in a public header, but "
                    "base is a private use of top (only sources and *_internal.h may include it; "
                    "scripts/rooms.txt)")


def test_an_include_cycle_is_named_with_every_step(tree):
    write(tree, "src/patlab/base/base.cpp", '#include "patlab/mid/mid.h"\n')
    expect_problems(tree,
                    "src/patlab/base/base.cpp:1: base includes mid/, which base may not use (an "
                    "upward include: mid comes after base; scripts/rooms.txt)",
                    "src/patlab/base/base.cpp:1: the includes make a cycle of rooms: base -> mid "
                    "(src/patlab/base/base.cpp:1), mid -> base (src/patlab/mid/mid.cpp:2)")


def test_a_declared_cycle_in_rooms_txt_is_named(tree):
    write(tree, "scripts/rooms.txt", ROOMS.replace("base:\n", "base: mid\n"))
    expect_problems(tree,
                    "scripts/rooms.txt:2: base uses mid, which is not before it in the order (a "
                    "room may use only rooms before it)",
                    "scripts/rooms.txt:2: the declared uses make a cycle: base -> mid -> base")


def test_a_link_that_rooms_txt_does_not_declare_is_named(tree):
    write(tree, "src/patlab/base/CMakeLists.txt",
          "# base\npatlab_add_module(base\n  PUBLIC patlab_core\n  PRIVATE patlab_top)\n")
    expect_problems(tree, "src/patlab/base/CMakeLists.txt:4: base links patlab_top PRIVATE, which "
                    "scripts/rooms.txt does not declare (base: -)")


def test_a_declared_use_that_is_not_linked_is_named(tree):
    write(tree, "src/patlab/top/CMakeLists.txt", "patlab_add_module(top PUBLIC patlab_mid)\n")
    expect_problems(tree, "src/patlab/top/CMakeLists.txt:1: scripts/rooms.txt declares that top "
                    "uses base (PRIVATE), but this file does not link patlab_base PRIVATE")


def test_a_file_over_500_lines_is_named_and_500_pass(tree):
    write(tree, "tests/top/long_test.cpp", "\n" * 501)
    write(tree, "src/patlab/mid/long.h", "\n" * 600)
    expect_problems(tree,
                    "tests/top/long_test.cpp:501: 501 lines; a source file has at most 500 "
                    "(split it along its concepts)",
                    "src/patlab/mid/long.h:501: 600 lines; a source file has at most 500 (split "
                    "it along its concepts)")


def test_the_long_files_list_allows_a_ceiling_and_only_shrinks(tree):
    write(tree, "src/patlab/mid/long.cpp", "\n" * 600)
    write(tree, "src/patlab/mid/grown.cpp", "\n" * 602)
    write(tree, "scripts/long_files.txt", "# list\nsrc/patlab/mid/long.cpp 600\n"
          "src/patlab/mid/grown.cpp 601\nsrc/patlab/mid/mid.h 700\nsrc/patlab/gone.cpp 900\n")
    expect_problems(tree,
                    "src/patlab/mid/grown.cpp:602: 602 lines; a source file has at most 601 "
                    "(split it along its concepts)",
                    "scripts/long_files.txt:4: src/patlab/mid/mid.h has 1 lines now, within the "
                    "limit of 500; remove its entry",
                    "scripts/long_files.txt:5: src/patlab/gone.cpp does not exist; remove its "
                    "entry")


def test_a_build_order_other_than_rooms_txt_is_named(tree):
    write(tree, "CMakeLists.txt", "project(x)\nforeach(module base mid side top)\n"
          "  add_subdirectory(src/patlab/${module})\nendforeach()\n")
    expect_problems(tree, "CMakeLists.txt:2: the rooms are built in the order base mid side top; "
                    "scripts/rooms.txt says base side mid top")


def test_a_document_table_that_disagrees_is_named(tree):
    write(tree, "docs/architecture.md", "# rooms\n\n" + TABLE.replace("| mid; base |", "| mid |"))
    expect_problems(tree, "docs/architecture.md:8: top uses 'mid'; scripts/rooms.txt:5 says "
                    "'mid ; base'")


def test_a_room_directory_that_rooms_txt_does_not_list_is_named(tree):
    write(tree, "src/patlab/extra/extra.h", "#pragma once\n")
    expect_problems(tree, "src/patlab/extra/: a room that scripts/rooms.txt does not list")


def test_a_namespace_other_than_the_room_s_is_named(tree):
    write(tree, "src/patlab/mid/mid.cpp",
          '#include "patlab/mid/mid.h"\n#include "patlab/base/base.h"\n\n'
          "namespace patlab::mid {\nnamespace {\nint Local() { return 1; }\n}  // namespace\n"
          "}  // namespace patlab::mid\n\nnamespace patlab::mid::internal {\n"
          "namespace detail {}\n}  // namespace patlab::mid::internal\n\n"
          "// namespace patlab::top { in a comment\nconst char* k = \"namespace patlab::top {\";\n"
          "namespace patlab::top {\nint Stray();\n}  // namespace patlab::top\n"
          "namespace patlab {\nint Loose();\n}  // namespace patlab\n"
          "namespace ceres {\nclass LossFunction;\n}  // a library's type, forward-declared\n")
    write(tree, "src/patlab/top/top_internal.h",
          '#pragma once\n#include "patlab/base/base.h"\n\nnamespace patlab::base::internal {\n}\n')
    expect_problems(tree,
                    "src/patlab/mid/mid.cpp:16: namespace patlab::top in room mid; expected "
                    "patlab::mid",
                    "src/patlab/mid/mid.cpp:19: namespace patlab in room mid; expected "
                    "patlab::mid",
                    "src/patlab/top/top_internal.h:4: namespace patlab::base::internal in room "
                    "top; expected patlab::top")
    code, lines = check(tree)
    assert len(lines) == 4, "\n".join(lines)


def test_core_opens_patlab_and_its_math_namespace_only(tree):
    write(tree, "scripts/rooms.txt", ROOMS.replace("base:\n", "core:\nbase:\n"))
    write(tree, "CMakeLists.txt", "foreach(module core base side mid top)\n"
          "  add_subdirectory(src/patlab/${module})\nendforeach()\n")
    write(tree, "docs/architecture.md", "# rooms\n\n" + TABLE.replace(
        "| `base/` |", "| `core/` | c | — | — |\n| `base/` |"))
    write(tree, "src/patlab/core/CMakeLists.txt", "patlab_add_module(core)\n")
    write(tree, "src/patlab/core/core.h",
          "#pragma once\nnamespace patlab {\nnamespace detail {}\n}  // namespace patlab\n"
          "namespace patlab::pmath {\n}  // namespace patlab::pmath\n")
    write(tree, "src/patlab/core/math.h", "#pragma once\nnamespace patlab::core {\n}\n")
    expect_problems(tree, "src/patlab/core/math.h:2: namespace patlab::core in room core; "
                    "expected patlab or patlab::pmath")
    code, lines = check(tree)
    assert len(lines) == 2, "\n".join(lines)
