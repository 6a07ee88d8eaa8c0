#!/usr/bin/env python3
"""docs/setup.md's per-frame tables of random cameras say what results/setup's CSVs say.

Every rendered.csv under results/setup (written by scripts/setup_rendered.py) holds one row per
seed. docs/setup.md reports each seed in a table with the header

    | seed | true model | kept | robots right / shown | false IDs | camera height: true, setup's (decided by) | position error of those found |

and this script checks each such row against its seed's CSV row: the true model, the model kept
(the first word of the column; "–" for a refused frame, which also names the CSV's outcome), the
robots right and shown, the false IDs, the camera's true height and setup's (in m, 2 decimals)
with what decided it, and the position error (mm, 1 decimal). The column's words after the model
are the docs' own notes and are not checked. It also checks that every seed of the CSVs has
exactly one row, and that no seed is in two CSVs. A difference is reported as
`docs/setup.md:LINE: seed N: COLUMN reads 'X', results/setup/.../rendered.csv says 'Y'` and the
exit status is 1. Run by scripts/check_style.sh and the ctest setup_tables.

usage: scripts/check_setup_tables.py [--root DIR]
"""
import argparse
import pathlib
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import setup_rendered_summary  # noqa: E402  (the one reader of results/setup's CSVs)

HEADER = ("| seed | true model | kept | robots right / shown | false IDs | camera height: true, "
          "setup's (decided by) | position error of those found |")
DASH = "–"


def csv_rows(root):
    """{seed: (row, the CSV's path relative to root)} over every rendered.csv; errors."""
    rows, errors = {}, []
    for rel, set_rows in setup_rendered_summary.read_sets(root):
        for row in set_rows:
            seed = int(row["seed"])
            if seed in rows:
                errors.append("%s: seed %d is also in %s" % (rel, seed, rows[seed][1]))
            rows[seed] = (row, rel)
    return rows, errors


def doc_rows(page):
    """(line number, the row's cells) for every row of the per-frame tables."""
    lines = page.read_text().splitlines()
    inside = False
    for number, line in enumerate(lines, 1):
        if line.strip() == HEADER:
            inside = True
        elif inside and line.startswith("|---"):
            continue
        elif inside and line.startswith("| "):
            yield number, [cell.strip() for cell in line.strip().strip("|").split("|")]
        else:
            inside = False


def metres(mm):
    return "%.2f m" % (float(mm) / 1000.0)


def expected(row):
    """The columns the docs must show for a CSV row (the kept column's first word only)."""
    refused = row["outcome"] != "detected"
    kept = DASH if refused else row["model_kept"]
    setup_height = DASH if not row["setup_height_mm"] else "%s (%s)" % (
        metres(row["setup_height_mm"]), row["height_decided_by"])
    error = DASH if not row["position_error_mm"] else "%.1f mm" % float(row["position_error_mm"])
    return {
        "true model": row["model"],
        "kept": kept,
        "robots right / shown": "%s / %s" % (row["right"], row["robots"]),
        "false IDs": row["false_ids"],
        "camera height": "%s, %s" % (metres(row["height_mm"]), setup_height),
        "position error": error,
    }


def check(root):
    rows, errors = csv_rows(root)
    page = root / "docs" / "setup.md"
    rel_page = page.relative_to(root).as_posix()
    seen = {}
    for number, cells in doc_rows(page):
        where = "%s:%d" % (rel_page, number)
        if len(cells) != 7 or not cells[0].isdigit():
            errors.append("%s: a row of 7 columns starting with a seed expected, got %d columns"
                          % (where, len(cells)))
            continue
        seed = int(cells[0])
        if seed in seen:
            errors.append("%s: seed %d already has a row at line %d" % (where, seed, seen[seed]))
        seen[seed] = number
        if seed not in rows:
            errors.append("%s: seed %d is in no results/setup/*/rendered.csv" % (where, seed))
            continue
        row, source = rows[seed]
        shown = {
            "true model": cells[1],
            "kept": cells[2].split(" ")[0],
            "robots right / shown": cells[3],
            "false IDs": cells[4],
            "camera height": cells[5],
            "position error": cells[6],
        }
        for column, value in expected(row).items():
            if shown[column] != value:
                errors.append("%s: seed %d: %s reads '%s', %s says '%s'"
                              % (where, seed, column, shown[column], source, value))
        if row["outcome"] != "detected" and "(" + row["outcome"] + ")" not in cells[2]:
            errors.append("%s: seed %d: kept does not name the outcome '%s' of %s"
                          % (where, seed, row["outcome"], source))
    for seed in sorted(set(rows) - set(seen)):
        errors.append("%s: seed %d of %s has no row in its per-frame tables"
                      % (rel_page, seed, rows[seed][1]))
    return errors


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", default=pathlib.Path(__file__).resolve().parent.parent,
                        type=pathlib.Path, help="the repository (default: this script's)")
    errors = check(parser.parse_args().root)
    for error in errors:
        print(error)
    if errors:
        print("docs/setup.md's per-frame tables differ from results/setup: correct the table rows "
              "(or rerun scripts/setup_rendered.py for the CSV)")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
