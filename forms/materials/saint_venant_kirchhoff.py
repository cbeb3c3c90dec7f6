# Saint Venant-Kirchhoff solid in plane strain.
#
#   E = (F^T F - I)/2 (2x2; E33 = 0 in plane strain)
#   Psi = lmbda/2 (tr E)^2 + mu tr(E E)
#
# Same material file contract as neo_hookean.py. Its small-strain limit is the
# same linear elasticity as neo-Hookean; it stiffens differently (and loses
# stability in strong compression), which makes it a useful contrast.
from ufl import (Constant, Identity, TestFunction, TrialFunction,
                 Coefficient, FiniteElement, VectorElement, derivative, dx,
                 grad, inner, tr, triangle)

element = VectorElement("Lagrange", triangle, 1)
cell_element = FiniteElement("DG", triangle, 0)

u = Coefficient(element)
v = TestFunction(element)
du = TrialFunction(element)
q = TestFunction(cell_element)

mu = Constant(triangle)
lmbda = Constant(triangle)

F = Identity(2) + grad(u)
E = (F.T * F - Identity(2)) / 2
psi = lmbda / 2 * tr(E) ** 2 + mu * inner(E, E)

energy = psi * dx
residual = derivative(energy, u, v)
tangent = derivative(residual, u, du)
energy_density = psi * q * dx

forms = [energy, residual, tangent, energy_density]
