"""The integral of each body's Cauchy stress, derived from a law's energy.

Used by forms/CMakeLists.txt, which writes for every material file LAW.py a
wrapper ``build/forms/LAW_cauchy.py`` (from ``cauchy_wrapper.py.in``) that
runs the material file and compiles one form, ``cauchy_integral``, with
FFCx. The constitutive law is never written twice: P is the derivative of
the material's ``energy`` form.

In plane strain per unit length along z (F33 = 1, F the 2x2 in-plane
gradient, J = det F), the in-plane Cauchy stress is sigma = P F^T / J, so
its integral over a deformed cell is

    int sigma da = int P F^T dA0.

For the constant matrix A = e_i (x) e_j, the Gateaux derivative of the
energy along w = A x, x = X + u the current position (a P1 field: no
approximation), is

    dE[u; A x] = int P : grad(A x) dA0 = int P : (A F) dA0
               = A : int P F^T dA0 = (int P F^T dA0)_ij,

so each component is the derivative of the energy along a field the form
builds from the spatial coordinate and u. The form is rank 1 against a
cell-wise constant (DG0) 4-vector test function: entry c of cell k is
component c (order xx, yy, xy, yx; tension positive, N per unit length,
i.e. Pa m^2 per m) of the integral over cell k; the driver sums cells by
body (driver/bodies/stress_average.cpp).
"""

from ufl import (Form, SpatialCoordinate, TestFunction, VectorElement,
                 as_vector, derivative, triangle)
from ufl.algorithms import expand_derivatives

#: Component order of the form's DG0 4-vector (i, j of sigma_ij).
COMPONENTS = (("xx", 0, 0), ("yy", 1, 1), ("xy", 0, 1), ("yx", 1, 0))


def cauchy_integral(energy, u):
    """The rank-1 DG0 form of the per-cell integrals of P F^T.

    Parameters
    ----------
    energy : ufl.Form
        The material's ``energy`` (int Psi(F) dX, F = I + grad u).
    u : ufl.Coefficient
        The displacement the energy depends on (P1, 2D).
    """
    x = SpatialCoordinate(triangle) + u
    zero = 0 * x[0]
    q = TestFunction(VectorElement("DG", triangle, 0, dim=len(COMPONENTS)))
    integrals = []
    for c, (_, i, j) in enumerate(COMPONENTS):
        w = as_vector([x[j] if k == i else zero for k in range(2)])
        dE = expand_derivatives(derivative(energy, u, w))
        integrals += [it.reconstruct(integrand=it.integrand() * q[c])
                      for it in dE.integrals()]
    return Form(integrals)
