"""patlab.simulate and simulate_experiment: the CLI's results bit for bit, threads, raw errors,
errors, and Ctrl-C."""
import math
import os
import signal
import threading
import time

import numpy as np
import pytest

import patlab
from conftest import cli_message

FIG5 = ["simple", "linear", "triangle", "butterfly", "ssl-standard"]
SIGMAS = [0.0, 0.5, 2.0]
TRIALS = 3000
SEED = 7


@pytest.fixture(scope="module")
def cli_csv(cli, tmp_path_factory):
    """results of `patlab simulate experiments/fig5.toml` for SIGMAS, TRIALS, SEED."""
    out = tmp_path_factory.mktemp("cli")
    run = cli("simulate", "experiments/fig5.toml", "--trials", TRIALS, "--seed", SEED,
              "--sigmas", ",".join(map(str, SIGMAS)), "--out", out, "-q")
    assert run.returncode == 0, run.stderr
    return (out / "fig5.csv").read_text()


def test_experiment_equals_the_cli_byte_for_byte(cli_csv, root):
    result = patlab.simulate_experiment(root / "experiments" / "fig5.toml", trials=TRIALS,
                                        seed=SEED, sigmas=SIGMAS)
    assert result.csv == cli_csv


def test_simulate_equals_the_cli_byte_for_byte(cli_csv):
    result = patlab.simulate(FIG5, SIGMAS, trials=TRIALS, estimators=["fast", "ml"], seed=SEED)
    assert result.csv == cli_csv


def test_table_holds_the_values_the_csv_prints(cli_csv):
    result = patlab.simulate(FIG5, SIGMAS, trials=TRIALS, estimators=["fast", "ml"], seed=SEED)
    lines = cli_csv.splitlines()
    header = lines[0].split(",")
    assert list(result.columns) == header
    for row, line in enumerate(lines[1:]):
        for name, cell in zip(header, line.split(",")):
            value = result.columns[name][row]
            if isinstance(value, str):
                assert value == cell
            elif cell == "":
                assert math.isnan(value)
            else:
                assert f"{value:.10g}" == cell, (name, row)


def test_results_do_not_depend_on_threads():
    one = patlab.simulate("butterfly", [1.0], trials=20000, estimators=["fast", "ml", "lsq"],
                          seed=3, threads=1)
    two = patlab.simulate("butterfly", [1.0], trials=20000, estimators=["fast", "ml", "lsq"],
                          seed=3, threads=2)
    assert one.csv == two.csv and one.threads == 1 and two.threads == 2


def test_table_is_a_dataframe_with_pandas():
    pandas = pytest.importorskip("pandas")
    result = patlab.simulate("butterfly", [1.0, 2.0], trials=1000, estimators=["fast"])
    assert isinstance(result.table, pandas.DataFrame)
    assert list(result.table["sigma_mm"]) == [1.0, 2.0]


def test_kept_errors_are_the_trials_summarised():
    result = patlab.simulate(["butterfly", "simple"], [0.5, 2.0], trials=5000,
                             estimators=["ml", "fast"], seed=11, keep_errors=True)
    errors = result.errors
    assert errors.shape == (4, 2, 5000, 3) and errors.dtype == np.float64
    for row in range(4 * 2):
        point, estimator = divmod(row, 2)
        e = errors[point, estimator]
        assert result.columns["estimator"][row] == ["ml", "fast"][estimator]
        for axis, name in enumerate(["std_x_mm", "std_y_mm", "std_theta_rad"]):
            assert math.isclose(e[:, axis].std(ddof=1), result.columns[name][row], rel_tol=1e-12)
        assert math.isclose(e[:, 2].mean(), result.columns["mean_theta_rad"][row],
                            rel_tol=1e-9, abs_tol=1e-15)


def test_noise_model_reaches_the_run():
    result = patlab.simulate("butterfly", [1.0], trials=2000, estimators=["fast"],
                             noise={"sigma_y_ratio": 2.0})
    assert result.columns["noise"][0] == "anisotropic"
    bound = patlab.crlb("butterfly", 1.0, noise={"sigma_y_ratio": 2.0})
    assert math.isclose(result.columns["crlb_pos_mm"][0], bound.position_mm, rel_tol=1e-12)


def test_bad_override_has_the_cli_message(cli, root):
    with pytest.raises(ValueError) as error:
        patlab.simulate_experiment(root / "experiments" / "fig5.toml", trials=1)
    assert str(error.value) == cli_message(
        cli("simulate", "experiments/fig5.toml", "--trials", 1), "simulate")


def test_missing_experiment_is_file_not_found(cli, tmp_path):
    missing = tmp_path / "none" / "x.toml"
    with pytest.raises(FileNotFoundError) as error:
        patlab.simulate_experiment(missing)
    assert str(error.value) == cli_message(cli("simulate", missing), "simulate")


@pytest.mark.parametrize("kwargs, message", [
    ({"estimators": ["fast", "best"]}, 'estimators is "best"; expected'),
    ({"noise": {"sigma_x_ratio": 1.0}}, "noise has an unknown key 'sigma_x_ratio'"),
    ({"noise": {"outlier_probability": 1.0}}, "noise options: outlier_probability is 1"),
    ({"trials": 1}, "trials is 1; expected"),
])
def test_bad_arguments_are_value_errors(kwargs, message):
    arguments = {"trials": 100, **kwargs}
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        patlab.simulate("butterfly", [1.0], **arguments)


def test_ctrl_c_interrupts_a_long_simulation():
    """SIGINT from a timer thread: KeyboardInterrupt long before the run would have ended."""
    sigmas = [0.002 * k for k in range(1, 2001)]  # 2000 points of 10^6 ML trials: minutes
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            patlab.simulate("butterfly", sigmas, trials=1000000, estimators=["fast", "ml"])
    finally:
        timer.cancel()
    assert time.monotonic() - start < 30.0


DETECT_FRAMES = 120
DETECT_SIGMAS = [1.0, 4.5]


@pytest.fixture(scope="module")
def cli_detect_csv(cli, tmp_path_factory):
    """results of `patlab simulate experiments/id_confusion.toml` (correspondence = "detect":
    whole frames through the detector) for DETECT_SIGMAS, DETECT_FRAMES frames, seed SEED."""
    out = tmp_path_factory.mktemp("cli_detect")
    run = cli("simulate", "experiments/id_confusion.toml", "--trials", DETECT_FRAMES, "--seed",
              SEED, "--sigmas", ",".join(map(str, DETECT_SIGMAS)), "--out", out, "-q")
    assert run.returncode == 0, run.stderr
    return (out / "id_confusion.csv").read_text()


def test_detect_mode_equals_the_cli_byte_for_byte(cli_detect_csv, root):
    """A detect-mode experiment (scenes, detector, scoring) gives the CLI's CSV to the last bit,
    on one thread or two, and its table holds the CSV's values."""
    for threads in (1, 2):
        result = patlab.simulate_experiment(root / "experiments" / "id_confusion.toml",
                                            trials=DETECT_FRAMES, seed=SEED, sigmas=DETECT_SIGMAS,
                                            threads=threads)
        assert result.csv == cli_detect_csv
        assert result.threads == threads
    lines = cli_detect_csv.splitlines()
    header = lines[0].split(",")
    assert list(result.columns) == header
    rows = len(lines) - 1
    assert rows == 3 * 2 * len(DETECT_SIGMAS)  # patterns x false-blob rates x sigmas
    assert result.total_trials == rows * DETECT_FRAMES
    for row, line in enumerate(lines[1:]):
        for name, cell in zip(header, line.split(",")):
            value = result.columns[name][row]
            if isinstance(value, str):
                assert value == cell
            elif cell == "":
                assert math.isnan(value)
            else:
                assert float(cell) == value, (name, row)
    detection = np.asarray(result.columns["detection_rate"])
    assert ((detection >= 0) & (detection <= 1)).all() and detection.max() > 0.5


def test_detect_mode_by_name_and_its_seed(root):
    """The shipped experiment by name; another seed draws other frames."""
    one = patlab.simulate_experiment("id_confusion", trials=40, seed=1, sigmas=[3.0])
    again = patlab.simulate_experiment(root / "experiments" / "id_confusion.toml", trials=40,
                                       seed=1, sigmas=[3.0])
    other = patlab.simulate_experiment("id_confusion", trials=40, seed=2, sigmas=[3.0])
    assert one.csv == again.csv and one.csv != other.csv


def test_detect_mode_keeps_no_errors(root):
    with pytest.raises(ValueError, match=r'correspondence is "detect" .*expected keep_errors=False'):
        patlab.simulate_experiment("id_confusion", trials=10, sigmas=[1.0], keep_errors=True)
