# A material whose default expression names something that is not one of
# its parameters: forms/registry.py must refuse it.
from ufl import (Coefficient, Constant, Identity, VectorElement, dx, grad,
                 inner, triangle)

element = VectorElement("Lagrange", triangle, 1)
u = Coefficient(element)
shear_modulus = Constant(triangle)
lame_lambda = Constant(triangle)

parameters = {
    "shear_modulus": {"unit": "Pa", "range": "(0, inf)", "default": 1.0,
                      "doc": "shear modulus"},
    "lame_lambda": {"unit": "Pa", "range": "[0, inf)",
                    "default": "2 * mu", "doc": "Lame lambda"},
}

F = Identity(2) + grad(u)
energy = (shear_modulus + lame_lambda) * inner(F, F) * dx
