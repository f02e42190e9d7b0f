"""``threadmate settle`` and ``threadmate search``: the mechanics of the compliance-held bolt.

``settle`` prints one rest state (docs/mechanics.md: a local minimum of the potential
under the axial force and the compliance's spring, with the contact forces that hold it);
``search`` simulates the counter-clockwise search from a start, its events and the snap.
Both are thin wrappers over :func:`threadmate.contact.settle` and
:func:`threadmate.contact.search`; their ``--json`` documents are the results' ``to_dict()``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from .._errors import InputError, NoPathError
from .._text import number_text
from .._validate import FIGURE_FORMATS, MAX_TILT, check_configuration
from ..contact import (
    CONTINUATION_STEP,
    MAX_SCREW_IN,
    MAX_STEP,
    MAX_TURNS,
    PHASE_TOLERANCE,
    SCREW_IN,
    TIGHTEN_STEP,
    UNSTABLE,
    Compliance,
    check_continuation,
    check_screw,
)
from ..geometry import SpecParts, check_chord
from ._common import (
    SPEC_HELP,
    echo_err,
    emit_json,
    resolve_spec,
    shown_phase,
    turn_words,
    writable_output,
)
from ._main import cli
from ._options import (
    DEFAULTS_NOTE,
    MeshFiles,
    chord_option,
    compliance_from_options,
    compliance_option_list,
    condition_option,
    echo_mesh_notes,
    mesh_files_option,
    mesh_summary,
    parts_option,
)
from ._progress import progress_bar

# The mechanics (scipy, trimesh, numba) and the figures (matplotlib) are imported where they
# are used, so that --help and a refused option answer at once.
if TYPE_CHECKING:
    from ..contact import Mechanics, RestState, ScrewResult, SearchEvent, SearchResult
    from ..geometry import ThreadSpec

__all__ = ["search_command", "settle_command", "screw_command"]


# -- options ---------------------------------------------------------------------------------
def _mechanics_options(func: Callable[..., Any]) -> Callable[..., Any]:
    """The configuration and the compliance's parameters, shared by both commands."""
    options: list[Callable[[Any], Any]] = [
        click.argument("spec_text", metavar="DESIGNATION|SPEC"),
        click.option(
            "--roll",
            type=float,
            required=True,
            help=f"Held tilt about fixed X in degrees (within +/-{MAX_TILT:g}).",
        ),
        click.option(
            "--pitch",
            type=float,
            required=True,
            help=f"Held tilt about fixed Y in degrees (within +/-{MAX_TILT:g}).",
        ),
        click.option(
            "--phase",
            type=float,
            required=True,
            help="Spin of the bolt about its axis in degrees (counter-clockwise seen from above).",
        ),
        *compliance_option_list(),
        chord_option,
        condition_option,
        parts_option,
        mesh_files_option,
        click.option(
            "--json",
            "as_json",
            is_flag=True,
            help="Print one JSON document on stdout instead of text.",
        ),
    ]
    for option in reversed(options):
        func = option(func)
    return func


def _setup(
    spec_text: str,
    roll: float,
    pitch: float,
    phase: float,
    force: float,
    stiffness_text: str,
    lateral_stiffness: float | None,
    friction: float,
    compliance_z: float,
    chord: float | None,
    condition: str,
    parts: SpecParts,
    meshes: MeshFiles,
) -> tuple[ThreadSpec, Mechanics]:
    """Check the options (cheapest first), then build the spec, the compliance and the
    mechanics on them.

    Every check runs before the meshes are built and before anything is written.
    """
    check_configuration(roll, pitch, phase)
    # The Compliance refuses non-finite or out-of-range values with a message naming them.
    compliance = compliance_from_options(
        force, stiffness_text, lateral_stiffness, friction, compliance_z
    )
    spec = resolve_spec(spec_text, condition, parts)
    check_chord(spec, chord)  # the meshes' own range, before any mesh is built
    compliance.check_for(spec.pitch)
    return spec, _mechanics(spec, compliance, chord, meshes)


def _mechanics(
    spec: ThreadSpec, compliance: Compliance, chord: float | None, meshes: MeshFiles
) -> Mechanics:
    """The mechanics on the generated meshes or the CAD meshes given (``--bolt-mesh``,
    ``--nut-mesh``: loaded and checked by the analyser; notes and warnings on stderr)."""
    from ..contact import Mechanics, contact_scene

    scene = contact_scene(spec, chord=chord, **meshes.arguments())
    echo_mesh_notes(scene.mesh_info, spec.units)
    return Mechanics(spec, compliance, scene=scene)


# -- text ------------------------------------------------------------------------------------
def _name(spec: ThreadSpec) -> str:
    return spec.designation or f"spec (pitch {spec.pitch:g} {spec.units})"


def _parameters(p: dict[str, Any], units: str) -> list[str]:
    return [f"Parameters: {Compliance.from_dict(p).describe(units)}"]


def _settle_text(spec: ThreadSpec, rest: RestState) -> str:
    u = rest.units
    s = rest.state
    touching = s.touching
    unsettled = _unsettled(rest)
    lines = [
        f"{_name(spec)}: {'rest state' if unsettled is None else 'NO rest state'} of the bolt "
        f"held at roll {rest.held_roll:g}, pitch {rest.held_pitch:g} deg, turned to phase "
        f"{rest.phase:g} deg (lengths in {u})",
        *_parameters(rest.parameters, u),
        f"Class: {s.classification}",
        ("Rest pose" if unsettled is None else f"Not a rest state ({unsettled}); where it stopped")
        + f": roll {s.roll:.4f}  pitch {s.pitch:.4f} deg;  origin "
        f"({s.origin[0]:.6f}, {s.origin[1]:.6f}, {s.origin[2]:.6f}) {u};  "
        f"compliance centre height {s.centre[2]:.6f} {u}",
        f"Contacts ({len(touching)} touching):",
    ]
    if touching:
        lines.append(
            f"  {'X':>10} {'Y':>10} {'Z':>10}  {'normal (nut -> bolt)':<26} "
            f"{'force N':>9}  bolt/nut"
        )
        for c in touching:
            p = " ".join(f"{v:10.6f}" for v in c.point)
            n = " ".join(f"{v:8.5f}" for v in c.normal)
            lines.append(f"  {p}  {n} {number_text(c.force, '9.4f'):>9}  {c.regions}")
    lines.append(
        f"Potential: {number_text(s.potential, '.6g')} mJ   driver torque: "
        f"{number_text(s.driver_torque, '.6g')} N m (friction part "
        f"{number_text(s.friction_torque, '.6g')} N m)"
    )
    b = rest.balance
    if "force" in b and "moment" in b:
        lines.append(
            f"Balance residuals (relative to the load): force {b['force']:.2g}, "
            f"moment {b['moment']:.2g}"
        )
    if "touching_gap" in b:
        lines.append(
            f"The balance counts the contacts within {b['touching_gap']:.2g} {u} of touching "
            "(the meshes' accuracy); their gaps:  "
            + "  ".join(f"{c.regions} {c.gap:.2g}" for c in touching)
        )
    if rest.path:
        lines.append(f"Path from first contact ({len(rest.path)} unstable state(s)):")
        lines.append(f"  {'kind':<14} {'turn deg':>9}  regions")
        for step in rest.path:
            lines.append(f"  {step.kind:<14} {step.turn:9.4f}  {step.region_combination or '-'}")
    else:
        lines.append("Path from first contact: none (the first contact is at rest)")
    return "\n".join(lines)


def _unsettled(rest: RestState) -> str | None:
    """Why ``rest`` is not a rest state (its descent did not converge), or None when it
    is one."""
    b = rest.balance
    if bool(b.get("converged", True)):
        return None
    force = float(rest.parameters.get("force", math.nan))
    res = b.get("force", math.nan)
    return (
        f"the descent did not converge: force residual {number_text(res * force, '.3g')} N "
        f"({number_text(res, '.2g')} of the load), moment residual "
        f"{number_text(b.get('moment'), '.2g')} of "
        f"the load times the major radius, after {rest.iterations} steps"
    )


def _settle_document(rest: RestState) -> dict[str, Any]:
    """``settle --json``: the rest state's document, ``converged`` a boolean (top level
    and in ``balance``; so is ``arrived``)."""
    doc = rest.to_dict()
    balance = doc["balance"]
    for key in ("converged", "arrived"):
        if key in balance:
            balance[key] = bool(balance[key])
    doc["converged"] = bool(balance.get("converged", True))
    return doc


def _search_text(spec: ThreadSpec, run: SearchResult, step: float) -> str:
    u = run.units
    sense = "counter-clockwise" if spec.handedness > 0 else "clockwise"
    start = run.states[0] if run.states else None
    lines = [
        f"{_name(spec)}: {sense} search from roll {run.held_roll:g}, pitch "
        f"{run.held_pitch:g} deg, phase {run.start_phase:g} deg ({run.turns:g} turn(s), "
        f"step {step:g} deg; lengths in {u})",
        *_parameters(run.parameters, u),
    ]
    if start is not None:
        lines.append(
            f"Start: {start.classification} on {start.region_combination or '-'}, "
            f"compliance centre height {start.centre[2]:.6f} {u}"
        )
    if run.snap is None:
        lines.append(f"Snap: no snap within {run.turns:g} turn(s)")
        over = "over the turns searched"
    else:
        lines.append(
            f"Snap: at phase {shown_phase(run.snap.phase):.4f} deg after a turn of "
            f"{turn_words(run.snap_turn or 0.0)}; click {run.snap.click:.6f} {u} (the fall "
            f"within a degree of turn; across the jump itself {run.snap.drop:.6f} {u})"
        )
        lo, hi = run.snap_window or (run.snap.phase, run.snap.phase)
        if hi > lo:
            lines.append(
                f"  window: the bolt may drop anywhere from phase {shown_phase(lo):.2f} to "
                f"{shown_phase(hi):.2f} deg (a shallow basin before the snap)"
            )
        over = "to the snap"
    lines.append(
        f"Work {over}: total {run.work:.6g} mJ (friction {run.work_friction:.6g} "
        f"mJ, potential {run.work_potential:.6g} mJ)"
    )
    torques = [s.driver_torque for s in run.states if math.isfinite(s.driver_torque)]
    if torques:
        lines.append(f"Peak driver torque: {max(torques, key=abs):.6g} N m")
    lines.append(f"Events ({len(run.events)}):")
    if run.events:
        lines.append(_events_head(u))
        lines += [_event_line(e, run.start_phase) for e in run.events]
    return "\n".join(lines)


def _events_head(u: str) -> str:
    """The head of a turn's table of events: phases wrapped into [0, 360), the turn from
    the start beside them."""
    return (
        f"  {'phase deg':>10} {'turned deg':>10}  {'kind':<14} {'drop ' + u:>11} "
        f"{'tilt chg deg':>12}  before -> after"
    )


def _event_line(e: SearchEvent, start_phase: float) -> str:
    return (
        f"  {shown_phase(e.phase):10.4f} {abs(e.phase - start_phase):10.4f}  {e.kind:<14} "
        f"{e.drop:11.6f} {e.tilt_change:12.4f}  {e.before or '-'} -> {e.after or '-'}"
    )


# -- figure ----------------------------------------------------------------------------------
def _figure_path(plot: Path | None) -> Path | None:
    """Refuse a figure path with a wrong suffix or naming a folder, before any work."""
    if plot is None:
        return None
    if plot.suffix.lower() not in FIGURE_FORMATS:
        raise InputError(
            f"--plot {plot}: expected a file ending in "
            f"{', '.join(FIGURE_FORMATS)} (got {plot.suffix or 'no suffix'!r})"
        )
    if plot.is_dir():
        raise InputError(f"--plot {plot}: is a folder; give a file name")
    return writable_output(plot, "--plot")


def _page_path(page: Path | None) -> Path | None:
    """Refuse a page path that is not an .html file, before any work."""
    if page is None:
        return None
    if page.suffix.lower() not in (".html", ".htm"):
        raise InputError(
            f"--html {page}: expected a file ending in .html (got {page.suffix or 'no suffix'!r})"
        )
    if page.is_dir():
        raise InputError(f"--html {page}: is a folder; give a file name")
    return writable_output(page, "--html")


# -- commands --------------------------------------------------------------------------------
_torque_limit_option = click.option(
    "--torque-limit",
    "torque_limit",
    type=float,
    default=None,
    help="Tightening torque in N m (> 0) past which the bolt counts as jammed (default: the "
    "axial force times the bolt's major radius).",
)


def _emit(
    run: SearchResult | ScrewResult,
    text: str,
    as_json: bool,
    mech: Mechanics,
    meshes: MeshFiles,
    figure: Path | None,
    page: Path | None = None,
) -> None:
    """A turn's result out: its figure and its page, then its JSON document or its
    text."""
    spec = mech.spec
    if figure is not None:
        from ..contact import SearchResult, plot_screw, plot_search  # matplotlib, if asked

        if isinstance(run, SearchResult):
            plot_search(run, figure, spec=spec)
        else:
            plot_screw(run, figure, spec=spec)
    document = _turn_document(run, mech)
    if page is not None:
        from ..view import write_search_page  # plotly, if asked

        write_search_page(document, page, spec=spec)
    if as_json:
        emit_json(document)
        return
    click.echo(text)
    if meshes.given:
        click.echo(mesh_summary(mech.scene.mesh_info, spec.units))
    if figure is not None:
        click.echo(f"wrote {figure}")
    if page is not None:
        click.echo(f"wrote {page}")


def _turn_document(run: SearchResult | ScrewResult, mech: Mechanics) -> dict[str, Any]:
    """A turn's ``--json`` document: the result's, the meshes used and the thread pair
    (``spec``, the spec-file layout), so that ``threadmate view`` can draw it."""
    return {**run.to_dict(), "mesh": mech.scene.mesh_info, "spec": mech.spec.to_dict()}


def _phase_tolerance(step: float) -> float:
    """How closely a turn's events are located: the API's default, or the step if finer."""
    return min(PHASE_TOLERANCE, step)


@cli.command(
    "settle",
    help=f"""The rest state of a bolt held through a compliance.

The tool holds the bolt's tilt at ROLL and PITCH through a rotational stiffness about the
compliance centre, spins it to PHASE and presses it down with FORCE (degrees,
conventions.md). The bolt comes down to first contact and tips, pivots and rolls on its
contacts until the contact forces balance the load and the spring: a local minimum of the
potential F z_C + k/2 |tilt - held tilt|^2 (docs/mechanics.md). Prints the class
(stable: the contacts alone hold the load; quasi-stable: the rest needs the compliance;
in-phase: the bolt dropped into the thread), the rest pose, each touching contact with its
normal force, the potential (mJ), the driver's torque (N m) and the unstable states passed
on the way. Forces in N, stiffness in N m/rad, lateral stiffness in N/m, lengths in the
spec's units, angles in degrees. For the thesis's fixed-pivot procedure see threadmate
contact.

{DEFAULTS_NOTE}

{SPEC_HELP}""",
)
@_mechanics_options
def settle_command(
    spec_text: str,
    roll: float,
    pitch: float,
    phase: float,
    force: float,
    stiffness_text: str,
    lateral_stiffness: float | None,
    friction: float,
    compliance_z: float,
    chord: float | None,
    condition: str,
    as_json: bool,
    parts: SpecParts,
    meshes: MeshFiles,
) -> None:
    """One rest state (see the command's help)."""
    spec, mech = _setup(
        spec_text,
        roll,
        pitch,
        phase,
        force,
        stiffness_text,
        lateral_stiffness,
        friction,
        compliance_z,
        chord,
        condition,
        parts,
        meshes,
    )
    from ..contact import settle

    rest = settle(mech, roll, pitch, phase)
    unsettled = _unsettled(rest)
    if unsettled is not None:
        echo_err(f"threadmate: warning: not a rest state: {unsettled}")
    if as_json:
        emit_json({**_settle_document(rest), "mesh": mech.scene.mesh_info})
    else:
        click.echo(_settle_text(spec, rest))
        if meshes.given:
            click.echo(mesh_summary(mech.scene.mesh_info, spec.units))


@cli.command(
    "search",
    help=f"""The counter-clockwise search simulated from a start.

From the rest state at the held tilt ROLL, PITCH and the start PHASE, the driver turns the
bolt the way that unscrews it (counter-clockwise for a right-hand thread) in steps of
--step degrees, and the bolt follows its rest state (a quasi-static continuation,
docs/mechanics.md). Contact changes and jumps (the rest state ceases to exist and the
bolt tips, rolls or drops) are located by bisection to {PHASE_TOLERANCE:g} deg; the jump
into the thread is the snap, and its drop of the compliance centre the click a sensor
feels. Prints the start, the snap (phase, turn, drop) and the driver's work to it (mJ:
total, against friction, against the potential) and the events. Exits 3 (after printing
the result) when no snap comes within --turns. Forces in N, stiffness in N m/rad, lateral
stiffness in N/m, lengths in the spec's units, angles in degrees, work in mJ.

{DEFAULTS_NOTE}

{SPEC_HELP}""",
)
@_mechanics_options
@click.option(
    "--turns",
    type=float,
    default=1.0,
    show_default=True,
    help=f"How far to search, in turns of 360 degrees (> 0, at most {MAX_TURNS:g}).",
)
@click.option(
    "--step",
    type=float,
    default=CONTINUATION_STEP,
    show_default=True,
    help=f"Continuation step in degrees of phase (> 0, at most {MAX_STEP:g}; the "
    f"screw-in proofs step by at most {TIGHTEN_STEP:g}).",
)
@click.option(
    "--plot",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Write the snap signature (compliance centre height, tilt of the bolt "
    "axis, driver torque against phase, events marked) to this .png, .pdf "
    "or .svg file.",
)
@click.option(
    "--screw-in",
    "screw_in",
    type=float,
    default=SCREW_IN,
    show_default=True,
    help=f"Turn (degrees, within [0, {MAX_SCREW_IN:g}]; 0: none) of the clockwise "
    "continuation that proves each snap: a landing in phase that does not then descend at "
    "the lead is a jump, and says why.",
)
@click.option(
    "--html",
    "page",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Write the search's interactive page to this .html file: the bolt on the nut at "
    "every state under a slider, the contacts and their forces, height, tilt and torque "
    "against phase (one self-contained file; threadmate view draws a saved --json the "
    "same way).",
)
@_torque_limit_option
def search_command(
    spec_text: str,
    roll: float,
    pitch: float,
    phase: float,
    force: float,
    stiffness_text: str,
    lateral_stiffness: float | None,
    friction: float,
    compliance_z: float,
    chord: float | None,
    condition: str,
    as_json: bool,
    turns: float,
    step: float,
    plot: Path | None,
    page: Path | None,
    screw_in: float,
    torque_limit: float | None,
    parts: SpecParts,
    meshes: MeshFiles,
) -> None:
    """The simulated search (see the command's help)."""
    # The API's checks, before anything is built.
    check_continuation(turns=turns, step=step, phase_tolerance=_phase_tolerance(step))
    check_screw(screw_in=screw_in, torque_limit=torque_limit)
    figure = _figure_path(plot)
    html_page = _page_path(page)
    spec, mech = _setup(
        spec_text,
        roll,
        pitch,
        phase,
        force,
        stiffness_text,
        lateral_stiffness,
        friction,
        compliance_z,
        chord,
        condition,
        parts,
        meshes,
    )
    from ..contact import search

    with progress_bar("search (deg)") as callback:
        run = search(
            mech,
            roll,
            pitch,
            phase,
            turns=turns,
            step=step,
            phase_tolerance=_phase_tolerance(step),
            progress=callback,
            screw_in=screw_in,
            torque_limit=torque_limit,
        )
    if run.states and run.states[0].classification == UNSTABLE:
        echo_err(
            "threadmate: warning: the start is not a rest state (its descent did not "
            "converge): the search begins where the descent stopped"
        )
    _emit(run, _search_text(spec, run, step), as_json, mech, meshes, figure, html_page)
    if run.snap is None:
        raise NoPathError(
            f"no snap within {turns:g} turn(s) from roll {roll:g}, pitch "
            f"{pitch:g}, phase {phase:g} deg"
        )


def _screw_text(spec: ThreadSpec, run: ScrewResult, step: float) -> str:
    u = run.units
    sense = "clockwise" if spec.handedness > 0 else "counter-clockwise"
    start = run.states[0]
    lines = [
        f"{_name(spec)}: {sense} (tightening) start from roll {run.held_roll:g}, pitch "
        f"{run.held_pitch:g} deg, phase {run.start_phase:g} deg ({run.turns:g} turn(s), "
        f"step {step:g} deg; lengths in {u})",
        *_parameters(run.parameters, u),
        f"Start: {start.classification} on {start.region_combination or '-'}, "
        f"compliance centre height {start.centre[2]:.6f} {u}",
        f"Outcome: {run.outcome}"
        + (
            ""
            if run.decided_phase is None
            else f" at phase {shown_phase(run.decided_phase):.4f} deg after a turn of "
            f"{turn_words(abs(run.decided_phase - run.start_phase))}"
        ),
        f"  {run.reason}",
        f"Descent over the last 90 deg turned: {number_text(run.descent, '.6g')} {u} per turn "
        f"(lead {run.lead:g} {u})",
        f"Work: total {run.work:.6g} mJ (friction {run.work_friction:.6g} mJ, potential "
        f"{run.work_potential:.6g} mJ)",
        f"Peak tightening torque: {number_text(run.torque_peak, '.6g')} N m "
        f"(limit {run.torque_limit:.6g} N m)",
        f"Events ({len(run.events)}):",
    ]
    if run.events:
        lines.append(_events_head(u))
        lines += [_event_line(e, run.start_phase) for e in run.events]
    return "\n".join(lines)


@cli.command(
    "screw",
    help=f"""Turn the bolt clockwise (tightening) directly from a start.

The thesis's clockwise question (its section 5.3): from the rest state at the held tilt
ROLL, PITCH and PHASE the driver turns the bolt the way that screws it in (clockwise for
a right-hand thread), and the bolt follows its rest state. It is engaged when it descends
at the lead (within 10 %) over 90 degrees turned in phase, jammed when no rest state
continues the turn (the bolt wedged: it could go on only by rising against the load) or
the tightening torque passes --torque-limit, and riding when neither comes within
--turns. Prints the outcome, the phase where it is decided, the descent per turn, the
work and the peak torque. Exits 3 (after printing the result) unless engaged. Forces in
N, stiffness in N m/rad, torque in N m, lengths in the spec's units, angles in degrees,
work in mJ.

{DEFAULTS_NOTE}

{SPEC_HELP}""",
)
@_mechanics_options
@click.option(
    "--turns",
    type=float,
    default=1.0,
    show_default=True,
    help=f"How far to turn, in turns of 360 degrees (> 0, at most {MAX_TURNS:g}).",
)
@click.option(
    "--step",
    type=float,
    default=CONTINUATION_STEP,
    show_default=True,
    help=f"Continuation step in degrees of phase (> 0, at most {MAX_STEP:g}; turned "
    f"clockwise, steps of at most {TIGHTEN_STEP:g} are taken).",
)
@click.option(
    "--plot",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Write the compliance centre height, the tilt of the bolt axis and the "
    "tightening torque against phase (events marked) to this .png, .pdf or .svg file.",
)
@_torque_limit_option
def screw_command(
    spec_text: str,
    roll: float,
    pitch: float,
    phase: float,
    force: float,
    stiffness_text: str,
    lateral_stiffness: float | None,
    friction: float,
    compliance_z: float,
    chord: float | None,
    condition: str,
    as_json: bool,
    turns: float,
    step: float,
    plot: Path | None,
    torque_limit: float | None,
    parts: SpecParts,
    meshes: MeshFiles,
) -> None:
    """A clockwise start (see the command's help)."""
    # The API's checks, before anything is built.
    check_continuation(turns=turns, step=step, phase_tolerance=_phase_tolerance(step))
    check_screw(torque_limit=torque_limit)
    figure = _figure_path(plot)
    spec, mech = _setup(
        spec_text,
        roll,
        pitch,
        phase,
        force,
        stiffness_text,
        lateral_stiffness,
        friction,
        compliance_z,
        chord,
        condition,
        parts,
        meshes,
    )
    from ..contact import screw

    with progress_bar("screw (deg)") as callback:
        run = screw(
            mech,
            roll,
            pitch,
            phase,
            turns=turns,
            step=step,
            phase_tolerance=_phase_tolerance(step),
            torque_limit=torque_limit,
            progress=callback,
        )
    _emit(run, _screw_text(spec, run, step), as_json, mech, meshes, figure)
    if run.outcome != "engaged":
        raise NoPathError(
            f"{run.outcome}: the bolt does not screw in from roll {roll:g}, pitch "
            f"{pitch:g}, phase {phase:g} deg within {turns:g} turn(s)"
        )
