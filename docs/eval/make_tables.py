#!/usr/bin/env python3
"""Turns `squint eval corridor` reports into the Markdown tables of docs/eval/README-tables.md.

usage: make_tables.py TITLE HEADING_REPORT.json DRIVE_REPORT.json [GATE_REPORT.json]
"""
import json
import sys


def heading_table(r):
    rows = ["| estimator | heading RMSE (°) | coverage | right sign, \\|h\\| ≥ 5° |", "| --- | ---: | ---: | ---: |"]
    for k, v in r["heading"].items():
        s = v["right_sign"]
        rows.append(f"| {k} | {v['rmse_deg']:.2f} | {100 * v['coverage']:.0f} % | "
                    f"{100 * s['fraction']:.1f} % of {s['frames']} |")
    return "\n".join(rows)


def distance_table(r):
    rows = ["| estimator | RMSE 0.3–5 m | RMSE 5–15 m | RMSE 0.3–15 m | coverage 0.3–15 m |",
            "| --- | ---: | ---: | ---: | ---: |"]
    for k, v in r["distance"].items():
        g = {(x["min_m"], x["max_m"]): x for x in v["ranges"]}
        a, b, c = g[(0.3, 5.0)], g[(5.0, 15.0)], g[(0.3, 15.0)]
        rows.append(f"| {k} | {a['rmse_m']:.2f} m | {b['rmse_m']:.2f} m | {c['rmse_m']:.2f} m | "
                    f"{100 * c['coverage']:.0f} % |")
    return "\n".join(rows)


def gate_line(r):
    p = r["rapid_perception"]
    s = (f"rapid perception: {100 * p['fraction_skipped']:.1f} % of {p['frames']} frames skipped by the gate")
    if "heading_rmse_every_frame_deg" in p:
        s += (f"; fused heading RMSE {p['heading_rmse_every_frame_deg']:.2f}° with every frame processed, "
              f"{p['heading_rmse_processed_frames_gated_deg']:.2f}° on the gate's processed frames "
              f"({p['heading_rmse_processed_frames_ungated_deg']:.2f}° on those frames without the gate), "
              f"{p['heading_rmse_held_between_processed_deg']:.2f}° holding the last processed estimate")
    return s


def main():
    title, hpath, dpath = sys.argv[1:4]
    h, d = json.load(open(hpath)), json.load(open(dpath))
    print(f"### {title}\n")
    print("Heading (test sweeps):\n")
    print(heading_table(h) + "\n")
    print("Distance to the end (test drives):\n")
    print(distance_table(d) + "\n")
    print("- " + gate_line(d))
    if len(sys.argv) > 4:
        print("- " + gate_line(json.load(open(sys.argv[4]))))
    print()


if __name__ == "__main__":
    main()
