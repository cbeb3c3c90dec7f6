"""softpack: assemblies of soft particles under compaction.

The package is grouped by stage (docs/contract.md section 7): ``scene``
(configuration, walls, species, packing, meshes), ``simulation`` (the
driver.json writer, the C++ driver, ``./softpack run``), ``analysis``
(observables), ``plots`` and ``references`` (the single-disk and 3D
cylinder checks).

From the repository root, with ``python/`` on the path (as ``./softpack``
sets it)::

    import softpack
    config = softpack.load_config("examples/small.toml")
"""

__version__ = "0.2.0"

__all__ = ["load_config"]


def load_config(path, overrides=None):
    """Read and validate a run's TOML file
    (:func:`softpack.scene.config.load_config`)."""
    from softpack.scene.config import load_config as load

    return load(path, overrides)
