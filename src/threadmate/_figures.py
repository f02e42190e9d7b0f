"""Figure output shared by the stages: an Agg canvas (no display needed) and an atomic
save that refuses an unwritable path with one clear message."""

from __future__ import annotations

import os
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ._errors import InputError
from ._io import atomic_path

__all__ = ["new_figure", "save_figure", "DPI"]

#: Resolution of raster figures.
DPI = 150


def new_figure(size: tuple[float, float]) -> Figure:
    """A figure of ``size`` inches on its own Agg canvas (pyplot's state is not touched)."""
    fig = Figure(figsize=size, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def save_figure(fig: Figure, path: str | os.PathLike[str], fmt: str | None = None) -> Path:
    """Write ``fig`` to ``path`` in format ``fmt`` (default: the path's suffix, PNG without
    one) atomically (temp file + rename)."""
    if fmt is None:
        fmt = Path(path).suffix.lstrip(".").lower() or "png"
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format=fmt, dpi=DPI)
    except OSError as exc:
        raise InputError(
            f"cannot write figure {os.fspath(path)!r}: {exc.strerror or exc}"
        ) from None
    return Path(path)
