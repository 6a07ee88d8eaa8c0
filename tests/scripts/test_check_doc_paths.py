"""scripts/check_doc_paths.py on small planted trees: paths that exist pass, and each form of a
source path that does not (src/..., patlab/<room>/x.h, <room>/x.h, a brace list) fails with its
docs/x.md:LINE message.

Run by ctest as `doc_paths_planted` (tests/CMakeLists.txt).
"""
import os
import subprocess
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECKER = os.path.join(ROOT, "scripts", "check_doc_paths.py")


def write(root, rel, text):
    path = os.path.join(root, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def tree(tmp_path, page):
    root = str(tmp_path)
    write(root, "scripts/rooms.txt", "# room: public uses ; private uses\ncore:\nsim: core\n")
    write(root, "src/patlab/core/rng.h", "")
    write(root, "src/patlab/sim/track.h", "")
    write(root, "src/patlab/sim/track.cpp", "")
    write(root, "src/cli/progress.h", "")
    write(root, "README.md", "See `src/cli/`.\n")
    write(root, "docs/page.md", page)
    return root


def run(root):
    return subprocess.run([sys.executable, CHECKER, "--root", root], capture_output=True,
                          text=True)


def test_existing_paths_pass(tmp_path):
    root = tree(tmp_path, "Code: `src/patlab/sim/track.{h,cpp}`, `core/rng.h`,\n"
                          "`#include \"patlab/sim/track.h\"`, cli/progress.h, `src/patlab/*/` and\n"
                          "`sim/<name>.h`; pbrt-v4 `src/pbrt/samplers.h`; io/data_path alone.\n")
    result = run(root)
    assert result.returncode == 0, result.stderr
    assert result.stderr == ""


def test_each_missing_form_is_reported_with_its_line(tmp_path):
    root = tree(tmp_path, "fine `core/rng.h`\n"
                          "moved `src/patlab/vision/camera.h`.\n"
                          "and `sim/analyze.h`, `patlab/core/gone.h`\n"
                          "Code: `src/patlab/sim/track.{h,cpp,py}`\n"
                          "the tool: `cli/nothing.cpp`\n")
    result = run(root)
    assert result.returncode == 1
    assert result.stderr.splitlines() == [
        "docs/page.md:2: 'src/patlab/vision/camera.h' does not exist; expected a path in the "
        "source tree (src/patlab/vision/camera.h is not)",
        "docs/page.md:3: 'sim/analyze.h' does not exist; expected a path in the source tree "
        "(src/patlab/sim/analyze.h is not)",
        "docs/page.md:3: 'patlab/core/gone.h' does not exist; expected a path in the source tree "
        "(src/patlab/core/gone.h is not)",
        "docs/page.md:4: 'src/patlab/sim/track.{h,cpp,py}' does not exist; expected a path in the "
        "source tree (src/patlab/sim/track.py is not)",
        "docs/page.md:5: 'cli/nothing.cpp' does not exist; expected a path in the source tree "
        "(src/cli/nothing.cpp is not)",
    ]


def test_readme_is_checked(tmp_path):
    root = tree(tmp_path, "nothing here\n")
    write(root, "README.md", "line one\nsee `src/patlab/core/missing.h`\n")
    result = run(root)
    assert result.returncode == 1
    assert result.stderr.startswith("README.md:2: 'src/patlab/core/missing.h' does not exist")
