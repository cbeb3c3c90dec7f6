# Compressible Mooney-Rivlin solid in plane strain.
#
#   Psi = c10 (I1 - 3) + c01 (I2 - 3) - 2 (c10 + 2 c01) ln J
#         + lambda/2 (ln J)^2
#   F = I + grad u (2x2), F33 = 1; C = F^T F with C33 = 1:
#   I1 = tr C + 1, I2 = (I1^2 - tr(C C) - 1) / 2, J = det F
#   (3D, tetrahedra: F 3x3, I1 = tr C, I2 = (I1^2 - tr(C C)) / 2)
#
# The ln J term makes the reference state stress free; the small-strain
# shear modulus is mu = 2 (c10 + c01), and c01 = 0 is neo-Hookean with
# mu = 2 c10. Kirchhoff stress (tests/cpp/bodies/test_stress_average.cpp):
#   tau = 2 c10 B + 2 c01 (I1 B - B B) + (lambda ln J - 2 c10 - 4 c01) I,
#   B = F F^T. Same material file contract as neo_hookean.py.
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

c10 = Constant(cell)
c01 = Constant(cell)
lame_lambda = Constant(cell)

parameters = {
    "c10": {"unit": "Pa", "range": "(0, inf)", "default": 0.05e6,
            "doc": "Mooney-Rivlin constant of the first invariant (with c01:"
                   " small-strain shear modulus 2 (c10 + c01); the defaults"
                   " give the paper's 0.15 MPa)"},
    "c01": {"unit": "Pa", "range": "[0, inf)", "default": 0.025e6,
            "doc": "Mooney-Rivlin constant of the second invariant"},
    "lame_lambda": {"unit": "Pa", "range": "[0, inf)",
                    "default": "4 * (c10 + c01)",
                    "doc": "effective first Lame parameter lambda of the "
                           "plane-strain model (default 2 mu, nu = 1/3, as "
                           "neo_hookean's)"},
}

# Plane strain (2D): F33 = 1, the out-of-plane stretch, adds 1 to I1 and
# to tr(C C)
d = cell.geometric_dimension()
out_of_plane = 1.0 if d == 2 else 0.0
F = Identity(d) + grad(u)
C = F.T * F
I1 = tr(C) + out_of_plane
I2 = (I1 ** 2 - tr(C * C) - out_of_plane) / 2
J = det(F)
psi = (c10 * (I1 - 3) + c01 * (I2 - 3) - 2 * (c10 + 2 * c01) * ln(J)
       + lame_lambda / 2 * ln(J) ** 2)

energy = psi * dx
residual = derivative(energy, u, v)
tangent = derivative(residual, u, du)

forms = [energy, residual, tangent]
