"""patlab.ids, evaluate and compare: the CLI's reports for the same options."""
import json

import pytest

import patlab

SMALL = {"trials": 2000, "frames": 40, "sigmas_mm": [1.0, 2.0], "colour_counts": [2],
         "seed": 5}
SMALL_FLAGS = ["--trials", 2000, "--frames", 40, "--sigmas", "1,2", "--colors", 2, "--seed", 5]


@pytest.mark.parametrize("colours", [2, 3, 4])
def test_butterfly_has_every_colouring(colours):
    """Table II: the Butterfly's four ID slots have no rotational symmetry, so n^4 IDs."""
    result = patlab.ids("butterfly", colours)
    assert result.count == colours ** 4 == len(result) and result.rotations == 1
    assert sorted(result.ids) == list(range(colours ** 4))


def test_symmetric_pattern_has_fewer_ids_than_colourings():
    """A pattern whose rotations about the key geometry cannot tell apart: colourings that a
    rotation maps onto each other are one ID (Burnside), never more than n^slots / rotations."""
    result = patlab.ids("simple", ["pink", "green"])
    slots = len(result.slots)
    assert result.count * result.rotations <= 2 ** slots
    assert list(result.table.columns)[0] == "id"


def test_ids_counts_are_the_clis(cli):
    out = cli("ids", "patterns/triangle.toml", "--colors", "2,3").stdout
    row = next(line for line in out.splitlines() if line.startswith("triangle"))
    counts = [int(v) for v in row.split()[-2:]]
    assert counts == [patlab.ids("triangle", n).count for n in (2, 3)]


def test_evaluate_is_the_clis_json(cli, root, monkeypatch):
    monkeypatch.chdir(root)
    result = patlab.evaluate("patterns/butterfly.toml", **SMALL)
    run = cli("evaluate", "patterns/butterfly.toml", "--format", "json", *SMALL_FLAGS)
    assert run.returncode == 0, run.stderr
    assert result.json == json.loads(run.stdout)
    assert result.reports[0]["pattern"] == "butterfly" or "butterfly" in json.dumps(result.json)


def test_compare_is_the_clis_csv(cli, root, monkeypatch):
    monkeypatch.chdir(root)
    designs = ["patterns/butterfly.toml", "patterns/ssl-standard.toml"]
    result = patlab.compare(designs, **SMALL)
    run = cli("compare", *designs, "--format", "csv", *SMALL_FLAGS)
    assert run.returncode == 0, run.stderr
    assert result.csv == run.stdout
    assert len(result.table["design"]) == 2


def test_bad_options_are_value_errors():
    with pytest.raises(ValueError, match="unknown option 'sigma'"):
        patlab.evaluate("butterfly", sigma=1.0)
    with pytest.raises(ValueError, match="tolerance_mm is -1; expected a distance in mm >= 0"):
        patlab.ids("butterfly", 2, tolerance_mm=-1)
