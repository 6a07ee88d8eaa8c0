"""Shipped data found by name ("butterfly", "fig5"), by the library's lookup the CLI uses
(io/data_path.h): $PATLAB_DATA, the installed <prefix>/share/patlab above this package, and,
for a package in a build tree, the source tree that build was configured from."""
import functools
import os
import pathlib

from . import _patlab


@functools.lru_cache(maxsize=1)
def _binary_dir():
    """What the CLI's own folder is to the lookup: the build tree holding this package
    (<build>/python/patlab), or <prefix>/bin for a package installed under <prefix>."""
    here = pathlib.Path(__file__).resolve().parent
    for ancestor in here.parents:
        if (ancestor / "CMakeCache.txt").is_file():
            return str(ancestor)
        if (ancestor / "share" / "patlab").is_dir():
            return str(ancestor / "bin")
    return ""


def find(reference, kind):
    """`reference` if it names an existing file or has a folder in it, else the shipped file of
    that name and kind ("pattern", "experiment", "settings", "field"); ValueError with the
    CLI's message when there is none."""
    return _patlab._find_data(os.fspath(reference), kind, _binary_dir())
