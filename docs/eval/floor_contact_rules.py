#!/usr/bin/env python3
"""Offline comparison of end-wall base rules for the floor contact (corridor::FloorContact), on
sequence folders with ground truth (squint sim record ... --protocol drive, ../shared/data/drive-*).

Per frame, the centre columns within +-2 deg (3 columns averaged each, as the C++) are scanned
down from the horizon; each rule picks a boundary row, the row's floor point gives a distance
(camera height and pitch from sequence.yaml), the frame's reading is the median over the columns
when at least half answered and it lies in 0.3-20 m. No temporal median, no odometry: the raw
per-frame reading, whose RMSE against gt_dist_end_m is printed at 0.3-5 and 5-15 m with the
fraction of frames that have a reading. `first` is the C++ rule (first step of 6 grey levels,
refined to the strongest of the next rows, sub-pixel).

    /usr/bin/python3 docs/eval/floor_contact_rules.py SEQ [SEQ...] --rules first,rel.5,persist3 --step 6

Rules: first; rel.R (first step >= max(6, R x the column's strongest step below the horizon));
persistW (first step whose mean over W rows below differs from the mean over W rows above by >= 6,
same sign); relpersist[.R] (both); noline[.K] (skip a step with an opposite step of >= K x it in
the next or previous row: a thin line such as mortar); lined[.R] (the lined-wall rule of
FloorContactOptions::lined_wall_rel_step, session 15: `first`, but where the band of rows just above
the horizon, as deep as that edge lies below it, has a step >= 6, rel.R instead; R 0.5 by default).
"""
import argparse
import csv
import math

import cv2
import numpy as np
import yaml


def load(seq, step):
    with open(seq + "/sequence.yaml") as f:
        cam = yaml.safe_load(f)["camera"]
    with open(seq + "/frames.csv", newline="") as f:
        rows = list(csv.DictReader(f))[::step]
    return cam, rows


def dist_of_row(cam, v):
    a = math.atan((v - cam["cy"]) / cam["fy"]) - math.radians(cam["pitch_deg"])
    return cam["height_m"] / math.tan(a) if a > 1e-6 else None


def horizon(cam):
    return cam["cy"] + cam["fy"] * math.tan(math.radians(cam["pitch_deg"]))


def profiles(img, cam, half_deg=2.0):
    half = cam["fx"] * math.tan(math.radians(half_deg))
    u0 = max(1, round(cam["cx"] - half))
    u1 = min(cam["width"] - 2, round(cam["cx"] + half))
    f = img.astype(np.float64)
    return [(f[:, u - 1] + f[:, u] + f[:, u + 1]) / 3.0 for u in range(u0, u1 + 1)]


def refine(st, best):
    a, b, c = st[best - 1], st[best], st[best + 1]
    den = a - 2 * b + c
    off = max(-0.5, min(0.5, 0.5 * (a - c) / den)) if den != 0 else 0.0
    return best + 0.5 + off


def strongest_after(st, v, limit):
    best = v
    for j in range(v + 1, min(v + 3, limit)):
        if st[j] > st[best]:
            best = j
    return best


def rule_first(p, top, ms=6.0):
    st = np.abs(np.diff(p))
    h = len(p)
    for v in range(top + 1, h - 2):
        if st[v] >= ms:
            return refine(st, strongest_after(st, v, h - 2))
    return None


def rule_rel(p, top, rho, ms=6.0):
    st = np.abs(np.diff(p))
    h = len(p)
    if h - 2 <= top + 1:
        return None
    thr = max(ms, rho * st[top + 1:h - 2].max())
    for v in range(top + 1, h - 2):
        if st[v] >= thr:
            return refine(st, strongest_after(st, v, h - 2))
    return None


def rule_persist(p, top, w, rho=0.0, ms=6.0):
    sd = np.diff(p)
    st = np.abs(sd)
    h = len(p)
    if h - 2 <= top + 1:
        return None
    thr = max(ms, rho * st[top + 1:h - 2].max())
    need = ms if rho == 0.0 else 0.5 * thr
    for v in range(top + 1 + w, h - 2 - w):
        if st[v] < thr:
            continue
        best = strongest_after(st, v, h - 2 - w)
        above = p[best - w + 1:best + 1].mean()
        below = p[best + 1:best + 1 + w].mean()
        if abs(below - above) < need or (below - above) * sd[best] < 0:
            continue
        return refine(st, best)
    return None


def rule_noline(p, top, k, ms=6.0):
    sd = np.diff(p)
    st = np.abs(sd)
    h = len(p)
    v = top + 1
    while v < h - 3:
        if st[v] < ms:
            v += 1
            continue
        best = strongest_after(st, v, h - 2)
        nxt, prv = sd[best + 1], sd[best - 1]
        if (nxt * sd[best] < 0 and abs(nxt) >= k * st[best]) or (prv * sd[best] < 0 and abs(prv) >= k * st[best]):
            v = best + 2
            continue
        return refine(st, best)
    return None


def rule_lined(p, top, hz, rho, ms=6.0):
    y = rule_first(p, top, ms)
    if y is None:
        return None
    lo = max(0, math.floor(hz - (y - hz)))
    band = p[lo:top]
    if len(band) > 1 and np.abs(np.diff(band)).max() >= ms:
        return rule_rel(p, top, rho, ms)
    return y


def make_rule(name, hz=None):
    if name == "first":
        return rule_first
    if name.startswith("relpersist"):
        rho = float(name[len("relpersist"):] or 0.5)
        return lambda p, t: rule_persist(p, t, 2, rho)
    if name.startswith("rel"):
        return lambda p, t: rule_rel(p, t, float(name[3:]))
    if name.startswith("persist"):
        return lambda p, t: rule_persist(p, t, int(name[7:]))
    if name.startswith("lined"):
        rho = float(name[5:] or 0.5)
        return lambda p, t: rule_lined(p, t, hz, rho)
    if name.startswith("noline"):
        k = float(name[6:] or 0.5)
        return lambda p, t: rule_noline(p, t, k)
    raise SystemExit(f"unknown rule '{name}'")


def run(seq, step, names):
    cam, rows = load(seq, step)
    top = max(0, math.ceil(horizon(cam)))
    rules = {name: make_rule(name, horizon(cam)) for name in names}
    out = {name: [] for name in rules}
    for r in rows:
        d = float(r["gt_dist_end_m"])
        if not 0.3 <= d <= 15.0:
            continue
        img = cv2.imread(seq + "/" + r["image"], cv2.IMREAD_GRAYSCALE)
        if img is None:
            raise SystemExit(f"{seq}/{r['image']}: cannot read image")
        cols = profiles(img, cam)
        for name, rule in rules.items():
            readings = []
            for p in cols:
                y = rule(p, top)
                x = dist_of_row(cam, y) if y is not None else None
                if x and x > 0:
                    readings.append(x)
            val = None
            if readings and len(readings) >= 0.5 * len(cols):
                m = float(np.median(readings))
                val = m if 0.3 <= m <= 20.0 else None
            out[name].append((d, val))
    return out


def summary(pairs):
    parts = []
    for lo, hi in ((0.3, 5.0), (5.0, 15.0)):
        errs = [v - d for d, v in pairs if lo <= d < hi and v is not None]
        n = sum(1 for d, _ in pairs if lo <= d < hi)
        rmse = math.sqrt(float(np.mean(np.square(errs)))) if errs else float("nan")
        parts.append(f"{rmse:6.2f} m ({100 * len(errs) / max(n, 1):3.0f} %)")
    return "  ".join(parts)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sequences", nargs="+")
    ap.add_argument("--rules", default="first,rel.5,persist2,persist3,relpersist")
    ap.add_argument("--step", type=int, default=1, help="use every STEP-th frame")
    a = ap.parse_args()
    rules = a.rules.split(",")
    for name in rules:
        make_rule(name, 0.0)  # an unknown rule fails before any image is read
    print(f"{'sequence':<16} {'rule':<12} {'0.3-5 m':>16}  {'5-15 m':>16}")
    for seq in a.sequences:
        out = run(seq, a.step, rules)
        for name in rules:
            print(f"{seq.rstrip('/').split('/')[-1]:<16} {name:<12} {summary(out[name])}")


if __name__ == "__main__":
    main()
