"""scripts/setup_rendered_summary.py: the agreement rule of a stated mapping error with the true
one, and the totals over planted CSVs.

Run by ctest as `setup_tables_planted` (tests/CMakeLists.txt).
"""
import os
import subprocess
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import setup_rendered_summary as summary  # noqa: E402

COLUMNS = ("seed,model,height_mm,f_px,k1,brightness,exposure_gain,read_noise_levels,robots,outcome,"
           "model_kept,right,false_ids,position_error_mm,mapping_error_mm,true_mapping_error_mm,"
           "setup_height_mm,setup_f_px,height_decided_by\n")


def test_a_stated_error_agrees_within_a_factor_of_one_and_a_half():
    assert summary.agreement("1.0", 1.5) == "agrees"
    assert summary.agreement("1.0", 1.51) == "too low"
    assert summary.agreement("1.0", 0.67) == "agrees"
    assert summary.agreement("1.0", 0.66) == "too high"
    # "below R": any truth up to 1.5 R agrees, however small.
    assert summary.agreement("<0.2", 0.0) == "agrees"
    assert summary.agreement("<0.2", 0.3) == "agrees"
    assert summary.agreement("<0.2", 0.31) == "too low"


def test_totals_over_every_set(tmp_path):
    rows = {
        "results/setup/rendered.csv": [
            "1,ssl-2015,3847,632,0,1,1,3,8,detected,ssl-2015,8,0,1.4,<0.19,0.25,3772,619,robots",
            "2,ssl-2014,3174,572,0,1,1,2,6,setup refused (exit 2),,0,0,,,,,,"],
        "results/setup/seeds-3-4/rendered.csv": [
            "3,ssl-div-a,3870,518,0,1,1,3,6,detected,ssl-2018,5,1,11.4,<0.23,9.62,3120,418,robots",
            "4,ssl-div-b,3750,562,0,1,1,3,10,detected,ssl-div-b,10,0,0.7,0.72,0.25,3800,569,lines"],
    }
    for rel, lines in rows.items():
        path = tmp_path / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(COLUMNS + "\n".join(lines) + "\n")
    done = subprocess.run([sys.executable, os.path.join(ROOT, "scripts",
                                                        "setup_rendered_summary.py"),
                           "--root", str(tmp_path)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    last = [line for line in done.stdout.splitlines() if line.startswith("all ")][0]
    assert "23 /   30 robots right ( 76.7 %), 1 false IDs, 1 / 4 frames refused" in last
    assert "floor within 5 mm in 2 / 3, median 0.25 mm" in last
    assert "stated error agrees 1, too low 1, too high 1" in last
    assert "seed 3 9.62 mm (stated <0.23, too low, height by robots)" in done.stdout


def test_results_names_another_folder(tmp_path):
    path = tmp_path / "results" / "setup-named-model" / "rendered.csv"
    path.parent.mkdir(parents=True)
    path.write_text(COLUMNS + "5,ssl-2015,3847,632,0,1,1,3,8,detected,ssl-2015,7,0,1.4,<0.19,0.25,"
                    "3772,619,robots\n")
    script = os.path.join(ROOT, "scripts", "setup_rendered_summary.py")
    default = subprocess.run([sys.executable, script, "--root", str(tmp_path)],
                             capture_output=True, text=True)
    assert default.returncode == 2 and "no rendered.csv under" in default.stdout
    named = subprocess.run([sys.executable, script, "--root", str(tmp_path), "--results",
                            "results/setup-named-model"], capture_output=True, text=True)
    assert named.returncode == 0, named.stderr
    assert "results/setup-named-model       7 /    8 robots right ( 87.5 %)" in named.stdout
