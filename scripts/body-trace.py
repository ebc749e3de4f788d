#!/usr/bin/env python3
"""What acts on one body over a time window, from a body trace (`fem2rbd run --trace-body
NAME --trace-body-file FILE`, src/ruin/body_trace.rs): its position and velocity at the
first and last traced substep; per connection partner and constraint k (0–5 the rigid
rows, 6 the plastic spring) the impulse of the joint force on the body summed over the
substeps, Σ F·h (N·s, world x y z); the contacts' normal impulses per partner (N·s, sum
of magnitudes); and the substeps in which each spring was enabled.

Usage: python3 scripts/body-trace.py TRACE FROM_S TO_S [H_S (substep, default 0.005)]
"""
import re
import sys
from collections import defaultdict

CONN = re.compile(
    r"\s*conn (\d+) (\S+) k(\d) on (\w+)->(\w+) lambda (\S+) thr (\S+) F (\S+) (\S+) (\S+)")


def main(path, t0, t1, h):
    impulse = defaultdict(lambda: [0.0, 0.0, 0.0])
    spring_on = defaultdict(int)
    contact = defaultdict(float)
    steps = []
    inside = False
    for line in open(path):
        if line.startswith("t "):
            p = line.split()
            t = float(p[1])
            inside = t0 <= t <= t1
            if inside:
                steps.append((t, p[3:6], p[7:10], p[11:14]))
        elif not inside:
            continue
        elif line.lstrip().startswith("conn"):
            _, other, k, _, on, _, _, fx, fy, fz = CONN.match(line).groups()
            for j, f in enumerate((fx, fy, fz)):
                impulse[(other, int(k))][j] += float(f) * h
            if k == "6" and on == "true":
                spring_on[other] += 1
        elif line.lstrip().startswith("contact"):
            p = line.split()
            contact[p[1]] += abs(float(p[-1]))
    if not steps:
        sys.exit(f"{path}: no substep in [{t0}, {t1}] s")
    print(f"{len(steps)} substeps from {steps[0][0]} to {steps[-1][0]} s")
    print(f"  first: position {' '.join(steps[0][1])} m, velocity before {' '.join(steps[0][2])} m/s")
    print(f"  last:  position {' '.join(steps[-1][1])} m, velocity after {' '.join(steps[-1][3])} m/s")
    print("joint impulses on the body, N·s (partner, constraint): x y z")
    for (other, k), v in sorted(impulse.items(), key=lambda kv: -abs(kv[1][2])):
        if any(abs(x) > 0.5 for x in v):
            print(f"  {other:24s} k{k} {v[0]:12.0f} {v[1]:12.0f} {v[2]:12.0f}")
    tot = [sum(v[j] for v in impulse.values()) for j in range(3)]
    print(f"  {'all joints':24s}    {tot[0]:12.0f} {tot[1]:12.0f} {tot[2]:12.0f}")
    print("springs enabled (substeps): " + ", ".join(f"{o} {n}" for o, n in sorted(spring_on.items())))
    print("contact normal impulses, N·s (sum of magnitudes):")
    for other, v in sorted(contact.items(), key=lambda kv: -kv[1]):
        print(f"  {other:24s} {v:12.0f}")


if __name__ == "__main__":
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    main(sys.argv[1], float(sys.argv[2]), float(sys.argv[3]),
         float(sys.argv[4]) if len(sys.argv) == 5 else 0.005)
