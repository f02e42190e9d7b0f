"""``run_pipeline``: library -> network -> recommendation -> GraphML, figures, report.

Layout of the output folder::

    DIR/library/            the mechanics library (Parquet dataset, resumable); with
                            several compliances, DIR/library-F<force>-k<stiffness>/ each
    DIR/network.graphml     the contact-state network (of the first compliance)
    DIR/network.json        the same graph as node-link JSON
    DIR/starts.csv          every start's passive outcome (snap, turn, work, click, ...),
                            each column named with its unit (turn_deg, work_mJ, ...)
    DIR/recommendation.json the SRCC recommendation
    DIR/sensor.json         the snap a sensor can detect, per compliance (threadmate sensor)
    DIR/program.json        what to program on the controller, for the first compliance
                            (threadmate program)
    DIR/figures/            recommendation, click signature, click against tilt, class
                            map and strips, region combinations, planar figures
    DIR/report.md           the report, figures embedded
    DIR/report.html         the report as one interactive page, each start linked to
                            its search's page
    DIR/views/              the search's page (and JSON) of the start the click
                            signature shows (threadmate view DIR --start adds others)
"""

from __future__ import annotations

import concurrent.futures as cf
import math
import multiprocessing
import os
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Generic, TypeVar

from .._io import atomic_write_text, remove_stale_temporaries
from .._json import json_text
from .._system import cpu_count
from .._text import number_text
from .._units import json_units
from .._validate import check_roll_spread
from .._version import __version__
from ..contact import (
    CONTINUATION_STEP,
    PHASE_TOLERANCE,
    UNSTABLE,
    Compliance,
    Mechanics,
    SearchResult,
    contact_scene,
    plot_search,
    search,
)
from ..design import (
    Envelope,
    SnapDetection,
    controller_program,
    format_controller_program,
    format_snap_detection,
    grid_envelope,
    plot_envelope,
    plot_snap_detection,
    snap_detection,
)
from ..geometry import ThreadSpec
from ..library import Grid, info, load, sweep, write_figures
from ..network import (
    WEIGHT_FORMULA,
    Recommendation,
    build_network,
    format_recommendation,
    from_library,
    least_resistance_path,
    plot_click_signature,
    plot_click_vs_tilt,
    plot_recommendation,
    recommend,
    start_outcomes,
    start_outcomes_csv,
    write_graphml,
    write_node_link,
    write_recommendation,
)
from ..planar import plot_pivot_axes, plot_region_disk
from ..view import start_page_name, write_run_page, write_start_views
from ._defaults import RUN_GRID
from ._folder import check_run_folder

__all__ = ["RunResult", "run_pipeline"]

_T = TypeVar("_T")


@dataclass(frozen=True)
class RunResult:
    """What :func:`run_pipeline` wrote, and the headline figures."""

    out: Path
    libraries: list[Path]
    graphml: Path
    node_link: Path
    starts: Path
    recommendation: Path
    report: Path
    figures: dict[str, Path] = field(default_factory=dict)
    counts: dict[str, int] = field(default_factory=dict)
    recommended: dict[str, Any] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    #: The meshes used (the library metadata's ``mesh`` entry: chord, and per body a CAD
    #: mesh's file, SHA-256, units, deviation and off-spec shares, or None: generated).
    meshes: dict[str, Any] = field(default_factory=dict)
    #: ``report.html`` and the start pages written into ``views/``.
    pages: list[Path] = field(default_factory=list)
    #: ``envelope.json`` (when the grid holds a misalignment), ``sensor.json`` and
    #: ``program.json``: the design stage's documents.
    design: dict[str, Path] = field(default_factory=dict)
    #: The most tolerant compliance's envelope read off the grid (``tilt``,
    #: ``worst_directions``, ``first_failure``, ``force``, ``stiffness``), or None.
    tolerated: dict[str, Any] | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready mapping of paths and figures (``threadmate run --json``)."""
        return {
            "units": json_units(
                self.recommended.get("units", ""), "angle", "work", "torque", "force", "stiffness"
            ),
            "out": str(self.out),
            "libraries": [str(p) for p in self.libraries],
            "graphml": str(self.graphml),
            "node_link": str(self.node_link),
            "starts": str(self.starts),
            "recommendation": str(self.recommendation),
            "report": str(self.report),
            "pages": [str(p) for p in self.pages],
            "figures": {k: str(v) for k, v in self.figures.items()},
            "counts": self.counts,
            "recommended": self.recommended,
            "notes": self.notes,
            "mesh": self.meshes,
            "design": {k: str(v) for k, v in self.design.items()},
            "tolerated": self.tolerated,
        }


def _library_dir(out: Path, compliance: Compliance, many: bool) -> Path:
    if not many:
        return out / "library"
    k = compliance.stiffness
    return out / f"library-F{compliance.force:g}-k{k[0]:g}-{k[1]:g}"  # type: ignore[index]


def run_pipeline(
    spec: ThreadSpec,
    out: str | os.PathLike[str],
    *,
    roll: Any = None,
    pitch: Any = None,
    phase: Any = None,
    compliances: Sequence[Compliance] | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    chord: float | None = None,
    roll_spread: float | None = None,
    step: float = CONTINUATION_STEP,
    progress: Callable[[int, int], None] | None = None,
    bolt_mesh: str | os.PathLike[str] | None = None,
    nut_mesh: str | os.PathLike[str] | None = None,
    mesh_units: str | None = None,
    clockwise: bool = False,
    max_starts: int | None = None,
    max_faces: int | None = None,
) -> RunResult:
    """Run the whole pipeline into ``out`` (see the module docstring for the layout).

    Each library is resumed (or reused when complete); a library for another spec, grid or
    compliance is refused by the sweep stage, never mixed. Grid arguments default to
    :data:`RUN_GRID`; ``compliances`` to the default :class:`Compliance` (give several to
    compare stiffnesses or forces: one library each, one recommendation over all).
    ``bolt_mesh``, ``nut_mesh`` and ``mesh_units``: meshes from CAD for the sweep (see
    :func:`threadmate.library.sweep`); the report names them. ``clockwise``: also turn
    every start clockwise directly (the sweep's ``clockwise``); the report gives the share
    that engages against the held tilt. ``max_starts`` and ``max_faces``: the sweep's limits
    on the grid's starts and on a CAD mesh's triangles. ``roll_spread``: as
    :func:`threadmate.network.recommend`'s, checked before anything is swept.

    ``out`` must be missing, empty or a previous run's folder (:func:`check_run_folder`).
    """
    check_roll_spread(roll_spread)
    out = check_run_folder(out)
    for folder in (out, out / "figures", out / "views"):
        remove_stale_temporaries(folder)  # left by a run killed while writing
    grid = {
        "roll": RUN_GRID["roll"] if roll is None else roll,
        "pitch": RUN_GRID["pitch"] if pitch is None else pitch,
        "phase": RUN_GRID["phase"] if phase is None else phase,
    }
    compliances = list(compliances or [Compliance()])
    libs = [_library_dir(out, c, len(compliances) > 1) for c in compliances]
    for comp, lib in zip(compliances, libs, strict=True):
        sweep(
            spec,
            grid["roll"],
            grid["pitch"],
            grid["phase"],
            out=lib,
            workers=workers,
            scheduler=scheduler,
            chord=chord,
            compliance=comp,
            step=step,
            progress=progress,
            bolt_mesh=bolt_mesh,
            nut_mesh=nut_mesh,
            mesh_units=mesh_units,
            clockwise=clockwise,
            max_starts=max_starts,
            max_faces=max_faces,
        )
    graphs = [from_library(lib) for lib in libs]
    graph = graphs[0]
    rec = recommend(graphs, roll_spread)
    outcomes = start_outcomes(graph)
    # The files carry each state's rotation and contact points and normals from the library.
    graphml = write_graphml(graph, out / "network.graphml", library=libs[0])
    node_link = write_node_link(graph, out / "network.json", library=libs[0])
    starts_csv = start_outcomes_csv(outcomes, out / "starts.csv", spec.units)
    rec_path = write_recommendation(rec, out / "recommendation.json")

    figdir = out / "figures"
    figures: dict[str, Path] = {}
    figures["recommendation"] = plot_recommendation(rec, figdir / "recommendation.png")
    signature = _click_signature_start(outcomes, rec)
    pages: list[Path] = []
    traced: SearchResult | None = None
    failed = ""  # why the signature's search failed, if it did
    signature_search = None
    if signature is not None:
        figures["click_signature"] = figdir / "click-signature.png"  # (drawn below)
        # The search itself from that start, at its own resolution (every step, both sides
        # of each event), on the library's mechanics; the library holds grid phases only.
        # It runs beside the design stage below, which needs none of it.
        scene = {
            "chord": chord,
            "bolt_mesh": bolt_mesh,
            "nut_mesh": nut_mesh,
            "mesh_units": mesh_units,
            "max_faces": max_faces,
        }
        signature_search = _Beside(
            workers,
            _signature_search,
            spec,
            compliances[0],
            scene,
            signature,
            step,
            figures["click_signature"],
            out / "views",
        )
    figures["click_vs_tilt"] = plot_click_vs_tilt(
        outcomes, figdir / "click-vs-tilt.png", spec.units
    )
    lib_info = info(libs[0])
    run_grid = Grid.from_dict(lib_info["metadata"]["grid"])
    # The design stage, from the libraries' rows alone (no new search): the snap a sensor
    # sees per compliance, and the controller's program for the first.
    # One library's rows in memory at a time (they hold the contact forces the lateral
    # force needs, which the network leaves in the library).
    detections = [snap_detection(g, load(lib)) for g, lib in zip(graphs, libs, strict=True)]
    figures["snap_detection"] = plot_snap_detection(detections, figdir / "snap-detection.png")
    # What each compliance tolerates, read off its library's grid (no new search); a grid
    # of the upright bolt alone has no direction to read.
    lead_text = ""
    design_files: dict[str, Path] = {}
    if any(r or p for r, p in run_grid.held_tilts):
        envelopes = [grid_envelope(lib) for lib in libs]
        lead = _most_tolerant(envelopes)
        figures["envelope"] = plot_envelope(envelopes[lead], figdir / "envelope.png")
        lead_text = _lead_section(envelopes, lead, detections[lead], spec)
        design_files["envelope"] = atomic_write_text(
            out / "envelope.json",
            json_text(
                {
                    "units": envelopes[lead].to_dict()["units"],
                    "most_tolerant": lead,
                    "settings": [
                        {"library": str(lib), **e.to_dict()}
                        for lib, e in zip(libs, envelopes, strict=True)
                    ],
                }
            ),
        )
    program = controller_program(build_network(load(libs[0]), active=True), detections[0])
    design_files |= {
        "sensor": atomic_write_text(
            out / "sensor.json",
            json_text(
                {
                    "units": detections[0].to_dict()["units"],
                    "settings": [
                        {"library": str(lib), **d.to_dict()}
                        for lib, d in zip(libs, detections, strict=True)
                    ],
                }
            ),
        ),
        "program": atomic_write_text(
            out / "program.json", json_text({"library": str(libs[0]), **program.to_dict()})
        ),
    }
    map_phase = _telling_phase(outcomes)
    figures.update(
        {
            f"library_{k}": Path(v)
            for k, v in write_figures(libs[0], figdir, phase=map_phase[0]).items()
        }
    )
    figures["region_disk"] = plot_region_disk(spec, figdir / "planar-region-disk.png")
    figures["pivot_axes"] = plot_pivot_axes(spec, figdir / "planar-pivot-axes.png")
    if signature_search is not None:
        assert signature is not None
        traced, failed, page = signature_search.result()
        if page is not None:
            pages.append(page)
        if traced is None:
            path = least_resistance_path(graph, *signature)
            plot_click_signature(graph, path, figures["click_signature"])

    meshes = dict(lib_info["metadata"].get("mesh") or {})
    counts = {f"starts {k}": v for k, v in lib_info["classifications"].items()}
    counts.update({f"states {k}": v for k, v in lib_info["states"].get("by_class", {}).items()})
    report = _report(
        spec,
        compliances,
        run_grid,
        step,
        rec,
        outcomes,
        counts,
        signature,
        figures,
        out,
        meshes,
        map_phase,
        traced or failed,
        _design_sections(detections, program, len(compliances) > 1),
        lead_text,
    )
    if clockwise:
        report += "\n" + _clockwise_section(load(libs[0]))
    report_path = atomic_write_text(out / "report.md", report)
    pages.insert(0, write_run_page(out))
    recommended = dict(rec.best, units=spec.units)
    return RunResult(
        out,
        libs,
        graphml,
        node_link,
        starts_csv,
        rec_path,
        report_path,
        figures,
        counts,
        recommended,
        rec.notes,
        meshes,
        pages,
        design_files,
        _tolerated(envelopes[lead]) if lead_text else None,
    )


def _signature_search(
    spec: ThreadSpec,
    compliance: Compliance,
    scene: dict[str, Any],
    signature: tuple[float, float, float],
    step: float,
    figure: Path,
    views: Path,
) -> tuple[SearchResult | None, str, Path | None]:
    """The search from the click signature's start, its figure and its page: the search
    (None where it failed), why it failed, the page."""
    mech = Mechanics(spec, compliance, scene=contact_scene(spec, **scene))
    try:
        traced = search(mech, *signature, step=step)
    except Exception as exc:  # noqa: BLE001 - the library's path stands in for it
        return None, f"{type(exc).__name__}: {exc}", None
    plot_search(traced, figure, spec=spec)
    doc = {**traced.to_dict(), "mesh": mech.scene.mesh_info, "spec": spec.to_dict()}
    return traced, "", write_start_views(views, doc, spec)


class _Beside(Generic[_T]):
    """``fn(*args)`` in a process forked from this one, while this one goes on; in this
    process at once where there is no core to spare (one worker asked for, or one CPU),
    processes are not forked here (they would import and build everything anew) or this
    process has run a Dask client (a fork copies its threads' locks, held or not).
    :meth:`result` waits for it; the forked process ends with it."""

    def __init__(self, workers: int | None, fn: Callable[..., _T], *args: Any) -> None:
        self._pool: cf.ProcessPoolExecutor | None = None
        if (
            (workers or cpu_count()) > 1
            and multiprocessing.get_start_method() == "fork"
            and "distributed" not in sys.modules
        ):
            self._pool = cf.ProcessPoolExecutor(1, mp_context=multiprocessing.get_context())
            self._future = self._pool.submit(fn, *args)
        else:
            self._value = fn(*args)

    def result(self) -> _T:
        if self._pool is None:
            return self._value
        try:
            return self._future.result()
        finally:
            self._pool.shutdown(wait=True, cancel_futures=True)


def _tolerated(env: Envelope) -> dict[str, Any]:
    """The headline of an envelope read off a grid: what ``run --json`` gives."""
    t = env.tolerated["100%"]
    fails = [
        x["first_failure"]["100%"]
        for x in env.directions
        if x["direction"] in t["worst_directions"] and x["first_failure"]["100%"]
    ]
    return {
        "tilt": t["tilt"],
        "worst_directions": t["worst_directions"],
        "first_failure": min(fails) if fails else None,
        "located": env.located,
        "force": env.compliance["force"],
        "stiffness": env.compliance["stiffness"],
    }


def _most_tolerant(envelopes: list[Envelope]) -> int:
    """The compliance that tolerates the most misalignment (then the least mean turn to
    the snap, work and peak torque inside it)."""

    def rank(i: int) -> tuple[float, ...]:
        inside = envelopes[i].inside
        return (
            -envelopes[i].tolerated_tilt,
            *(math.inf if inside[k] is None else inside[k] for k in _TIES),
        )

    return min(range(len(envelopes)), key=rank)


_TIES = ("turn_mean", "work_mean", "torque_peak")


def _lead_section(
    envelopes: list[Envelope], lead: int, detection: SnapDetection, spec: ThreadSpec
) -> str:
    """The report's first section: what to buy and set, and what it tolerates."""
    env = envelopes[lead]
    c = env.compliance
    u = spec.units
    k = c["stiffness"]
    stiffness = f"{k['roll']:g}" if k["roll"] == k["pitch"] else f"{k['roll']:g}/{k['pitch']:g}"
    t = env.tolerated["100%"]
    worst = [x for x in env.directions if x["direction"] in t["worst_directions"]]
    fails = [x["first_failure"]["100%"] for x in worst if x["first_failure"]["100%"]]
    if t["tilt"] > 0:
        tolerates = (
            f"every start phase snaps within one turn up to **{t['tilt']:.2f} deg** of "
            f"misalignment in each of the {len(env.directions)} directions the grid holds"
        )
    else:
        tolerates = (
            "every start phase snaps within one turn when upright, **but not at the "
            "smallest misalignment the grid holds** in the worst direction(s)"
        )
    if fails:
        where = ", ".join(
            f"{x['direction']:g}" for x in worst if x["first_failure"]["100%"] == min(fails)
        )
        bound = (
            f"; toward {where} deg the grid's next size, {min(fails):.2f} deg, already "
            "fails, so the misalignment tolerated in every direction is less than that"
        )
    else:
        bound = "; every size the grid holds passes there, so the envelope lies beyond it"
    inside = env.inside
    lines = [
        "## What to buy and set",
        "",
        f"- **F = {c['force']:g} N, k = {stiffness} N m/rad, held upright**: {tolerates}{bound}.",
    ]
    if inside["snapped"]:
        lines.append(
            f"- {'Inside it' if t['tilt'] > 0 else 'Upright'} the bolt snaps within "
            f"{inside['turn_worst']:.0f} deg of turn (mean "
            f"{inside['turn_mean']:.0f} deg), for {inside['work_mean']:.3g} mJ of driver work "
            f"on average and a peak torque of {number_text(inside['torque_peak'], '.3g')} N m."
        )
    click = detection.signals.get("click")
    if click is not None and click.separates and click.threshold is not None:
        lines.append(
            f"- Detect the snap by a drop of at least {click.threshold:.4g} {u} within a "
            "degree of turn: every snap of these searches falls further, every other jump "
            'less ("The snap a sensor sees").'
        )
    elif inside["click_min"] is not None:
        lines.append(
            f"- The snap drops the compliance centre by {inside['click_min']:.4g} {u} or "
            f"more {'inside it' if t['tilt'] > 0 else 'upright'}, but no drop threshold "
            'tells it from the other jumps of these searches ("The snap a sensor sees" '
            'and "What to program" below).'
        )
    if len(envelopes) > 1:
        lines.append(
            f"- Of the {len(envelopes)} compliances compared, this one tolerates the most; "
            "the others: "
            + "; ".join(
                f"{e.compliance['force']:g} N, {e.compliance['stiffness']['roll']:g} N m/rad: "
                f"{e.tolerated_tilt:.2f} deg"
                for i, e in enumerate(envelopes)
                if i != lead
            )
            + "."
        )
    lines += [
        "- Read off the run's grid, not located: the directions between the grid's are not "
        "computed, nor the sizes between its steps. `threadmate envelope SPEC --force "
        f"{c['force']:g} --stiffness {stiffness}` locates the envelope in every direction "
        "(docs/design.md), and `threadmate design` finds the compliance that tolerates the "
        "most.",
        "",
        "![envelope](figures/envelope.png)",
        "",
        "*The misalignment every start phase (solid), 95 % and 50 % of them tolerate, by "
        "direction (the azimuth toward which the bolt leans, from the nut's +X toward +Y, "
        "relative to its thread start), read off the grid.*",
        "",
    ]
    return "\n".join(lines) + "\n"


def _design_sections(detections: list[Any], program: Any, many: bool) -> str:
    """The report's sections on the snap a sensor sees (per compliance) and on what to
    program on the controller (the first compliance)."""
    lines = [
        "## The snap a sensor sees",
        "",
        "A snap is only useful if a sensor can tell it from the other jumps of a search. "
        "For every start's search: its snap's click (the fall of the compliance centre "
        "within the last degree of turn) against the largest drop of any other jump in the "
        "same search (the bolt tipping off the bore's edge or a crest, or landing in phase "
        "and jamming), and the same for the change of the tilt spring's moment and of the "
        "driver's torque. A threshold separates them when the largest other jump lies below "
        "the smallest snap; it is then the midpoint of the gap (docs/design.md). "
        "`sensor.json` holds the numbers; `threadmate sensor DIR/library` recomputes them.",
        "",
    ]
    for det in detections:
        if many:
            c = det.compliance
            lines += [
                f"### {c['force']:g} N, {c['stiffness']['roll']:g}/"
                f"{c['stiffness']['pitch']:g} N m/rad",
                "",
            ]
        lines += [format_snap_detection(det).rstrip(), ""]
    lines += [
        "![snap detection](figures/snap-detection.png)",
        "",
        "*Snap clicks and each search's largest other jump, with the threshold (solid: it "
        "separates; dashed: the best where none does).*",
        "",
        "## What to program",
        "",
        "For the compliance "
        + ("of the first library " if many else "")
        + "(`program.json`; `threadmate program DIR/library`), each figure derived from "
        "the library and said how:",
        "",
        format_controller_program(program).rstrip(),
        "",
    ]
    return "\n".join(lines) + "\n"


def _clockwise_section(rows: Any) -> str:
    """The report's section on clockwise starts: the share of starts that engage when
    turned clockwise directly, by held tilt (the thesis's clockwise question)."""
    starts = rows[(rows["role"] == "start") & (rows["clockwise"] != "")]
    lines = [
        "## Clockwise starts",
        "",
        "Every start turned clockwise (tightening) directly, without a search first: "
        "*engaged* when it then descends at the lead, *jammed* when no rest state continues "
        "the turn or the torque passes its limit, *riding* otherwise (docs/mechanics.md, "
        "Clockwise starts). Share of the start phases that engage, by held tilt:",
        "",
    ]
    if starts.empty:
        return "\n".join([*lines, "No start was turned clockwise."]) + "\n"
    rolls = sorted(starts["held_roll"].unique())
    lines += [
        "| held pitch \\ roll deg | " + " | ".join(f"{r:+g}" for r in rolls) + " |",
        "|---" * (len(rolls) + 1) + "|",
    ]
    for p in sorted(starts["held_pitch"].unique(), reverse=True):
        cells = []
        for r in rolls:
            here = starts[(starts["held_pitch"] == p) & (starts["held_roll"] == r)]
            share = (here["clockwise"] == "engaged").mean() if len(here) else math.nan
            cells.append("-" if math.isnan(share) else f"{100 * share:.0f}%")
        lines.append(f"| {p:+g} | " + " | ".join(cells) + " |")
    by = starts["clockwise"].value_counts()
    lines += [
        "",
        "Starts: "
        + ", ".join(f"{k} {int(by.get(k, 0))}" for k in ("engaged", "riding", "jammed"))
        + ".",
    ]
    return "\n".join(lines) + "\n"


def _not_at_rest(outcomes: Any) -> Any:
    """The starts whose descent did not reach a rest state (class unstable: it did not
    converge), failed ones aside."""
    return outcomes[~outcomes["failed"] & (outcomes["classification"] == UNSTABLE)]


def _not_at_rest_line(unsettled: Any) -> str:
    """The report's line on the starts that did not reach a rest state, shown apart."""
    n = len(unsettled)
    if n == 0:
        return "0 starts did not reach a rest state: every start's descent converged."
    shown = ", ".join(
        f"({r:g}, {p:g}, {ph:g})"
        for r, p, ph in zip(
            unsettled["held_roll"].iloc[:20],
            unsettled["held_pitch"].iloc[:20],
            unsettled["phase"].iloc[:20],
            strict=True,
        )
    ) + (f" and {n - 20} more (starts.csv: class unstable)" if n > 20 else "")
    return (
        f"**{n} start{'s' if n != 1 else ''} did not reach a rest state**: the descent "
        "stopped short of the balance (it did not converge), so the state it left is not "
        "at rest and the search from it is not a start's. They are left out of the ranking "
        "and its figures (the snap share counts the starts at rest) and drawn red, "
        f"*unstable*, in the class map and strips. Held roll, pitch, phase (deg): {shown}; "
        "`threadmate settle` on one says how far its descent got."
    )


def _count_name(key: str) -> str:
    """A count of the library's by-class tally as the report names it."""
    return f"starts not at rest ({UNSTABLE})" if key == f"starts {UNSTABLE}" else key


def _telling_phase(outcomes: Any) -> tuple[float, int, int]:
    """The start phase whose class map says most: where the classes of the held tilts
    are most mixed (largest Shannon entropy of their shares; the first such phase).

    Returns ``(phase, classes at that phase, classes over every phase)``.
    """
    best: tuple[float, float, int] | None = None
    for phase, rows in outcomes.groupby("phase", sort=True):
        shares = rows["classification"].value_counts(normalize=True)
        entropy = -float(sum(q * math.log(q) for q in shares))
        if best is None or entropy > best[1] + 1e-12:
            best = (float(phase), entropy, len(shares))
    if best is None:
        return (0.0, 0, 0)
    return best[0], best[2], int(outcomes["classification"].nunique())


def _map_caption(map_phase: tuple[float, int, int] | None) -> str:
    """The class map's caption: which start phase it shows and why."""
    head = "Class of the rest state each start reaches, over the held tilts"
    if map_phase is None:
        return head + "."
    phase, here, overall = map_phase
    head += f", at start phase {phase:g} deg"
    if overall <= 1:
        return f"{head}: every start at every phase reaches the same class."
    if here <= 1:
        return (
            f"{head}: at each start phase every held tilt reaches the same class; the "
            "strips below show how it changes with the phase."
        )
    return (
        f"{head}, the start phase where the classes of the held tilts differ most ({here} "
        "classes); the strips below give every phase."
    )


def _planar_note(spec: ThreadSpec) -> str:
    """What the planar figures leave out: they take flat ends, whatever the parts have."""
    ends = []
    if spec.bolt.point.form != "flat":
        ends.append(f"a bolt point {spec.bolt.point.describe(spec.units)}")
    if spec.nut.countersink is not None:
        ends.append(f"a nut countersink {spec.nut.countersink.describe(spec.units)}")
    if not ends:
        return ""
    return (
        " It takes flat ends (a flat bolt tip on the nut's flat, sharp-edged bore, the "
        f"thesis's bodies), while the parts analysed above have {' and '.join(ends)}: read it "
        "for the thread's geometry over a turn, not for these parts' contacts."
    )


def _click_signature_start(outcomes: Any, rec: Recommendation) -> tuple[float, float, float] | None:
    """A start of the recommended setting whose search snaps, with the median turn (the
    figure then shows a typical search); the smallest held roll preferred."""
    best = rec.best
    rows = outcomes[
        (outcomes["held_pitch"] == best["held_pitch"])
        & outcomes["snapped"]
        & (outcomes["turn"] > 0)
        & (outcomes["classification"] != UNSTABLE)  # a start at rest
    ]
    if rows.empty:
        return None
    rows = rows[rows["held_roll"].abs() == rows["held_roll"].abs().min()]
    row = rows.iloc[(rows["turn"] - rows["turn"].median()).abs().argsort().iloc[0]]
    return float(row["held_roll"]), float(row["held_pitch"]), float(row["phase"])


def _signature_caption(
    signature: tuple[float, float, float] | None, traced: SearchResult | str, step: float, u: str
) -> str:
    """The click signature's caption: which search, at what resolution, and its page."""
    head = (
        "The click signature a force/torque sensor would see: height of the compliance "
        "centre, tilt and driver torque against phase along the search from "
    )
    if signature is None:
        return head + "a start."
    head += f"held roll {signature[0]:g}, pitch {signature[1]:g}, phase {signature[2]:g} deg"
    if isinstance(traced, str):
        return (
            f"{head}, drawn from the library's states (grid phases and both sides of each "
            f"jump): the search itself failed ({traced}); the snap in red."
        )
    events = len(traced.events)
    name = start_page_name(*signature)
    snap = (
        "no snap within the turn"
        if traced.snap is None
        else f"the snap at {traced.snap.phase:.2f} deg in bold red, its click "
        f"{traced.snap.click:.4g} {u}"
    )
    return (
        f"{head}, at the search's own resolution: its {len(traced.states)} states, every "
        f"{step:g} deg step and both sides of each of its {events} event"
        f"{'s' if events != 1 else ''}; {snap}. Interactive: views/{name}.html "
        "(or report.html)."
    )


def _lean(pitch: float) -> str:
    """Where a held pitch leans the bolt's head, in the nut's frame (conventions.md)."""
    if pitch == 0:
        return "upright about Y (no pre-tilt)"
    side = "+X" if pitch > 0 else "-X"
    return (
        f"{abs(pitch):g} deg about the nut's Y axis, right-handed sign {pitch:+g}: the "
        f"bolt's head leans toward {side} of the nut's frame"
    )


def _lead(value: float | None, scale: float, ahead: str, behind: str) -> str:
    """A lead over the next setting in words (``value`` > 0: the pick is ahead)."""
    if value is None:
        return "not comparable"
    if not behind:
        return f"{scale * value:.0f} {ahead}"
    return f"{abs(value):.3g} {ahead if value >= 0 else behind}"


def _meshes_line(meshes: dict[str, Any], u: str) -> str:
    """Which meshes the library was swept on: generated (chord), or files from CAD."""
    chord = meshes.get("chord")
    words = []
    for kind in ("bolt", "nut"):
        part = meshes.get(kind)
        if not isinstance(part, dict):
            words.append(f"{kind} generated" + (f" (chord {chord:g} {u})" if chord else ""))
            continue
        facts = [f"SHA-256 `{str(part.get('sha256'))[:16]}`", f"units {part.get('units')}"]
        if part.get("units") not in (None, u):
            facts.append(f"scaled into {u}")
        if part.get("deviation") is not None:
            facts.append(f"deviation from the spec {part['deviation']:.3g} {u}")
        if part.get("zone_off_spec_share") is not None:
            facts.append(f"{part['zone_off_spec_share']:.0%} of its contact zone off the spec")
        words.append(f"{kind} from CAD `{part.get('file')}` ({', '.join(facts)})")
    line = "- Meshes: " + "; ".join(words) + "."
    if any(isinstance(meshes.get(k), dict) for k in ("bolt", "nut")):
        line += (
            " Regions and normals come from the spec's exact bodies; contacts where a CAD "
            "mesh leaves the spec are labelled point, countersink or other."
        )
    return line


def _report(
    spec: ThreadSpec,
    compliances: list[Compliance],
    grid: Grid,
    step: float,
    rec: Recommendation,
    outcomes: Any,
    counts: dict[str, int],
    signature: tuple[float, float, float] | None,
    figures: dict[str, Path],
    out: Path,
    meshes: dict[str, Any] | None = None,
    map_phase: tuple[float, int, int] | None = None,
    traced: SearchResult | str = "",
    design: str = "",
    lead: str = "",
) -> str:
    name = spec.designation or "custom spec"
    u = spec.units
    best = rec.best
    unsettled = _not_at_rest(outcomes)
    ok = outcomes[~outcomes["failed"] & ~outcomes["node"].isin(unsettled["node"])]
    lines = [
        f"# threadmate run: {name}",
        "",
        f"threadmate {__version__}. Lengths in {u}, angles in degrees, forces in N, "
        "stiffness in N m/rad, torques in N m, work in mJ. Frames, poses and regions follow "
        "the conventions (docs/conventions.md); the physical model is docs/mechanics.md.",
        "",
        *([lead] if lead else []),
        *([design] if design else []),
        "## The pre-tilt, where the nut's azimuth is known",
        "",
        "A pre-tilt helps only a robot that knows where the nut's thread starts (the held "
        "pitch is about the nut's Y axis, fixed by that start); the ranking of every "
        "setting is further down.",
        "",
        f"- **Pre-tilt (held pitch): {best['held_pitch']:+g} deg**, that is "
        f"{_lean(best['held_pitch'])}.",
        f"- With it, {best['share_snap']:.0%} of the starts with a roll error within "
        f"+/-{rec.roll_spread:g} deg (every start phase) snap within one counter-clockwise "
        f"turn, after {number_text(best['turn_mean'], '.0f')} deg on average "
        f"(worst {number_text(best['turn_worst'], '.0f')} deg), for "
        f"{number_text(best['work_mean'], '.3g')} mJ of driver work on average (worst "
        f"{number_text(best['work_worst'], '.3g')} mJ) and a peak torque of "
        f"{number_text(best['torque_peak'], '.3g')} N m. The click to listen for: a fall of "
        f"{number_text(best['click_mean'], '.4g')} {u} within a degree of turn.",
    ]
    snaps = outcomes[outcomes["snapped"] & (outcomes["turn"] > 0)]
    windows = snaps[snaps["snap_window"] > 0]
    if len(windows):
        lines.append(
            f"- {len(windows)} of the {len(snaps)} snaps (every setting) are windows: the "
            "snap may come up to "
            f"{float(windows['snap_window'].max()):.1f} deg before the phase given "
            f"(median {float(windows['snap_window'].median()):.1f} deg), where the branch "
            'before it is a shallow basin (docs/mechanics.md, "The snap\'s window").'
        )
    if rec.margin is not None:
        m, nxt = rec.margin, rec.settings[1]
        lines.append(
            f"- Margin over the next setting (held pitch {nxt['held_pitch']:+g} deg"
            + (
                f", {nxt['force']:g} N, {nxt['stiffness'][0]:g} N m/rad"
                if len(compliances) > 1
                else ""
            )
            + "): "
            + _lead(m["share_snap"], 100, "percentage points more starts snap", "")
            + "; "
            + _lead(m["turn_mean"], 1, "deg less mean turn", "deg more mean turn")
            + "; "
            + _lead(m["work_mean"], 1, "mJ less mean work", "mJ more mean work")
            + "."
        )
    if rec.azimuth_proof:
        p = rec.azimuth_proof[0]
        lines.append(
            f"- **Whatever the nut's thread-start azimuth** (worst of the four quarter-turn "
            f"directions): a pre-tilt of {p['tilt_size']:g} deg, worst direction "
            f"{p['worst_direction']}, {p['share_snap']:.0%} snap within one turn, mean turn "
            f"{number_text(p['turn_mean'], '.0f')} deg. Use this when the robot does not know "
            "where the nut's thread starts; the pick above assumes it does (the pre-tilt "
            "about the nut's Y axis as the conventions fix it)."
        )
    lines += [f"- Note: {note}." for note in rec.notes]
    lines += [
        "",
        "## What was computed",
        "",
        f"- Thread: {name}; pitch {spec.pitch:g} {u}, handedness "
        f"{'right' if spec.handedness > 0 else 'left'}.",
        f"- Parts: bolt point {spec.bolt.point.describe(u)}, bolt length "
        f"{spec.bolt.length:g} {u}; nut countersink "
        + (spec.nut.countersink.describe(u) if spec.nut.countersink else "none (flat bore)")
        + f", nut height {spec.nut.height:g} {u}.",
        _meshes_line(meshes or {}, u),
        "- Compliance"
        + (f" ({len(compliances)} settings compared)" if len(compliances) > 1 else "")
        + ": "
        + "; ".join(c.describe(u) for c in compliances)
        + ".",
        f"- Grid: {grid.describe()}. Every configuration is a start: the bolt is dropped "
        "there, settles to a rest state, and is turned counter-clockwise (the unscrewing "
        f"sense) in quasi-static continuation (steps of {step:g} deg, events located to "
        f"{PHASE_TOLERANCE:g} deg) until it snaps into the thread.",
        f"- Work: {WEIGHT_FORMULA}.",
        "",
        "## Reading the results",
        "",
        "- **stable**: a rest state the contacts hold by themselves (a strict minimum of the "
        "potential even without the compliance's stiffness).",
        "- **quasi-stable**: a rest state that needs the compliance to hold.",
        "- **unstable**: a contact state that is not at rest (first contact, a contact on "
        "the way, a state the bolt leaves by a jump).",
        "- **in-phase**: engaged: every contact that carries the load lies on the helices, so "
        "that turning moves the bolt along the thread. A snap is a jump into such a state "
        "that then screws in: turned clockwise half a turn it descends at the lead. A landing "
        "in phase that jams when screwed in (a tilted bolt cross-threading) is not a snap.",
        "- A transition is *stable* when it stays on stable rest states, *quasi-stable* when "
        "it passes quasi-stable ones, *unstable* when it jumps or passes an unstable state "
        "(every snap is a jump).",
        "- Columns of the table: *share snap*, the share of starts that snap within one "
        "turn; *turn* and *work*, to the snap, over those that snap; *click*, the fall of "
        "the compliance centre a sensor sees at the snap, from the highest the bolt stands "
        "within the last degree of turn to the landing; *torque peak*, the largest driver torque; "
        "*share unstable*, starts whose search jumps or passes an unstable state before "
        "the snap. The starts of a held tilt share their search once their continuations "
        "join, so this share moves by many starts at once: one continuation step that "
        "does not balance (most often where the thread starts meet) marks every start "
        "whose search passes it, often most of a held tilt's. It is also the column the "
        "continuation's step moves most (docs/mechanics.md, Accuracy): read it as a "
        "warning, not a ranking.",
        "",
        "## Settings ranked",
        "",
        format_recommendation(rec).rstrip(),
        "",
        f"Starts: {len(outcomes)} ({int(outcomes['failed'].sum())} failed, "
        f"{len(unsettled)} not at rest); of those at rest, snap within one "
        f"turn: {int(ok['snapped'].sum())}; never within one turn: "
        f"{int((~ok['snapped']).sum())}; search passes an unstable transition: "
        f"{int(ok['passes_unstable'].sum())}. States by class: "
        + ", ".join(f"{_count_name(k)} {v}" for k, v in counts.items())
        + ".",
        "",
        _not_at_rest_line(unsettled),
        "",
        "## Figures",
        "",
    ]
    captions = {
        "recommendation": "Snap share and mean turn against the pre-tilt.",
        "click_signature": _signature_caption(signature, traced, step, u),
        "click_vs_tilt": "The click and the turn to the snap against the tilt's size.",
        "library_stability_map": _map_caption(map_phase),
        "library_phase_strips": "The same over every start phase (phase 0 to 360 deg left to "
        "right within each held tilt's strip); red: the descent did not reach a rest state.",
        "library_region_combinations": "Which regions touch at rest.",
        "region_disk": "The planar analysis: regions in contact against phase (upright)."
        + _planar_note(spec),
        "pivot_axes": "The planar analysis: pivot axes against phase." + _planar_note(spec),
    }
    for key, path in figures.items():
        if key in ("snap_detection", "envelope"):
            continue  # shown in their sections
        rel = path.relative_to(out).as_posix()
        lines += [f"![{key.replace('_', ' ')}]({rel})", "", f"*{captions.get(key, key)}*", ""]
    lines += [
        "## Files and where to look next",
        "",
        "- `report.html`: this report as one interactive page (open it in a browser; it "
        "needs no network): the settings ranked, the class map over the held tilts at any "
        "start phase, and every start linked to its search's page in `views/`; "
        "`threadmate view DIR --start R,P,PH` writes the page of any other start.",
        "- `library/`: every state (Parquet; `threadmate library info`), "
        "`network.graphml` / `network.json`: the network (open in yEd, Gephi or Cytoscape), "
        "`starts.csv`: every start's outcome, `recommendation.json`: the ranking.",
        "- A start of interest: `threadmate path DIR/library --roll R --pitch P --phase PH` "
        "(the passive search; add `--active` for plans that change the tilt), and "
        "`threadmate search` to recompute it finely with `--plot`.",
        "- Other compliances: `threadmate run ... --compare-stiffness 0.5,1,2` compares them; a "
        "pick at the edge of the grid calls for a wider `--pitch` range.",
    ]
    return "\n".join(lines) + "\n"
