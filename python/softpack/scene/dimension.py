"""The model's dimension: what a 2D and a 3D scene each accept.

``[model] dimension`` says which shapes, box and features a configuration
may use (docs/bodies_3d.md, 3D scenes): a 2D scene takes the plane shapes
and a box of two edges; a 3D scene the solids (sphere, cylinder,
ellipsoid, a user's .msh of tetrahedra) in a box of three edges, with the
features the 3D driver has (no periodic cell or walls beside the box's
yet); a 2D scene's gravity lies in the plane. :func:`check` refuses the rest naming the key
and what is allowed; the config stage prefixes the file name.
"""

from __future__ import annotations

import math

from softpack.scene import species as species_sizes
from softpack.scene.solids import spheroid_axes
from softpack.scene.walls import BOX_WALLS

#: The shapes of each dimension (msh: triangles in 2D, tetrahedra in 3D).
SHAPES = {2: ("disk", "polygon", "ellipse", "geo", "msh"),
          3: ("sphere", "cylinder", "ellipsoid", "msh")}
#: Densest packing of equal spheres (face-centred cubic), pi / sqrt(18).
FCC_FRACTION = math.pi / math.sqrt(18)


class DimensionError(ValueError):
    """A key that does not fit the model's dimension; the message names
    it and what is allowed."""


def check(sections, registry=None) -> None:
    """Refuse what the model's dimension does not take (see the module
    doc); ``registry`` (law name -> Law) checks the laws' dimensions."""
    dim = sections["model"]["dimension"]
    _check_shapes(sections["species"], dim)
    if dim == 2:
        height = sections["box"]["height"]
        if height != 0:
            raise DimensionError(
                f"[box] height = {height!r}: a box of three edges is 3D; set"
                " [model] dimension = 3, or leave height at 0 in 2D")
        gravity = sections["gravity"]["acceleration"]
        if len(gravity) == 3:
            raise DimensionError(
                f"[gravity] acceleration = {gravity}: three components in a"
                " 2D scene ([model] dimension = 2), whose gravity acts in the"
                " plane: [gx, gy]")
        if sections["stop"].get("base_area_fraction", 0) > 0:
            raise DimensionError(
                "[stop] base_area_fraction: the bottom faces of standing"
                " cylinders, a 3D measure; in 2D [stop] packing_fraction is"
                " the disks' area fraction")
        if sections["contact"]["nlgs_condensation"] == "on":
            raise DimensionError(
                "[contact] nlgs_condensation = \"on\": the base held out of"
                " the sweeps is 3D only ([model] dimension = 3); in 2D:"
                " \"auto\" or \"off\"")
        return
    _check_features(sections)
    _check_laws(sections, registry)
    _check_box(sections)


def _check_shapes(species, dim) -> None:
    for k, spec in enumerate(species):
        if int(spec["count"]) > 0 and spec["shape"] not in SHAPES[dim]:
            other = 3 if dim == 2 else 2
            raise DimensionError(
                f"[species.{k}] shape = {spec['shape']!r}: a {other}D shape"
                f" in a {dim}D scene ([model] dimension = {dim}); allowed:"
                f" {', '.join(SHAPES[dim])}")
    used = {s["shape"] for s in species if int(s["count"]) > 0}
    if dim == 3 and "cylinder" in used and len(used) > 1:
        raise DimensionError(
            f"[[species]] shape: cylinders stand on the base and are placed"
            f" by their end disks; they do not mix with"
            f" {', '.join(sorted(used - {'cylinder'}))} (placed by their"
            " bounding spheres) in one scene")


def _check_features(sections) -> None:
    """What the 3D driver does not have yet."""
    if sections["cell"]["enabled"]:
        raise DimensionError("[cell] enabled = true: a periodic cell is 2D"
                             " only for now ([model] dimension = 3)")
    if not sections["box"]["enabled"]:
        raise DimensionError("[box] enabled = false: a 3D scene needs its box"
                             " for now ([model] dimension = 3)")
    other = [n for n in sections["walls"] if n not in BOX_WALLS]
    if other:
        raise DimensionError(
            f"[walls.{other[0]}]: a 3D scene has the box's walls only for now"
            f" ({', '.join(BOX_WALLS)}, and the base and lid of [box]"
            " height)")


def _check_laws(sections, registry) -> None:
    if registry is None:
        return
    tables = [("material", sections["material"])] + [
        (f"materials.{n}", t) for n, t in sections["materials"].items()]
    for title, table in tables:
        law = registry.get(table["law"])
        if law is not None and 3 not in law.dimensions:
            allowed = sorted(n for n, v in registry.items()
                             if 3 in v.dimensions)
            raise DimensionError(
                f"[{title}] law = {table['law']!r}: plane strain only (its"
                f" file has no `dimensions = (2, 3)`); in 3D: "
                f"{', '.join(allowed)}")


def body_extent(spec, diameter, thickness) -> float:
    """The largest extent of a species' body of diameter D along any axis
    of the box (a .msh solid: its equal-volume diameter, checked exactly
    when it is read)."""
    if spec["shape"] == "ellipsoid":
        return 2 * spheroid_axes(spec["aspect_ratio"], diameter)[0]
    return diameter


def _check_box(sections) -> None:
    """Every body fits in the box; the bodies fill less of it than the
    Phi target and than the densest packing."""
    box, gap = sections["box"], sections["packing"]["gap"]
    if not box["height"] > 0:
        raise DimensionError(f"[box] height = {box['height']!r}: must be > 0"
                             " in 3D (the box's edge along z)")
    thickness = sections["model"]["thickness"]
    plan = min(box["length"], box["width"]) - 2 * gap
    volume = 0.0
    for k, spec in enumerate(sections["species"]):
        if int(spec["count"]) == 0:
            continue
        d_max = species_sizes.size_bounds(spec)[1]
        keys = species_sizes.size_bound_keys(spec, "max")
        where = f"[species.{k}] (species {spec['name']!r})"
        if spec["shape"] == "cylinder":
            if thickness + gap > box["height"]:
                raise DimensionError(
                    f"{where}: a cylinder of height [model] thickness ="
                    f" {thickness!r} does not fit under [box] height ="
                    f" {box['height']!r} with [packing] gap = {gap!r}")
            room = plan
        else:
            room = min(plan, box["height"] - 2 * gap)
        if body_extent(spec, d_max, thickness) >= room:
            raise DimensionError(
                f"{where} {keys}: a body larger than the box (its extent"
                f" {body_extent(spec, d_max, thickness):g} m, the box's"
                f" shortest room {room:g} m: [box] length, width, height"
                " minus twice [packing] gap)")
        # the expected area pi <D^2> / 4 of the species' bodies, times the
        # cylinders' height or a sphere's 2 D / 3
        area = species_sizes.total_area([spec])
        volume += (area * thickness if spec["shape"] == "cylinder" else
                   area * 2 / 3 * math.sqrt(4 * area / math.pi
                                            / int(spec["count"])))
    phi0 = volume / (box["length"] * box["width"] * box["height"])
    target = sections["stop"]["packing_fraction"]
    limit = min(target, FCC_FRACTION) if target > 0 else FCC_FRACTION
    if phi0 >= limit:
        raise DimensionError(
            f"[[species]] count and diameter: the bodies fill {phi0:.3f} of"
            f" the {box['length']:g} x {box['width']:g} x {box['height']:g} m"
            f" box, not less than {limit:.3f} ([stop] packing_fraction, a"
            " volume fraction in 3D, or the densest packing of spheres)")
    if sections["stop"].get("base_area_fraction", 0) > 0 and any(
            s["shape"] != "cylinder" for s in sections["species"]
            if int(s["count"]) > 0):
        raise DimensionError(
            "[stop] base_area_fraction: for standing cylinders only (the"
            " area fraction of their bottom faces on the base)")
    if sections["packing"]["initial_packing_fraction"] > 0 and any(
            s["shape"] != "cylinder" for s in sections["species"]
            if int(s["count"]) > 0):
        raise DimensionError(
            "[packing] initial_packing_fraction: in 3D for standing"
            " cylinders only (the area fraction of their end disks in the"
            " box's plan)")

