"""Figures of a turn of the bolt: the snap signature of a search (:func:`plot_search`) and
the signature of a clockwise start (:func:`plot_screw`).

Each draws what a robot's sensors see against phase (the compliance centre's height, the
tilt of the bolt axis, the driver's torque) with the turn's events marked, through the
drawing a network path's signature shares (``threadmate._figures.signature_figure``).
Lengths in the spec's units, angles in degrees, torques in N m, work in mJ.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..._angles import wrap_phase
from ..._errors import InputError
from ..._figures import EventLabel, Mark, save_figure, signature_figure
from ..._validate import FIGURE_FORMATS
from ...geometry import ThreadSpec
from ._rest_state import SearchEvent, SearchResult
from ._screw import ScrewResult

__all__ = ["plot_screw", "plot_search"]


def plot_search(
    run: SearchResult, path: str | os.PathLike[str], *, spec: ThreadSpec | None = None
) -> Path:
    """The snap signature of a search: the compliance centre's height, the tilt of the
    bolt axis and the driver's torque against phase, each event marked and labelled (the
    snap in bold, with its click).

    Parameters
    ----------
    run : SearchResult
        The search (:func:`threadmate.contact.search`).
    path : path-like
        The figure file: ``.png``, ``.pdf`` or ``.svg`` (written atomically).
    spec : ThreadSpec, optional
        The thread pair, to name it in the title.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    outcome = (
        f"no snap within {run.turns:g} turn(s)"
        if run.snap is None
        else f"snap at {wrap_phase(run.snap.phase):.2f} deg after {run.snap_turn:.2f} deg"
    )
    torque = [s.driver_torque for s in run.states]
    return _plot_turn(run, "search", outcome, torque, "snap", path, spec)


def plot_screw(
    run: ScrewResult, path: str | os.PathLike[str], *, spec: ThreadSpec | None = None
) -> Path:
    """A clockwise start (:func:`threadmate.contact.screw`): the compliance centre's
    height, the tilt of the bolt axis and the tightening torque against phase, the events
    marked, the outcome and where it is decided in the title. Parameters as
    :func:`plot_search`'s."""
    where = "" if run.decided_phase is None else f" at {wrap_phase(run.decided_phase):.2f} deg"
    return _plot_turn(
        run, "clockwise start", f"{run.outcome}{where}", list(run.torques), "", path, spec
    )


def _name(spec: ThreadSpec | None) -> str:
    if spec is None:
        return "thread pair"
    return spec.designation or f"spec (pitch {spec.pitch:g} {spec.units})"


def _plot_turn(
    run: SearchResult | ScrewResult,
    what: str,
    outcome: str,
    torque: list[float],
    marked: str,
    path: str | os.PathLike[str],
    spec: ThreadSpec | None,
) -> Path:
    """A turn's signature figure, its events of kind ``marked`` in bold with their click."""
    path = Path(path)
    fmt = FIGURE_FORMATS.get(path.suffix.lower())
    if fmt is None:
        raise InputError(
            f"figure {path}: expected a file ending in {', '.join(FIGURE_FORMATS)} "
            f"(got {path.suffix or 'no suffix'!r})"
        )
    states = run.states
    p = run.parameters
    k = p["stiffness"]
    fig = signature_figure(
        [s.phase for s in states],
        [s.centre[2] for s in states],
        [s.roll for s in states],
        [s.pitch for s in states],
        torque,
        units=run.units,
        xlabel="phase (deg)",
        title=(
            f"{_name(spec)}: {what} from roll {run.held_roll:g}, pitch "
            f"{run.held_pitch:g}, phase {run.start_phase:g} deg - {outcome}\n"
            f"F {p['force']:g} N, k {k['roll']:g}/{k['pitch']:g} N m/rad, "
            f"mu {p['friction']:g}, work {run.work:.4g} mJ"
        ),
        marks=[Mark(e.phase, e.kind == marked) for e in run.events],
        labels=[_event_label(e, e.kind == marked, run.units) for e in run.events],
    )
    return save_figure(fig, path, fmt)


def _event_label(e: SearchEvent, bold: bool, units: str) -> EventLabel:
    """An event's label (the marked kind in bold red, with its click)."""
    if bold:
        style = {"fontsize": "small", "fontweight": "bold", "color": "#d62728"}
        return EventLabel(e.phase, f"{e.kind}: click {e.click:.4g} {units}", style)
    return EventLabel(e.phase, e.kind, {"fontsize": "x-small", "color": "0.35"})
