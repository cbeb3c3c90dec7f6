# Compressible neo-Hookean solid in 3D, the same law as the plane-strain
# material (paper Eq. 1) without the plane-strain restriction:
#
#   Psi = mu/2 (I1 - 3) - mu ln J + lmbda/2 (ln J)^2,  I1 = tr(F^T F), J = det F
#
# For the 3D single-cylinder reference (nu = 0.495 => lmbda = 99 mu). P2
# tetrahedra; quadrature degree limited to 4 (FFCx would otherwise pick a
# very high degree because of ln J).
from ufl import (Constant, Identity, TestFunction, TrialFunction,
                 Coefficient, VectorElement, derivative, det, dx, grad, ln, tr,
                 tetrahedron)

element = VectorElement("Lagrange", tetrahedron, 2)

u = Coefficient(element)
v = TestFunction(element)
du = TrialFunction(element)

mu = Constant(tetrahedron)
lmbda = Constant(tetrahedron)

F = Identity(3) + grad(u)
J = det(F)
psi = mu / 2 * (tr(F.T * F) - 3) - mu * ln(J) + lmbda / 2 * ln(J) ** 2

dxq = dx(metadata={"quadrature_degree": 4})
energy = psi * dxq
residual = derivative(energy, u, v)
tangent = derivative(residual, u, du)

forms = [energy, residual, tangent]
