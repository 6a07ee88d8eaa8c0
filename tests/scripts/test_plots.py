"""The plotting scripts (scripts/plot_*.py) and their shared input checks (scripts/plotinput.py).

Every script, given a missing or malformed input file, prints one line `plot_x.py: FILE: what is
wrong` and exits 2 (no traceback); from the committed CSVs each draws its figures. The figures'
content that a reviewer reads is checked on the figure objects: zero rates drawn at 1/N and not
joined to the measured ones, one panel per design, a legend that says which curve is which.

Run by ctest (tests/CMakeLists.txt): /usr/bin/python3 -m pytest tests/scripts/test_plots.py.
"""
import json
import math
import os
import shutil
import struct
import subprocess
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree

import pytest  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPTS = os.path.join(ROOT, "scripts")
RESULTS = os.path.join(ROOT, "results")
sys.path.insert(0, SCRIPTS)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import plot_compare  # noqa: E402
import plot_id_confusion  # noqa: E402
import plotinput  # noqa: E402


def run(script, *args):
    return subprocess.run([sys.executable, os.path.join(SCRIPTS, script), *args], cwd=ROOT,
                          capture_output=True, text=True,
                          env=dict(os.environ, PYTHONDONTWRITEBYTECODE="1"))


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    return struct.unpack(">II", head[16:24])


def copy(src, dst_dir, name=None):
    os.makedirs(dst_dir, exist_ok=True)
    dst = os.path.join(dst_dir, name or os.path.basename(src))
    shutil.copyfile(src, dst)
    return dst


# Each script's inputs laid out in a fresh directory: (script, setup(tmp) -> (args, main input
# file, outputs), a numeric column of the main input).
def fig5(tmp):
    src = copy(os.path.join(RESULTS, "fig5.csv"), tmp)
    out = os.path.join(tmp, "fig5.png")
    return [src, out], src, [out]


def id_confusion(tmp):
    src = copy(os.path.join(RESULTS, "id_confusion.csv"), tmp)
    out = os.path.join(tmp, "id_confusion.png")
    return [src, out], src, [out]


def compare(tmp):
    src = copy(os.path.join(RESULTS, "team-designs", "compare.csv"), tmp)
    out = os.path.join(tmp, "compare.png")
    return [src, out], src, [out]


def track(tmp):
    src = copy(os.path.join(RESULTS, "track_errors.csv"), tmp)
    quant = os.path.join(tmp, "quantisation")
    copy(os.path.join(RESULTS, "track_quantisation", "track_errors.csv"), quant)
    return [tmp, quant], src, [os.path.join(tmp, f) for f in ("fig2.png", "fig3.png", "fig6.png")]


def analyze(tmp):
    src = copy(os.path.join(RESULTS, "analyze", "chain_errors.csv"), tmp)
    return [tmp, "chain"], src, [os.path.join(tmp, f"chain_fig{n}.png") for n in (2, 3, 6)]


def camera_noise(tmp):
    camera = os.path.join(RESULTS, "camera-noise", "camera")
    for name in sorted(os.listdir(camera)):
        copy(os.path.join(camera, name), os.path.join(tmp, "camera"))
    src = os.path.join(tmp, "camera", "all-colour.csv")
    return [tmp], src, [os.path.join(tmp, "camera_shares.png")]


def camera_noise_fit(tmp):
    fit = os.path.join(RESULTS, "camera-noise", "fit")
    for name in ("fit.csv", "profiles.csv", "sensitivity.csv"):
        copy(os.path.join(fit, name), tmp)
    outs = [os.path.join(tmp, "profiles.png"), os.path.join(tmp, "sensitivity.png")]
    return [tmp], os.path.join(tmp, "profiles.csv"), outs


CASES = {
    "plot_fig5.py": (fig5, "std_pos_mm"),
    "plot_id_confusion.py": (id_confusion, "wrong_id_rate"),
    "plot_compare.py": (compare, "rotation_errors_3mm"),
    "plot_track.py": (track, "est_x_mm"),
    "plot_analyze.py": (analyze, "est_y_mm"),
    "plot_camera_noise.py": (camera_noise, "sx_mm"),
    "plot_camera_noise_fit.py": (camera_noise_fit, "minus2_delta_log_l"),
}


def test_every_plotting_script_has_a_case():
    scripts = sorted(f for f in os.listdir(SCRIPTS) if f.startswith("plot_") and f.endswith(".py"))
    assert scripts == sorted(CASES)


def assert_one_line(result, script, path, message):
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr
    assert result.stderr.count("\n") == 1, result.stderr
    line = result.stderr.rstrip("\n")
    assert line.startswith(f"{script}: {path}: "), line
    assert message in line, line


@pytest.mark.parametrize("script", sorted(CASES))
def test_draws_its_figures_from_the_committed_csvs(script, tmp_path):
    setup, _ = CASES[script]
    args, _, outputs = setup(str(tmp_path))
    result = run(script, *args)
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr
    for out in outputs:
        width, height = png_size(out)
        assert width >= 800 and height >= 300, (out, width, height)


def test_camera_noise_merges_and_shares_exactly_as_committed(tmp_path):
    args, _, _ = camera_noise(str(tmp_path))
    assert run("plot_camera_noise.py", *args).returncode == 0
    for name in ("camera.csv", "camera_shares.csv"):
        with open(os.path.join(tmp_path, name), "rb") as f:
            made = f.read()
        with open(os.path.join(RESULTS, "camera-noise", name), "rb") as f:
            assert made == f.read(), name


@pytest.mark.parametrize("script", sorted(CASES))
def test_a_missing_input_is_one_line_and_exit_2(script, tmp_path):
    setup, _ = CASES[script]
    args, src, _ = setup(str(tmp_path))
    if script == "plot_camera_noise.py":
        shutil.rmtree(os.path.dirname(src))
        assert_one_line(run(script, *args), script, os.path.dirname(src), "no camtrack CSV files")
        return
    os.remove(src)
    assert_one_line(run(script, *args), script, src, "no such file; expected ")


def lines_of(path):
    with open(path, encoding="utf-8") as f:
        return f.read().split("\n")


def rewrite(path, edit):
    with open(path, newline="", encoding="utf-8") as f:
        lines = f.read().split("\n")
    with open(path, "w", newline="", encoding="utf-8") as f:
        f.write("\n".join(edit(lines)))


def column_index(path, name):
    with open(path, encoding="utf-8") as f:
        return f.readline().rstrip("\r\n").split(",").index(name)


def break_cell(lines, index, text, line_number):
    fields = lines[line_number - 1].split(",")
    fields[index] = text
    return lines[:line_number - 1] + [",".join(fields)] + lines[line_number:]


@pytest.mark.parametrize("script", sorted(CASES))
def test_a_cell_that_is_not_a_number_is_named_by_line_and_column(script, tmp_path):
    setup, column = CASES[script]
    args, src, _ = setup(str(tmp_path))
    index = column_index(src, column)
    rewrite(src, lambda lines: break_cell(lines, index, "12.x", 3))
    assert_one_line(run(script, *args), script, src,
                    f"line 3, column '{column}': '12.x' is not a number")


@pytest.mark.parametrize("script", sorted(CASES))
def test_a_missing_column_is_named(script, tmp_path):
    setup, column = CASES[script]
    args, src, _ = setup(str(tmp_path))
    rewrite(src, lambda lines: [lines[0].replace(column, column + "_renamed", 1)] + lines[1:])
    assert_one_line(run(script, *args), script, src, f"no column '{column}'")


@pytest.mark.parametrize("script", sorted(CASES))
def test_a_short_row_is_named_by_line(script, tmp_path):
    setup, _ = CASES[script]
    args, src, _ = setup(str(tmp_path))
    rewrite(src, lambda lines: lines[:1] + [lines[1].rsplit(",", 1)[0]] + lines[2:])
    fields = len(lines_of(src)[0].split(","))
    assert_one_line(run(script, *args), script, src,
                    f"line 2: {fields - 1} fields, the header has {fields}")


@pytest.mark.parametrize("content, message", [
    ("", "empty; expected "),
    (lines_of(os.path.join(RESULTS, "fig5.csv"))[0] + "\n", "a header and no rows; expected "),
    ("pattern,estimator\nsimple,\"fast\n", "line 2: unexpected end of data"),
    (b"\xff\xfe\x00pattern", "not UTF-8 text (byte 0)"),
])
def test_an_empty_headless_or_broken_file_is_one_line(content, message, tmp_path):
    src = tmp_path / "fig5.csv"
    if isinstance(content, bytes):
        src.write_bytes(content)
    else:
        src.write_text(content)
    assert_one_line(run("plot_fig5.py", str(src), str(tmp_path / "f.png")), "plot_fig5.py",
                    str(src), message)


def test_a_directory_given_as_input_is_one_line(tmp_path):
    assert_one_line(run("plot_compare.py", str(tmp_path), str(tmp_path / "c.png")),
                    "plot_compare.py", str(tmp_path), "is a directory")


def test_wrong_arguments_print_the_usage_and_exit_2():
    result = run("plot_compare.py", "only-one-argument")
    assert result.returncode == 2
    assert result.stderr == "usage: plot_compare.py DIR/compare.csv DIR/compare.png\n"


def test_a_figure_that_cannot_be_written_is_one_line_and_exit_1(tmp_path):
    out = tmp_path / "no-such-dir" / "c.png"
    result = run("plot_compare.py", os.path.join(RESULTS, "compare", "compare.csv"), str(out))
    assert result.returncode == 1, result.stderr
    message = f"plot_compare.py: {out}: cannot be written: No such file or directory\n"
    assert result.stderr == message


def test_csv_reader_takes_quotes_crlf_and_a_bom_and_counts_lines(tmp_path):
    src = tmp_path / "quoted.csv"
    src.write_bytes('\ufeffdesign,note,rate\r\n"a, b","two\r\nlines",0.5\r\nc,"say ""x""",nan\r\n'
                    .encode("utf-8"))
    table = plotinput.read_csv(str(src), "a test file", columns=["design"], numbers=["rate"])
    assert [r["design"] for r in table.rows] == ["a, b", "c"]
    assert table.rows[0]["note"] == "two\r\nlines"
    assert table.rows[1]["note"] == 'say "x"'
    assert table.lines == [2, 4]  # the second record starts after the quoted line break


# What the figures show: checked on the figure objects against values computed here.

def test_zero_count_interval_gives_back_its_robots():
    # A count of 0 in N has the Wilson upper end z^2 / (N + z^2); patlab prints 6 digits.
    for n in (1, 7, 4000, 10000, 20000, 100000):
        upper = float("%.6g" % (plot_compare.Z95 ** 2 / (n + plot_compare.Z95 ** 2)))
        assert plot_compare.robots_behind_zero(upper) == n
    assert math.isnan(plot_compare.robots_behind_zero(0.0))
    assert math.isnan(plot_compare.robots_behind_zero(1.0))


def test_compare_draws_zero_rates_at_one_over_n_and_does_not_join_them():
    path = os.path.join(RESULTS, "compare", "compare.csv")
    rows, sigmas = plot_compare.read(path)
    with open(os.path.join(RESULTS, "compare", "compare.json")) as f:
        frames = json.load(f)["options"]["frames"]
    fig = plot_compare.figure(rows, sigmas, "t")
    panels = [ax for ax in fig.subfigs[1].axes if ax.get_title()]
    row = next(r for r in rows if r["design"] == "butterfly")
    butterfly = next(ax for ax in panels if ax.get_title().endswith("butterfly"))
    # The Butterfly's 16 IDs give every frame 10 robots (5 a team): N = frames x 10 a sigma.
    rates = [float(row["rotation_errors_%gmm" % s]) for s in sigmas]
    zero = [s for s, r in zip(sigmas, rates) if r == 0]
    assert zero and len(zero) < len(sigmas)  # the file has both kinds, or the test tests nothing
    line, *rest = butterfly.get_lines()
    for y, r in zip(line.get_ydata(), rates):
        assert math.isnan(y) if r == 0 else y == r  # zeros break the line
    zeros = [ln for ln in rest if ln.get_marker() == "v"]
    assert len(zeros) == 1
    assert list(zeros[0].get_xdata()) == zero
    assert list(zeros[0].get_ydata()) == pytest.approx([1 / (frames * 10)] * len(zero), rel=1e-12)
    drawn = [y for ln in butterfly.get_lines() if ln.get_marker() in ("o", "v")
             for y in ln.get_ydata() if not math.isnan(y)]  # the points, not bar caps or onset
    assert min(drawn) >= 1 / (frames * 10) * (1 - 1e-12)  # nothing below 1/N, no made-up floor


def test_compare_gives_each_of_the_seventeen_team_designs_its_own_panel():
    rows, sigmas = plot_compare.read(os.path.join(RESULTS, "team-designs", "compare.csv"))
    assert len(rows) == 17
    fig = plot_compare.figure(rows, sigmas, "t")
    titles = [ax.get_title() for ax in fig.subfigs[1].axes if ax.get_title()]
    assert titles == [f"{r['rank']}. {r['design']}" for r in rows]
    shared = {ax.get_ylim() for ax in fig.subfigs[1].axes if ax.get_title()}
    assert len(shared) == 1  # the same axes in every panel, so that they compare


def test_id_confusion_legend_names_every_curve():
    rows = plot_id_confusion.read(os.path.join(RESULTS, "id_confusion.csv"))
    fig, _ = plot_id_confusion.figure(rows)
    legend = fig.legends[0]
    texts = [t.get_text() for t in legend.get_texts()]
    assert texts == ["detection rate (correct ID / robots)",
                     "ambiguous / robots (geometry fits several rotations, colours decide none)",
                     "wrong ID / (correct + wrong)", "0 false blobs per m²",
                     "2 false blobs per m²", "rate 0 in N: below 1/N, drawn at 1/N"]
    handles = legend.legend_handles if hasattr(legend, "legend_handles") else legend.legendHandles
    colours = [matplotlib.colors.to_hex(h.get_color()) for h in handles[:3]]
    assert len(set(colours)) == 3
    styles = [(h.get_marker(), h.get_linestyle(), matplotlib.colors.to_hex(h.get_markerfacecolor()))
              for h in handles[3:5]]
    assert styles[0] != styles[1]
    # Every curve drawn in a panel has one of the legend's colours and one of its markers.
    known_marker = {h.get_marker() for h in handles[3:]}
    for ax in fig.axes:
        for ln in ax.get_lines():
            if len(ln.get_xdata()) and ln.get_marker() not in ("None", None, "", "_"):
                assert matplotlib.colors.to_hex(ln.get_color()) in colours
                assert ln.get_marker() in known_marker


def test_id_confusion_draws_zero_rates_at_one_over_robots():
    rows = plot_id_confusion.read(os.path.join(RESULTS, "id_confusion.csv"))
    sel = [r for r in rows if r["pattern"] == "triangle" and r["false_blob_rate_per_m2"] == "0"]
    (sigma, shown, _, _), (zero_sigma, floor) = plot_id_confusion.series(sel, "ambiguous_rate")
    # The Triangle's colours fix its rotation: never ambiguous; N is the point's robots.
    assert all(math.isnan(v) for v in shown)
    assert zero_sigma == sigma
    assert floor == pytest.approx([1 / int(r["robots"]) for r in sel], rel=1e-12)
    assert int(sel[0]["robots"]) == 50000  # 5000 frames of 10 robots (id_confusion.toml)
