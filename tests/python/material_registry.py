"""A stand-in for the build's material registry, for tests without a build.

``build/forms/materials.json`` is written by the build from
forms/materials/*.py (docs/contract.md section 3). Tests that validate
configurations use it when it exists and otherwise this copy of the
shipped laws' declarations, in the same format.
"""

import json

from softpack import paths

LAW = {"shear_modulus": {"unit": "Pa", "range": "(0, inf)",
                         "default": 150000.0, "doc": "shear modulus mu"},
       "lame_lambda": {"unit": "Pa", "range": "[0, inf)",
                       "default": "2 * shear_modulus",
                       "doc": "first Lame parameter of the plane-strain"
                              " model"}}
FIXTURE = {"schema_version": 2, "materials": {
    "neo_hookean": {"doc": "compressible neo-Hookean", "parameters": LAW},
    "saint_venant_kirchhoff": {"doc": "Saint Venant-Kirchhoff",
                               "parameters": LAW}}}


def use_registry(tmp_path_factory, monkeypatch, document=None):
    """Point softpack.paths.MATERIALS at the build's registry, else at a
    copy of :data:`FIXTURE` (or ``document``); return the path."""
    if document is None and paths.MATERIALS.is_file():
        return paths.MATERIALS
    path = tmp_path_factory.mktemp("registry") / "materials.json"
    path.write_text(json.dumps(document or FIXTURE))
    monkeypatch.setattr(paths, "MATERIALS", path)
    return path
