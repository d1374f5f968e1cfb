#!/usr/bin/env python3
"""Offline sweep of the rapid-perception gate (threshold x max_skipped_frames) on `squint perceive
--no-gate` CSVs, for the per-frame heading fusion (column heading_instant_deg, or heading_deg in
CSVs written before it existed). The per-frame fusion has no memory, so the heading of a frame the
gate lets through equals its ungated heading: the gate only chooses which frames count, and its
decisions depend only on the gate_change column (|H(t) - H(t-1)| / H(reference), previous-frame
mode). The heading filter (heading.filter in calibrated options) has memory: its gated heading
differs from the ungated one, so measure it with `squint eval corridor` (rapid_perception).

    squint perceive SEQ --no-gate --calib calib.yaml --out SEQ.csv      # per sequence
    python3 docs/eval/gate_sweep.py --cal c0.csv ... --test c5.csv ...

Prints, per setting, the fraction of frames skipped and the fused heading RMSE on every frame and
on the processed frames, for the calibration and the test CSVs.
"""
import argparse
import csv
import math


def load(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def simulate(runs, threshold, max_skipped):
    every, processed = [], []
    frames = kept = 0
    for rows in runs:
        skipped = 0
        for i, r in enumerate(rows):
            change = r["gate_change"]
            process = (i == 0 or change == "" or float(change) >= threshold
                       or (max_skipped > 0 and skipped >= max_skipped))
            skipped = 0 if process else skipped + 1
            frames += 1
            kept += process
            h = r.get("heading_instant_deg", r["heading_deg"])
            if h == "" or r["gt_heading_deg"] == "":
                continue
            e = float(h) - float(r["gt_heading_deg"])
            every.append(e)
            if process:
                processed.append(e)
    rmse = lambda v: math.sqrt(sum(x * x for x in v) / len(v)) if v else float("nan")
    return 1.0 - kept / frames, rmse(every), rmse(processed)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cal", nargs="+", required=True)
    ap.add_argument("--test", nargs="+", required=True)
    ap.add_argument("--thresholds", default="0.01,0.02,0.03,0.05")
    ap.add_argument("--max-skipped", default="0,4,6,8,10")
    a = ap.parse_args()
    cal = [load(p) for p in a.cal]
    test = [load(p) for p in a.test]
    print("| threshold | max skip | cal skipped | cal RMSE every / processed | test skipped | test RMSE every / processed |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: |")
    for t in [float(x) for x in a.thresholds.split(",")]:
        for m in [int(x) for x in a.max_skipped.split(",")]:
            cs, ca, cp = simulate(cal, t, m)
            ts, ta, tp = simulate(test, t, m)
            print(f"| {t:g} | {m} | {cs:.1%} | {ca:.2f}° / {cp:.2f}° | {ts:.1%} | {ta:.2f}° / {tp:.2f}° |")


if __name__ == "__main__":
    main()
