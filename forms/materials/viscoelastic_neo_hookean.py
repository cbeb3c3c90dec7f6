# Finite-strain viscoelastic solid: neo-Hookean at equilibrium plus two Maxwell branches on the isochoric part.
#
#   Psi = Psi_eq(F) + sum_k mu_k/2 (tr(Cbar A_k) - 3 - ln det A_k)
#   Psi_eq = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2   (neo_hookean.py)
#   mu_k = branch_ratio_k mu,  Cbar = J^(-2/3) C  (3x3, C33 = 1)
#
# A_k (symmetric, A_k = C_v,k^-1 of the branch's viscous strain, identity in
# the virgin state) is the internal variable of branch k: constant over each
# cell (P1: one point), held fixed during a step (the forms below are then
# hyperelastic in u), and relaxed at the step's end, at the converged
# configuration, exactly for dA/dt = -(A - Cbar^-1)/tau_k at fixed C:
#
#   A_k <- Cbar^-1 + (A_k - Cbar^-1) exp(-h / tau_k)   (internal_update)
#
# Psi_k is convex in A_k with its minimum at Cbar^-1, so the relaxation lowers
# it: the drop is the step's viscous dissipation. At small strain Psi_k =
# mu_k |e - e_v|^2 (e the deviatoric strain): the linear Maxwell branch of
# modulus mu_k and relaxation time tau_k (shear relaxation modulus
# mu (1 + sum_k g_k exp(-t / tau_k))). Kirchhoff stress of branch k:
# mu_k dev(Fbar A_k Fbar^T), Fbar = J^(-1/3) F.
#
# Same material file contract as neo_hookean.py, plus the internal variables:
# the DG0 coefficient `internal` (per cell: A_1 then A_2, each as
# (A11, A12, A22, A33)), its value in the virgin state `internal_initial`,
# and the rank-1 form `internal_update` (the cell integral of the relaxed
# values against a DG0 test function, followed by the cell's dissipation
# over the relaxation, Psi(F, A) - Psi(F, A relaxed), integrated: the
# driver then need not evaluate the energy before and after). `time_step` is
# the step size h, set by the driver at each update: no parameter
# (`driver_constants`).
from ufl import (Constant, Identity, TestFunction, TrialFunction,
                 Coefficient, VectorElement, as_vector, derivative, det, dx,
                 exp, grad, inner, inv, ln, tr, triangle)

# Plane strain only (no `dimensions = (2, 3)`): the internal variables are
# the plane-strain A_k (four entries each).
element = VectorElement("Lagrange", triangle, 1)
internal_element = VectorElement("DG", triangle, 0, dim=8)
# internal_update's test space: the relaxed values, then the dissipation
update_element = VectorElement("DG", triangle, 0, dim=9)

u = Coefficient(element)
internal = Coefficient(internal_element)
v = TestFunction(element)
du = TrialFunction(element)
q = TestFunction(update_element)

shear_modulus = Constant(triangle)
lame_lambda = Constant(triangle)
branch_ratio_1 = Constant(triangle)
relaxation_time_1 = Constant(triangle)
branch_ratio_2 = Constant(triangle)
relaxation_time_2 = Constant(triangle)
time_step = Constant(triangle)

driver_constants = ["time_step"]
internal_initial = [1.0, 0.0, 1.0, 1.0] * 2

parameters = {
    "shear_modulus": {"unit": "Pa", "range": "(0, inf)", "default": 0.15e6,
                      "doc": "equilibrium (long-time) shear modulus mu"},
    "lame_lambda": {"unit": "Pa", "range": "[0, inf)",
                    "default": "2 * shear_modulus",
                    "doc": "effective first Lame parameter lambda of the "
                           "equilibrium part (default 2 mu, nu = 1/3, as "
                           "neo_hookean's)"},
    "branch_ratio_1": {"unit": "", "range": "[0, inf)", "default": 1.0,
                       "doc": "shear modulus of Maxwell branch 1 over mu "
                              "(g_1; 0: no branch)"},
    "relaxation_time_1": {"unit": "s", "range": "(0, inf)", "default": 1e-2,
                          "doc": "relaxation time tau_1 of branch 1"},
    "branch_ratio_2": {"unit": "", "range": "[0, inf)", "default": 0.0,
                       "doc": "shear modulus of Maxwell branch 2 over mu "
                              "(g_2; 0: no branch)"},
    "relaxation_time_2": {"unit": "s", "range": "(0, inf)", "default": 1e-1,
                          "doc": "relaxation time tau_2 of branch 2"},
}

# Every integrand is constant over a P1 cell: one quadrature point.
dx1 = dx(metadata={"quadrature_degree": 1})

F = Identity(2) + grad(u)
I1 = tr(F.T * F) + 1.0
J = det(F)
C = F.T * F
# Cbar = J^(-2/3) diag(C, 1) (3x3, C33 = 1), written by its 2x2 block: the
# compiled kernels stay small. J^(+-2/3) as exp(+-2/3 ln J): ln J is
# psi_eq's, and the derivatives of exp(a ln J) reuse exp(a ln J), where
# those of J ** a call pow for every exponent they make (a -1, a - 2):
# the residual 1.4x faster (docs/materials.md, Cost)
J23 = exp(2.0 / 3.0 * ln(J))
Jm23 = exp(-2.0 / 3.0 * ln(J))
Cinv = inv(C)


def entries(k, values=internal):
    """(A11, A12, A22, A33) of branch k, from `values` (8 entries)."""
    return [values[4 * k + i] for i in range(4)]


def log_det(k, values=internal):
    """ln det A_k, A_k = [[a11, a12, 0], [a12, a22, 0], [0, 0, a33]]."""
    a11, a12, a22, a33 = entries(k, values)
    return ln((a11 * a22 - a12 ** 2) * a33)


def relaxed(k, tau):
    """A_k after a step h at the current Cbar, as its four entries."""
    decay = exp(-time_step / tau)
    target = [J23 * Cinv[0, 0], J23 * Cinv[0, 1], J23 * Cinv[1, 1], J23]
    return [t + (a - t) * decay for t, a in zip(target, entries(k))]


psi_eq = (shear_modulus / 2 * (I1 - 3) - shear_modulus * ln(J)
          + lame_lambda / 2 * ln(J) ** 2)
# sum_k g_k mu/2 (tr(Cbar A_k) - 3 - ln det A_k) with the traces summed
# first, tr(Cbar sum_k g_k A_k): the forms then differentiate one trace
# (ln det A_k does not depend on u; the residual 10 % faster)
ratios = (branch_ratio_1, branch_ratio_2)


def branch_energy(values=internal):
    """sum_k Psi_k at the branches' `values` (8 entries)."""
    weighted = [sum(r * entries(k, values)[i] for k, r in enumerate(ratios))
                for i in range(4)]
    trace = (C[0, 0] * weighted[0] + 2 * C[0, 1] * weighted[1]
             + C[1, 1] * weighted[2] + weighted[3]) * Jm23
    return shear_modulus / 2 * (
        trace - sum(r * (3 + log_det(k, values))
                    for k, r in enumerate(ratios)))


energy = (psi_eq + branch_energy()) * dx1
residual = derivative(energy, u, v)
tangent = derivative(residual, u, du)
relaxed_values = relaxed(0, relaxation_time_1) + relaxed(1, relaxation_time_2)
# Psi_eq does not depend on the A_k: the drop is the branches' alone
dissipation = branch_energy() - branch_energy(relaxed_values)
internal_update = inner(as_vector(relaxed_values + [dissipation]), q) * dx1

forms = [energy, residual, tangent, internal_update]
