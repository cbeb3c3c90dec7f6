"""Snapshots of a run's deformed particles at chosen states.

``./softpack plot RUN --at phi=0.78 --at stage=1 --at time=0.05 --at last``
(and Fig. 7 of the paper case). Each state is an output row of
``series.csv`` (``phi=``: the row nearest in Phi, refused beyond
:data:`PHI_TOLERANCE`; ``time=``: nearest in time; ``stage=K``: the last row
of stage K; ``last``), drawn from the stored field frame nearest its time
(frames are written every ``output.fields_every`` rows and at the last one),
labelled with that frame's own Phi and time.

A panel shows the particles coloured by their strain-energy density Psi
(kPa, or Psi / mu when the law has a shear modulus), their outlines (one
colour per species when there are several), rigid particles in grey, the
walls where they are at that output (``raw/steps.csv``) or a periodic
cell's edges (dashed, the particles that cross them drawn whole), and a scale
bar.
"""

from __future__ import annotations

import math

import numpy as np

from softpack.analysis.cell import edges as cell_edges
from softpack.analysis.fields import read_snapshot, stored_times
from softpack.analysis.setup import read_setup
from softpack.contract.run_directory import RunDirectory, RunError
from softpack.contract.tables import read_table
from softpack.plots import style

#: How far in Phi the row drawn for ``phi=`` may be from the value asked.
PHI_TOLERANCE = 0.01


def parse_at(text: str) -> tuple[str, float]:
    """``"phi=0.78"`` -> ``("phi", 0.78)``; ``"last"`` -> ``("last", nan)``."""
    if text == "last":
        return "last", math.nan
    kind, sep, value = text.partition("=")
    if not sep or kind not in ("phi", "time", "stage"):
        raise ValueError(f"--at {text!r}: expected phi=VALUE, time=SECONDS,"
                         " stage=INDEX or last")
    try:
        return kind, float(value)
    except ValueError:
        raise ValueError(f"--at {text!r}: {value!r} is not a number") from None


def pick_row(series: dict, stages, kind: str, value: float) -> int:
    """The output row of a state (see the module's doc)."""
    rows = len(series["step"])
    if kind == "last":
        return rows - 1
    if kind == "time":
        return int(np.argmin(np.abs(np.asarray(series["time"]) - value)))
    if kind == "stage":
        mine = np.flatnonzero(np.asarray(stages) == value)
        if not len(mine):
            raise RunError(f"stage={value:g}: the run has stages"
                           f" {sorted(set(np.asarray(stages, int)))}")
        return int(mine[-1])
    phi = np.asarray(series["phi"], float)
    k = int(np.nanargmin(np.abs(phi - value)))
    if abs(phi[k] - value) > PHI_TOLERANCE:
        raise RunError(f"phi={value:g}: the run's Phi comes no closer than"
                       f" {phi[k]:.4f} (within {PHI_TOLERANCE} asked)")
    return k


class RunStates:
    """What the panels of one run read: its tables, set-up and fields."""

    def __init__(self, run_dir):
        self.run = RunDirectory(run_dir)
        if not self.run.fields_h5.is_file():
            raise RunError(f"{self.run.fields_h5} missing (run with [output]"
                           " fields = true)")
        self.series = read_table(self.run.series_csv)
        self.setup = read_setup(run_dir)
        self.steps = (read_table(self.run.raw.steps_csv)
                      if self.run.raw.steps_csv.is_file() else None)
        self.times = stored_times(self.run.fields_h5)
        self.stage_names = self.setup.stage_names

    @property
    def stages(self):
        count = len(self.series["step"])
        if self.steps is None or "stage" not in self.steps:
            return np.zeros(count)
        return np.asarray(self.steps["stage"][:count])

    def frame_row(self, k: int) -> int:
        """The row of the stored frame nearest row k's time."""
        t = self.times[np.argmin(np.abs(self.times - self.series["time"][k]))]
        return int(np.argmin(np.abs(np.asarray(self.series["time"]) - t)))

    def cell(self, k: int):
        """The periodic cell's corners at row k (closed: 5 points), or
        None without a cell (docs/periodic_cell.md)."""
        if not self.setup.cell or self.steps is None:
            return None
        h = cell_edges(self.steps, k)
        return np.array([[0, 0], h[:, 0], h[:, 0] + h[:, 1], h[:, 1],
                         [0, 0]])

    def walls(self, k: int) -> dict:
        """``{name: ((x0, y0), (x1, y1))}``: each wall's segment at row k,
        across the box (box walls: between their neighbours)."""
        if self.steps is None:
            return {}
        at = {w: np.array([self.steps[f"{w}_x"][k], self.steps[f"{w}_y"][k]])
              for w in self.setup.walls}
        if self.setup.has_box:
            x0, x1 = at["left"][0], at["right"][0]
            y0, y1 = at["bottom"][1], at["top"][1]
            return {"left": ((x0, y0), (x0, y1)),
                    "right": ((x1, y0), (x1, y1)),
                    "bottom": ((x0, y0), (x1, y0)),
                    "top": ((x0, y1), (x1, y1))}
        span = 0.5 * max(self.setup.length, self.setup.width, 0.1)
        out = {}
        for name, wall in self.setup.walls.items():
            tangent = np.array([-wall.normal[1], wall.normal[0]])
            out[name] = (tuple(at[name] - span * tangent),
                         tuple(at[name] + span * tangent))
        return out


def snapshot_figure(run_dir, selectors, width=style.DOUBLE_COLUMN):
    """The figure of the states ``selectors`` (``[(kind, value)]``) of a
    run; its panels' walls are Line2D with gid ``wall:NAME``."""
    import matplotlib.pyplot as plt

    states = RunStates(run_dir)
    rows = [states.frame_row(pick_row(states.series, states.stages, *s))
            for s in selectors]
    snaps = [read_snapshot(states.run.fields_h5, states.series["time"][k])
             for k in rows]
    mu = states.setup.shear_modulus
    scale, label = ((mu, r"$\Psi/\mu$") if np.isfinite(mu)
                    else (1e3, r"$\Psi$ (kPa)"))
    vmax = max(float(np.nanpercentile(s.psi / scale, 99.5)) for s in snaps)
    n = len(rows)
    with style.context():
        fig, axes = plt.subplots(1, n, figsize=(width, 0.42 * width),
                                 squeeze=False, layout="constrained")
        for ax, k, snap in zip(axes[0], rows, snaps):
            image = _draw_panel(ax, states, k, snap, scale, vmax or 1.0)
        # one length scale for every panel, and one bar
        limits = np.array([ax.get_xlim() + ax.get_ylim() for ax in axes[0]])
        for ax in axes[0]:
            ax.set_xlim(limits[:, 0].min(), limits[:, 1].max())
            ax.set_ylim(limits[:, 2].min(), limits[:, 3].max())
        style.scale_bar(axes[0][0])
        for ax in axes[0][1:]:
            ax.set_ylim(axes[0][0].get_ylim())
        fig.set_figheight(_panel_height(axes[0][0], width, n))
        fig.colorbar(image, ax=axes[0].tolist(), label=label, shrink=0.85)
        _fit_height(fig, axes[0][0])
        _species_legend(fig, states)
    return fig


def _panel_height(ax, width, n) -> float:
    """The figure height (inches) at which ``n`` panels of ``ax``'s limits
    (equal aspect) side by side in ``width`` fill it, with room for the
    titles: no empty band above and below the boxes, and a colour bar as
    tall as they are."""
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    panel = (width - 0.9) / n  # the colour bar and its label take ~0.9 in
    return panel * (y1 - y0) / (x1 - x0) + 0.45


def _fit_height(fig, ax, passes=2) -> None:
    """Take off the figure's height the band that the equal aspect leaves
    empty above and below ``ax`` (laid out, then measured)."""
    for _ in range(passes):
        fig.canvas.draw()
        slot = ax.get_position(original=True).height
        used = ax.get_position(original=False).height
        spare = (slot - used) * fig.get_figheight()
        if spare < 0.02:
            return
        fig.set_figheight(fig.get_figheight() - spare)


def _draw_panel(ax, states, k, snap, scale, vmax):
    """One state: Psi, outlines, rigid particles, walls, scale bar."""
    from matplotlib.collections import LineCollection
    from matplotlib.tri import Triangulation

    x = snap.current
    rigid = np.asarray(states.setup.body_rigid, bool)[snap.body]
    psi = np.where(rigid, np.nan, snap.psi / scale)
    triangulation = Triangulation(x[:, 0], x[:, 1], snap.cells)
    # The field is drawn as an image even in a PDF (outlines, text and
    # axes stay vector): ~90,000 triangles per panel as vector paths made
    # 4-6 MB files.
    image = ax.tripcolor(triangulation, facecolors=psi, vmin=0, vmax=vmax,
                         cmap="viridis", rasterized=True)
    if rigid.any():
        ax.tripcolor(Triangulation(x[:, 0], x[:, 1], snap.cells[rigid]),
                     facecolors=np.zeros(rigid.sum()), cmap="Greys",
                     vmin=-1, vmax=4, rasterized=True)
    colours = style.species_colours(len(states.setup.species))
    edges = _outline_edges(snap.cells, snap.body)
    species = np.asarray(states.setup.body_species)[snap.body[edges[:, 2]]]
    ax.add_collection(LineCollection(x[edges[:, :2]], colors=[
        colours[s] for s in species], linewidths=0.8))
    for name, (a, b) in states.walls(k).items():
        ax.plot([a[0], b[0]], [a[1], b[1]], "k-", lw=1.6, gid=f"wall:{name}",
                solid_capstyle="butt")
    corners = states.cell(k)
    if corners is not None:  # bodies cross its edges: drawn whole
        ax.plot(corners[:, 0], corners[:, 1], "k--", lw=1.0, gid="cell")
    ax.set_aspect("equal")
    ax.autoscale()
    ax.set_axis_off()
    stage = int(states.stages[k])
    name = (states.stage_names[stage] if stage < len(states.stage_names)
            else "")
    ax.set_title(rf"$\Phi$ = {states.series['phi'][k]:.3f}, t ="
                 f" {states.series['time'][k]:.3g} s"
                 + (f"\n{name}" if name else ""))
    return image


def _outline_edges(cells, body) -> np.ndarray:
    """``(edges, 3)``: the boundary edges of each particle (node, node,
    one of its cells)."""
    e = np.concatenate([cells[:, [0, 1]], cells[:, [1, 2]], cells[:, [2, 0]]])
    owner = np.tile(np.arange(len(cells)), 3)
    key = np.sort(e, axis=1)
    _, first, count = np.unique(key, axis=0, return_index=True,
                                return_counts=True)
    once = first[count == 1]
    return np.column_stack((e[once], owner[once]))


def _species_legend(fig, states) -> None:
    """A legend of the species' outline colours, and of rigid particles."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    species = states.setup.species
    handles = []
    if len(species) > 1:
        colours = style.species_colours(len(species))
        handles = [Line2D([], [], color=colours[i], lw=1.2,
                          label=s.get("name", f"species {i}"))
                   for i, s in enumerate(species)]
    if np.asarray(states.setup.body_rigid, bool).any():
        handles.append(Patch(color="0.8", label="rigid"))
    if handles:
        fig.legend(handles=handles, loc="upper center",
                   bbox_to_anchor=(0.5, 0.0), ncols=min(len(handles), 5),
                   frameon=False)


def write_snapshots(run_dir, selectors, path) -> list:
    """Draw the states into ``path`` (PNG and PDF); the files written."""
    return style.save(snapshot_figure(run_dir, selectors), path)
