"""Adding a UFL file to forms/materials/ adds a material.

The check copies forms/ into a temporary directory, writes a new material
file there (a Mooney-Rivlin-like law with its own parameter), and builds a
minimal CMake project (tests/cmake/material_registry) that uses the very
forms/CMakeLists.txt of the project: the new law must come out of FFCx and
be listed by the registry with its parameters, next to the shipped ones.
"""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(os.environ.get("SOFTPACK_ROOT", Path(__file__).resolve().parents[2]))

NEW_MATERIAL = '''
# A test law: neo-Hookean plus a second-invariant term (plane strain).
from ufl import (Constant, Identity, TestFunction, TrialFunction, Coefficient,
                 FiniteElement, VectorElement, derivative, det, dx, grad, ln,
                 tr, triangle)

element = VectorElement("Lagrange", triangle, 1)
cell_element = FiniteElement("DG", triangle, 0)
u = Coefficient(element)
v = TestFunction(element)
du = TrialFunction(element)
q = TestFunction(cell_element)
mu = Constant(triangle)
lmbda = Constant(triangle)
c2 = Constant(triangle)

F = Identity(2) + grad(u)
C = F.T * F
I1 = tr(C) + 1.0
I2 = 0.5 * (tr(C) ** 2 - tr(C * C)) + tr(C)
J = det(F)
psi = (mu / 2 * (I1 - 3) + c2 * (I2 - 3) - mu * ln(J)
       + lmbda / 2 * ln(J) ** 2)

energy = psi * dx
residual = derivative(energy, u, v)
tangent = derivative(residual, u, du)
energy_density = psi * q * dx
forms = [energy, residual, tangent, energy_density]
'''


@pytest.mark.skipif(shutil.which("cmake") is None, reason="needs cmake")
def test_new_ufl_file_becomes_a_registered_material(tmp_path):
    forms = tmp_path / "forms"
    shutil.copytree(ROOT / "forms", forms)
    (forms / "materials" / "test_second_invariant.py").write_text(NEW_MATERIAL)
    build = tmp_path / "build"
    source = ROOT / "tests" / "cmake" / "material_registry"
    subprocess.run(["cmake", "-S", source, "-B", build,
                    "-DCMAKE_BUILD_TYPE=Release", f"-DFORMS_DIR={forms}"],
                   check=True, capture_output=True)
    subprocess.run(["cmake", "--build", build, "-j", "2",
                    "--target", "list-materials"],
                   check=True, capture_output=True)
    out = subprocess.run([build / "list-materials"], check=True,
                         capture_output=True, text=True).stdout
    listed = {line.split(":")[0]: sorted(line.split(":")[1].split())
              for line in out.strip().splitlines()}
    assert listed["test_second_invariant"] == ["c2", "lmbda", "mu"]
    assert listed["neo_hookean"] == ["lmbda", "mu"]
    assert listed["saint_venant_kirchhoff"] == ["lmbda", "mu"]
