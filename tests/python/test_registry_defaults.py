"""forms/registry.py turns each material's declared defaults into C++
(forms/material_defaults.h): numbers as doubles (C++ would make 1/3 zero),
names as the values given, the names used listed for the resolver."""

import importlib.util
from pathlib import Path

import pytest

FORMS = Path(__file__).resolve().parents[2] / "forms"


@pytest.fixture(scope="module")
def forms_registry():
    pytest.importorskip("ufl")
    spec = importlib.util.spec_from_file_location("registry",
                                                  FORMS / "registry.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_defaults_become_cpp_expressions(forms_registry):
    assert forms_registry.cpp_expression(1.5e5) == ("150000.0", [])
    assert forms_registry.cpp_expression("2 * shear_modulus") == (
        '(2.0 * p.at("shear_modulus"))', ["shear_modulus"])
    code, uses = forms_registry.cpp_expression("-(a + b) / 3 - 1/3 * a")
    assert code == ('(((-(p.at("a") + p.at("b"))) / 3.0) - ((1.0 / 3.0)'
                    ' * p.at("a")))')
    assert uses == ["a", "b"]
    # the expression means what Python means
    a, b = 2.0, 5.0
    cpp = code.replace('p.at("a")', "a").replace('p.at("b")', "b")
    assert eval(cpp) == pytest.approx(-(a + b) / 3 - 1 / 3 * a)


def test_the_shipped_materials_table(forms_registry, tmp_path):
    files = sorted(str(p) for p in (FORMS / "materials").glob("*.py"))
    cpp = tmp_path / "table.cpp"
    assert forms_registry.main(["registry.py", "--cpp", str(cpp),
                          str(tmp_path / "m.json"), *files]) == 0
    text = cpp.read_text()
    assert '{"lame_lambda", {"shear_modulus"},' in text
    assert 'return (2.0 * p.at("shear_modulus"));' in text
    assert 'if (law == "neo_hookean")' in text
    assert (tmp_path / "m.json").is_file()
