"""Tatara's "extensive" force-approach law of an elastic sphere between two
rigid plates, and its comparison with the axisymmetric reference
(:mod:`softpack.references.sphere_axisym`); issue 40's large-strain check.

The law (Y. Tatara, "Extensive theory of force-approach relations of
elastic spheres in compression and in impact", J. Eng. Mater. Technol. 111
(1989) 163-168), in the form restated by a public FEA script labelled
"Tatara theory" (``tatara_disp`` in the code index; its repository is not
named there; it names no paper: the 1989 one is attributed here from the
1991 abstract's "Hertz theory ... with an extensive term"): the approach
of one plate to the sphere's centre is Hertz's half-space approach minus
the displacement, under the same contact force, of the half-space point at
depth 2 R (the opposite pole) and radial offset a (the contact radius) --
Boussinesq's point-load displacement (K. L. Johnson, *Contact Mechanics*,
1985, section 3.2)::

    delta(F) = (3 F / (4 E* sqrt(R)))^(2/3)
             - F (1 + nu) / (2 pi E) [2 (1 - nu) / s^(1/2) + 4 R^2 / s^(3/2)],
    s = a^2 + 4 R^2,  a = (3 F R / (4 E*))^(1/3),  E* = E / (1 - nu^2),

and the plates' closure is 2 delta (one such contact at each pole). At
a -> 0 the bracket is Boussinesq's u_z = F (1 + nu) (3 - 2 nu) / (4 pi E R)
on the axis at depth 2 R. Linear elastic, any nu; no finite-strain term.

Not coded here: Tatara's large-deformation theory ("On compression of
rubber elastic sphere over a large range of displacements -- Part 1",
J. Eng. Mater. Technol. 113 (1991) 285-291, equations (12), (13), (31),
(40), (43): rubber-elastic nonlinear modulus, lateral extension). Its
five equations were not found written out in the sources at hand; only
its abstract (https://doi.org/10.1115/1.2903407) and Part 2's
(J. Eng. Mater. Technol. 113 (1991) 292) were.
"""

from __future__ import annotations

import math

import numpy as np


def young_poisson(mu, lam):
    """E and nu of the Lame constants (the neo-Hookean law's small strain)."""
    return mu * (3 * lam + 2 * mu) / (lam + mu), lam / (2 * (lam + mu))


def approach(force, radius, E, nu):
    """Tatara's approach delta (m) of one plate for the force F (N)."""
    F = np.asarray(force, dtype=float)
    e_star = E / (1 - nu * nu)
    a = (3 * F * radius / (4 * e_star)) ** (1 / 3)
    s = a * a + 4 * radius * radius
    hertz = (3 * F / (4 * e_star * math.sqrt(radius))) ** (2 / 3)
    far_pole = F * (1 + nu) / (2 * math.pi * E) * (
        2 * (1 - nu) / np.sqrt(s) + 4 * radius ** 2 / s ** 1.5)
    return hertz - far_pole


def force(closure, diameter, mu, lam, tol=1e-13):
    """Tatara's force (N) for the plates' closure (m): 2 delta(F) = closure,
    by bisection (delta rises monotonically with F up to closure / D ~ 0.9
    at nu = 1/3, far beyond 0.3)."""
    R = 0.5 * diameter
    E, nu = young_poisson(mu, lam)
    out = []
    for c in np.atleast_1d(np.asarray(closure, dtype=float)):
        # Hertz's force is a lower bound: the far-pole term only adds.
        lo = 4 / 3 * E / (1 - nu * nu) * math.sqrt(R) * (0.5 * c) ** 1.5
        hi = 2 * lo + 1e-30
        while 2 * approach(hi, R, E, nu) < c:
            hi *= 2
        while hi - lo > tol * hi:
            mid = 0.5 * (lo + hi)
            if 2 * approach(mid, R, E, nu) < c:
                lo = mid
            else:
                hi = mid
        out.append(0.5 * (lo + hi))
    return np.array(out) if np.ndim(closure) else out[0]


def compare(table, diameter, mu, lam, strains=None):
    """The reference's force against Tatara's at each strain.

    ``table``: columns ``eps`` and ``force_N`` (``force_sphere_<tag>.csv``
    of ``./softpack reference-sphere``). ``strains``: the strains to
    report (default: all rows). Returns {eps, force_N, tatara_N, ratio}
    with ratio = F_reference / F_Tatara.
    """
    eps = np.asarray(table["eps"], dtype=float)
    f_ref = np.asarray(table["force_N"], dtype=float)
    if strains is not None:
        rows = [int(np.argmin(np.abs(eps - e))) for e in strains]
        if any(abs(eps[i] - e) > 1e-9 for i, e in zip(rows, strains)):
            raise ValueError("a requested strain is not in the table")
        eps, f_ref = eps[rows], f_ref[rows]
    f_t = force(eps * diameter, diameter, mu, lam)
    return {"eps": eps, "force_N": f_ref, "tatara_N": f_t,
            "ratio": f_ref / f_t}


def main(argv=None) -> int:
    """Print the comparison table of a reference run's CSV."""
    import argparse
    import json
    from pathlib import Path

    from softpack.contract.tables import read_table

    parser = argparse.ArgumentParser(
        prog="python -m softpack.references.tatara",
        description="reference-sphere forces against Tatara (1989)")
    parser.add_argument("csv", help="force_sphere_<tag>.csv")
    parser.add_argument("--strains", default="0.05,0.1,0.15,0.2,0.25,0.3")
    args = parser.parse_args(argv)
    csv = Path(args.csv)
    run = json.loads(csv.with_name(
        csv.name.replace("force_sphere_", "run_sphere_").replace(
            ".csv", ".json")).read_text())
    strains = [float(s) for s in args.strains.split(",")]
    cmp = compare(read_table(csv), run["diameter"], run["mu"],
                  run["lame_lambda"], strains)
    E, nu = young_poisson(run["mu"], run["lame_lambda"])
    print(f"# D {run['diameter']} m, mu {run['mu']} Pa, nu {nu:.4f}, "
          f"h {run['element_size']} m")
    print("eps  F_reference_N  F_Tatara_N  ratio-1")
    for e, f, t, r in zip(cmp["eps"], cmp["force_N"], cmp["tatara_N"],
                          cmp["ratio"]):
        print(f"{e:.3f}  {f:.6g}  {t:.6g}  {100 * (r - 1):+.2f} %")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
