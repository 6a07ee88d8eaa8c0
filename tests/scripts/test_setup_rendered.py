"""scripts/setup_rendered.py's true mapping error: floor_points against a camera looking straight
down (analytic) and against the forward projection of src/patlab/camera/camera.cpp's
WorldToPixel (a round trip through the radial distortion).

Run by ctest as `setup_tables_planted` (tests/CMakeLists.txt).
"""
import os
import sys

import numpy as np
from scipy.spatial.transform import Rotation

sys.dont_write_bytecode = True  # no __pycache__ in the source tree

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import setup_rendered  # noqa: E402


def pinhole(rotation, centre, f=600.0, k1=0.0, k2=0.0):
    return dict(fx_px=f, fy_px=f, cx_px=390.0, cy_px=290.0, k1=k1, k2=k2,
                rotation_rodrigues=list(rotation.as_rotvec()),
                translation_mm=list(-rotation.apply(centre)))


def test_a_camera_straight_down_maps_a_pixel_by_height_over_focal_length():
    down = Rotation.from_matrix([[1, 0, 0], [0, -1, 0], [0, 0, -1]])  # camera z along world -z
    camera = pinhole(down, np.array([100.0, -200.0, 3000.0]))
    points = setup_rendered.floor_points(camera, np.array([[390.0, 290.0], [450.0, 290.0],
                                                            [390.0, 350.0]]))
    # 60 px at f 600 px from 3000 mm up: 300 mm on the floor; image y runs along world -y.
    np.testing.assert_allclose(points, [[100, -200], [400, -200], [100, -500]], atol=1e-9)


def test_the_floor_points_project_back_to_their_pixels_through_the_distortion():
    rotation = Rotation.from_euler("xyz", [178.0, 3.0, 40.0], degrees=True)
    camera = pinhole(rotation, np.array([700.0, -2500.0, 3500.0]), f=560.0, k1=-0.09, k2=0.01)
    u, v = np.meshgrid(np.arange(5, 780, 37), np.arange(5, 580, 29))
    pixels = np.stack([u.ravel(), v.ravel()], axis=1).astype(float)
    points = setup_rendered.floor_points(camera, pixels)
    assert not np.isnan(points).any()
    in_camera = rotation.apply(np.c_[points, np.zeros(len(points))]) + camera["translation_mm"]
    x, y = in_camera[:, 0] / in_camera[:, 2], in_camera[:, 1] / in_camera[:, 2]
    r2 = x * x + y * y
    scale = 1.0 + camera["k1"] * r2 + camera["k2"] * r2 * r2
    back = np.c_[560.0 * x * scale + 390.0, 560.0 * y * scale + 290.0]
    np.testing.assert_allclose(back, pixels, atol=1e-9)


def test_a_pixel_above_the_horizon_does_not_reach_the_floor():
    level = Rotation.from_euler("x", 90.0, degrees=True)  # looking along the floor, image up is up
    camera = pinhole(level, np.array([0.0, 0.0, 3000.0]))
    points = setup_rendered.floor_points(camera, np.array([[390.0, 100.0], [390.0, 500.0]]))
    assert np.isnan(points[0]).all()
    assert not np.isnan(points[1]).any()


def test_a_scaled_scene_sees_the_same_floor_at_its_own_pixels(tmp_path, monkeypatch):
    """--scale: the camera of S times the resolution (focal lengths and principal point scaled
    about the pixel corners), and the true mapping error measured on the same floor points."""
    cam = {"rotation": Rotation.from_euler("xyz", [178.0, 3.0, 40.0], degrees=True),
           "centre": np.array([700.0, -1500.0, 3500.0]), "fx": 560.0, "fy": 560.0,
           "cx": 388.0, "cy": 291.0, "k1": -0.06}
    errors = []
    for scale in (1.0, 2.5):
        monkeypatch.setattr(setup_rendered, "SCALE", scale)
        scene, fitted = tmp_path / ("scene%g" % scale), tmp_path / ("fitted%g" % scale)
        scene.mkdir()
        fitted.mkdir()
        setup_rendered.write_scene(str(scene), "ssl-2015", cam, [], {}, 1)
        truth = setup_rendered.read_pinhole(str(scene / "camera.toml"))
        text = (scene / "camera.toml").read_text()
        if scale != 1.0:
            assert "image_size_px = [1950, 1450]" in text
            assert truth["fx_px"] == 2.5 * 560.0
            assert truth["cx_px"] == 2.5 * (388.0 + 0.5) - 0.5
        # The fitted camera: the truth 20 mm along x.
        shifted = dict(cam, centre=cam["centre"] + np.array([20.0, 0.0, 0.0]))
        setup_rendered.write_scene(str(fitted), "ssl-2015", shifted, [], {}, 1)
        (fitted / "camera.toml").rename(fitted / "calibration.toml")
        errors.append(setup_rendered.true_mapping_error(str(scene), str(fitted), "ssl-2015"))
    assert errors[0] == errors[1] == 20.0
