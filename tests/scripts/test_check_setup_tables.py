"""scripts/check_setup_tables.py on small planted trees: tables that say what the CSVs say pass,
and each kind of difference fails with its docs/setup.md:LINE message.

Run by ctest as `setup_tables_planted` (tests/CMakeLists.txt).
"""
import os
import subprocess
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECKER = os.path.join(ROOT, "scripts", "check_setup_tables.py")

COLUMNS = ("seed,model,height_mm,f_px,k1,brightness,exposure_gain,read_noise_levels,robots,outcome,"
           "model_kept,right,false_ids,position_error_mm,mapping_error_mm,setup_height_mm,"
           "setup_f_px,height_decided_by\n")
DETECTED = ("7,ssl-2015,3847,632.1,-0.041,1.1,1.0,3.1,8,detected,ssl-2015,8,0,1.4,<0.19,3772,619.5,"
            "robots\n")
REFUSED = "8,ssl-2014,3174,572.5,-0.036,0.9,1.2,2.2,6,setup refused (exit 2),,0,0,,,,,\n"
HEADER = ("| seed | true model | kept | robots right / shown | false IDs | camera height: true, "
          "setup's (decided by) | position error of those found |\n|---|---|---|---|---|---|---|\n")
ROW_7 = "| 7 | ssl-2015 | ssl-2015 (a note) | 8 / 8 | 0 | 3.85 m, 3.77 m (robots) | 1.4 mm |\n"
ROW_8 = "| 8 | ssl-2014 | – (setup refused (exit 2)) | 0 / 6 | 0 | 3.17 m, – | – |\n"


def write(root, rel, text):
    path = os.path.join(root, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def run(tmp_path, rows, csvs=None):
    root = str(tmp_path)
    csvs = csvs or {"results/setup/seeds-7-8/rendered.csv": COLUMNS + DETECTED + REFUSED}
    for rel, text in csvs.items():
        write(root, rel, text)
    page = "# Setup\n\nPer frame:\n\n" + HEADER + "".join(rows) + "\nAfter.\n"
    write(root, "docs/setup.md", page)
    return subprocess.run([sys.executable, CHECKER, "--root", root], capture_output=True, text=True)


def test_rows_that_agree_pass(tmp_path):
    done = run(tmp_path, [ROW_7, ROW_8])
    assert done.returncode == 0, done.stdout


def test_each_column_that_differs_fails_with_its_line(tmp_path):
    changes = {
        "true model": ROW_7.replace("| ssl-2015 | ssl", "| ssl-2014 | ssl"),
        "kept": ROW_7.replace("| ssl-2015 (a note)", "| ssl-2014 (a note)"),
        "robots right / shown": ROW_7.replace("8 / 8", "7 / 8"),
        "false IDs": ROW_7.replace("| 0 |", "| 1 |"),
        "camera height": ROW_7.replace("3.77 m (robots)", "3.77 m (lines)"),
        "position error": ROW_7.replace("1.4 mm", "1.5 mm"),
    }
    for column, row in changes.items():
        done = run(tmp_path, [row, ROW_8])
        assert done.returncode == 1, column
        assert "docs/setup.md:7: seed 7: %s reads" % column in done.stdout, done.stdout


def test_a_refused_frame_must_name_its_outcome(tmp_path):
    done = run(tmp_path, [ROW_7, ROW_8.replace(" (setup refused (exit 2))", "")])
    assert done.returncode == 1
    assert "docs/setup.md:8: seed 8: kept does not name the outcome" in done.stdout


def test_a_seed_without_a_row_or_with_two_fails(tmp_path):
    done = run(tmp_path, [ROW_7])
    assert done.returncode == 1
    assert "seed 8 of results/setup/seeds-7-8/rendered.csv has no row" in done.stdout
    done = run(tmp_path, [ROW_7, ROW_8, ROW_7])
    assert done.returncode == 1
    assert "docs/setup.md:9: seed 7 already has a row at line 7" in done.stdout


def test_a_row_of_no_csv_and_a_seed_in_two_csvs_fail(tmp_path):
    done = run(tmp_path, [ROW_7, ROW_8, ROW_8.replace("| 8 |", "| 9 |")])
    assert done.returncode == 1
    assert "docs/setup.md:9: seed 9 is in no results/setup/*/rendered.csv" in done.stdout
    done = run(tmp_path, [ROW_7, ROW_8], csvs={
        "results/setup/a/rendered.csv": COLUMNS + DETECTED + REFUSED,
        "results/setup/b/rendered.csv": COLUMNS + DETECTED})
    assert done.returncode == 1
    assert ("results/setup/b/rendered.csv: seed 7 is also in results/setup/a/rendered.csv"
            in done.stdout)
