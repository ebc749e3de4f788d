#!/usr/bin/env python3
"""Elastic spectral displacement S_d(T) of a PEER NGA AT2 record, per 1 g of PGA: the
peak |u| of a linear oscillator ü + 2ξω u̇ + ω² u = −a_g(t)·g/PGA, ω = 2π/T, integrated
on the record's own samples by Newmark's average-acceleration method (γ = 1/2, β = 1/4,
unconditionally stable; Chopra, Dynamics of Structures, §5.4). Used to choose the PGA of
docs/case3.md's scenario.

    python3 scripts/spectral-displacement.py RECORD.AT2 [RECORD.AT2 ...] --periods 0.745,1.0 [--xi 0.05]

Prints, per record and period: the record's PGA (g), S_d per g of PGA (m) and
S_a/PGA = ω²·S_d/g.
"""
import argparse
import math
import re


def read_at2(path):
    """Acceleration samples (g) and time step (s) of an AT2 file (4 header lines)."""
    with open(path) as f:
        lines = f.read().splitlines()
    head = lines[3]
    npts = int(re.search(r"NPTS=\s*(\d+)", head).group(1))
    dt = float(re.search(r"DT=\s*([0-9.Ee+-]+)", head).group(1))
    acc = [float(x) for x in " ".join(lines[4:]).split()][:npts]
    if len(acc) != npts:
        raise SystemExit(f"{path}: {len(acc)} samples, the header says NPTS={npts}")
    return acc, dt


def peak_displacement(acc, dt, period, xi):
    """Peak |u| (m) of the oscillator under the ground acceleration acc (m/s²)."""
    w = 2.0 * math.pi / period
    c, k = 2.0 * xi * w, w * w
    k_hat = k + 2.0 * c / dt + 4.0 / dt**2
    u = v = 0.0
    a = -acc[0]
    peak = 0.0
    for ag in acc[1:]:
        p = -ag + (4.0 / dt**2 * u + 4.0 / dt * v + a) + c * (2.0 / dt * u + v)
        u_new = p / k_hat
        v_new = 2.0 / dt * (u_new - u) - v
        a = 4.0 / dt**2 * (u_new - u) - 4.0 / dt * v - a
        u, v = u_new, v_new
        peak = max(peak, abs(u))
    return peak


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("records", nargs="+")
    ap.add_argument("--periods", required=True, help="comma-separated periods, s")
    ap.add_argument("--xi", type=float, default=0.05, help="damping ratio")
    args = ap.parse_args()
    periods = [float(t) for t in args.periods.split(",")]
    for path in args.records:
        acc, dt = read_at2(path)
        pga = max(abs(x) for x in acc)
        scaled = [x / pga * 9.81 for x in acc]
        for t in periods:
            sd = peak_displacement(scaled, dt, t, args.xi)
            sa = (2.0 * math.pi / t) ** 2 * sd / 9.81
            print(f"{path}: PGA {pga:.3f} g, T {t} s: S_d {sd:.4f} m per g of PGA, S_a/PGA {sa:.3f}")


if __name__ == "__main__":
    main()
