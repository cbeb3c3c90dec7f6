"""The experiment's energy estimator (paper Eqs. 2, 12-13) on simulated fields.

The paper measures the strain energy of its rubber cylinders by digital image
correlation (DIC) of their lower face: from the in-plane displacement it
forms ``F_2D`` (Eq. 12), takes the in-plane eigenvalues ``lambda_x^2,
lambda_y^2`` of ``C_2D = F_2D^T F_2D``, closes the out-of-plane stretch by
incompressibility, ``lambda_z^2 = 1 / (lambda_x^2 lambda_y^2)``, so that

    I1 = lambda_x^2 + lambda_y^2 + 1/(lambda_x^2 lambda_y^2)
       = tr(F_2D^T F_2D) + 1/det(F_2D)^2                         (Eq. 13)

and integrates the incompressible neo-Hookean density (Eq. 2)

    Psi_DIC = mu/2 (I1 - 3)

over the particles' reference area, times the cylinders' height H.

Applied here to the P1 displacement of the simulation (``fields.h5``):
``F_2D`` is constant on each triangle, so the integral is a sum over
triangles of ``Psi_DIC x reference area``, exact for the P1 field. The
simulation itself is the paper's plane-strain model (``F33 = 1``,
``det F = det F_2D != 1``, compressible neo-Hookean with
``lambda~ = 2 mu``, Eq. 7), so E_DIC and the finite-element energy differ by
the closure: they agree to second order in the strain (the paper's Eqs. 5
and 8) and for any isochoric plane deformation exactly, and differ where
the model's particles change area.

Energies returned here are in J (the 2D energy per unit length x H) unless
the name says ``per_length``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softpack.analysis import fields as fields_io
from softpack.analysis.setup import read_setup
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table

#: Paper Fig. 5's packing fractions.
FIG5_PHI = (0.79, 0.84, 0.88)


def triangle_areas(points, cells) -> np.ndarray:
    """Signed areas of triangles ``cells`` on nodes ``points`` (m^2)."""
    p = np.asarray(points, dtype=float)[np.asarray(cells)]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    return 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def deformation_gradients(points, cells, displacement) -> np.ndarray:
    """In-plane deformation gradient ``F_2D = I + grad u`` per triangle (Eq. 12).

    Parameters
    ----------
    points : ndarray, shape (n, 2)
        Reference node coordinates.
    cells : ndarray of int, shape (m, 3)
    displacement : ndarray, shape (n, 2)
        In-plane nodal displacement (a P1 field: its gradient is constant on
        each triangle).

    Returns
    -------
    ndarray, shape (m, 2, 2)
        ``F[k, i, j] = delta_ij + d u_i / d X_j`` on triangle k.
    """
    cells = np.asarray(cells)
    x = np.asarray(points, dtype=float)[cells]
    u = np.asarray(displacement, dtype=float)[cells]
    dX = np.stack([x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]], axis=2)  # (m,2,2)
    du = np.stack([u[:, 1] - u[:, 0], u[:, 2] - u[:, 0]], axis=2)
    return np.eye(2) + du @ np.linalg.inv(dX)


def closure_invariant(F) -> np.ndarray:
    """``I1`` of Eq. 13: ``tr(F_2D^T F_2D) + 1/det(F_2D)^2``.

    ``lambda_x^2 + lambda_y^2 = tr(C_2D)`` and ``lambda_x^2 lambda_y^2 =
    det(C_2D) = det(F_2D)^2``, so no eigenvalues are needed.
    """
    F = np.asarray(F, dtype=float)
    return np.einsum("...ij,...ij->...", F, F) + 1.0 / np.linalg.det(F) ** 2


def dic_energy_density(F, shear_modulus) -> np.ndarray:
    """Eq. 2 with Eq. 13: ``mu/2 (I1 - 3)`` (J/m^3)."""
    return 0.5 * shear_modulus * (closure_invariant(F) - 3.0)


def plane_strain_energy_density(F, shear_modulus, lame_lambda) -> np.ndarray:
    """The simulation's model, Eq. 7 with ``F33 = 1`` (J/m^3).

    ``mu/2 (tr C_2D + 1 - 3 - 2 ln J) + lambda/2 (ln J)^2``, ``J = det F_2D``.
    Given for comparison; the run's own values are the ``Psi`` field.
    """
    F = np.asarray(F, dtype=float)
    log_j = np.log(np.linalg.det(F))
    trace = np.einsum("...ij,...ij->...", F, F)
    return (0.5 * shear_modulus * (trace - 2.0 - 2.0 * log_j)
            + 0.5 * lame_lambda * log_j ** 2)


@dataclass(frozen=True)
class DicEnergy:
    """The DIC estimate of one stored time.

    Attributes
    ----------
    time : float
    total : float
        E_DIC (J): the sum of ``per_particle``.
    per_particle : ndarray, shape (bodies,)
        Each particle's E_DIC (J).
    fe_total : float
        The finite-element energy of the same fields (J): the ``Psi``
        field x reference area x H; NaN when the file has no ``Psi``.
    fe_per_particle : ndarray, shape (bodies,)
    i1 : ndarray, shape (m,)
        I1 of Eq. 13 on each triangle.
    det : ndarray, shape (m,)
        ``det F_2D`` on each triangle: the model's area change, which the
        closure reads as ``1/lambda_z^2``.
    area : ndarray, shape (m,)
        Reference area of each triangle (m^2), the weight of ``i1``.
    body : ndarray of int, shape (m,)
    """

    time: float
    total: float
    per_particle: np.ndarray
    fe_total: float
    fe_per_particle: np.ndarray
    i1: np.ndarray
    det: np.ndarray
    area: np.ndarray
    body: np.ndarray


def dic_energy(snapshot, shear_modulus, thickness, bodies=None) -> DicEnergy:
    """E_DIC per particle and in total for one :class:`fields.Snapshot`.

    Parameters
    ----------
    snapshot : softpack.analysis.fields.Snapshot
        Its ``body`` ids may be None (then every triangle is body 0).
    shear_modulus : float
        mu (Pa) of Eq. 2.
    thickness : float
        The cylinders' height H (m).
    bodies : int, optional
        Number of particles (default: the largest body id + 1).
    """
    cells = snapshot.cells
    area = np.abs(triangle_areas(snapshot.points, cells))
    F = deformation_gradients(snapshot.points, cells, snapshot.displacement)
    i1 = closure_invariant(F)
    body = (np.zeros(len(cells), dtype=np.int64) if snapshot.body is None
            else np.asarray(snapshot.body, dtype=np.int64))
    count = int(body.max()) + 1 if bodies is None else int(bodies)
    weights = 0.5 * shear_modulus * (i1 - 3.0) * area * thickness
    per_particle = np.bincount(body, weights=weights, minlength=count)
    if snapshot.psi is None:
        fe = np.full(count, math.nan)
    else:
        fe = np.bincount(body, weights=snapshot.psi * area * thickness,
                         minlength=count)
    return DicEnergy(time=snapshot.time, total=float(per_particle.sum()),
                     per_particle=per_particle, fe_total=float(fe.sum()),
                     fe_per_particle=fe, i1=i1, det=np.linalg.det(F),
                     area=area, body=body)


def dic_series(run_dir) -> dict:
    """E_DIC and the finite-element E at every stored field time of a run.

    Phi and the run's own strain energy are read from ``series.csv`` at the
    row of the same time (field outputs are output rows).

    Returns
    -------
    dict of str -> ndarray
        ``time, phi, eps, E_dic, E_fe_fields, E_fe_series`` (J),
        ``E_dic_over_WHLmu, E_fe_over_WHLmu`` (the paper's Fig. 6
        normalisation, W, L the initial box; the FE one is series.csv's
        column) and ``ratio = E_dic / E_fe_series``, NaN where E_fe is 0.
        ``E_fe_fields`` (the ``Psi`` field integrated) checks that the
        fields and the series describe the same state.
    """
    run_dir = Path(run_dir)
    setup = read_setup(run_dir)
    series = read_table(RunDirectory(run_dir).series_csv)
    path = RunDirectory(run_dir).fields_h5
    rows = {key: [] for key in ("time", "phi", "eps", "E_dic",
                                "E_fe_fields", "E_fe_series",
                                "E_fe_over_WHLmu")}
    for time in fields_io.stored_times(path):
        k = int(np.argmin(np.abs(series["time"] - time)))
        estimate = dic_energy(fields_io.read_snapshot(path, time),
                              setup.shear_modulus, setup.thickness,
                              setup.count)
        rows["time"].append(time)
        rows["phi"].append(series["phi"][k])
        rows["eps"].append(series["eps"][k])
        rows["E_dic"].append(estimate.total)
        rows["E_fe_fields"].append(estimate.fe_total)
        # series.csv gives the energies times H already (J)
        rows["E_fe_series"].append(series["strain_energy"][k])
        rows["E_fe_over_WHLmu"].append(series["E_over_WHLmu"][k])
    out = {key: np.asarray(value, dtype=float) for key, value in rows.items()}
    out["E_dic_over_WHLmu"] = out["E_dic"] / (
        setup.width * setup.thickness * setup.length * setup.shear_modulus)
    with np.errstate(divide="ignore", invalid="ignore"):
        out["ratio"] = np.where(out["E_fe_series"] > 0,
                                out["E_dic"] / out["E_fe_series"], math.nan)
    return out


def nearest_field_times(run_dir, targets=FIG5_PHI, tolerance=0.005):
    """For each target Phi, the stored field time whose Phi is nearest.

    Returns
    -------
    list of (float, float, float, bool)
        ``(target, time, phi, within)``: ``within`` says whether
        ``|phi - target| <= tolerance``.
    """
    run = RunDirectory(run_dir)
    series = read_table(run.series_csv)
    times = fields_io.stored_times(run.fields_h5)
    rows = [int(np.argmin(np.abs(series["time"] - t))) for t in times]
    phis = series["phi"][rows]
    out = []
    for target in targets:
        j = int(np.nanargmin(np.abs(phis - target)))
        out.append((target, float(times[j]), float(phis[j]),
                    bool(abs(phis[j] - target) <= tolerance)))
    return out
