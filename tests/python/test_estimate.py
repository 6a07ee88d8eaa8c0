"""patlab.estimate, crlb and predicted_std against exact poses, an independent numpy fast
estimator and the bound's formula; strided input read in place."""
import math

import numpy as np
import pytest

import patlab


def observe(pattern, poses, sigma=0.0, seed=0):
    """World positions (trials, patches, 2) of the pattern's patches at `poses` plus noise."""
    p = pattern.positions_mm
    c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
    x = poses[:, 0:1] + c * p[:, 0] - s * p[:, 1]
    y = poses[:, 1:2] + s * p[:, 0] + c * p[:, 1]
    v = np.stack([x, y], axis=-1)
    return v + np.random.default_rng(seed).normal(0.0, sigma, v.shape)


def random_poses(trials, seed=1):
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(-1400, 1400, trials), rng.uniform(-1150, 1150, trials),
                            rng.uniform(-3.1, 3.1, trials)])


def numpy_fast(pattern, v):
    """The paper's fast estimator (section III) in numpy: mean of the patches; each orientation
    pair's displacement rotated back by its model angle, summed, atan2; the mean mapped back to
    the model origin."""
    p = pattern.positions_mm
    sum_cos = np.zeros(len(v))
    sum_sin = np.zeros(len(v))
    for i, j in pattern.orientation_pairs:
        model_angle = math.atan2(*(p[j] - p[i])[::-1])
        d = v[:, j] - v[:, i]
        angle = np.arctan2(d[:, 1], d[:, 0]) - model_angle
        length = np.hypot(d[:, 0], d[:, 1])
        sum_cos += length * np.cos(angle)
        sum_sin += length * np.sin(angle)
    theta = np.arctan2(sum_sin, sum_cos)
    centroid = p.mean(axis=0)
    mean = v.mean(axis=1)
    c, s = np.cos(theta), np.sin(theta)
    x = mean[:, 0] - (c * centroid[0] - s * centroid[1])
    y = mean[:, 1] - (s * centroid[0] + c * centroid[1])
    return np.column_stack([x, y, theta])


@pytest.mark.parametrize("method", patlab.ESTIMATORS)
@pytest.mark.parametrize("name", ["butterfly", "triangle", "ssl-standard"])
def test_exact_patches_give_the_pose(method, name):
    pattern = patlab.Pattern.load(name)
    poses = random_poses(500)
    estimated = patlab.estimate(pattern, observe(pattern, poses), method=method)
    assert estimated.shape == (500, 3)
    np.testing.assert_allclose(estimated, poses, atol=1e-9)


def test_fast_equals_an_independent_numpy_fast():
    pattern = patlab.Pattern.load("butterfly")
    v = observe(pattern, random_poses(20000), sigma=2.0)
    np.testing.assert_allclose(patlab.estimate(pattern, v), numpy_fast(pattern, v), rtol=0,
                               atol=1e-9)


def test_ml_reaches_the_least_squares_minimum():
    """Isotropic Gaussian noise: the ML pose is the least-squares (Procrustes) pose."""
    pattern = patlab.Pattern.load("butterfly")
    v = observe(pattern, random_poses(5000), sigma=3.0)
    ml, converged = patlab.estimate(pattern, v, method="ml", return_converged=True)
    assert converged.dtype == bool and converged.all()
    np.testing.assert_allclose(ml, patlab.estimate(pattern, v, method="lsq"), atol=1e-7)


def test_strided_views_are_read_in_place():
    pattern = patlab.Pattern.load("butterfly")
    v = observe(pattern, random_poses(3000), sigma=1.0)
    wide = np.zeros((3000, 5, 4))
    wide[:, :, ::2] = v  # x, y two doubles apart: a non-contiguous (trials, 5, 2) view
    view = wide[:, :, ::2]
    assert not view.flags.c_contiguous
    assert patlab._patlab._observed_address(view) == view.__array_interface__["data"][0]
    np.testing.assert_array_equal(patlab.estimate(pattern, view), patlab.estimate(pattern, v))
    backwards = v[::-1]  # negative strides
    assert patlab._patlab._observed_address(backwards) == backwards.__array_interface__["data"][0]
    np.testing.assert_array_equal(patlab.estimate(pattern, backwards),
                                  patlab.estimate(pattern, v)[::-1])


def test_threads_do_not_change_the_poses():
    pattern = patlab.Pattern.load("butterfly")
    v = observe(pattern, random_poses(50000), sigma=2.0)
    whole = patlab.estimate(pattern, v, method="ml")
    np.testing.assert_array_equal(whole, patlab.estimate(pattern, v, method="ml", threads=1))
    pieces = np.concatenate([patlab.estimate(pattern, v[k:k + 7], method="ml")
                             for k in range(0, 50000, 7)])
    np.testing.assert_array_equal(whole, pieces)


@pytest.mark.parametrize("shape, text", [((10, 4, 2), "(10, 4, 2)"), ((10, 5, 3), "(10, 5, 3)"),
                                         ((10,), "(10,)")])
def test_wrong_shape_is_a_value_error(shape, text):
    with pytest.raises(ValueError) as error:
        patlab.estimate("butterfly", np.zeros(shape))
    assert str(error.value) == (f"observed has shape {text}; expected (trials, 5, 2): the "
                                "pattern's patches in its order, x and y in mm")


@pytest.mark.parametrize("method", ["best", "robust"])
def test_unknown_method_is_a_value_error(method):
    # robust needs the noise model's sigma and outlier mixture: simulate runs it, estimate does not.
    with pytest.raises(ValueError,
                       match=f'method is "{method}"; expected "fast", "ml", "lsq" or "key"'):
        patlab.estimate("butterfly", np.zeros((1, 5, 2)), method=method)


def test_crlb_is_the_formula():
    pattern = patlab.Pattern.load("butterfly")
    p = pattern.positions_mm
    spread = ((p - p.mean(axis=0)) ** 2).sum()
    sigma = 1.5
    bound = patlab.crlb(pattern, sigma)
    assert math.isclose(bound.theta_rad, sigma / math.sqrt(spread), rel_tol=1e-12)
    centroid_sq = (p.mean(axis=0) ** 2).sum()
    expected = sigma * math.sqrt(1 / len(p) + centroid_sq / (2 * spread))
    assert math.isclose(bound.position_mm, expected, rel_tol=1e-12)
    # A common offset adds (g sigma)^2 to the position's variance and nothing to the angle's;
    # camera roll has no bound.
    common = patlab.crlb(pattern, sigma, noise={"common_sigma_ratio": 0.5})
    assert math.isclose(common.theta_rad, bound.theta_rad, rel_tol=1e-9)
    assert math.isclose(common.position_mm, math.hypot(bound.position_mm, 0.5 * sigma),
                        rel_tol=1e-9)
    assert math.isnan(patlab.crlb(pattern, sigma, noise={"rotation_jitter_rad": 0.001}).theta_rad)


def test_predicted_std_matches_the_monte_carlo_std():
    pattern = patlab.Pattern.load("butterfly")
    v = observe(pattern, np.zeros((200000, 3)), sigma=0.5, seed=5)
    theta = patlab.estimate(pattern, v)[:, 2]
    predicted = patlab.predicted_std(pattern, "fast", 0.5).theta_rad
    assert math.isnan(patlab.predicted_std(pattern, "robust", 0.5).theta_rad)
    # The std's own standard error is std / sqrt(2 (n - 1)); 4 of them.
    assert abs(theta.std(ddof=1) - predicted) < 4 * predicted / math.sqrt(2 * len(theta))


@pytest.mark.parametrize("method", ["fast", "key", "lsq"])
@pytest.mark.parametrize("name", ["butterfly", "triangle", "linear"])
def test_vectorised_estimators_are_the_one_trial_estimators_bit_for_bit(method, name):
    """fast, key and lsq run vectorised over blocks of trials (estimate::EstimateMany), in
    parallel: the poses are the one-trial estimators' bits, for C-ordered and strided arrays,
    any thread count, and arrays cut at any trial."""
    pattern = patlab.Pattern.load(name)
    v = observe(pattern, random_poses(40001), sigma=2.0)
    v[::11] = np.random.default_rng(2).normal(0.0, 700.0, v[::11].shape)  # anything at all
    v[5] = 1.0  # every patch at one point: atan2(0, 0)

    def bits(a):
        return np.ascontiguousarray(a).view(np.uint64)

    reference = patlab._patlab._estimate(pattern, v, method, 20, 1, True)[0]
    for observed in (v, v[::-1], np.asfortranarray(v)):
        for threads in (0, 1, 2):
            poses = patlab.estimate(pattern, observed, method, threads=threads)
            expected = reference[::-1] if observed.strides[0] < 0 else reference
            np.testing.assert_array_equal(bits(poses), bits(expected))
    pieces = np.concatenate([patlab.estimate(pattern, v[k:k + 777], method)
                             for k in range(0, len(v), 777)])
    np.testing.assert_array_equal(bits(pieces), bits(reference))
