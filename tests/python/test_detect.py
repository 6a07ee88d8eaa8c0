"""patlab.detect and read_frame on the golden frame: the CLI's detections, any strides read in
place."""
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


def test_blobs_are_the_clis(cli, frame, in_root):
    run = cli("detect", f"{GOLDEN}.png", "--thresholds", FILES["thresholds"], "--calibration",
              FILES["calibration"], "--blobs")
    assert run.returncode == 0, run.stderr
    result = patlab.detect(frame, FILES["thresholds"], FILES["calibration"], blobs=True,
                           name=f"{GOLDEN}.png")
    assert result.csv == run.stdout


def test_strided_views_are_read_in_place(frame, in_root):
    """A BGR view (negative channel stride) of a BGR frame and a frame inside a wider buffer: the
    binding reads the view's own memory (no numpy copy) and finds the same detections."""
    plain = patlab.detect(frame, **FILES).csv
    bgr = np.ascontiguousarray(frame[:, :, ::-1])
    rgb_view = bgr[:, :, ::-1]
    assert not rgb_view.flags.c_contiguous
    assert patlab._patlab._image_address(rgb_view) == rgb_view.__array_interface__["data"][0]
    assert patlab.detect(rgb_view, **FILES).csv == plain
    wide = np.zeros((frame.shape[0], frame.shape[1], 4), np.uint8)
    wide[:, :, :3] = frame
    rgba_view = wide[:, :, :3]
    assert patlab._patlab._image_address(rgba_view) == rgba_view.__array_interface__["data"][0]
    assert patlab.detect(rgba_view, **FILES).csv == plain


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
