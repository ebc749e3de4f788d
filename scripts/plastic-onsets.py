#!/usr/bin/env python3
"""The ruin stage's energy injection beside its connections' plastic onsets, frame by frame
after the hand-off: for every recorded frame in the first WINDOW seconds of the ruin
stage, the energy the solver injected since the frame before (`history.csv`
`injected_j`), how many connections turned plastic and how many broke in that frame
(`connections.csv` `time_plastic_s`, `time_broken_s`; connections that start plastic
at the hand-off are counted apart); then the share of the whole run's injection that
came in the window. A plastic spring whose rest pose is the start pose is switched on
stretched by whatever the connection moved before (docs/ruin-numerics.md, "At full scale").

Usage: python3 scripts/plastic-onsets.py RUN_DIR [WINDOW_S (default 1.0)]
Reads history.csv and connections.csv of a run folder (fem2rbd run).
"""
import csv
import sys


def main(run, window):
    hist = [r for r in csv.DictReader(open(f"{run}/history.csv")) if r["stage"] == "ruin"]
    t0 = float(hist[0]["t"])
    onsets, breaks, at_start = [], [], 0
    for r in csv.DictReader(open(f"{run}/connections.csv")):
        if r["time_plastic_s"]:
            t = float(r["time_plastic_s"])
            if t <= t0 + 1e-9:
                at_start += 1
            else:
                onsets.append(t)
        if r["time_broken_s"]:
            breaks.append(float(r["time_broken_s"]))
    total = float(hist[-1]["injected_j"])
    print(f"hand-off at {t0:.3f} s; {at_start} connections plastic from the start; "
          f"{total / 1e3:.1f} kJ injected in the whole run (to {float(hist[-1]['t']):.2f} s)")
    print("t_s  after_s  injected_kJ  plastic_onsets  breaks")
    prev_t, prev_inj, in_window = t0, 0.0, 0.0
    for r in hist[1:]:
        t = float(r["t"])
        if t > t0 + window + 1e-9:
            break
        inj = float(r["injected_j"])
        n_on = sum(1 for x in onsets if prev_t < x <= t + 1e-9)
        n_br = sum(1 for x in breaks if prev_t < x <= t + 1e-9)
        print(f"{t:.3f}  {t - t0:.3f}  {(inj - prev_inj) / 1e3:11.2f}  {n_on:14d}  {n_br:6d}")
        in_window = inj
        prev_t, prev_inj = t, inj
    share = in_window / total if total > 0 else 0.0
    print(f"injected in the first {window:g} s: {in_window / 1e3:.1f} kJ ({100 * share:.1f} % "
          "of the run's)")


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    main(sys.argv[1], float(sys.argv[2]) if len(sys.argv) == 3 else 1.0)
