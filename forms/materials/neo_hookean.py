# Compressible neo-Hookean solid in plane strain (paper Eq. 1, METHOD.md §2).
#
#   Psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2
#   (mu = shear_modulus, lambda = lame_lambda)
#   F = I + grad u (2x2), F33 = 1  =>  I1 = tr(F^T F) + 1,  J = det F
#   (3D, tetrahedra: F = I + grad u (3x3), I1 = tr(F^T F))
#
# Per unit reference area and unit length along the cylinder axis.
# The paper's effective plane-strain parameters are mu~ = mu, lambda~ = 2 mu.
#
# Material file contract (read by forms/CMakeLists.txt, forms/registry.py and
# the driver's material registry): P1 vector displacement `u`, test `v`, trial
# `du`, and the three forms below under these exact names. Each
# UFL Constant is a material parameter, named by its Python variable (the one
# name used in the TOML file, driver.json and the outputs; bind each Constant
# to one name only) and declared in the dict `parameters` (unit, range,
# default, doc; docs/contract.md section 3).
from ufl import (Constant, Identity, TestFunction, TrialFunction,
                 Coefficient, VectorElement, derivative, det,
                 dx, grad, ln, tr, triangle)

# The cell: triangle (plane strain) unless the build compiles this law for
# tetrahedra (3D, no plane-strain restriction): `dimensions` lists both, and
# forms/solid_wrapper.py.in runs this file with `cell` = tetrahedron.
cell = globals().get("cell", triangle)
dimensions = (2, 3)

element = VectorElement("Lagrange", cell, 1)

u = Coefficient(element)
v = TestFunction(element)
du = TrialFunction(element)

shear_modulus = Constant(cell)
lame_lambda = Constant(cell)

parameters = {
    "shear_modulus": {"unit": "Pa", "range": "(0, inf)", "default": 0.15e6,
                      "doc": "shear modulus mu (paper: 0.15 MPa)"},
    "lame_lambda": {"unit": "Pa", "range": "[0, inf)",
                    "default": "2 * shear_modulus",
                    "doc": "effective first Lame parameter lambda of the "
                           "plane-strain model (paper: 2 mu, nu = 1/3, "
                           "matching the incompressible 3D cylinder)"},
}

# Plane strain (2D): F33 = 1, the out-of-plane stretch, adds 1 to I1
d = cell.geometric_dimension()
out_of_plane = 1.0 if d == 2 else 0.0
F = Identity(d) + grad(u)
I1 = tr(F.T * F) + out_of_plane
J = det(F)
psi = (shear_modulus / 2 * (I1 - 3) - shear_modulus * ln(J)
       + lame_lambda / 2 * ln(J) ** 2)

energy = psi * dx
residual = derivative(energy, u, v)
tangent = derivative(residual, u, du)

forms = [energy, residual, tangent]
