# Material-independent forms of a deformable body (P1 triangles, and P1
# tetrahedra: the build compiles this file for both, forms/solid_wrapper.py.in).
#
#   mass          M_ij   = int rho phi_i . phi_j dx          (consistent)
#   lumped_mass   M_ii   = int rho phi_i . phi_i dx_vertex   (vertex quadrature:
#                          for P1 this is the row-sum lumped mass, area/3 per
#                          node, volume/4 on tetrahedra)
#   current_area  a_cell = int det(F) q dx                   (DG0 test q: the
#                          current area (3D: volume) of each cell; the tests'
#                          independent check of BodySet::body_current_area,
#                          which takes the deformed boundary's)
from ufl import (Constant, Identity, TestFunction, TrialFunction,
                 Coefficient, FiniteElement, VectorElement, det, dx, grad,
                 inner, triangle)

cell = globals().get("cell", triangle)
dimensions = (2, 3)

element = VectorElement("Lagrange", cell, 1)
cell_element = FiniteElement("DG", cell, 0)

u = Coefficient(element)
v = TestFunction(element)
du = TrialFunction(element)
q = TestFunction(cell_element)

rho = Constant(cell)

dx_vertex = dx(metadata={"quadrature_rule": "vertex", "quadrature_degree": 1})

mass = rho * inner(du, v) * dx
lumped_mass = rho * inner(du, v) * dx_vertex
current_area = det(Identity(cell.geometric_dimension()) + grad(u)) * q * dx

forms = [mass, lumped_mass, current_area]
