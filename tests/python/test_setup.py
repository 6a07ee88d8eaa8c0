"""patlab.setup on the rendered scene of settings/ssl-half-field.toml (a known camera, ten
robots): the report as a dict, the folder `detect(image, setup=DIR)` reads finds every robot,
the same files and report as `patlab setup` writes."""
import csv
import io

import numpy as np
import pytest

import patlab

SCENE = "settings/ssl-half-field.toml"


@pytest.fixture(scope="module")
def scene(root):
    image, truth_csv = patlab.render(root / SCENE)
    return image, list(csv.DictReader(io.StringIO(truth_csv)))


@pytest.fixture
def in_root(root, monkeypatch):
    monkeypatch.chdir(root)


def test_setup_then_detect_finds_every_robot(scene, tmp_path, in_root):
    image, truth = scene
    report = patlab.setup(image, field="ssl-2009", settings="ssl-frame.detector", out=tmp_path)
    assert report["field"] == "ssl-2009"
    assert 0.0 <= report["mapping_error_mm"] < 2.0
    assert report["mm_per_px"] > 5.0
    assert {c["name"] for c in report["colour_classes"]} >= {"blue", "yellow"}
    assert report["colour_fit"] in ("blobs", "pixels")
    kept = report["robots_by_" + report["colour_fit"]]
    assert kept >= max(report["robots_by_blobs"], report["robots_by_pixels"])
    assert report["tolerances"]["reach_margin_mm"] >= 20.0
    assert [f["frame"] for f in report["robots"]] == ["frame0"]
    assert len(report["robots"][0]["robots"]) == len(truth) == 10
    assert (tmp_path / "setup.toml").is_file()
    found = patlab.detect(image, setup=tmp_path)
    columns = patlab._results._columns_from_csv(found.csv)
    got = {(t, int(i)): (x, y) for t, i, x, y in
           zip(columns["team"], columns["id"], columns["x_mm"], columns["y_mm"])}
    want = {(r["team"], int(r["id"])): (float(r["x_mm"]), float(r["y_mm"])) for r in truth}
    assert set(got) == set(want)
    for key, (x, y) in want.items():
        assert np.hypot(got[key][0] - x, got[key][1] - y) < 5.0, key


def test_the_family_and_the_clis_report(cli, root, tmp_path, in_root):
    """A frame's path and the family: the CLI's model, runner-up and files."""
    run = cli("render", SCENE, "--out", tmp_path / "r")
    assert run.returncode == 0, run.stderr
    frame = tmp_path / "r" / "frame.png"
    run = cli("setup", frame, "--field", "ssl", "--settings", "ssl-frame.detector", "-o",
              tmp_path / "cli")
    assert run.returncode == 0, run.stderr
    report = patlab.setup(str(frame), field="ssl", settings="ssl-frame.detector",
                          out=tmp_path / "py")
    assert report["field"] == "ssl-2009"
    tried = report["tried"]
    assert tried[0]["field"] == "ssl-2009" and tried[0]["fitted"]
    assert tried[1]["fitted"] and tried[1]["score_px"] < tried[0]["score_px"]
    assert any(t["same_as"] for t in tried)
    assert any(not t["fitted"] and t["failure"].startswith("not fitted") for t in tried)
    # The lines decide this view: no other camera explains nearly as much line.
    assert report["undecided"] == [] and not report["robots_decided"]
    for name in ("calibration.toml", "thresholds.toml", "settings.toml", "setup.toml"):
        assert (tmp_path / "py" / name).read_text() == (tmp_path / "cli" / name).read_text()
    text = report["report"]
    assert text.split("seconds:")[0] in run.stdout


def test_bad_input_is_a_value_error(scene, tmp_path, in_root):
    image, _ = scene
    with pytest.raises(ValueError, match=r"expected at least 4 landmarks"):
        patlab.setup(image, field="ssl-2009", settings="ssl-frame.detector", out=tmp_path,
                     landmarks=["centre=390,290"])
    with pytest.raises(FileNotFoundError, match=r"no such file"):
        patlab.setup(str(tmp_path / "none.png"), field="ssl", settings="ssl-frame.detector",
                     out=tmp_path)
    assert not (tmp_path / "setup.toml").exists()
