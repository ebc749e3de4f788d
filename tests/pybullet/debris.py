#!/usr/bin/env python3
"""pybullet side of the debris-phase cross-check (tests/it/bullet/pybullet_debris.rs).

Reads a scene written by the Rust test (JSON: gravity, substep, number of substeps, solver
iterations, a static ground box and dynamic boxes with their poses, linear and angular
velocities and BCB body settings), builds it in pybullet 3.2.7 (DIRECT, plain rigid
bodies: useMaximalCoordinates=True, in the same order: ground first), steps it substep
by substep and prints the poses after each substep count listed in "report_substeps" as
JSON on stdout:
{"api": <pybullet API version>, "poses": {"<substeps>": [[x, y, z, qw, qx, qy, qz], ...]}}.

Exit code 2 when pybullet or numpy is missing.
Usage: debris.py SCENE.json
"""
import json
import sys

try:
    import numpy  # noqa: F401  (pybullet needs it at import time)
    import pybullet as p
except ImportError as e:  # pragma: no cover
    sys.stderr.write(
        "debris.py: pybullet and numpy are required (%s).\n"
        "Install them with: python3 -m pip install pybullet==3.2.7 numpy\n"
        "(or run scripts/setup.sh)\n" % e
    )
    sys.exit(2)


def add_box(cid, b, mass):
    shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=b["half_extents"],
                                   physicsClientId=cid)
    qw, qx, qy, qz = b["orientation"]
    bid = p.createMultiBody(baseMass=mass, baseCollisionShapeIndex=shape,
                            basePosition=b["position"], baseOrientation=[qx, qy, qz, qw],
                            useMaximalCoordinates=True, physicsClientId=cid)
    p.changeDynamics(bid, -1, lateralFriction=b["friction"], restitution=b["restitution"],
                     rollingFriction=0.0, spinningFriction=0.0,
                     linearDamping=b["linear_damping"], angularDamping=b["angular_damping"],
                     collisionMargin=b["margin"],
                     activationState=p.ACTIVATION_STATE_DISABLE_SLEEPING,
                     physicsClientId=cid)
    if mass > 0:
        p.resetBaseVelocity(bid, b["linear_velocity"], b["angular_velocity"],
                            physicsClientId=cid)
    return bid


def main():
    if len(sys.argv) != 2:
        sys.stderr.write(__doc__)
        sys.exit(1)
    with open(sys.argv[1]) as f:
        sc = json.load(f)
    cid = p.connect(p.DIRECT)
    try:
        p.resetSimulation(physicsClientId=cid)
        p.setGravity(*sc["gravity"], physicsClientId=cid)
        p.setPhysicsEngineParameter(fixedTimeStep=sc["substep"],
                                    numSolverIterations=sc["solver_iterations"],
                                    # Bullet 3.24's btDispatcherInfo default (fem2rbd's
                                    # world); pybullet switches it off. Measured: without it
                                    # the first substep already differs by 7e-8 m.
                                    deterministicOverlappingPairs=1,
                                    physicsClientId=cid)
        add_box(cid, sc["ground"], 0.0)
        ids = [add_box(cid, b, b["mass"]) for b in sc["bodies"]]
        report = set(sc["report_substeps"])
        poses = {}
        for k in range(1, max(report) + 1):
            p.stepSimulation(physicsClientId=cid)
            if k in report:
                rows = []
                for bid in ids:
                    pos, orn = p.getBasePositionAndOrientation(bid, physicsClientId=cid)
                    rows.append(list(pos) + [orn[3], orn[0], orn[1], orn[2]])
                poses[str(k)] = rows
        json.dump({"api": p.getAPIVersion(), "poses": poses}, sys.stdout)
    finally:
        p.disconnect(cid)


if __name__ == "__main__":
    main()
