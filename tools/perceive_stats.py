#!/usr/bin/env python3
"""Heading / distance accuracy of `squint perceive` CSVs against their ground-truth columns.

Usage: tools/perceive_stats.py OUT.csv [OUT.csv ...]
Prints, per measure and for the fused estimate: coverage (estimate on % of frames), RMSE and
median absolute error (degrees or metres) over frames with an estimate, and for headings the
share of frames with |gt| >= 5 deg whose estimate has the right sign (a missing estimate counts
as wrong). Not part of CI; the README's figures come from it.
"""
import csv
import math
import sys

HEAD = ["heading_deg", "heading_entropy_deg", "heading_symmetry_deg", "heading_phase_deg",
        "heading_vanishing_deg", "heading_bright_deg"]
DIST = ["dist_end_m", "dist_ttc_m", "dist_jeffrey_m", "dist_entropy_m", "dist_floor_m"]


def median(xs):
    xs = sorted(xs)
    n = len(xs)
    if n == 0:
        return float("nan")
    return xs[n // 2] if n % 2 else 0.5 * (xs[n // 2 - 1] + xs[n // 2])


def main(paths):
    rows = []
    for p in paths:
        with open(p) as f:
            rows += [r for r in csv.DictReader(f)]
    rows = [r for r in rows if r["processed"] == "1"]
    print(f"frames: {len(rows)} from {len(paths)} file(s)")
    print(f"{'heading':24s} {'cover%':>7s} {'rmse':>7s} {'median':>7s} {'sign%':>7s}")
    for col in HEAD:
        errs, signs, n_sign = [], 0, 0
        for r in rows:
            gt = float(r["gt_heading_deg"])
            v = r[col]
            if abs(gt) >= 5:
                n_sign += 1
            if v == "":
                continue
            e = float(v) - gt
            errs.append(e)
            if abs(gt) >= 5 and (float(v) > 0) == (gt > 0):
                signs += 1
        cover = 100.0 * len(errs) / max(1, len(rows))
        rmse = math.sqrt(sum(e * e for e in errs) / max(1, len(errs)))
        med = median([abs(e) for e in errs])
        print(f"{col:24s} {cover:7.1f} {rmse:7.2f} {med:7.2f} {100.0 * signs / max(1, n_sign):7.1f}")
    if any(r["gt_dist_end_m"] for r in rows):
        print(f"{'distance':24s} {'cover%':>7s} {'rmse':>7s} {'median':>7s}")
        for col in DIST:
            if col not in rows[0]:  # CSVs written before the column existed
                continue
            errs = [float(r[col]) - float(r["gt_dist_end_m"]) for r in rows if r[col] != "" and r["gt_dist_end_m"]]
            cover = 100.0 * len(errs) / max(1, len(rows))
            rmse = math.sqrt(sum(e * e for e in errs) / max(1, len(errs)))
            print(f"{col:24s} {cover:7.1f} {rmse:7.2f} {median([abs(e) for e in errs]):7.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
