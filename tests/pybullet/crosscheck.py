#!/usr/bin/env python3
"""Cross-check `fem2rbd scene` (Debian's Bullet 3.24, double) against pybullet 3.2.7.

Each scenario is built twice from one description: as a fem2rbd JSON scene (world preset
"pybullet", run with --frames 1 so every substep is written) and directly in pybullet
(DIRECT, plain rigid bodies via useMaximalCoordinates=True, pybullet's own defaults, which
the "pybullet" preset mirrors: docs/bullet-ffi.md §3.3). Positions and
orientations of every dynamic body are compared at every substep.

Usage: crosscheck.py --bin PATH/TO/fem2rbd [--write-scenes DIR] [--only NAME]
Exit code 0 when every scenario is within its bound; 1 when one is not; 2 when pybullet
or numpy is missing.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

try:
    import numpy  # noqa: F401  (pybullet needs it at import time)
    import pybullet as p
except ImportError as e:  # pragma: no cover
    sys.stderr.write(
        "crosscheck.py: pybullet and numpy are required (%s).\n"
        "Install them with: python3 -m pip install pybullet==3.2.7 numpy\n"
        "(or run scripts/setup.sh)\n" % e
    )
    sys.exit(2)

G = 9.81
HZ = 240
GROUND = {"name": "ground", "half_extents": [10.0, 10.0, 0.5], "mass": 0.0,
          "position": [0.0, 0.0, -0.5], "friction": 1.0}


def quat_axis_angle(axis, angle):
    """Unit quaternion (w, x, y, z) for a rotation of `angle` rad about `axis`."""
    n = math.sqrt(sum(a * a for a in axis))
    s = math.sin(angle / 2.0)
    return [math.cos(angle / 2.0)] + [a / n * s for a in axis]


def box(name, he, mass, pos, q=None, v=None, w=None, friction=0.5):
    b = {"name": name, "half_extents": list(he), "mass": mass, "position": list(pos),
         "friction": friction}
    if q is not None:
        b["orientation"] = list(q)
    if v is not None:
        b["linear_velocity"] = list(v)
    if w is not None:
        b["angular_velocity"] = list(w)
    return b


def scene(bodies, duration=2.0):
    return {"world": {"preset": "pybullet", "gravity": [0.0, 0.0, -G]},
            "duration": duration, "substeps_per_second": HZ, "bodies": bodies}


def pile_bodies():
    """24 boxes of three sizes in a loose 2 x 3 x 4 stack, each slightly turned and offset,
    dropped together onto the ground."""
    bodies = [dict(GROUND)]
    sizes = [(0.25, 0.15, 0.1), (0.2, 0.2, 0.12), (0.3, 0.1, 0.1)]
    k = 0
    for layer in range(4):
        for i in range(2):
            for j in range(3):
                he = sizes[k % 3]
                pos = (-0.35 + 0.7 * i + 0.02 * ((k * 7) % 5 - 2),
                       -0.6 + 0.6 * j + 0.015 * ((k * 3) % 5 - 2),
                       0.4 + 0.45 * layer + 0.01 * (k % 4))
                q = quat_axis_angle((0.1 * (k % 3), 0.2, 1.0), 0.15 * ((k * 5) % 7 - 3))
                mass = 1.0 + 0.25 * (k % 4)
                bodies.append(box("b%02d" % k, he, mass, pos, q=q, friction=0.6))
                k += 1
    return bodies


def bouncing_box():
    """Restitution (0.6 on the box, 0.8 on the ground: Bullet combines them as the product
    0.48), linear and angular damping, and rolling and spinning friction, on a box thrown
    with spin."""
    ground = dict(GROUND, restitution=0.8)
    b = box("box", (0.3, 0.2, 0.25), 1.5, (0.0, 0.0, 2.0),
            q=quat_axis_angle((0.3, 1.0, 0.2), 0.4), v=(1.0, -0.5, 0.0), w=(1.0, 2.0, 4.0))
    b.update(restitution=0.6, linear_damping=0.1, angular_damping=0.2,
             rolling_friction=0.01, spinning_friction=0.02)
    return scene([ground, b])


def welded_pair():
    """Two boxes welded by a fixed constraint (pybullet's JOINT_FIXED between two maximal
    rigid bodies is a btGeneric6DofSpring2Constraint with all six limits 0 and identity
    frame orientations, added with collisions between the bodies on — the same object
    as btFixedConstraint in Bullet 3.24), thrown tumbling onto the ground."""
    a_pos, b_pos, pivot = (0.0, 0.0, 2.0), (0.65, 0.0, 2.2), (0.425, 0.0, 2.1)
    bodies = [dict(GROUND),
              box("a", (0.4, 0.2, 0.2), 2.0, a_pos, v=(1.0, 0.5, 0.0), w=(0.5, 1.0, 2.0)),
              box("b", (0.2, 0.2, 0.4), 1.0, b_pos, v=(1.0, 0.5, 0.0), w=(0.5, 1.0, 2.0))]
    sc = scene(bodies)
    sc["constraints"] = [{
        "kind": "fixed", "body_a": "a", "body_b": "b",
        "frame_a": {"position": [pc - p for pc, p in zip(pivot, a_pos)]},
        "frame_b": {"position": [pc - p for pc, p in zip(pivot, b_pos)]},
        "disable_collisions_between": False}]
    return sc


def welded(bodies, pairs, duration=2.0, kind="fixed"):
    """A scene whose consecutive bodies in `pairs` are joined by `kind` constraints (fixed
    or point-to-point) at the midpoint of their centres (collisions between the joined
    bodies on, as pybullet adds them)."""
    sc = scene(bodies, duration)
    pos = {b["name"]: b["position"] for b in bodies}
    sc["constraints"] = []
    for a, b in pairs:
        pivot = [(x + y) / 2.0 for x, y in zip(pos[a], pos[b])]
        sc["constraints"].append({
            "kind": kind, "body_a": a, "body_b": b,
            "frame_a": {"position": [c - x for c, x in zip(pivot, pos[a])]},
            "frame_b": {"position": [c - x for c, x in zip(pivot, pos[b])]},
            "disable_collisions_between": False})
    return sc


def hanging_tower():
    """Four boxes welded one below the other under a static anchor (a hanging column of
    fixed joints), the lowest one pushed sideways: the column, held only by the joints'
    rows (corrected by ERP each substep), is struck and rings."""
    bodies = [box("anchor", (0.3, 0.3, 0.1), 0.0, (0.0, 0.0, 4.0))]
    for k in range(4):
        v = (1.5, 0.5, 0.0) if k == 3 else None
        bodies.append(box("t%d" % k, (0.1, 0.1, 0.2), 1.0 + 0.5 * k,
                          (0.0, 0.0, 3.7 - 0.4 * k), v=v))
    names = ["anchor"] + ["t%d" % k for k in range(4)]
    return welded(bodies, list(zip(names, names[1:])))


def welded_chain():
    """Six boxes welded end to end, cantilevered sideways from a static anchor and
    released under gravity: the chain of fixed joints droops, springs back and rings."""
    bodies = [box("anchor", (0.1, 0.3, 0.3), 0.0, (0.0, 0.0, 3.0))]
    for k in range(6):
        bodies.append(box("c%d" % k, (0.15, 0.05, 0.05), 0.5, (0.25 + 0.3 * k, 0.0, 3.0)))
    names = ["anchor"] + ["c%d" % k for k in range(6)]
    return welded(bodies, list(zip(names, names[1:])))


def pendulum():
    """A box hanging from a static anchor by a point-to-point joint at its top, started
    sideways: it swings and spins about the pivot."""
    bodies = [box("anchor", (0.1, 0.1, 0.1), 0.0, (0.0, 0.0, 3.3)),
              box("bob", (0.1, 0.1, 0.4), 2.0, (0.0, 0.0, 2.5), v=(2.0, 0.5, 0.0), w=(0.0, 0.0, 1.0))]
    return welded(bodies, [("anchor", "bob")], duration=1.3, kind="point2point")


def p2p_chain():
    """Five boxes linked end to end by point-to-point joints, the first hung from a static
    anchor, released horizontally: a chain that falls and swings. Not in SCENARIOS: it
    differs from pybullet from the second substep on (2.3e-7 m, growing to 0.08 m by
    1.7 s), while one point-to-point joint to a static anchor (`pendulum`) agrees to the
    bit; the setting behind the difference is not found (docs/ruin-convergence.md §3)."""
    bodies = [box("anchor", (0.05, 0.05, 0.05), 0.0, (0.0, 0.0, 3.0))]
    for k in range(5):
        bodies.append(box("l%d" % k, (0.1, 0.03, 0.03), 0.4, (0.15 + 0.2 * k, 0.0, 3.0)))
    names = ["anchor"] + ["l%d" % k for k in range(5)]
    return welded(bodies, list(zip(names, names[1:])), kind="point2point")


SCENARIOS = [
    # name, scene, bound on position difference [m], bound on orientation difference [rad]
    ("freefall", scene([box("box", (0.5, 0.5, 0.5), 1.0, (0.0, 0.0, 10.0))]), 1e-9, 1e-9),
    ("drop", scene([dict(GROUND), box("box", (0.5, 0.5, 0.5), 1.0, (0.0, 0.0, 1.5))]),
     1e-9, 1e-9),
    ("slide", scene([dict(GROUND),
                     box("box", (0.5, 0.5, 0.5), 1.0, (0.0, 0.0, 0.5), v=(5.0, 0.0, 0.0))]),
     1e-9, 1e-9),
    ("tumble", scene([dict(GROUND),
                      box("box", (0.5, 0.3, 0.2), 2.0, (0.0, 0.0, 2.0),
                          q=quat_axis_angle((1.0, 1.0, 0.0), 0.5),
                          v=(2.0, 0.0, 0.0), w=(0.0, 0.0, 3.0))]),
     1e-9, 1e-9),
    # The pile: contacts between many boxes amplify any round-off difference chaotically
    # (a 1-ulp difference in one initial coordinate grew to 0.2 m by step 372 while
    # fem2rbd's JSON parser was not correctly rounded). Measured with both sides reading
    # the same bits: 0 m and 0 rad at every substep; the bound is set a little above that.
    ("pile", scene(pile_bodies()), 1e-9, 1e-9),
    ("welded", welded_pair(), 1e-9, 1e-9),
    ("hanging", hanging_tower(), 1e-9, 1e-9),
    ("chain", welded_chain(), 1e-9, 1e-9),
    ("pendulum", pendulum(), 1e-9, 1e-9),
    ("bounce", bouncing_box(), 1e-9, 1e-9),
]


def tumble_without_two_friction_directions():
    """Negative control: the tumble with fem2rbd's solver mode 260 (Bullet's default)
    instead of pybullet's 276. bullet-ffi.md §3.4 measured 0.18-0.20 m of difference; the
    comparison must see it, or it could not detect a settings mismatch."""
    sc = json.loads(json.dumps(SCENARIOS[3][1]))
    sc["world"]["solver"] = {"solver_mode": 260}
    return sc


# name, scene, smallest position difference [m] the comparison must report
CONTROLS = [("control_tumble_mode260", tumble_without_two_friction_directions(), 0.05)]


def run_fem2rbd(binary, sc, workdir, name):
    path = os.path.join(workdir, name + ".json")
    out = os.path.join(workdir, name + ".csv")
    with open(path, "w") as f:
        json.dump(sc, f, indent=1)
    r = subprocess.run([binary, "scene", path, "--out", out, "--frames", "1"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError("fem2rbd scene %s failed:\n%s" % (name, r.stderr))
    steps = {}
    with open(out) as f:
        for row in csv.DictReader(f):
            step = int(row["step"])
            steps.setdefault(step, {})[row["body"]] = (
                [float(row[c]) for c in ("x", "y", "z")],
                [float(row[c]) for c in ("qw", "qx", "qy", "qz")])
    return steps


def run_pybullet(sc):
    cid = p.connect(p.DIRECT)
    try:
        p.resetSimulation(physicsClientId=cid)
        w = sc["world"]
        p.setGravity(*w["gravity"], physicsClientId=cid)
        p.setTimeStep(1.0 / sc["substeps_per_second"], physicsClientId=cid)
        ids = []
        for b in sc["bodies"]:
            shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=b["half_extents"],
                                           physicsClientId=cid)
            qw, qx, qy, qz = b.get("orientation", [1.0, 0.0, 0.0, 0.0])
            bid = p.createMultiBody(baseMass=b["mass"], baseCollisionShapeIndex=shape,
                                    basePosition=b["position"],
                                    baseOrientation=[qx, qy, qz, qw],
                                    useMaximalCoordinates=True, physicsClientId=cid)
            p.changeDynamics(bid, -1, lateralFriction=b.get("friction", 0.5),
                             restitution=b.get("restitution", 0.0),
                             rollingFriction=b.get("rolling_friction", 0.0),
                             spinningFriction=b.get("spinning_friction", 0.0),
                             linearDamping=b.get("linear_damping", 0.0),
                             angularDamping=b.get("angular_damping", 0.0),
                             physicsClientId=cid)
            if b["mass"] > 0:
                p.resetBaseVelocity(bid, b.get("linear_velocity", [0.0, 0.0, 0.0]),
                                    b.get("angular_velocity", [0.0, 0.0, 0.0]),
                                    physicsClientId=cid)
            ids.append((b["name"], bid, b["mass"] > 0))
        index = {name: bid for name, bid, _ in ids}
        for c in sc.get("constraints", []):
            if c["kind"] not in ("fixed", "point2point") or c.get("disable_collisions_between", True):
                raise ValueError("pybullet can only mirror fixed and point-to-point constraints "
                                 "with collisions on")
            joint = p.JOINT_FIXED if c["kind"] == "fixed" else p.JOINT_POINT2POINT
            p.createConstraint(index[c["body_a"]], -1, index[c["body_b"]], -1, joint,
                               [0.0, 0.0, 0.0], c["frame_a"]["position"],
                               c["frame_b"]["position"], physicsClientId=cid)
        n = int(round(sc["duration"] * sc["substeps_per_second"]))
        steps = {}
        for k in range(0, n + 1):
            if k > 0:
                p.stepSimulation(physicsClientId=cid)
            rec = {}
            for name, bid, dyn in ids:
                if dyn:
                    pos, orn = p.getBasePositionAndOrientation(bid, physicsClientId=cid)
                    rec[name] = (list(pos), [orn[3], orn[0], orn[1], orn[2]])
            steps[k] = rec
        return steps
    finally:
        p.disconnect(cid)


def angle_between(qa, qb):
    """Rotation angle [rad] between two unit quaternions, accurate for tiny angles: the
    chord |qa - s·qb| (s = ±1 aligning the signs) equals 2 sin(θ/4)."""
    s = 1.0 if sum(a * b for a, b in zip(qa, qb)) >= 0 else -1.0
    chord = math.sqrt(sum((a - s * b) ** 2 for a, b in zip(qa, qb)))
    return 4.0 * math.asin(min(1.0, chord / 2.0))


def compare(ours, theirs):
    """Largest position [m] and orientation [rad] difference over all substeps and bodies,
    with the substep where the position difference peaks."""
    worst_pos, worst_ang, worst_step = 0.0, 0.0, 0
    if sorted(ours) != sorted(theirs):
        raise RuntimeError("different substeps: %d vs %d" % (len(ours), len(theirs)))
    for k in sorted(theirs):
        for name, (pb_pos, pb_q) in theirs[k].items():
            pos, q = ours[k][name]
            d = math.sqrt(sum((a - b) ** 2 for a, b in zip(pos, pb_pos)))
            if d > worst_pos:
                worst_pos, worst_step = d, k
            worst_ang = max(worst_ang, angle_between(q, pb_q))
    return worst_pos, worst_ang, worst_step


def final_summary(steps):
    k = max(steps)
    return {name: pos for name, (pos, _) in steps[k].items()}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True, help="the fem2rbd binary")
    ap.add_argument("--write-scenes", help="also write the scenes as JSON into this folder")
    ap.add_argument("--only", help="run one scenario")
    args = ap.parse_args()
    print("pybullet API version %d" % p.getAPIVersion())
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, sc, pos_bound, ang_bound in SCENARIOS:
            if args.only and name != args.only:
                continue
            if args.write_scenes:
                with open(os.path.join(args.write_scenes, name + ".json"), "w") as f:
                    json.dump(sc, f, indent=1)
                    f.write("\n")
            ours = run_fem2rbd(args.bin, sc, tmp, name)
            theirs = run_pybullet(sc)
            dpos, dang, kpeak = compare(ours, theirs)
            ok = dpos <= pos_bound and dang <= ang_bound
            fin = final_summary(theirs)
            sample = next(iter(fin.items()))
            print("%-8s bodies=%2d substeps=%d  max|dx| = %.3e m (step %d, bound %.0e)  "
                  "max angle = %.3e rad (bound %.0e)  final %s = (%.6f, %.6f, %.6f)  %s"
                  % (name, len(sc["bodies"]), max(theirs), dpos, kpeak, pos_bound, dang,
                     ang_bound, sample[0], *sample[1], "ok" if ok else "FAIL"))
            if not ok:
                failures.append(name)
        for name, sc, min_diff in CONTROLS:
            if args.only and name != args.only:
                continue
            ours = run_fem2rbd(args.bin, sc, tmp, name)
            theirs = run_pybullet(sc)
            dpos, dang, kpeak = compare(ours, theirs)
            ok = dpos >= min_diff
            print("%s  max|dx| = %.3e m (step %d, must be >= %.2f: a settings mismatch is "
                  "detected)  max angle = %.3e rad  %s"
                  % (name, dpos, kpeak, min_diff, dang, "ok" if ok else "FAIL"))
            if not ok:
                failures.append(name)
    if failures:
        print("DISAGREE: " + ", ".join(failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
