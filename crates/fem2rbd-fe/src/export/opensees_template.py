

# --------------------------------------------------------------- analysis procedures

# Dense generalized LAPACK up to this many DOFs (exact, handles massless DOFs; O(n^3):
# over 10 minutes at 6 600 DOFs); above it OpenSees' default ARPACK (shift-invert
# Lanczos on the banded/sparse system).
FULL_LAPACK_MAX_DOF = 1500


def eigen_solver():
    """Solver flags for ops.eigen by model size (6 DOFs per not fully fixed node)."""
    if 6 * len(FREE_NODES) <= FULL_LAPACK_MAX_DOF:
        return ("-fullGenLapack",)
    return ("-genBandArpack",)


def eigen(n):
    """Periods (s) of the first n modes of the initial stiffness (no gravity), with each
    mode's effective-mass shares in X, Y, Z and about the vertical axis through the mass
    centre (RZ): share_d = (sum m phi.d)^2 / (sum m |phi|^2 * sum m |d|^2)."""
    lam = ops.eigen(*eigen_solver(), n)
    tot = sum(m[2] for m in MASSES.values())
    xc = sum(m[2] * NODE_XYZ[t][0] for t, m in MASSES.items()) / tot
    yc = sum(m[2] * NODE_XYZ[t][1] for t, m in MASSES.items()) / tot
    ip = sum(m[2] * ((NODE_XYZ[t][0] - xc) ** 2 + (NODE_XYZ[t][1] - yc) ** 2)
             for t, m in MASSES.items())
    modes = []
    for k, l in enumerate(lam, 1):
        gen = 0.0
        lx = ly = lz = lt = 0.0
        for t, m in MASSES.items():
            v = ops.nodeEigenvector(t, k)
            gen += sum(m[d] * v[d] ** 2 for d in range(6))
            lx += m[0] * v[0]
            ly += m[1] * v[1]
            lz += m[2] * v[2]
            dx, dy = NODE_XYZ[t][0] - xc, NODE_XYZ[t][1] - yc
            lt += m[2] * (dx * v[1] - dy * v[0]) + m[5] * v[5]
        ipk = ip + sum(m[5] for m in MASSES.values())
        modes.append({"mode": k, "T": 2.0 * math.pi / math.sqrt(l),
                      "X": lx * lx / (gen * tot), "Y": ly * ly / (gen * tot),
                      "Z": lz * lz / (gen * tot),
                      "RZ": lt * lt / (gen * ipk) if ipk > 0 else 0.0})
    return modes


def gravity():
    """Gravity loads Fz = -m g in GRAVITY_STEPS load-control steps, then loadConst."""
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for tag, fz in GRAVITY_LOADS:
        ops.load(tag, 0.0, 0.0, fz, 0.0, 0.0, 0.0)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.test("NormDispIncr", 1e-10, 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0 / GRAVITY_STEPS)
    ops.analysis("Static")
    ok = ops.analyze(GRAVITY_STEPS)
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()
    return ok


def read_at2(path):
    """PEER AT2 record: header line 4 is `NPTS= n, DT= dt SEC` or `n dt NPTS, DT`;
    then the accelerations in g. Returns (dt, values)."""
    with open(path) as fh:
        lines = fh.read().splitlines()
    m = re.search(r"NPTS\s*=\s*(\d+)\s*,\s*DT\s*=\s*([-+.\dEe]+)", lines[3], re.I)
    if m:
        npts, dt = int(m.group(1)), float(m.group(2))
    else:
        f = lines[3].replace(",", " ").split()
        npts, dt = int(f[0]), float(f[1])
    vals = [float(x) for ln in lines[4:] for x in ln.split()]
    if len(vals) != npts:
        raise SystemExit(f"{path}: header says {npts} points, file has {len(vals)}")
    return dt, vals


def ground_motion(direction, path, pga_g):
    """One component: (record dt (s), values, factor to m/s^2). The factor scales the
    record to its target PGA: pga_g / max|a| * g, or g when pga_g is None (as
    recorded). (This is the one place to switch to factors computed by fem2rbd's
    motion module.)"""
    dt, vals = read_at2(path)
    if pga_g is None:
        return dt, vals, G
    peak = max(abs(v) for v in vals)
    return dt, vals, pga_g / peak * G


def run_step(h):
    """One step of size h; on failure the fallbacks of the reference runs:
    ModifiedNewton -initial, KrylovNewton, NewtonLineSearch 0.8 (200 iterations each),
    at h/1, h/2, h/4, h/8, h/16. Returns (ok, used_fallback)."""
    if ops.analyze(1, h) == 0:
        return True, False
    algos = [("Newton",), ("ModifiedNewton", "-initial"), ("KrylovNewton",),
             ("NewtonLineSearch", 0.8)]
    for sub in (1, 2, 4, 8, 16):
        for alg in algos:
            ops.algorithm(*alg)
            ops.test("NormDispIncr", 1e-8, 200)
            ok = 0
            for _ in range(sub):
                ok = ops.analyze(1, h / sub)
                if ok != 0:
                    break
            ops.algorithm("Newton")
            ops.test("NormDispIncr", 1e-8, 50)
            if ok == 0:
                return True, True
    return False, True


def time_history(out_csv):
    """Gravity, Rayleigh damping, uniform excitation, Newmark (0.5, 0.25) + Newton.
    Writes t and ux, uy, uz of every free node per step to out_csv; stops at the end of
    the records (or DURATION), at divergence, or when a free node has uz < -STOP_UZ."""
    if gravity() != 0:
        raise SystemExit("gravity analysis failed")
    if RAYLEIGH is not None:
        ops.rayleigh(RAYLEIGH[0], 0.0, RAYLEIGH[1], 0.0)
    if not GROUND_MOTIONS:
        raise SystemExit("no ground motion: export with --gm X=path,pga_g ...")
    rec_len = None
    for k, (direction, path, pga_g) in enumerate(GROUND_MOTIONS):
        rdt, vals, factor = ground_motion(direction, path, pga_g)
        ops.timeSeries("Path", 10 + k, "-dt", rdt * TIME_SCALE, "-values", *vals,
                       "-factor", factor)
        ops.pattern("UniformExcitation", 10 + k, direction, "-accel", 10 + k)
        length = (len(vals) - 1) * rdt * TIME_SCALE
        rec_len = length if rec_len is None else min(rec_len, length)
    tmax = DURATION if DURATION is not None else rec_len
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.test("NormDispIncr", 1e-8, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    summary = {"t_end": 0.0, "steps": 0, "fallback_steps": 0, "t_stop_uz": None,
               "t_diverge": None}
    with open(out_csv + ".tmp", "w") as fh:
        fh.write("t," + ",".join(f"ux_{n},uy_{n},uz_{n}" for n in FREE_NODES) + "\n")
        t = 0.0
        while t < tmax - 1e-12:
            ok, fb = run_step(min(DT, tmax - t))
            if not ok:
                summary["t_diverge"] = ops.getTime()
                break
            t = ops.getTime()
            summary["steps"] += 1
            summary["fallback_steps"] += int(fb)
            row = [t]
            uzmin = 0.0
            for n in FREE_NODES:
                u = ops.nodeDisp(n)
                row.extend(u[:3])
                uzmin = min(uzmin, u[2])
            fh.write(",".join("%.9g" % x for x in row) + "\n")
            if STOP_UZ is not None and uzmin < -STOP_UZ:
                summary["t_stop_uz"] = t
                break
    os.replace(out_csv + ".tmp", out_csv)
    summary["t_end"] = ops.getTime()
    return summary


def pushover(spec_path):
    """Gravity (held), then the lateral loads of spec_path (JSON: "node", "dof" 1..6,
    "loads" [[tag, F], ...], "targets" [m, ...], "step" m) in displacement control of
    node/dof through the targets in turn, each leg in n = ceil(|leg| / step) equal
    steps, with the fallbacks KrylovNewton, NewtonLineSearch 0.8 and
    ModifiedNewton -initial. Returns per converged step the control displacement, the
    load factor and the summed reactions (Rx, Ry, Rz) of the supported nodes."""
    with open(spec_path) as fh:
        spec = json.load(fh)
    if gravity() != 0:
        raise SystemExit("gravity analysis failed")
    node, dof = spec["node"], spec["dof"]
    ops.timeSeries("Linear", 2)
    ops.pattern("Plain", 2, 2)
    for tag, f in spec["loads"]:
        ops.load(tag, *[f if k == dof else 0.0 for k in range(1, 7)])
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.test("NormDispIncr", 1e-8, 100)
    ops.algorithm("Newton")
    fixed = SUPPORT_NODES

    def point():
        ops.reactions()
        r = [sum(ops.nodeReaction(t, k) for t in fixed) for k in (1, 2, 3)]
        return {"u": ops.nodeDisp(node, dof), "lambda": ops.getLoadFactor(2), "r": r}

    curve = [point()]
    stop = None
    for target in spec["targets"]:
        start = ops.nodeDisp(node, dof)
        leg = target - start
        if abs(leg) <= 1e-12:
            continue
        n = max(1, math.ceil(abs(leg) / spec["step"] - 1e-9))
        for k in range(1, n + 1):
            du = start + leg * k / n - ops.nodeDisp(node, dof)
            ops.integrator("DisplacementControl", node, dof, du)
            ops.analysis("Static")
            ok = ops.analyze(1)
            if ok != 0:
                for alg in (("KrylovNewton",), ("NewtonLineSearch", 0.8),
                            ("ModifiedNewton", "-initial")):
                    ops.algorithm(*alg)
                    ok = ops.analyze(1)
                    ops.algorithm("Newton")
                    if ok == 0:
                        break
            if ok != 0:
                stop = ops.nodeDisp(node, dof)
                break
            curve.append(point())
        if stop is not None:
            break
    return {"curve": curve, "stopped_at": stop}


def main(argv):
    cmd = argv[1] if len(argv) > 1 else "eigen"
    build()
    if cmd == "eigen":
        n = int(argv[2]) if len(argv) > 2 else 9
        modes = eigen(n)
        for m in modes:
            print("mode %d: T = %.4f s  X %.2f Y %.2f Z %.2f RZ %.2f"
                  % (m["mode"], m["T"], m["X"], m["Y"], m["Z"], m["RZ"]))
        print(json.dumps({"modes": modes}))
    elif cmd == "gravity":
        ok = gravity()
        disp = {str(n): ops.nodeDisp(n) for n in FREE_NODES}
        print(json.dumps({"ok": ok == 0, "disp": disp}))
    elif cmd == "pushover":
        print(json.dumps(pushover(argv[2])))
    elif cmd == "print-json":
        out = argv[2] if len(argv) > 2 else os.path.splitext(argv[0])[0] + ".json"
        # OpenSees' own JSON of the domain (`fem2rbd import opensees-json` reads it back).
        # printModel overwrites the file.
        ops.printModel("-JSON", "-file", out)
        print(json.dumps({"file": out}))
    elif cmd == "th":
        out = argv[2] if len(argv) > 2 else os.path.splitext(argv[0])[0] + "_disp.csv"
        print(json.dumps(time_history(out)))
    else:
        raise SystemExit(f"unknown command {cmd!r}: use eigen [N], gravity, pushover SPEC.json, print-json [out.json] or th [out.csv]")


if __name__ == "__main__":
    main(sys.argv)
