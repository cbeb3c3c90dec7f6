# Nearly incompressible neo-Hookean solid: the paper's law (neo_hookean.py)
# with its volumetric energy at the nodes (the averaged nodal pressure;
# docs/incompressible.md), so that P1 triangles and tetrahedra do not lock
# as nu -> 1/2.
#
#   Psi_element = mu/2 (I1 - 3) - mu ln J          (these forms)
#   U_vol = sum_a V0_a lambda/2 (ln J_a)^2,        J_a = V_a / V0_a
#   (V_a: a third of the area of each triangle at node a, a quarter of the
#   volume of each tetrahedron; the driver adds it,
#   driver/bodies/nodal_volumetric.h)
#
# The same energy as neo_hookean.py where J is uniform. lame_lambda is
# lambda = 2 mu nu / (1 - 2 nu) (499 mu at nu = 0.499), in plane strain and
# in 3D alike.
#
# Same material file contract as neo_hookean.py, plus `nodal_volumetric`:
# the name of the parameter the driver's nodal energy takes as lambda (a
# UFL Constant the forms below do not use). The compiled cauchy_integral of
# this law is the element part only; the bodies' stress (from the internal
# force, stress_average.h) has the nodal pressure too.
from ufl import (Constant, Identity, TestFunction, TrialFunction,
                 Coefficient, VectorElement, derivative, det,
                 dx, grad, ln, tr, triangle)

# Triangles, or tetrahedra when the build compiles it for 3D (as
# neo_hookean.py; the driver's nodal energy sums either cell's measure).
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
                    "default": "499 * shear_modulus",
                    "doc": "the first Lame parameter lambda of the nodal "
                           "volumetric energy (499 mu: nu = 0.499)"},
}
nodal_volumetric = "lame_lambda"

# Plane strain (2D): F33 = 1, the out-of-plane stretch, adds 1 to I1
d = cell.geometric_dimension()
out_of_plane = 1.0 if d == 2 else 0.0
F = Identity(d) + grad(u)
I1 = tr(F.T * F) + out_of_plane
J = det(F)
psi = shear_modulus / 2 * (I1 - 3) - shear_modulus * ln(J)

energy = psi * dx
residual = derivative(energy, u, v)
tangent = derivative(residual, u, du)

forms = [energy, residual, tangent]
