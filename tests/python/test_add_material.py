"""Adding a UFL file to forms/materials/ adds a material usable from TOML.

The check copies forms/ into a temporary directory, writes a new material
file there (a Mooney-Rivlin-like law with its own parameter ``c2`` and a
default that is an expression of another), and builds a minimal CMake
project (tests/cmake/material_registry) around the very
forms/CMakeLists.txt of the project: the new law must come out of FFCx, be
listed by the C++ registry with its parameters next to the shipped ones,
and appear in the generated registry materials.json, from which a
configuration naming it validates, with no other edit anywhere. (A run
with it would need the driver rebuilt against the copied forms/, minutes
on this machine; the driver's side of the registry is tested in C++.)
"""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

from material_registry import use_registry
from softpack.scene.config import ConfigError, validate

ROOT = Path(os.environ.get("SOFTPACK_ROOT", Path(__file__).resolve().parents[2]))

NEW_MATERIAL = '''
# A test law: neo-Hookean plus a second-invariant term (plane strain).
from ufl import (Constant, Identity, TestFunction, TrialFunction, Coefficient,
                 VectorElement, derivative, det, dx, grad, ln,
                 tr, triangle)

element = VectorElement("Lagrange", triangle, 1)
u = Coefficient(element)
v = TestFunction(element)
du = TrialFunction(element)
shear_modulus = Constant(triangle)
lame_lambda = Constant(triangle)
c2 = Constant(triangle)

parameters = {
    "shear_modulus": {"unit": "Pa", "range": "(0, inf)", "default": 0.15e6,
                      "doc": "shear modulus"},
    "lame_lambda": {"unit": "Pa", "range": "[0, inf)",
                    "default": "2 * shear_modulus", "doc": "Lame lambda"},
    "c2": {"unit": "Pa", "range": "[0, inf)", "default": "shear_modulus / 10",
           "doc": "second-invariant coefficient"},
}

F = Identity(2) + grad(u)
C = F.T * F
I1 = tr(C) + 1.0
I2 = 0.5 * (tr(C) ** 2 - tr(C * C)) + tr(C)
J = det(F)
psi = (shear_modulus / 2 * (I1 - 3) + c2 * (I2 - 3) - shear_modulus * ln(J)
       + lame_lambda / 2 * ln(J) ** 2)

energy = psi * dx
residual = derivative(energy, u, v)
tangent = derivative(residual, u, du)
forms = [energy, residual, tangent]
'''


@pytest.mark.skipif(shutil.which("cmake") is None, reason="needs cmake")
def test_new_ufl_file_becomes_a_material_usable_from_toml(
        tmp_path, tmp_path_factory, monkeypatch):
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
    assert listed["test_second_invariant"] == ["c2", "lame_lambda",
                                               "shear_modulus"]
    assert listed["neo_hookean"] == ["lame_lambda", "shear_modulus"]
    assert listed["saint_venant_kirchhoff"] == ["lame_lambda",
                                                "shear_modulus"]

    # the Python side: the generated registry, and a config naming the law
    import json
    registry = json.loads((build / "forms" / "materials.json").read_text())
    use_registry(tmp_path_factory, monkeypatch, registry)
    piston = {"walls": {"right": {"velocity": [-0.1, 0.0]}}}
    config = validate({**piston, "material": {
        "law": "test_second_invariant",
        "parameters": {"shear_modulus": 2e5}}}, "new-law.toml")
    assert config["material"]["parameters"] == {
        "shear_modulus": 2e5, "lame_lambda": 4e5, "c2": 2e4}
    with pytest.raises(ConfigError, match=r"\[material.parameters\] c2 = -1.0:"
                       r" must be >= 0 Pa"):
        validate({**piston, "material": {"law": "test_second_invariant",
                                         "parameters": {"c2": -1.0}}}, "x")
