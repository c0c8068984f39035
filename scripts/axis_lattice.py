#!/usr/bin/env python3
"""The RZ pair sums next to the axis on a square lattice of rings, against the exact rates.

usage: axis_lattice.py [H_OVER_DX ...]        (default: 1.0 1.3 2.0)

Rings at r = (i + 1/2) dx, z = (k + 1/2) dx, rho = 1 kg/m^3, p = 1 Pa, planar mass mu = rho dx^2,
with their mirrors across the axis (r < 0, v_r reflected), the cubic spline of support 2h.
For the rings of the first three columns it prints de/dt (W/kg) of the force's asymmetric energy
sum (docs/theory.md section 16) under two velocity fields:

  radial   v = (r, 0)   exact -(p/rho) div v = -2 (1/s: dv_r/dr + v_r/r)
  axial    v = (0, z)   exact -1

with the pairs across the axis taken three ways: the code's (the real ring takes the work of the
mirror's force, p_bar v_i . grad W), the weight r_j/r_i with the radius of the mirror's source,
and with the signed radius (r_j < 0), the one with the parity of r v_z. Then the acceleration of
the symmetric pressure force under p = 1 + eps r^2 and p = 1 + eps z (exact -2 r eps and -eps).
dx = 1; the numbers are per unit of the exact rate's scale.
"""
import math
import sys

NR, NZ = 12, 24


def kernel(h):
    """The 2D cubic spline W(d) and dW/dd / d of support 2h."""
    a = 10.0 / (7.0 * math.pi * h * h)

    def w(d):
        q = d / h
        if q < 1.0:
            return a * (1.0 - 1.5 * q * q + 0.75 * q ** 3)
        return a * 0.25 * (2.0 - q) ** 3 if q < 2.0 else 0.0

    def f(d):
        q = d / h
        if d == 0.0 or q >= 2.0:
            return 0.0
        g = -3.0 * q + 2.25 * q * q if q < 1.0 else -0.75 * (2.0 - q) ** 2
        return a * g / (h * d)

    return w, f


def rings():
    """The lattice: (r, z) of every ring, the mirrors not included."""
    return [(i + 0.5, k + 0.5) for i in range(NR) for k in range(-NZ // 2, NZ // 2)]


def energy_rates(h, field, ri, zi):
    """de/dt of the ring (ri, zi): (code's, source's radius, signed radius)."""
    _, f = kernel(h)
    vel = (lambda r, z: (r, 0.0)) if field == "radial" else (lambda r, z: (0.0, z))
    vi = vel(ri, zi)
    q = 1.0  # p / rho^2
    real = code = absw = sgnw = 0.0
    for r, z in rings():
        v = vel(r, z)
        # the real neighbour: q (v_i - (r_j/r_i) v_j) . grad W
        dx, dz = ri - r, zi - z
        g = f(math.hypot(dx, dz))
        real += q * ((vi[0] - r / ri * v[0]) * g * dx + (vi[1] - r / ri * v[1]) * g * dz)
        # its mirror at -r, v_r reflected
        vm = (-v[0], v[1])
        dx = ri + r
        g = f(math.hypot(dx, dz))
        gx, gz = g * dx, g * dz
        code += 2.0 * q * (vi[0] * gx + vi[1] * gz)
        absw += q * ((vi[0] - r / ri * vm[0]) * gx + (vi[1] - r / ri * vm[1]) * gz)
        sgnw += q * ((vi[0] + r / ri * vm[0]) * gx + (vi[1] + r / ri * vm[1]) * gz)
    return real + code, real + absw, real + sgnw


def acceleration(h, which, ri, zi, eps=1e-3):
    """The symmetric pressure force's acceleration over eps, density from the sum."""
    w, f = kernel(h)
    lat = rings()

    def rho(r0, z0):
        return sum(w(math.hypot(r0 - r, z0 - z)) + w(math.hypot(r0 + r, z0 - z)) for r, z in lat)

    pres = (lambda r, z: 1.0 + eps * r * r) if which == "r2" else (lambda r, z: 1.0 + eps * z)
    rho_i = rho(ri, zi)
    qi = pres(ri, zi) / rho_i ** 2
    acc = [0.0, 0.0]
    for r, z in lat:
        qj = pres(r, z) / rho(r, z) ** 2
        for rj in (r, -r):
            dx, dz = ri - rj, zi - z
            g = f(math.hypot(dx, dz))
            acc[0] -= (qi + qj) * g * dx
            acc[1] -= (qi + qj) * g * dz
    return (acc[0] if which == "r2" else acc[1]) / eps


def main():
    hs = [float(a) for a in sys.argv[1:]] or [1.0, 1.3, 2.0]
    print("| h/dx | field | ring's r/dx | exact | code's | source's radius | signed radius |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for h in hs:
        for field, exact in (("radial", -2.0), ("axial", -1.0)):
            for ri in (0.5, 1.5, 2.5):
                c, a, s = energy_rates(h, field, ri, 0.5)
                print(f"| {h:g} | {field} | {ri:g} | {exact:g} | {c:.3f} | {a:.3f} | {s:.3f} |")
    print()
    print("| h/dx | pressure | ring's r/dx | exact a/eps | SPH a/eps |")
    print("| --- | --- | --- | --- | --- |")
    for h in hs:
        for which in ("r2", "z"):
            for ri in (0.5, 1.5):
                ex = -2.0 * ri if which == "r2" else -1.0
                a = acceleration(h, which, ri, 0.5)
                name = "1 + eps r^2" if which == "r2" else "1 + eps z"
                print(f"| {h:g} | {name} | {ri:g} | {ex:g} | {a:.3f} |")


if __name__ == "__main__":
    main()
