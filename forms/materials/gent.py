# Compressible Gent solid in plane strain: neo-Hookean at small strain,
# stiffening without bound as the chains approach their extensibility limit
# I1 - 3 -> gent_jm.
#
#   Psi = -mu/2 Jm ln(1 - (I1 - 3)/Jm) - mu ln J + lambda/2 (ln J)^2
#   (mu = shear_modulus, Jm = gent_jm, lambda = lame_lambda)
#   F = I + grad u (2x2), F33 = 1  =>  I1 = tr(F^T F) + 1,  J = det F
#   (3D, tetrahedra: F = I + grad u (3x3), I1 = tr(F^T F))
#
# Jm -> inf gives neo-Hookean. Kirchhoff stress
# (tests/cpp/bodies/test_stress_average.cpp):
#   tau = mu Jm / (Jm - (I1 - 3)) B - mu I + lambda ln J I,  B = F F^T.
# Same material file contract as neo_hookean.py.
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
gent_jm = Constant(cell)
lame_lambda = Constant(cell)

parameters = {
    "shear_modulus": {"unit": "Pa", "range": "(0, inf)", "default": 0.15e6,
                      "doc": "small-strain shear modulus mu"},
    "gent_jm": {"unit": "", "range": "(0, inf)", "default": 30.0,
                "doc": "Gent's extensibility limit Jm of I1 - 3 (rubbers:"
                       " about 30 to 100; large: neo-Hookean)"},
    "lame_lambda": {"unit": "Pa", "range": "[0, inf)",
                    "default": "2 * shear_modulus",
                    "doc": "effective first Lame parameter lambda of the "
                           "plane-strain model (default 2 mu, nu = 1/3, as "
                           "neo_hookean's)"},
}

# Plane strain (2D): F33 = 1, the out-of-plane stretch, adds 1 to I1
d = cell.geometric_dimension()
out_of_plane = 1.0 if d == 2 else 0.0
F = Identity(d) + grad(u)
I1 = tr(F.T * F) + out_of_plane
J = det(F)
psi = (-shear_modulus / 2 * gent_jm * ln(1 - (I1 - 3) / gent_jm)
       - shear_modulus * ln(J) + lame_lambda / 2 * ln(J) ** 2)

energy = psi * dx
residual = derivative(energy, u, v)
tangent = derivative(residual, u, du)

forms = [energy, residual, tangent]
