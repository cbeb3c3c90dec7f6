"""No import circle in python/softpack (issue 36), and no stage reaching up.

The graph counts every import, at module level or inside a function
(import_graph.py); a circle is a strongly connected component of more than
one module. Run ``/usr/bin/python3 tests/python/import_graph.py`` to list
them.
"""

import import_graph

#: Who may not import whom: a stage never imports a later one, and the
#: shared contract (schema, tables, run directory) imports no stage.
FORBIDDEN = {
    "softpack.contract": ("softpack.scene", "softpack.simulation",
                          "softpack.analysis", "softpack.plots",
                          "softpack.references", "softpack.bench"),
    "softpack.scene": ("softpack.simulation", "softpack.analysis",
                       "softpack.plots", "softpack.references",
                       "softpack.bench"),
    "softpack.analysis": ("softpack.plots", "softpack.references",
                          "softpack.bench"),
}

def _in(module, package):
    return module == package or module.startswith(package + ".")


def test_no_import_circle():
    circles = import_graph.circles(import_graph.graph())
    assert circles == []


def test_no_stage_imports_a_later_one():
    upward = sorted(
        f"{module} -> {target}"
        for module, targets in import_graph.graph().items()
        for target in targets
        for package, later in FORBIDDEN.items() if _in(module, package)
        if any(_in(target, p) for p in later))
    assert upward == []


def test_the_checker_sees_a_deferred_circle(tmp_path):
    """A circle closed by an import inside a function is still found."""
    package = tmp_path / "pkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "a.py").write_text("from pkg import b\n")
    (package / "b.py").write_text("def f():\n    from pkg.a import g\n")
    (package / "c.py").write_text("from . import a\n")
    edges = import_graph.graph(package)
    assert edges["pkg.c"] == {"pkg.a"}
    assert import_graph.circles(edges) == [["pkg.a", "pkg.b"]]
