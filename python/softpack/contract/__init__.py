"""What every stage agrees on, and imports without reaching across.

``schema`` (every parameter, from ``schema/parameters.toml``), ``tables``
(the one CSV reader and writer) and ``run_directory`` (every path of a run,
:class:`~softpack.contract.run_directory.RunDirectory`): docs/contract.md.
Nothing here imports a stage.
"""
