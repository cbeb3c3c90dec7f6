"""softpack: assemblies of soft particles under compaction.

The package is grouped by stage (docs/contract.md section 7): ``contract``
(what every stage shares: the parameter schema, the CSV tables, the run
directory's paths), ``scene`` (configuration, walls, species, packing,
meshes), ``simulation`` (the driver.json writer, the one launch of the C++
driver, ``./softpack run``), ``analysis`` (observables), ``plots``,
``references`` (the single-disk, plates and 3D cylinder checks) and
``bench``.

The functions below are the scripting interface (docs/python_api.md). With
``python/`` on the path (``./softpack`` sets it; in a shell:
``eval "$(./softpack env)"``)::

    import softpack
    config = softpack.load_config("examples/small.toml")
    series = softpack.run(config, "runs/small")

Importing softpack is cheap: dolfinx, gmsh and matplotlib are imported only
by the function that needs them.
"""

__version__ = "0.2.0"

__all__ = ["load_config", "run", "resume", "read_run", "plot_runs",
           "plot_loading", "plot_shear", "plot_plane_strain",
           "plot_single_disk", "RunError",
           "RunFlagged"]


def __getattr__(name):
    """The API functions of :mod:`softpack.api`, imported on first use."""
    if name in __all__:
        from softpack import api
        return getattr(api, name)
    raise AttributeError(f"module 'softpack' has no attribute {name!r}")


def __dir__():
    """The public names (the API's are imported on first use)."""
    return sorted(set(globals()) | set(__all__))
