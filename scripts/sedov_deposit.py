#!/usr/bin/env python3
"""Writes a Sedov-Taylor point-blast case with the energy in a few particles about the centre.

usage: sedov_deposit.py KIND N OUT.toml [GAMMA]

KIND   (R > 0, in spacings)
       2d_r<R>_odd | 2d_r<R>_even   2D plane, the box [-0.5, 0.5]^2 with N x N particles; the
                                    energy E = 1 J/m shared equally by the particles within R dx
                                    of the centre (odd: a particle at the centre; even: none)
       3d_r<R>_odd | 3d_r<R>_even   the same in 3D, the cube [-0.5, 0.5]^3, E = 1 J
       rz_r<R>                      axisymmetric, r in [0, 0.5], z in [-0.5, 0.5] (N rings along r,
                                    2N along z), E = 1 J over the rings within R dx of the
                                    origin, shared in proportion to their masses
N      particles a side (along r in RZ)
GAMMA  ratio of specific heats (default 1.4)

The ambient gas: rho = 1 kg/m^3, e = 1e-9 J/kg; t = 0.1 s; everything else at the defaults.
Used for the deposit table of docs/validation.md ("Deposits in a few particles").
"""
import math
import sys


def lattice(n, lo, dx):
    """The node coordinates of one axis: the box's cell-centred lattice."""
    return [lo + (i + 0.5) * dx for i in range(n)]


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    kind, n, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    gamma = float(sys.argv[4]) if len(sys.argv) > 4 else 1.4
    parts = kind.split("_")
    geom, rad = parts[0], float(parts[1][1:])
    if geom in ("2d", "3d"):
        dim = int(geom[0])
        odd = parts[2] == "odd"
        if odd != (n % 2 == 1):
            sys.exit(f"{kind}: N must be {'odd' if odd else 'even'}")
        dx = 1.0 / n
        axis = lattice(n, -0.5, dx)
        near = [a for a in axis if abs(a) <= rad * dx + 1e-12]
        count = 0
        for a in near:
            for b in near:
                for c in (near if dim == 3 else [0.0]):
                    if a * a + b * b + c * c <= (rad * dx) ** 2 * (1 + 1e-9):
                        count += 1
        mass = dx ** dim
        e_hot = 1.0 / (count * mass)
        lo, hi = [-0.5] * dim, [0.5] * dim
        center = [0.0] * dim
        walls = ""
        dims = f"dim = {dim}\n"
    elif geom == "rz":
        dim = 2
        dx = 0.5 / n
        rs = lattice(n, 0.0, dx)
        zs = lattice(2 * n, -0.5, dx)
        ring = [(r, z) for r in rs for z in zs if r * r + z * z <= (rad * dx) ** 2 * (1 + 1e-9)]
        count = len(ring)
        ring_mass = sum(2.0 * math.pi * r * dx * dx for r, _ in ring)
        # e is the same in every hot ring: E over the rings' total mass
        e_hot = 1.0 / ring_mass
        lo, hi = [0.0, -0.5], [0.5, 0.5]
        center = [0.0, 0.0]
        walls = ""
        dims = 'dim = 2\ngeometry = "axisymmetric"\n'
    else:
        sys.exit(f"{kind}: unknown kind")
    r_region = rad * dx * (1 + 1e-6)
    text = f"""# Sedov point blast, {kind}, {n} a side, gamma = {gamma}: E = 1 in the {count} particles
# within {rad} dx of the centre (written by scripts/sedov_deposit.py)
name = "sedov_{kind.replace('.', 'p')}_{n}"
{dims}
[time]
end_s = 0.1
output_interval_s = 0.01

[[material]]
name = "gas"
eos = {{ kind = "ideal_gas", gamma = {gamma} }}

[[region]]
name = "hot"
material = "gas"
shape = "sphere"
center_m = {center}
radius_m = {r_region}
lo_m = {lo}
hi_m = {hi}
spacing_m = {dx}
rho_kgm3 = 1.0
e_jkg = {e_hot}

[[region]]
name = "ambient"
material = "gas"
shape = "box"
lo_m = {lo}
hi_m = {hi}
spacing_m = {dx}
rho_kgm3 = 1.0
e_jkg = 1.0e-9
subtract = ["hot"]
{walls}
[analysis]
kind = "sedov"
center_m = {center}
energy_j = 1.0
"""
    with open(out, "w") as f:
        f.write(text)
    print(f"{out}: {count} hot particles, e = {e_hot:.6g} J/kg")


if __name__ == "__main__":
    main()
