"""patlab.detect and read_frame on the golden frame: the CLI's detections, any strides read in
place."""
import json
import os

import numpy as np
import pytest

import patlab

GOLDEN = "tests/data/golden/ssl-frame"
FILES = {"thresholds": f"{GOLDEN}.thresholds.toml", "calibration": f"{GOLDEN}.calibration.toml",
         "settings": f"{GOLDEN}.detector.toml"}


@pytest.fixture(scope="module")
def frame(root):
    return patlab.read_frame(root / f"{GOLDEN}.png")


@pytest.fixture
def in_root(root, monkeypatch):
    monkeypatch.chdir(root)


def in_root_path():
    return os.getcwd()


def png_pixels(path):
    """An 8-bit RGB PNG's pixels through matplotlib's decoder (floats k / 255), independent of
    patlab's."""
    image = pytest.importorskip("matplotlib.image").imread(path)
    return np.round(image[:, :, :3] * 255.0).astype(np.uint8)


def test_read_frame_is_the_pngs_pixels(frame, root):
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
    np.testing.assert_array_equal(frame, png_pixels(root / f"{GOLDEN}.png"))


def test_detections_are_the_clis(cli, frame, in_root):
    run = cli("detect", f"{GOLDEN}.png", "--thresholds", FILES["thresholds"], "--calibration",
              FILES["calibration"], "--settings", FILES["settings"])
    assert run.returncode == 0, run.stderr
    result = patlab.detect(frame, name=f"{GOLDEN}.png", **FILES)
    assert result.csv == run.stdout
    assert len(result) > 0


def test_explain_gives_the_clis_diagnoses(cli, frame, in_root, tmp_path):
    """explain=True: the JSON's "explanations" are those of `detect --explain --format json`;
    with reach_margin_mm 0.5 some robots are rejected at stage 2 with a reach_margin_mm change."""
    settings = open(FILES["settings"]).read().replace("reach_margin_mm = 20.0",
                                                      "reach_margin_mm = 0.5")
    settings = settings.replace('"../../../patterns/', f'"{in_root_path()}/patterns/')
    broken = tmp_path / "broken.toml"
    broken.write_text(settings)
    run = cli("detect", f"{GOLDEN}.png", "--thresholds", FILES["thresholds"], "--calibration",
              FILES["calibration"], "--settings", str(broken), "--explain", "--format", "json")
    assert run.returncode == 0, run.stderr
    result = patlab.detect(frame, FILES["thresholds"], FILES["calibration"], str(broken),
                           name=f"{GOLDEN}.png", explain=True)
    assert result.json == json.loads(run.stdout)
    explanations = result.json[0]["explanations"]
    rejected = [e for e in explanations if e["outcome"] != "detected"]
    assert rejected and all(e["outcome"] == "few_neighbours" for e in rejected)
    assert all(e["change"]["key"] == "reach_margin_mm" and e["change"]["from"] == 0.5
               and e["change"]["to"] > 0.5 for e in rejected)
    assert "explanations" not in patlab.detect(frame, FILES["thresholds"], FILES["calibration"],
                                               str(broken)).json[0]


def test_blobs_are_the_clis(cli, frame, in_root):
    run = cli("detect", f"{GOLDEN}.png", "--thresholds", FILES["thresholds"], "--calibration",
              FILES["calibration"], "--blobs")
    assert run.returncode == 0, run.stderr
    result = patlab.detect(frame, FILES["thresholds"], FILES["calibration"], blobs=True,
                           name=f"{GOLDEN}.png")
    assert result.csv == run.stdout


def assert_read_in_place(image):
    """The view detect() hands the detector is the array's own memory with its own strides."""
    address, height, width, row, pixel, channel = patlab._patlab._image_view(image)
    assert address == image.__array_interface__["data"][0]
    assert (height, width) == image.shape[:2]
    assert (row, pixel, channel) == image.strides


def test_strided_views_are_read_in_place(frame, in_root):
    """Views that are not C-contiguous -- RGB channels of a BGR buffer (negative channel
    stride), the RGB channels of an RGBA buffer, Fortran order, a frame stored upside down
    (negative row stride) -- are read where they are, with no copy, and give the detections of
    the packed frame."""
    plain = patlab.detect(frame, **FILES).csv
    assert_read_in_place(frame)
    bgr = np.ascontiguousarray(frame[:, :, ::-1])
    rgba = np.zeros((frame.shape[0], frame.shape[1], 4), np.uint8)
    rgba[:, :, :3] = frame
    upside_down = np.ascontiguousarray(frame[::-1])
    views = [bgr[:, :, ::-1], rgba[:, :, :3], np.asfortranarray(frame), upside_down[::-1]]
    for view in views:
        assert not view.flags.c_contiguous
        assert_read_in_place(view)
        assert patlab.detect(view, **FILES).csv == plain


def test_the_detector_reads_the_arrays_memory(frame, in_root):
    """Zero-copy, seen from outside: pixels changed in the array between two calls (through
    another view of the same memory) change what is detected, and putting them back restores
    it; a crop of a larger buffer is read in place."""
    wide = np.zeros((frame.shape[0] + 20, frame.shape[1] + 30, 4), np.uint8)
    view = wide[10:10 + frame.shape[0], 5:5 + frame.shape[1], :3]
    view[...] = frame
    assert_read_in_place(view)
    before = patlab.detect(view, **FILES)
    assert before.csv == patlab.detect(frame, **FILES).csv and len(before) > 0
    saved = wide.copy()
    wide[:, :, :3] = 0  # the same memory, written through the buffer, not the view
    after = patlab.detect(view, **FILES)
    assert len(after) == 0
    wide[...] = saved
    assert patlab.detect(view, **FILES).csv == before.csv


def test_detector_object_gives_the_clis_detections(frame, in_root):
    """patlab.Detector, built once, frame after frame: the detections `patlab detect` prints
    (the CSV's rounded numbers), as numpy columns; the frame read in place."""
    table = patlab.detect(frame, **FILES).table
    detector = patlab.Detector(**FILES)
    for image in (frame, np.ascontiguousarray(frame[:, :, ::-1])[:, :, ::-1], frame):
        found = detector.detect(image)
        assert len(found["x_mm"]) == len(table["x_mm"]) > 0
        assert [detector.patterns[p] for p in found["pattern"]] == list(table["pattern"])
        assert [detector.palette[t] for t in found["team_colour"]] == list(table["team"])
        np.testing.assert_array_equal(found["id"], np.asarray(table["id"]))
        np.testing.assert_allclose(found["x_mm"], table["x_mm"], rtol=0, atol=0.005)
        np.testing.assert_allclose(found["y_mm"], table["y_mm"], rtol=0, atol=0.005)
        np.testing.assert_allclose(found["theta_rad"], table["theta_rad"], rtol=0, atol=5e-5)
        assert 0 < found["cpp_seconds"] < 10
    assert len(detector.detect(np.zeros_like(frame))["id"]) == 0


def test_detector_needs_its_files(in_root, tmp_path):
    with pytest.raises(FileNotFoundError):
        patlab.Detector(str(tmp_path / "no.toml"), FILES["calibration"], FILES["settings"])


def test_empty_image_is_a_value_error(in_root):
    with pytest.raises(ValueError, match=r"expected at least one row and one column"):
        patlab.detect(np.zeros((0, 5, 3), np.uint8), **FILES)


@pytest.mark.parametrize("image", [np.zeros((4, 4), np.uint8), np.zeros((4, 4, 3), np.float32),
                                   np.zeros((4, 4, 4), np.uint8)])
def test_wrong_images_are_value_errors(image, in_root):
    with pytest.raises(ValueError, match=r"expected RGB bytes"):
        patlab.detect(image, **FILES)


def test_missing_thresholds_is_file_not_found(cli, frame, in_root, tmp_path):
    missing = str(tmp_path / "none" / "t.toml")
    with pytest.raises(FileNotFoundError):
        patlab.detect(frame, missing, FILES["calibration"])


def test_render_is_the_clis_frame(cli, root, tmp_path, in_root):
    """The golden scene rendered in Python: the pixels of `patlab render`'s PNG, the truth CSV."""
    out, truth = tmp_path / "frame.png", tmp_path / "truth.csv"
    run = cli("render", f"{GOLDEN}.toml", "--out", tmp_path)
    assert run.returncode == 0, run.stderr
    image, truth_csv = patlab.render(f"{GOLDEN}.toml")
    assert image.dtype == np.uint8 and image.shape[2] == 3
    np.testing.assert_array_equal(image, png_pixels(out))
    assert truth_csv == truth.read_text()


def write_setup(folder, root):
    """A setup folder as `patlab setup` writes it: setup.toml naming the three files."""
    folder.mkdir()
    (folder / "setup.toml").write_text("".join(
        f'{key} = "{root / path}"\n' for key, path in FILES.items()))
    return folder


def test_a_setup_folder_stands_for_its_three_files(frame, root, tmp_path, in_root):
    """detect(setup=DIR) and Detector(setup=DIR) read the files DIR/setup.toml names, as
    `patlab detect --setup DIR` does."""
    setup = write_setup(tmp_path / "camera", root)
    plain = patlab.detect(frame, **FILES)
    assert patlab.detect(frame, setup=setup).csv == plain.csv
    found = patlab.Detector(setup=str(setup)).detect(frame)
    np.testing.assert_array_equal(found["id"], np.asarray(plain.table["id"]))


def test_setup_and_files_are_one_or_the_other(frame, root, tmp_path, in_root):
    setup = write_setup(tmp_path / "camera", root)
    with pytest.raises(ValueError, match=r"expected setup= or the three files, not both"):
        patlab.detect(frame, setup=setup, thresholds=FILES["thresholds"])
    with pytest.raises(ValueError, match=r"expected setup= \(a folder written by patlab setup\)"):
        patlab.Detector(FILES["thresholds"], FILES["calibration"])
    with pytest.raises(FileNotFoundError, match=r"no such folder"):
        patlab.detect(frame, setup=tmp_path / "missing")
    (tmp_path / "empty").mkdir()
    with pytest.raises(ValueError, match=r"no setup.toml in it"):
        patlab.Detector(setup=tmp_path / "empty")
