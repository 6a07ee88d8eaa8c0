"""patlab.setup on the rendered scene of settings/ssl-half-field.toml (a known camera, ten
robots): the report as a dict, the folder `detect(image, setup=DIR)` reads finds every robot,
the same files and report as `patlab setup` writes."""
import csv
import io
import math
import tomllib

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
    # Where the robots' fit set the height, the stated error is at least its spread over the field.
    if report["mapping_error_source"]:
        assert report["mapping_error_mm"] == report["floor_sd_mm"]
    if not math.isnan(report["floor_sd_mm"]):
        assert report["mapping_error_mm"] >= report["floor_sd_mm"]
    assert report["mm_per_px"] > 5.0
    assert {c["name"] for c in report["colour_classes"]} >= {"blue", "yellow"}
    assert all(c["thin_alike"] >= 0 for c in report["colour_classes"])
    assert report["colour_fit"] in ("blobs", "pixels")
    kept = report["robots_by_" + report["colour_fit"]]
    assert kept >= max(report["robots_by_blobs"], report["robots_by_pixels"])
    # Six blobs' fits: the given stand-out threshold and 0.7 of it, each at three scales.
    fits = report["blob_fits"]
    assert [f[0] for f in fits] == pytest.approx([20.0] * 3 + [14.0] * 3)
    assert [f[1] for f in fits] == pytest.approx([60.0, 40.0, 90.0] * 2)
    assert report["robots_by_blobs"] == max(f[2] for f in fits)
    assert (report["standout_delta_e"], report["segment_k"]) in [(f[0], f[1]) for f in fits]
    assert report["tolerances"]["reach_margin_mm"] >= 20.0
    height = report["camera_height"]
    assert height["decided_by"] in ("lines", "robots", "undetermined")
    assert 2000.0 < height["height_mm"] < 6000.0  # the known camera is 3.8 m up
    assert height["robots"] == 10 and height["scan"]
    assert report["few_lines"]["used"] is False  # the lines fixed the camera
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


def test_a_frame_over_1024_px_is_set_up_binned_as_the_frame_it_bins_to(scene, root, tmp_path,
                                                                       in_root):
    """Each pixel a 2 x 2 block: binned 2 x 2 it is the frame itself, so setup finds the same
    camera and colours; the files differ by the calibration's pixels and [frame] binning only."""
    image, truth = scene
    big = np.repeat(np.repeat(image, 2, axis=0), 2, axis=1)
    small = patlab.setup(image, field="ssl-2009", settings="ssl-frame.detector",
                         out=tmp_path / "small")
    report = patlab.setup(big, field="ssl-2009", settings="ssl-frame.detector",
                          out=tmp_path / "big")
    assert (small["binning"], small["frame_size_px"]) == (1, (780, 580))
    assert (report["binning"], report["frame_size_px"]) == (2, (1560, 1160))
    assert report["mm_per_px"] == small["mm_per_px"]
    assert report["mapping_error_mm"] == small["mapping_error_mm"]
    assert "frames binned 2 x 2: 1560 x 1160 px worked on at 780 x 580" in report["report"]
    assert (tmp_path / "big" / "thresholds.toml").read_text() == \
        (tmp_path / "small" / "thresholds.toml").read_text()
    settings = (tmp_path / "big" / "settings.toml").read_text()
    assert "\nbinning = 2 " in settings
    assert "binning" not in (tmp_path / "small" / "settings.toml").read_text()
    small_camera = tomllib.loads((tmp_path / "small" / "calibration.toml").read_text())
    big_camera = tomllib.loads((tmp_path / "big" / "calibration.toml").read_text())
    assert big_camera["image_size_px"] == [1560, 1160]
    assert big_camera["pinhole"]["fx_px"] == pytest.approx(2 * small_camera["pinhole"]["fx_px"])
    assert big_camera["pinhole"]["cx_px"] == pytest.approx(
        2 * (small_camera["pinhole"]["cx_px"] + 0.5) - 0.5)
    found = patlab.detect(big, setup=tmp_path / "big")
    columns = patlab._results._columns_from_csv(found.csv)
    got = {(t, int(i)) for t, i in zip(columns["team"], columns["id"])}
    assert got == {(r["team"], int(r["id"])) for r in truth}
    # Setup decides the binning: a [frame] binning in the settings given is not written, nor
    # does it bin the frames setup decodes robots in.
    given = (root / "settings" / "ssl-frame.detector.toml").read_text().replace(
        '"../patterns/', '"%s/patterns/' % root) + "\n[frame]\nbinning = 3\n"
    (tmp_path / "given.toml").write_text(given)
    mine = patlab.setup(image, field="ssl-2009", settings=str(tmp_path / "given.toml"),
                        out=tmp_path / "given")
    assert len(mine["robots"][0]["robots"]) == 10
    assert "binning" not in (tmp_path / "given" / "settings.toml").read_text()
    with pytest.raises(ValueError, match="--binning is 9; expected 0"):
        patlab.setup(image, field="ssl-2009", settings="ssl-frame.detector",
                     out=tmp_path / "bad", binning=9)


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
    # Each model's best view, its own search's or one another's found ("" its own): ssl-2012's
    # search refined the camera ssl-2009 fits a little further (2478.4 px of ssl-2009's lines
    # against 2465.4), and the report says so.
    lent = {t["field"]: t["screen_view_of"] for t in tried}
    assert lent["ssl-2009"] == "ssl-2012" and lent["ssl-2012"] == ""
    assert all(v in lent and v != k for k, v in lent.items() if v)
    assert "(search 2478.4 px, a view ssl-2012's search found)" in report["report"]
    assert any(not t["fitted"] and t["failure"].startswith("not fitted") for t in tried)
    # Named alone, ssl-2009 is the one model fitted and tried; the rest of its family is searched
    # only to lend it views, and ssl-2012's search lends the one it has from it in the family.
    named = patlab.setup(str(frame), field="ssl-2009", settings="ssl-frame.detector",
                         out=tmp_path / "named")
    assert [t["field"] for t in named["tried"]] == ["ssl-2009"]
    assert named["tried"][0]["screen_view_of"] == "ssl-2012"
    assert named["field"] == "ssl-2009"
    # The lines decide this view: no other camera explains nearly as much line.
    assert report["undecided"] == [] and not report["robots_decided"]
    assert not report["lines_overruled"]
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
    with pytest.raises(ValueError, match=r"--camera-height is 100 mm; expected above the robots'"):
        patlab.setup(image, field="ssl-2009", settings="ssl-frame.detector", out=tmp_path,
                     camera_height=100)
    assert not (tmp_path / "setup.toml").exists()


def test_camera_height_is_the_clis(scene, tmp_path, in_root):
    """camera_height=MM is --camera-height MM: the calibration's height, reported as given."""
    image, _ = scene
    report = patlab.setup(image, field="ssl-2009", settings="ssl-frame.detector", out=tmp_path,
                          camera_height=2500)
    height = report["camera_height"]
    assert height["decided_by"] == "given" and height["scan"] == []
    assert abs(height["height_mm"] - 2500.0) < 30.0
    assert "(given: --camera-height;" in report["report"]


def test_colour_options_are_the_clis(cli, root, tmp_path, in_root):
    """colour_options={...} is --colour-option NAME=VALUE: the same files; another value of the
    colour fit's segmentation writes other thresholds; a bad name or value is a ValueError."""
    run = cli("render", SCENE, "--camera", "--out", tmp_path / "r")
    assert run.returncode == 0, run.stderr
    frame = tmp_path / "r" / "frame.png"
    run = cli("setup", frame, "--field", "ssl-2009", "--settings", "ssl-frame.detector",
              "--colour-option", "segment_k=200", "--colour-option", "standout_delta_e=14",
              "-o", tmp_path / "cli")
    assert run.returncode == 0, run.stderr
    patlab.setup(str(frame), field="ssl-2009", settings="ssl-frame.detector",
                 out=tmp_path / "py", colour_options={"segment_k": 200, "standout_delta_e": 14})
    patlab.setup(str(frame), field="ssl-2009", settings="ssl-frame.detector",
                 out=tmp_path / "defaults")
    for name in ("calibration.toml", "thresholds.toml", "settings.toml", "setup.toml"):
        assert (tmp_path / "py" / name).read_text() == (tmp_path / "cli" / name).read_text()
    assert ((tmp_path / "py" / "thresholds.toml").read_text() !=
            (tmp_path / "defaults" / "thresholds.toml").read_text())
    with pytest.raises(ValueError, match=r"unknown colour option 'segment'; expected one of "
                                         r"light_cell_px, .*segment_k"):
        patlab.setup(str(frame), field="ssl-2009", settings="ssl-frame.detector",
                     out=tmp_path / "bad", colour_options={"segment": 1})
    with pytest.raises(ValueError, match=r"segment_k is -1; expected in \(0, 10000\]"):
        patlab.setup(str(frame), field="ssl-2009", settings="ssl-frame.detector",
                     out=tmp_path / "bad", colour_options={"segment_k": -1})
    with pytest.raises(ValueError, match=r"margin_levels is 2.5; expected an integer"):
        patlab.setup(str(frame), field="ssl-2009", settings="ssl-frame.detector",
                     out=tmp_path / "bad", colour_options={"margin_levels": 2.5})
    assert not (tmp_path / "bad").exists()


def _project(calibration, world_mm):
    """World points (N, 3) mm -> pixels (N, 2) by the calibration file's pinhole with radial
    distortion, written out from docs/formats (x_cam = R x + t; x_d = x (1 + k1 r^2 + k2 r^4))."""
    import tomllib
    from scipy.spatial.transform import Rotation
    with open(calibration, "rb") as f:
        p = tomllib.load(f)["pinhole"]
    cam = Rotation.from_rotvec(p["rotation_rodrigues"]).apply(world_mm) + p["translation_mm"]
    x, y = cam[:, 0] / cam[:, 2], cam[:, 1] / cam[:, 2]
    r2 = x * x + y * y
    d = 1.0 + p["k1"] * r2 + p["k2"] * r2 * r2
    return np.column_stack([p["fx_px"] * x * d + p["cx_px"], p["fy_px"] * y * d + p["cy_px"]])


def test_pixel_to_floor_inverts_the_cameras_projection(root):
    calibration = root / "settings" / "ssl-half-field.calibration.toml"
    rng = np.random.default_rng(7)
    for height in (None, 0.0, 21.5):
        z = 140.0 if height is None else height  # the file's default_mm is 140
        world = np.column_stack([rng.uniform(700, 2300, 50), rng.uniform(-400, 1000, 50),
                                 np.full(50, z)])
        pixels = _project(calibration, world)
        floor = patlab.pixel_to_floor(calibration, pixels, height_mm=height)
        assert floor.shape == (50, 2)
        np.testing.assert_allclose(floor, world[:, :2], atol=1e-6)
    # A pixel far outside the lens's valid range does not reach the floor: NaN, not a number.
    beyond = patlab.pixel_to_floor(calibration, [[1e7, 1e7]])
    assert np.isnan(beyond).all()
    with pytest.raises(ValueError, match=r"no such file|cannot open|not found"):
        patlab.pixel_to_floor(root / "none.toml", [[0, 0]])
