# A material whose `parameters` dict forgets one of its UFL constants:
# forms/registry.py must refuse it, naming the file and the constant.
from ufl import (Coefficient, Constant, Identity, VectorElement, dx, grad,
                 inner, triangle)

element = VectorElement("Lagrange", triangle, 1)
u = Coefficient(element)
shear_modulus = Constant(triangle)
c2 = Constant(triangle)

parameters = {
    "shear_modulus": {"unit": "Pa", "range": "(0, inf)", "default": 1.0,
                      "doc": "shear modulus"},
}

F = Identity(2) + grad(u)
energy = (shear_modulus + c2) * inner(F, F) * dx
