#!/usr/bin/env python3
"""Where an RZ point blast's energy and entropy sit, from a run's particles.h5 (needs h5py).

usage: axis_cones.py RUN_DIR [GAMMA]        (GAMMA default 1.4)

For a blast centred at the origin (cases/verify/sedov_rz_axis.toml) it prints three tables:

1. the energy (internal + kinetic) per steradian in bands of the angle from the axis (both
   hemispheres), over the mean E/(4 pi), at every output (exact: 1 in every band);
2. the entropy p/rho^gamma of the rings of the first four columns (starting r = 0.5, 1.5, 2.5,
   3.5 dx) over that of the ring of the fifth column that started at the same z, the median over
   the rings that started between 0.2 and 0.8 of the exact shock radius along the axis, at the
   last output (exact: p/rho^gamma goes as R0^-3 of the starting distance R0, 1.02 to 1.03
   for the first column);
3. the deposit's rings (starting e above 1 J/kg), by starting column: their mean e over the
   adiabat e_0 (rho/rho_0)^(gamma-1) of their own start, at every output (exact: 1 for the
   deposit, which no shock crosses once it has spread).
"""
import math
import sys

import h5py
import numpy as np

BANDS = [(0, 10), (10, 30), (30, 60), (60, 80), (80, 90)]


def frames(path):
    f = h5py.File(path + "/particles.h5", "r")
    steps = [k for k in f.keys() if k.startswith("Step")]
    steps.sort(key=lambda s: int(s.split("#")[1]))
    return [(float(f[s].attrs["TimeValue"]), f[s]) for s in steps]


def by_id(g, name):
    return g[name][:][np.argsort(g["id"][:])]


def main():
    run = sys.argv[1]
    gamma = float(sys.argv[2]) if len(sys.argv) > 2 else 1.4
    fr = frames(run)
    print("| t (s) | " + " | ".join(f"{a}-{b} deg" for a, b in BANDS) + " |")
    print("| --- |" + " --- |" * len(BANDS))
    for t, g in fr:
        r, z, m = g["x"][:], g["y"][:], g["mass"][:]
        en = m * (g["e"][:] + 0.5 * (g["vx"][:] ** 2 + g["vy"][:] ** 2))
        th = np.degrees(np.arctan2(r, np.abs(z)))
        mean = en.sum() / (4.0 * math.pi)
        cells = []
        for a, b in BANDS:
            sel = (th >= a) & ((th < b) | (b == 90))
            om = 4.0 * math.pi * (math.cos(math.radians(a)) - math.cos(math.radians(b)))
            cells.append(f"{en[sel].sum() / om / mean:.3f}")
        print(f"| {t:.4g} | " + " | ".join(cells) + " |")

    t0, g0 = fr[0]
    t, g = fr[-1]
    r0, z0 = by_id(g0, "x"), by_id(g0, "y")
    dx = float(np.diff(np.unique(np.round(r0, 9)))[0])
    rs = 1.0328 * t ** 0.4  # the exact radius for E = 1 J, rho_0 = 1 kg/m^3, gamma = 1.4
    ent = by_id(g, "p") / by_id(g, "rho") ** gamma
    band = (np.abs(z0) > 0.2 * rs) & (np.abs(z0) < 0.8 * rs)
    col = np.round(r0 / dx - 0.5).astype(int)
    ref = {round(zz / dx): k for zz, k in zip(z0[band & (col == 4)], ent[band & (col == 4)])}
    cells = []
    for c in range(4):
        sel = band & (col == c)
        rat = [k / ref[round(zz / dx)] for zz, k in zip(z0[sel], ent[sel]) if round(zz / dx) in ref]
        cells.append(f"{np.median(rat):.3f}")
    print()
    print(f"entropy over the fifth column's at t = {t:.4g} s")
    print("| column 1 | column 2 | column 3 | column 4 |")
    print("| --- | --- | --- | --- |")
    print("| " + " | ".join(cells) + " |")

    e0, rho0 = by_id(g0, "e"), by_id(g0, "rho")
    hot = e0 > 1.0
    cols = sorted(set(col[hot]))
    print()
    print("| t (s) | " + " | ".join(f"deposit column {c + 1}" for c in cols) + " |")
    print("| --- |" + " --- |" * len(cols))
    for t, g in fr[1:]:
        e, rho = by_id(g, "e"), by_id(g, "rho")
        cells = []
        for c in cols:
            k = hot & (col == c)
            adiabat = (e0[k] * (rho[k] / rho0[k]) ** (gamma - 1.0)).mean()
            cells.append(f"{e[k].mean() / adiabat:.3f}")
        print(f"| {t:.4g} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
