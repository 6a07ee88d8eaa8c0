#!/usr/bin/env python3
"""The totals docs/setup.md quotes over every random camera of results/setup.

Reads every rendered.csv under results/setup (scripts/setup_rendered.py writes them, one per set
of seeds) and prints, per set and over all of them: the robots right with their team and ID out
of those shown, the false IDs, the frames setup refused; and, for the frames setup kept, how its
calibration maps the floor against the truth:

  * the true mapping error (true_mapping_error_mm: where setup's camera and the true camera put
    the floor every 10th pixel shows inside the field's lines, RMS in mm) within 5 mm;
  * setup's stated error (mapping_error_mm: its held-out line pixels, a number, or "<R" when it is
    below the line finder's resolution R) against the true one: they agree when the ratio is
    within 1.5 either way, or, for "<R", when the true error is at most 1.5 R. A stated error the
    truth exceeds more than 1.5 times is "too low", one it undercuts is "too high".

usage: scripts/setup_rendered_summary.py [--root DIR] [--results DIR] [--worst N]
  --results: the folder of rendered.csv files, relative to the root (default results/setup;
  results/setup-named-model holds the runs with each frame's model named).
"""
import argparse
import csv
import math
import os
import pathlib
import sys

FACTOR = 1.5
LIMIT_MM = 5.0


def read_sets(root, results="results/setup"):
    """[(the CSV's path relative to root, its rows)] for every rendered.csv under root/results,
    in seed order."""
    sets = []
    for path in (root / results).rglob("rendered.csv"):
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        if rows:
            sets.append((path.relative_to(root).as_posix(), rows))
    return sorted(sets, key=lambda s: (int(s[1][0]["seed"]), s[0]))


def kept_frames(rows):
    """The frames setup kept whose true mapping error was measured."""
    return [r for r in rows if r["outcome"] == "detected" and r.get("true_mapping_error_mm")]


def agreement(stated, true_mm):
    """'agrees', 'too low' or 'too high' for a stated error ("0.72" or "<0.29") and the truth."""
    if stated.startswith("<"):
        return "agrees" if true_mm <= FACTOR * float(stated[1:]) else "too low"
    value = float(stated)
    if true_mm > FACTOR * value:
        return "too low"
    return "too high" if value > FACTOR * true_mm else "agrees"


def summary(rows):
    shown = sum(int(r["robots"]) for r in rows)
    right = sum(int(r["right"]) for r in rows)
    false = sum(int(r["false_ids"]) for r in rows)
    refused = [r["seed"] for r in rows if r["outcome"] != "detected"]
    kept = kept_frames(rows)
    true_mm = [float(r["true_mapping_error_mm"]) for r in kept]
    verdicts = [agreement(r["mapping_error_mm"], t) for r, t in zip(kept, true_mm)]
    return dict(shown=shown, right=right, false=false, frames=len(rows), refused=refused,
                kept=len(kept), within=sum(t <= LIMIT_MM for t in true_mm),
                agrees=verdicts.count("agrees"), too_low=verdicts.count("too low"),
                too_high=verdicts.count("too high"),
                median=sorted(true_mm)[len(true_mm) // 2] if true_mm else math.nan)


def line(name, s):
    text = "%-28s %4d / %4d robots right (%5.1f %%), %d false IDs, %d / %d frames refused" % (
        name, s["right"], s["shown"], 100.0 * s["right"] / max(s["shown"], 1), s["false"],
        len(s["refused"]), s["frames"])
    if s["kept"]:
        text += "; floor within %.0f mm in %d / %d, median %.2f mm, stated error agrees %d, " \
                "too low %d, too high %d" % (LIMIT_MM, s["within"], s["kept"], s["median"],
                                              s["agrees"], s["too_low"], s["too_high"])
    return text


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", default=pathlib.Path(__file__).resolve().parent.parent,
                        type=pathlib.Path, help="the repository (default: this script's)")
    parser.add_argument("--results", default="results/setup",
                        help="the folder of rendered.csv files under the root "
                             "(default results/setup)")
    parser.add_argument("--worst", type=int, default=10,
                        help="list the N frames of largest true mapping error (default 10)")
    args = parser.parse_args()
    sets = read_sets(args.root, args.results)
    if not sets:
        print("no rendered.csv under %s/%s" % (args.root, args.results))
        return 2
    every = []
    for path, rows in sets:
        print(line(os.path.dirname(path), summary(rows)))
        every += rows
    print(line("all", summary(every)))
    kept = sorted(kept_frames(every), key=lambda r: -float(r["true_mapping_error_mm"]))
    print("largest true mapping errors: " + "; ".join(
        "seed %s %s mm (stated %s, %s, height by %s)" % (
            r["seed"], r["true_mapping_error_mm"], r["mapping_error_mm"],
            agreement(r["mapping_error_mm"], float(r["true_mapping_error_mm"])),
            r["height_decided_by"]) for r in kept[:args.worst]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
