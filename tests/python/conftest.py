"""Fixtures of the Python module's tests: the source tree, the CLI binary and a runner for it.

ctest (`python`) sets PYTHONPATH to <build>/python and PATLAB_BINARY to the tool."""
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def cli():
    """cli(*args) -> CompletedProcess of the patlab tool (text), run from the source tree."""
    binary = os.environ.get("PATLAB_BINARY")
    if not binary or not os.path.exists(binary):
        pytest.skip("PATLAB_BINARY is not set to the patlab tool (ctest sets it)")

    def run(*args):
        return subprocess.run([binary, *map(str, args)], cwd=ROOT, capture_output=True,
                              text=True, check=False)
    return run


def cli_message(process, command):
    """The message of a failed CLI run: stderr without its 'patlab <command>: ' prefix."""
    assert process.returncode == 2, process.stderr
    prefix = f"patlab {command}: "
    text = process.stderr.strip()
    assert text.startswith(prefix), text
    return text[len(prefix):]
