# Saint Venant-Kirchhoff solid in plane strain.
#
#   E = (F^T F - I)/2 (2x2; E33 = 0 in plane strain; 3x3 in 3D)
#   Psi = lambda/2 (tr E)^2 + mu tr(E E)
#   (mu = shear_modulus, lambda = lame_lambda)
#
# Same material file contract as neo_hookean.py. Its small-strain limit is the
# same linear elasticity as neo-Hookean; it stiffens differently (and loses
# stability in strong compression), which makes it a useful contrast.
from ufl import (Constant, Identity, TestFunction, TrialFunction,
                 Coefficient, VectorElement, derivative, dx,
                 grad, inner, tr, triangle)

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
                      "doc": "shear modulus mu (second Lame parameter)"},
    "lame_lambda": {"unit": "Pa", "range": "[0, inf)",
                    "default": "2 * shear_modulus",
                    "doc": "first Lame parameter lambda of the plane-strain "
                           "model (default 2 mu: the same small-strain "
                           "elasticity as neo_hookean's)"},
}

# Plane strain (2D): E33 = 0
d = cell.geometric_dimension()
F = Identity(d) + grad(u)
E = (F.T * F - Identity(d)) / 2
psi = lame_lambda / 2 * tr(E) ** 2 + shear_modulus * inner(E, E)

energy = psi * dx
residual = derivative(energy, u, v)
tangent = derivative(residual, u, du)

forms = [energy, residual, tangent]
