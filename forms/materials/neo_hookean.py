# Compressible neo-Hookean solid in plane strain (paper Eq. 1, METHOD.md §2).
#
#   Psi = mu/2 (I1 - 3) - mu ln J + lmbda/2 (ln J)^2
#   F = I + grad u (2x2), F33 = 1  =>  I1 = tr(F^T F) + 1,  J = det F
#
# Per unit reference area and unit length along the cylinder axis.
# The paper's effective plane-strain parameters are mu~ = mu, lmbda~ = 2 mu.
#
# Material file contract (read by forms/CMakeLists.txt and the driver's
# material registry): P1 vector displacement `u`, test `v`, trial `du`,
# DG0 test `q`, and the four forms below under these exact names. Constants
# are the material parameters, set by name at run time.
from ufl import (Constant, Identity, TestFunction, TrialFunction,
                 Coefficient, FiniteElement, VectorElement, derivative, det,
                 dx, grad, ln, tr, triangle)

element = VectorElement("Lagrange", triangle, 1)
cell_element = FiniteElement("DG", triangle, 0)

u = Coefficient(element)
v = TestFunction(element)
du = TrialFunction(element)
q = TestFunction(cell_element)

mu = Constant(triangle)
lmbda = Constant(triangle)

F = Identity(2) + grad(u)
I1 = tr(F.T * F) + 1.0
J = det(F)
psi = mu / 2 * (I1 - 3) - mu * ln(J) + lmbda / 2 * ln(J) ** 2

energy = psi * dx
residual = derivative(energy, u, v)
tangent = derivative(residual, u, du)
energy_density = psi * q * dx

forms = [energy, residual, tangent, energy_density]
