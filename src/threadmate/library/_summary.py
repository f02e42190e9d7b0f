"""What a library shows: classification counts, region combinations and figures.

Both models are summarised per *configuration* (:func:`configurations`): for the thesis's
model a configuration's row, for the mechanics the rest state the bolt dropped at that
held tilt and start phase reaches (its ``start`` state). A mechanics library also reports
the counts of all its states, by role and by class, and of its passive transitions.

The figures follow the thesis's chapter 4: a stability map over roll x pitch at one phase,
the classification over phase for every orientation (Figure 4.5: a grid of small phase
strips, one per roll/pitch), and the contact-region combinations seen. Figures are drawn
on matplotlib's Agg canvas (no display, no global pyplot state) and written atomically
(:mod:`threadmate._figures`).
"""

from __future__ import annotations

import os
from collections import Counter
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np
import pandas as pd

from .._errors import InputError
from .._figures import new_figure, save_figure
from ..contact import ERROR_CLASS, IN_PHASE, NO_CONTACT, QUASI_STABLE, STABLE, UNSTABLE
from ._grid import AnyGrid, Grid, read_grid
from ._store import configurations, load

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

#: Classifications in report order: the thesis's three states, then the others. The
#: mechanics' classes are the first four (``threadmate.contact.REST_CLASSES``).
CLASS_ORDER = (UNSTABLE, QUASI_STABLE, STABLE, IN_PHASE, NO_CONTACT, ERROR_CLASS)
#: The classes each model can give a configuration.
_MODEL_CLASSES = {
    "thesis": CLASS_ORDER,
    "mechanics": (UNSTABLE, QUASI_STABLE, STABLE, IN_PHASE, ERROR_CLASS),
}
#: The classes among which ``most_common`` and ``least_common`` are picked: the thesis's
#: three states, or the rest states a mechanics drop can reach.
_RANKED = {
    "thesis": (UNSTABLE, QUASI_STABLE, STABLE),
    "mechanics": (QUASI_STABLE, STABLE, IN_PHASE),
}
_COLOURS = {
    UNSTABLE: "#d62728",
    QUASI_STABLE: "#ff9f1c",
    STABLE: "#2ca02c",
    IN_PHASE: "#1f77b4",
    NO_CONTACT: "#c7c7c7",
    ERROR_CLASS: "#000000",
}
_NOT_COMPUTED = "#ffffff"
_COLUMNS = ["roll", "pitch", "phase", "classification", "n_contacts", "region_combination"]
#: What a mechanics library's summary reads (the starts and the counts of every state).
_STATE_COLUMNS = [
    "held_roll",
    "held_pitch",
    "phase",
    "role",
    "classification",
    "n_contacts",
    "region_combination",
    "transition",
    "transition_label",
]

Library = str | os.PathLike[str] | pd.DataFrame


def _rows(library: Library) -> pd.DataFrame:
    """The library's rows, reading only the columns the summary and figures need."""
    if isinstance(library, pd.DataFrame):
        return library
    from ._store import read_metadata

    model = read_metadata(library)["model"]
    return load(library, columns=_STATE_COLUMNS if model == "mechanics" else _COLUMNS)


def _model(df: pd.DataFrame) -> str:
    if df.attrs.get("threadmate_model"):
        return str(df.attrs["threadmate_model"])
    meta = df.attrs.get("threadmate") or {}
    if "model" in meta:
        return str(meta["model"])
    return "mechanics" if "role" in df.columns else "thesis"


def _frame(library: Library) -> tuple[pd.DataFrame, AnyGrid, str, str]:
    """One row per configuration (the columns the summary needs), the grid, a title and
    the model."""
    df = _rows(library)
    model = _model(df)
    meta = df.attrs.get("threadmate")
    if "role" in df.columns:
        df = configurations(df)
        df.attrs["threadmate_model"] = model
    missing = [c for c in _COLUMNS if c not in df.columns]
    if missing:
        raise InputError(f"not library rows: column {missing[0]!r} is missing")
    if meta is not None:
        grid = read_grid(meta["grid"])
        spec = meta.get("spec", {})
        name = spec.get("designation") or f"pitch {spec.get('pitch', '?')} {meta['units']}"
    else:
        if df.empty:
            raise InputError("an empty table without library metadata has no grid")
        grid = Grid(
            tuple(sorted(df["roll"].unique())),
            tuple(sorted(df["pitch"].unique())),
            tuple(sorted(df["phase"].unique())),
        )
        name = "contact-state library"
    return df, grid, name, model


def _what(model: str) -> str:
    """What a configuration's class is, in a figure's words."""
    return (
        "rest state reached by the drop"
        if model == "mechanics"
        else "contact state (thesis's stages)"
    )


def _square(grid: AnyGrid) -> Grid:
    """The roll x pitch x phase grid the figures draw on: the grid itself, or for a polar
    grid the distinct held rolls and pitches of its held tilts (cells that are no held
    tilt stay blank)."""
    if isinstance(grid, Grid):
        return grid
    rolls = tuple(sorted({r for r, _ in grid.held_tilts}))
    pitches = tuple(sorted({p for _, p in grid.held_tilts}))
    return Grid(rolls, pitches, grid.phase)


def _class_index(df: pd.DataFrame, grid: AnyGrid) -> np.ndarray:
    """Array (n_roll, n_pitch, n_phase) of indices into CLASS_ORDER; -1 where not computed
    (on :func:`_square`'s grid)."""
    grid = _square(grid)
    cube = np.full(grid.shape, -1, dtype=np.int16)
    if df.empty:
        return cube
    i = np.searchsorted(np.asarray(grid.roll), df["roll"].to_numpy())
    j = np.searchsorted(np.asarray(grid.pitch), df["pitch"].to_numpy())
    k = np.searchsorted(np.asarray(grid.phase), df["phase"].to_numpy())
    lookup = {c: n for n, c in enumerate(CLASS_ORDER)}
    codes = df["classification"].map(lookup).fillna(lookup[ERROR_CLASS]).to_numpy(np.int16)
    cube[
        np.clip(i, 0, grid.shape[0] - 1),
        np.clip(j, 0, grid.shape[1] - 1),
        np.clip(k, 0, grid.shape[2] - 1),
    ] = codes
    return cube


def _nearest_phase(grid: AnyGrid, phase: float | None) -> tuple[int, float]:
    grid = _square(grid)
    if phase is None:
        return 0, grid.phase[0]
    _, (_, _, on_grid) = grid.nearest(grid.roll[0], grid.pitch[0], phase)
    k = grid.phase.index(on_grid)
    return k, on_grid


def _counts(values: pd.Series) -> dict[str, int]:
    return {str(k): int(v) for k, v in values.value_counts().items()}


def _states(rows: pd.DataFrame) -> dict[str, Any]:
    """Counts of every state of a mechanics library and of its passive transitions."""
    by_role_class: dict[str, dict[str, int]] = {}
    for key, n in rows.groupby(["role", "classification"]).size().items():
        role, cls = cast("tuple[str, str]", key)  # grouped by two columns
        by_role_class.setdefault(str(role), {})[str(cls)] = int(n)
    out: dict[str, Any] = {
        "total": len(rows),
        "by_role": _counts(rows["role"]),
        "by_class": _counts(rows["classification"]),
        "by_role_and_class": by_role_class,
    }
    if "transition" in rows.columns:
        moves = rows[rows["transition"] != ""]
        by_kind: dict[str, dict[str, int]] = {}
        if "transition_label" in moves.columns:
            for key, n in moves.groupby(["transition", "transition_label"]).size().items():
                kind, label = cast("tuple[str, str]", key)  # grouped by two columns
                by_kind.setdefault(str(kind), {})[str(label)] = int(n)
        out["transitions"] = by_kind
    return out


def summary(library: Library, phase: float | None = None) -> dict[str, Any]:
    """Counts of the contact states of a library (either model).

    Parameters
    ----------
    library : path-like or pandas.DataFrame
        A library directory, rows from :func:`load`, or one row per configuration as
        :func:`configurations` gives them.
    phase : float, optional
        Also count the configurations at this phase (moved to the nearest grid phase;
        default the first grid phase, as :func:`plot_stability_map`).

    Returns
    -------
    dict
        ``library`` (its name), ``model``, ``units``, ``grid``, ``configurations`` (grid
        size), ``done``; over the finished configurations (the thesis's rows, or the rest
        state each mechanics start reaches): ``counts`` and ``fractions`` per
        classification (every class the model can give), ``most_common`` and
        ``least_common`` (among unstable, quasi-stable and stable for the thesis's model;
        among quasi-stable, stable and in-phase for the mechanics, whose drops always end
        at rest), ``region_combinations`` (counts, most frequent first, each a set of
        contacts with repeats counted: "a/b x 3 + c/d"), ``n_contacts``
        (counts), ``orientations`` (counts per roll/pitch) and ``at_phase`` (the grid
        phase and its counts). A mechanics library adds ``states``:
        ``total``, ``by_role``, ``by_class``, ``by_role_and_class`` over all its states
        and ``transitions`` (counts by kind and stability label).
    """
    rows = _rows(library)
    df, grid, name, model = _frame(rows)
    classes = _MODEL_CLASSES.get(model, CLASS_ORDER)
    cls = df["classification"]
    counts = {c: int((cls == c).sum()) for c in classes}
    for other in sorted(set(cls.unique()) - set(classes)):
        counts[str(other)] = int((cls == other).sum())
    done = len(df)
    ranked = {c: counts[c] for c in _RANKED.get(model, _RANKED["thesis"])}
    combos = _combinations(df)
    per_orientation = []
    for key, group in df.groupby(["roll", "pitch"], sort=True):
        r, p = cast("tuple[float, float]", key)  # grouped by two columns
        per_orientation.append(
            {"roll": float(r), "pitch": float(p), "counts": _counts(group["classification"])}
        )
    meta = rows.attrs.get("threadmate") or {}
    out: dict[str, Any] = {
        "library": name,
        "model": model,
        "units": meta.get("units"),
        "grid": grid.describe(),
        "configurations": grid.size,
        "done": done,
        "counts": counts,
        "fractions": {c: (v / done if done else 0.0) for c, v in counts.items()},
        "most_common": max(ranked, key=lambda c: ranked[c]) if done else None,
        "least_common": min(ranked, key=lambda c: ranked[c]) if done else None,
        "region_combinations": {str(k): int(v) for k, v in combos.items()},
        "n_contacts": {
            int(cast("int", k)): int(v)
            for k, v in df["n_contacts"].value_counts().sort_index().items()
        },
        "orientations": per_orientation,
    }
    if "role" in rows.columns:
        out["states"] = _states(rows)
    _, on_grid = _nearest_phase(grid, phase)
    at = df.loc[np.isclose(df["phase"], on_grid, atol=1e-9), "classification"]
    out["at_phase"] = {"phase": on_grid, "counts": {c: int((at == c).sum()) for c in classes}}
    return out


# -- figures ------------------------------------------------------------------------------
# matplotlib is imported where a figure is drawn: reading a library does not need it.
def _cmap() -> ListedColormap:
    from matplotlib.colors import ListedColormap

    return ListedColormap([_NOT_COMPUTED] + [_COLOURS[c] for c in CLASS_ORDER])


def _figure(width: float, height: float) -> Figure:
    return new_figure((width, height))


def _legend(ax: Any, present: set[int]) -> None:
    from matplotlib.patches import Patch

    handles = [
        Patch(facecolor=_COLOURS[c], edgecolor="0.3", label=c)
        for n, c in enumerate(CLASS_ORDER)
        if n in present
    ]
    if -1 in present:
        handles.append(Patch(facecolor=_NOT_COMPUTED, edgecolor="0.3", label="not computed"))
    ax.legend(
        handles=handles,
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
        frameon=False,
        fontsize="small",
    )


def _ticks(values: tuple[float, ...], most: int = 19) -> tuple[list[int], list[str]]:
    step = max(1, int(np.ceil(len(values) / most)))
    idx = list(range(0, len(values), step))
    return idx, [f"{values[i]:g}" for i in idx]


def _axis_names(model: str) -> tuple[str, str]:
    if model == "mechanics":
        return "held roll (deg)", "held pitch (deg)"
    return "roll (deg)", "pitch (deg)"


def plot_stability_map(
    library: Library, path: str | os.PathLike[str], phase: float | None = None
) -> Path:
    """Classification over roll x pitch at one phase (nearest grid phase; default the
    first): the thesis's state, or the rest state the mechanics' drop reaches. Returns the
    figure's path (format from its suffix, PNG by default)."""
    df, grid, name, model = _frame(library)
    k, on_grid = _nearest_phase(grid, phase)
    cube = _class_index(df, grid)
    grid = _square(grid)
    plane = cube[:, :, k].T  # rows: pitch, columns: roll
    fig = _figure(6.4, 5.2)
    ax = fig.add_subplot()
    ax.imshow(
        plane + 1,
        cmap=_cmap(),
        vmin=0,
        vmax=len(CLASS_ORDER),
        origin="lower",
        interpolation="nearest",
    )
    # Cell borders keep neighbouring states of one colour apart.
    ax.set_xticks(np.arange(-0.5, grid.shape[0]), minor=True)
    ax.set_yticks(np.arange(-0.5, grid.shape[1]), minor=True)
    ax.grid(which="minor", color="white", linewidth=0.8)
    ax.tick_params(which="minor", length=0)
    ax.set_xticks(*_ticks(grid.roll))
    ax.set_yticks(*_ticks(grid.pitch))
    xlabel, ylabel = _axis_names(model)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(f"{name}: {_what(model)} at phase {on_grid:g} deg", fontsize="medium")
    _legend(ax, set(np.unique(plane).tolist()))
    return save_figure(fig, path)


def plot_phase_strips(library: Library, path: str | os.PathLike[str]) -> Path:
    """The classification over phase for each orientation (thesis Figure 4.5): one small
    strip per roll/pitch, phase increasing left to right from 0 to 360 deg."""
    df, grid, name, model = _frame(library)
    cube = _class_index(df, grid)
    grid = _square(grid)
    n_roll, n_pitch, n_phase = grid.shape
    width = n_phase
    height = max(2, int(round(n_phase / 5)))
    gap = max(1, int(round(n_phase / 10)))
    image = np.full(
        (n_pitch * (height + gap) + gap, n_roll * (width + gap) + gap), -2, dtype=np.int16
    )
    for i in range(n_roll):
        for j in range(n_pitch):
            row = (n_pitch - 1 - j) * (height + gap) + gap  # highest pitch on top
            col = i * (width + gap) + gap
            image[row : row + height, col : col + width] = cube[i, j][None, :]
    colours = ["#f4f4f4", _NOT_COMPUTED] + [_COLOURS[c] for c in CLASS_ORDER]
    aspect = image.shape[0] / image.shape[1]
    fig = _figure(11.0, max(3.0, 11.0 * aspect + 1.2))
    ax = fig.add_subplot()
    from matplotlib.colors import ListedColormap

    ax.imshow(
        image + 2,
        cmap=ListedColormap(colours),
        vmin=0,
        vmax=len(colours) - 1,
        interpolation="nearest",
        aspect="auto",
    )
    xi, xl = _ticks(grid.roll)
    yi, yl = _ticks(grid.pitch)
    ax.set_xticks([gap + i * (width + gap) + width / 2 for i in xi], xl)
    ax.set_yticks([(n_pitch - 1 - j) * (height + gap) + gap + height / 2 for j in yi], yl)
    # Phase ticks under each strip of the bottom row (a column of strips shares them), in
    # the margin below it: the cell of a grid phase is one pixel column centred on it.
    marks = [m for m in (0.0, 90.0, 180.0, 270.0) if grid.phase[0] <= m <= grid.phase[-1]]
    at = np.interp(marks, grid.phase, np.arange(n_phase))
    edge = n_pitch * (height + gap) - 0.5  # the bottom strip's lower edge
    for i in range(n_roll):
        for m, k in zip(marks, at, strict=True):
            x = i * (width + gap) + gap + float(k)
            ax.plot([x, x], [edge, edge + 0.25 * gap], color="0.3", lw=0.6)
            ax.text(x, edge + 0.3 * gap, f"{m:g}", ha="center", va="top", fontsize=5.5)
    ax.tick_params(axis="x", length=0, pad=8)
    xlabel, ylabel = _axis_names(model)
    ax.set_xlabel(f"{xlabel}; within each strip, start phase 0 to 360 deg left to right")
    ax.set_ylabel(ylabel)
    ax.set_title(
        f"{name}: {_what(model)} over phase for each held tilt"
        if model == "mechanics"
        else f"{name}: {_what(model)} over phase for each orientation"
    )
    for side in ax.spines.values():
        side.set_visible(False)
    _legend(ax, set(np.unique(cube).tolist()))
    return save_figure(fig, path)


def _counted(combination: str) -> str:
    """A region combination as a set of contacts with their counts, the most frequent
    first ("a/b x 3 + c/d"): the same contacts listed in another order are the same
    combination, and six contacts on one ring would make a label wider than the figure."""
    counts = Counter(combination.split(" + "))
    ordered = sorted(counts.items(), key=lambda item: (-item[1], item[0]))
    return " + ".join(part if n == 1 else f"{part} x {n}" for part, n in ordered)


def _combinations(df: pd.DataFrame) -> pd.Series:
    """Counts of the configurations' region combinations (:func:`_counted`), most
    frequent first."""
    return df["region_combination"].replace("", "(none)").map(_counted).value_counts()


def plot_region_combinations(library: Library, path: str | os.PathLike[str], top: int = 25) -> Path:
    """Counts of the contact-region combinations (bolt/nut per contact) of each
    configuration (at the thesis's last stage reached, or of the rest state the mechanics'
    drop reaches), most frequent first (the ``top`` ones)."""
    df, _, name, model = _frame(library)
    combos = _combinations(df).head(top)
    fig = _figure(8.0, 1.0 + 0.28 * max(1, len(combos)))
    ax = fig.add_subplot()
    y = np.arange(len(combos))
    ax.barh(y, combos.to_numpy(), color="#4c72b0")
    ax.set_yticks(y, [str(s) for s in combos.index], fontsize="small")
    ax.invert_yaxis()
    ax.set_xlabel("starts (held tilt, phase)" if model == "mechanics" else "configurations")
    where = "rest states reached" if model == "mechanics" else "last stage reached"
    ax.set_title(
        f"{name}: contact-region combinations,\n{where} (bolt/nut per contact)",
        fontsize="medium",
    )
    for yy, v in zip(y, combos.to_numpy(), strict=True):
        ax.text(float(v), float(yy), f" {v}", va="center", fontsize="x-small")
    return save_figure(fig, path)


def write_figures(
    library: Library, outdir: str | os.PathLike[str], phase: float | None = None
) -> dict[str, Path]:
    """Write the three figures into ``outdir`` (created if missing).

    Returns
    -------
    dict
        ``stability_map``, ``phase_strips`` and ``region_combinations`` -> PNG path.
    """
    outdir = Path(outdir)
    if outdir.exists() and not outdir.is_dir():
        raise InputError(f"-o {outdir} exists and is not a directory")
    # Read once, one row per configuration, for the three figures.
    configs, _, _, model = _frame(library)
    configs.attrs["threadmate_model"] = model
    return {
        "stability_map": plot_stability_map(configs, outdir / "stability_map.png", phase),
        "phase_strips": plot_phase_strips(configs, outdir / "phase_strips.png"),
        "region_combinations": plot_region_combinations(
            configs, outdir / "region_combinations.png"
        ),
    }
