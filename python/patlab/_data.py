"""Shipped data found by name (patterns/<name>.toml, experiments/<name>.toml), as the CLI finds it.

The data roots, in search order: $PATLAB_DATA, the installed <prefix>/share/patlab above this
package, and, for a package in a build tree, the source tree named by the build's CMakeCache.txt.
"""
import os
import pathlib

_FOLDERS = {"pattern": ("patterns",), "experiment": ("experiments", "experiments/camera-noise"),
            "settings": ("settings", "experiments")}


def _source_tree(build_dir):
    cache = build_dir / "CMakeCache.txt"
    if not cache.is_file():
        return None
    for line in cache.read_text(errors="replace").splitlines():
        if line.startswith("patlab_SOURCE_DIR:"):
            return pathlib.Path(line.split("=", 1)[1])
    return None


def data_roots():
    """The existing data roots, in search order."""
    roots = []
    env = os.environ.get("PATLAB_DATA")
    if env:
        roots.append(pathlib.Path(env))
    here = pathlib.Path(__file__).resolve().parent
    for ancestor in here.parents:
        if (ancestor / "share" / "patlab").is_dir():
            roots.append(ancestor / "share" / "patlab")
            break
    source = _source_tree(here.parent.parent)
    if source is not None:
        roots.append(source)
    return [str(r) for r in roots if r.is_dir()]


def find(reference, kind):
    """`reference` if it is an existing file or has a folder in it, else the first
    <root>/<folder>/<reference>[.toml] of the kind; ValueError when there is none."""
    reference = os.fspath(reference)
    if os.path.exists(reference) or os.sep in reference:
        return reference
    searched = []
    for root in data_roots():
        for folder in _FOLDERS[kind]:
            base = os.path.join(root, folder)
            searched.append(base + "/")
            for candidate in (os.path.join(base, reference), os.path.join(base, reference + ".toml")):
                if os.path.isfile(candidate):
                    return candidate
    where = ", ".join(searched) if searched else "no data folder (set PATLAB_DATA)"
    raise ValueError(f"{kind} '{reference}' not found; expected a file path or a name in {where}")
