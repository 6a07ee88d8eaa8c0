"""patlab.Pattern: loading by path, by name and from text; patches as arrays; errors."""
import math

import numpy as np
import pytest

import patlab
from conftest import cli_message

BUTTERFLY_TOML = """
name = "two"
[[patch]]
x = 0.0
y = 0.0
radius = 25.0
role = "key"
[[patch]]
x = 60.0
y = 0.0
radius = 20.0
role = "id"
"""


def test_load_by_path_and_by_name_agree(root):
    by_path = patlab.Pattern.load(root / "patterns" / "butterfly.toml")
    by_name = patlab.Pattern.load("butterfly")
    assert by_path.name == by_name.name == "butterfly"
    np.testing.assert_array_equal(by_path.positions_mm, by_name.positions_mm)


def test_patches_are_arrays_of_the_file(root):
    p = patlab.Pattern.load("butterfly")
    assert p.size == 5 and p.positions_mm.shape == (5, 2) and p.positions_mm.dtype == np.float64
    assert p.roles[p.key_index] == "key"
    # The paper's Butterfly: key at the origin, four patches at 65 mm (35, +-54.772), ...
    np.testing.assert_allclose(np.hypot(*p.positions_mm[1:].T), 65.0, atol=1e-3)
    spread = ((p.positions_mm - p.positions_mm.mean(axis=0)) ** 2).sum()
    assert math.isclose(p.spread_mm2, spread, rel_tol=1e-12)
    assert p.orientation_pairs.shape[1] == 2
    assert "butterfly" in repr(p)


def test_from_toml():
    p = patlab.Pattern.from_toml(BUTTERFLY_TOML)
    assert p.name == "two" and p.size == 2
    np.testing.assert_array_equal(p.radii_mm, [25.0, 20.0])


def test_missing_file_is_file_not_found_with_the_cli_message(cli, tmp_path):
    missing = tmp_path / "none" / "missing.toml"
    with pytest.raises(FileNotFoundError) as error:
        patlab.Pattern.load(missing)
    assert str(error.value) == cli_message(cli("ids", missing), "ids")


def test_bad_file_is_value_error_with_the_cli_message(cli, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(BUTTERFLY_TOML.replace('role = "key"', 'role = "boss"'))
    with pytest.raises(ValueError) as error:
        patlab.Pattern.load(bad)
    assert str(error.value) == cli_message(cli("ids", bad), "ids")


def test_unknown_name_is_value_error():
    with pytest.raises(ValueError, match="pattern 'no-such-pattern' not found"):
        patlab.Pattern.load("no-such-pattern")
