"""softpack: assemblies of soft (neo-Hookean) particles under compaction.

The Python side builds meshes and packings with gmsh, runs the 3D dolfinx
reference computations, and post-processes and plots the C++ driver's output.
"""

__version__ = "0.1.0"
