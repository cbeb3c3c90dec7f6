"""A periodic cell's stress-controlled components ([cell] control_xx,
control_yy, control_xy, control_mean, stress_xx, stress_yy, stress_xy,
stress_mean, stress_rate, mass; docs/periodic_cell.md, "A stress-controlled cell",
"Shear stress" and "Mean stress").

A component h_ii under ``control_ii = "stress"`` is an unknown of each step
found so that ``stress_ii`` holds: its rate is not imposed, so the
velocity gradient's L_ii must be 0, and L_yx too (the edge a1 stays along
x, so that the load on h_ii is conjugate to sigma_ii alone); h_xy under
``control_xy = "stress"`` likewise holds sigma_xy (L_xy and L_yx 0). The
isotropic
mode under ``control_mean = "stress"`` is one unknown acting on the whole
cell (dh/dt += V h / sqrt(det h)), found so that the mean stress holds; L
then gives the shape's change, and h_xx, h_yy must be under "velocity" (the
mode already moves them).

A drive is the [cell] table or a stage's ``cell`` table (the keys of
:data:`DRIVE_KEYS`); ``where`` names it in the messages.
"""

from __future__ import annotations

#: The controlled components: (key suffix, row of L, column of L)
AXES = (("xx", "velocity_gradient_x", 0), ("yy", "velocity_gradient_y", 1),
        ("xy", "velocity_gradient_x", 1))
#: The keys of the cell's drive (a stage's ``cell`` table has these)
DRIVE_KEYS = ("velocity_gradient_x", "velocity_gradient_y", "control_xx",
              "control_yy", "control_xy", "control_mean", "stress_xx",
              "stress_yy", "stress_xy", "stress_mean", "stress_rate")


class CellControlError(ValueError):
    """A stress control that cannot hold; the message names the keys."""


def controlled(cell) -> list[str]:
    """The stress-controlled components' suffixes (``"xx"``, ``"yy"``,
    ``"mean"``)."""
    return [axis for axis in ("xx", "yy", "xy", "mean")
            if cell[f"control_{axis}"] == "stress"]


def derive_mass(cell, total_mass: float) -> None:
    """``[cell] mass`` left out: the particles' total mass per unit
    length (the servo walls' rule)."""
    if cell["mass"] is None:
        cell["mass"] = total_mass


def check(cell, enabled=None, where="[cell]") -> None:
    """Refuse a stress control without a free cell degree of freedom, one
    given an imposed rate too, and a stress on an imposed component.

    Parameters
    ----------
    cell : dict
        The drive's keys (:data:`DRIVE_KEYS`).
    enabled : bool, optional
        Whether the run has a cell (default: ``cell["enabled"]``).
    where : str
        How the messages name the drive (``"[cell]"``, ``"[stages.1]
        cell."``).

    Raises
    ------
    CellControlError
        Naming the keys.
    """
    enabled = cell["enabled"] if enabled is None else enabled
    for axis, row, column in AXES:
        rate = cell[row][column]
        stress = cell[f"stress_{axis}"]
        if cell[f"control_{axis}"] == "stress":
            _check_free(cell, enabled, where, axis, row, column, rate)
        elif stress != 0:
            raise CellControlError(
                f"{_key(where, 'stress_' + axis)} = {stress!r} with"
                f" control_{axis} = \"velocity\": h_{axis} follows"
                f" {_key(where, row)}; set control_{axis} = \"stress\" to"
                f" impose the stress, or remove stress_{axis}")
    _check_mean(cell, enabled, where)
    if cell["stress_rate"] != 0 and not controlled(cell):
        raise CellControlError(
            f"{_key(where, 'stress_rate')} = {cell['stress_rate']!r} without"
            " a stress-controlled component: the ramp changes the imposed"
            " stresses; set control_xx, control_yy, control_xy or"
            " control_mean = \"stress\"")


def _key(where, key) -> str:
    """``[cell] key`` or ``[stages.1] cell.key``."""
    return f"{where}{key}" if where.endswith(".") else f"{where} {key}"


def _check_free(cell, enabled, where, axis, row, column, rate) -> None:
    key = f"{_key(where, 'control_' + axis)} = \"stress\""
    if not enabled:
        raise CellControlError(
            f"{key} with [cell] enabled = false: there is no cell degree"
            " of freedom to control (a run with walls controls a stress"
            " with servo walls, [walls.NAME] control = \"pressure\")")
    if rate != 0:
        raise CellControlError(
            f"{key} with {_key(where, row)}[{column}] = {rate!r}: the rate"
            f" of h_{axis} is the unknown that holds stress_{axis}, it"
            " cannot be imposed too; set it to 0.0")
    if cell["velocity_gradient_y"][0] != 0:
        raise CellControlError(
            f"{key} with {_key(where, 'velocity_gradient_y')}[0] (L_yx) ="
            f" {cell['velocity_gradient_y'][0]!r}: the edge a1 would tilt"
            f" and h_{axis}'s load would mix the shear stress into"
            f" sigma_{axis}; set L_yx to 0.0")


def _check_mean(cell, enabled, where) -> None:
    """The isotropic mode: a cell, and no diagonal component of its own."""
    key = f"{_key(where, 'control_mean')} = \"stress\""
    if cell["control_mean"] != "stress":
        if cell["stress_mean"] != 0:
            raise CellControlError(
                f"{_key(where, 'stress_mean')} = {cell['stress_mean']!r}"
                " with control_mean = \"velocity\": set control_mean ="
                " \"stress\" to impose the mean stress, or remove"
                " stress_mean")
        return
    if not enabled:
        raise CellControlError(
            f"{key} with [cell] enabled = false: there is no cell degree"
            " of freedom to control")
    for axis, _, _ in AXES:
        if cell[f"control_{axis}"] == "stress":
            raise CellControlError(
                f"{key} with {_key(where, 'control_' + axis)} = \"stress\":"
                " the mean stress moves h_xx, h_yy and h_xy already (its"
                " mode is the whole cell's isotropic change); control one"
                " or the other")
