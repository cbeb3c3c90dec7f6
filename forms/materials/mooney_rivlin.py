# Compressible Mooney-Rivlin solid in plane strain.
#
#   Psi = c10 (I1 - 3) + c01 (I2 - 3) - 2 (c10 + 2 c01) ln J
#         + lambda/2 (ln J)^2
#   F = I + grad u (2x2), F33 = 1; C = F^T F with C33 = 1:
#   I1 = tr C + 1, I2 = (I1^2 - tr(C C) - 1) / 2, J = det F
#
# The ln J term makes the reference state stress free; the small-strain
# shear modulus is mu = 2 (c10 + c01), and c01 = 0 is neo-Hookean with
# mu = 2 c10. Kirchhoff stress (tests/cpp/bodies/test_stress_average.cpp):
#   tau = 2 c10 B + 2 c01 (I1 B - B B) + (lambda ln J - 2 c10 - 4 c01) I,
#   B = F F^T. Same material file contract as neo_hookean.py.
from ufl import (Constant, Identity, TestFunction, TrialFunction,
                 Coefficient, VectorElement, derivative, det,
                 dx, grad, ln, tr, triangle)

element = VectorElement("Lagrange", triangle, 1)

u = Coefficient(element)
v = TestFunction(element)
du = TrialFunction(element)

c10 = Constant(triangle)
c01 = Constant(triangle)
lame_lambda = Constant(triangle)

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

F = Identity(2) + grad(u)
C = F.T * F
I1 = tr(C) + 1.0
I2 = (I1 ** 2 - tr(C * C) - 1.0) / 2
J = det(F)
psi = (c10 * (I1 - 3) + c01 * (I2 - 3) - 2 * (c10 + 2 * c01) * ln(J)
       + lame_lambda / 2 * ln(J) ** 2)

energy = psi * dx
residual = derivative(energy, u, v)
tangent = derivative(residual, u, du)

forms = [energy, residual, tangent]
