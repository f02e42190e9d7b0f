"""What a library shows: classification counts, region combinations and figures.

The figures follow the thesis's chapter 4: a stability map over roll x pitch at one phase,
the classification over phase for every orientation (Figure 4.5: a grid of small phase
strips, one per roll/pitch), and the contact-region combinations seen. Figures are drawn
with matplotlib's Agg canvas (no display, no global pyplot state) and written atomically.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from .._errors import InputError
from .._io import atomic_path
from ._grid import Grid
from ._store import load

if TYPE_CHECKING:
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure

__all__ = [
    "CLASS_ORDER",
    "summary",
    "plot_stability_map",
    "plot_phase_strips",
    "plot_region_combinations",
    "write_figures",
]

#: Classifications in report order: the thesis's three states, then the others.
CLASS_ORDER = ("unstable", "quasi-stable", "stable", "in-phase", "no-contact", "error")
_COLOURS = {
    "unstable": "#d62728",
    "quasi-stable": "#ff9f1c",
    "stable": "#2ca02c",
    "in-phase": "#1f77b4",
    "no-contact": "#c7c7c7",
    "error": "#000000",
}
_NOT_COMPUTED = "#ffffff"
_COLUMNS = ["roll", "pitch", "phase", "classification", "n_contacts", "region_combination"]

Library = str | os.PathLike[str] | pd.DataFrame


def _frame(library: Library) -> tuple[pd.DataFrame, Grid, str]:
    """Rows (the columns the summary needs), the grid and a title."""
    if isinstance(library, pd.DataFrame):
        df = library
        missing = [c for c in _COLUMNS if c not in df.columns]
        if missing:
            raise InputError(f"not library rows: column {missing[0]!r} is missing")
        meta = df.attrs.get("threadmate")
    else:
        df = load(library, columns=_COLUMNS)
        meta = df.attrs["threadmate"]
    if meta is not None:
        grid = Grid.from_dict(meta["grid"])
        spec = meta.get("spec", {})
        name = spec.get("designation") or f"pitch {spec.get('pitch', '?')} {meta['units']}"
    else:
        if df.empty:
            raise InputError("an empty table without library metadata has no grid")
        grid = Grid(tuple(df["roll"].unique()), tuple(df["pitch"].unique()),
                    tuple(df["phase"].unique()))
        name = "contact-state library"
    return df, grid, name


def _class_index(df: pd.DataFrame, grid: Grid) -> np.ndarray:
    """Array (n_roll, n_pitch, n_phase) of indices into CLASS_ORDER; -1 where not computed."""
    cube = np.full(grid.shape, -1, dtype=np.int16)
    if df.empty:
        return cube
    i = np.searchsorted(np.asarray(grid.roll), df["roll"].to_numpy())
    j = np.searchsorted(np.asarray(grid.pitch), df["pitch"].to_numpy())
    k = np.searchsorted(np.asarray(grid.phase), df["phase"].to_numpy())
    lookup = {c: n for n, c in enumerate(CLASS_ORDER)}
    codes = df["classification"].map(lookup).fillna(lookup["error"]).to_numpy(np.int16)
    cube[np.clip(i, 0, grid.shape[0] - 1), np.clip(j, 0, grid.shape[1] - 1),
         np.clip(k, 0, grid.shape[2] - 1)] = codes
    return cube


def _nearest_phase(grid: Grid, phase: float | None) -> tuple[int, float]:
    if phase is None:
        return 0, grid.phase[0]
    _, (_, _, on_grid) = grid.nearest(grid.roll[0], grid.pitch[0], phase)
    k = grid.phase.index(on_grid)
    return k, on_grid


def summary(library: Library, phase: float | None = None) -> dict[str, Any]:
    """Counts of the contact states of a library.

    Parameters
    ----------
    library : path-like or pandas.DataFrame
        A library directory or rows from :func:`load`.
    phase : float, optional
        Also count the states at this phase (snapped to the nearest grid phase).

    Returns
    -------
    dict
        ``configurations`` (grid size), ``done``, ``counts`` and ``fractions`` per
        classification (all of :data:`CLASS_ORDER`), ``most_common`` and
        ``least_common`` among unstable, quasi-stable and stable, ``region_combinations``
        (counts, most frequent first), ``n_contacts`` (counts), ``orientations`` (counts
        per roll/pitch) and, with ``phase``, ``at_phase`` (the grid phase and its counts).
    """
    df, grid, name = _frame(library)
    cls = df["classification"]
    counts = {c: int((cls == c).sum()) for c in CLASS_ORDER}
    for other in sorted(set(cls.unique()) - set(CLASS_ORDER)):
        counts[str(other)] = int((cls == other).sum())
    done = len(df)
    three = {c: counts[c] for c in ("unstable", "quasi-stable", "stable")}
    combos = df["region_combination"].replace("", "(none)").value_counts()
    per_orientation = []
    for (r, p), group in df.groupby(["roll", "pitch"], sort=True):
        vc = group["classification"].value_counts()
        per_orientation.append({"roll": float(r), "pitch": float(p),
                                "counts": {str(k): int(v) for k, v in vc.items()}})
    out: dict[str, Any] = {
        "library": name,
        "grid": grid.describe(),
        "configurations": grid.size,
        "done": done,
        "counts": counts,
        "fractions": {c: (v / done if done else 0.0) for c, v in counts.items()},
        "most_common": max(three, key=three.get) if done else None,
        "least_common": min(three, key=three.get) if done else None,
        "region_combinations": {str(k): int(v) for k, v in combos.items()},
        "n_contacts": {int(k): int(v) for k, v in
                       df["n_contacts"].value_counts().sort_index().items()},
        "orientations": per_orientation,
    }
    if phase is not None:
        _, on_grid = _nearest_phase(grid, phase)
        at = df.loc[np.isclose(df["phase"], on_grid, atol=1e-9), "classification"]
        out["at_phase"] = {"phase": on_grid,
                           "counts": {c: int((at == c).sum()) for c in CLASS_ORDER}}
    return out


# -- figures ------------------------------------------------------------------------------
# matplotlib is imported where a figure is drawn: reading a library does not need it.
def _cmap() -> ListedColormap:
    from matplotlib.colors import ListedColormap

    return ListedColormap([_NOT_COMPUTED] + [_COLOURS[c] for c in CLASS_ORDER])


def _figure(width: float, height: float) -> Figure:
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height))


def _legend(ax: Any, present: set[int]) -> None:
    from matplotlib.patches import Patch

    handles = [Patch(facecolor=_COLOURS[c], edgecolor="0.3", label=c)
               for n, c in enumerate(CLASS_ORDER) if n in present]
    if -1 in present:
        handles.append(Patch(facecolor=_NOT_COMPUTED, edgecolor="0.3", label="not computed"))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False,
              fontsize="small")


def _ticks(values: tuple[float, ...], most: int = 19) -> tuple[list[int], list[str]]:
    step = max(1, int(np.ceil(len(values) / most)))
    idx = list(range(0, len(values), step))
    return idx, [f"{values[i]:g}" for i in idx]


def _save(fig: Figure, path: str | os.PathLike[str]) -> Path:
    path = Path(path)
    fmt = path.suffix.lstrip(".").lower() or "png"
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=fmt, dpi=150, bbox_inches="tight")
    return path


def plot_stability_map(library: Library, path: str | os.PathLike[str],
                       phase: float | None = None) -> Path:
    """Classification over roll x pitch at one phase (nearest grid phase; default the
    first). Returns the figure's path (format from its suffix, PNG by default)."""
    df, grid, name = _frame(library)
    k, on_grid = _nearest_phase(grid, phase)
    cube = _class_index(df, grid)
    plane = cube[:, :, k].T  # rows: pitch, columns: roll
    fig = _figure(6.4, 5.2)
    ax = fig.add_subplot()
    ax.imshow(plane + 1, cmap=_cmap(), vmin=0, vmax=len(CLASS_ORDER), origin="lower",
              interpolation="nearest")
    # Cell borders keep neighbouring states of one colour apart.
    ax.set_xticks(np.arange(-0.5, grid.shape[0]), minor=True)
    ax.set_yticks(np.arange(-0.5, grid.shape[1]), minor=True)
    ax.grid(which="minor", color="white", linewidth=0.8)
    ax.tick_params(which="minor", length=0)
    ax.set_xticks(*_ticks(grid.roll))
    ax.set_yticks(*_ticks(grid.pitch))
    ax.set_xlabel("roll (deg)")
    ax.set_ylabel("pitch (deg)")
    ax.set_title(f"{name}: contact state at phase {on_grid:g} deg")
    _legend(ax, set(np.unique(plane).tolist()))
    return _save(fig, path)


def plot_phase_strips(library: Library, path: str | os.PathLike[str]) -> Path:
    """The classification over phase for each orientation (thesis Figure 4.5): one small
    strip per roll/pitch, phase increasing left to right from 0 to 360 deg."""
    df, grid, name = _frame(library)
    cube = _class_index(df, grid)
    n_roll, n_pitch, n_phase = grid.shape
    width = n_phase
    height = max(2, int(round(n_phase / 5)))
    gap = max(1, int(round(n_phase / 10)))
    image = np.full((n_pitch * (height + gap) + gap, n_roll * (width + gap) + gap), -2,
                    dtype=np.int16)
    for i in range(n_roll):
        for j in range(n_pitch):
            row = (n_pitch - 1 - j) * (height + gap) + gap  # highest pitch on top
            col = i * (width + gap) + gap
            image[row:row + height, col:col + width] = cube[i, j][None, :]
    colours = ["#f4f4f4", _NOT_COMPUTED] + [_COLOURS[c] for c in CLASS_ORDER]
    aspect = image.shape[0] / image.shape[1]
    fig = _figure(11.0, max(3.0, 11.0 * aspect + 1.2))
    ax = fig.add_subplot()
    from matplotlib.colors import ListedColormap

    ax.imshow(image + 2, cmap=ListedColormap(colours), vmin=0, vmax=len(colours) - 1,
              interpolation="nearest", aspect="auto")
    xi, xl = _ticks(grid.roll)
    yi, yl = _ticks(grid.pitch)
    ax.set_xticks([gap + i * (width + gap) + width / 2 for i in xi], xl)
    ax.set_yticks([(n_pitch - 1 - j) * (height + gap) + gap + height / 2 for j in yi], yl)
    ax.set_xlabel("roll (deg); within each strip, phase 0 to 360 deg left to right")
    ax.set_ylabel("pitch (deg)")
    ax.set_title(f"{name}: contact state over phase for each orientation")
    for side in ax.spines.values():
        side.set_visible(False)
    _legend(ax, set(np.unique(cube).tolist()))
    return _save(fig, path)


def plot_region_combinations(library: Library, path: str | os.PathLike[str],
                             top: int = 25) -> Path:
    """Counts of the contact-region combinations (bolt/nut per contact) at the last stage
    reached, most frequent first (the ``top`` ones)."""
    df, _, name = _frame(library)
    combos = df["region_combination"].replace("", "(none)").value_counts().head(top)
    fig = _figure(8.0, 1.0 + 0.28 * max(1, len(combos)))
    ax = fig.add_subplot()
    y = np.arange(len(combos))
    ax.barh(y, combos.to_numpy(), color="#4c72b0")
    ax.set_yticks(y, [str(s) for s in combos.index], fontsize="small")
    ax.invert_yaxis()
    ax.set_xlabel("configurations")
    ax.set_title(f"{name}: contact-region combinations (bolt/nut per contact)")
    for yy, v in zip(y, combos.to_numpy(), strict=True):
        ax.text(v, yy, f" {v}", va="center", fontsize="x-small")
    return _save(fig, path)


def write_figures(library: Library, outdir: str | os.PathLike[str],
                  phase: float | None = None) -> dict[str, Path]:
    """Write the three figures into ``outdir`` (created if missing).

    Returns
    -------
    dict
        ``stability_map``, ``phase_strips`` and ``region_combinations`` -> PNG path.
    """
    outdir = Path(outdir)
    if outdir.exists() and not outdir.is_dir():
        raise InputError(f"-o {outdir} exists and is not a directory")
    if not isinstance(library, pd.DataFrame):
        library = load(library, columns=_COLUMNS)  # read once for the three figures
    return {
        "stability_map": plot_stability_map(library, outdir / "stability_map.png", phase),
        "phase_strips": plot_phase_strips(library, outdir / "phase_strips.png"),
        "region_combinations": plot_region_combinations(
            library, outdir / "region_combinations.png"),
    }
