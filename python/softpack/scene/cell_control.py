"""A periodic cell's stress-controlled components ([cell] control_xx,
control_yy, stress_xx, stress_yy, mass; docs/periodic_cell.md, "A
stress-controlled cell").

A component h_ii under ``control_ii = "stress"`` is an unknown of each step
found so that ``stress_ii`` holds: its rate is not imposed, so the
velocity gradient's L_ii must be 0, and L_yx too (the edge a1 stays along
x, so that the load on h_ii is conjugate to sigma_ii alone).
"""

from __future__ import annotations

#: The controlled components: (key suffix, row of L, column of L)
AXES = (("xx", "velocity_gradient_x", 0), ("yy", "velocity_gradient_y", 1))


class CellControlError(ValueError):
    """A stress control that cannot hold; the message names the keys."""


def controlled(cell) -> list[str]:
    """The stress-controlled components' suffixes (``"xx"``, ``"yy"``)."""
    return [axis for axis, _, _ in AXES
            if cell[f"control_{axis}"] == "stress"]


def derive_mass(cell, total_mass: float) -> None:
    """``[cell] mass`` left out: the particles' total mass per unit
    length (the servo walls' rule)."""
    if cell["mass"] is None:
        cell["mass"] = total_mass


def check(cell) -> None:
    """Refuse a stress control without a free cell degree of freedom, one
    given an imposed rate too, and a stress on an imposed component.

    Raises
    ------
    CellControlError
        Naming the keys.
    """
    for axis, row, column in AXES:
        rate = cell[row][column]
        stress = cell[f"stress_{axis}"]
        if cell[f"control_{axis}"] == "stress":
            _check_free(cell, axis, row, column, rate)
        elif stress != 0:
            raise CellControlError(
                f"[cell] stress_{axis} = {stress!r} with control_{axis} ="
                f" \"velocity\": h_{axis} follows [cell] {row}; set"
                f" control_{axis} = \"stress\" to impose the stress, or"
                f" remove stress_{axis}")


def _check_free(cell, axis, row, column, rate) -> None:
    key = f"[cell] control_{axis} = \"stress\""
    if not cell["enabled"]:
        raise CellControlError(
            f"{key} with [cell] enabled = false: there is no cell degree"
            " of freedom to control (a run with walls controls a stress"
            " with servo walls, [walls.NAME] control = \"pressure\")")
    if rate != 0:
        raise CellControlError(
            f"{key} with [cell] {row}[{column}] = {rate!r}: the rate of"
            f" h_{axis} is the unknown that holds stress_{axis}, it cannot"
            " be imposed too; set it to 0.0")
    if cell["velocity_gradient_y"][0] != 0:
        raise CellControlError(
            f"{key} with [cell] velocity_gradient_y[0] (L_yx) ="
            f" {cell['velocity_gradient_y'][0]!r}: the edge a1 would tilt"
            f" and h_{axis}'s load would mix the shear stress into"
            f" sigma_{axis}; set L_yx to 0.0")
