"""Options shared by the commands, declared once, and the one map from the API's parameter
names to the options' flags (:data:`FLAGS`, :func:`flag_words`).

The options' defaults and ranges are the API's own names, imported from the light modules
that own them (nothing here restates a value), and their values are checked by the API
(one message naming the parameter and its range), which names parameters as the API does:
:func:`flag_words` turns those names into the flags when the command line reports.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import click

from .._errors import InputError
from .._units import unit_scale
from .._validate import MAX_FACES, MAX_STARTS, MAX_STARTS_CEILING, MAX_TILT, WARN_FACES
from ..contact import Compliance
from ..geometry import DEFAULT_CHORD, POINT_FORMS, SpecParts, material_condition

__all__ = [
    "COMPLIANCE_PARAMETERS",
    "DEFAULTS_NOTE",
    "FLAGS",
    "compliance_from_options",
    "chord_option",
    "compliance_option_list",
    "compliance_options",
    "condition_option",
    "flag_words",
    "max_starts_option",
    "parse_stiffness",
    "parts_option",
    "roll_spread_option",
    "RANGE_HELP",
    "envelope_grid_options",
    "DIRECTION_HELP",
    "polar_grid_options",
    "held_tilt_from_options",
    "check_grid_kind",
    "MeshFiles",
    "mesh_files_option",
    "echo_mesh_notes",
    "mesh_summary",
]

# -- the API's parameter names and the options' flags ----------------------------------------
#: The flag of each API parameter that a command takes as an option: the one place the
#: command line maps the API's names to its own.
FLAGS: dict[str, str] = {
    # the configuration and the grid
    "roll": "--roll",
    "pitch": "--pitch",
    "tilt": "--tilt",
    "direction": "--direction",
    "phase": "--phase",
    "nearest": "--nearest",
    # the compliance
    "force": "--force",
    "stiffness": "--stiffness",
    "lateral_stiffness": "--lateral-stiffness",
    "friction": "--friction",
    "compliance_z": "--compliance-z",
    # the continuation
    "turns": "--turns",
    "step": "--step",
    "phase_tolerance": "--phase-tolerance",
    "screw_in": "--screw-in",
    "torque_limit": "--torque-limit",
    # the sweep
    "model": "--model",
    "workers": "--workers",
    "scheduler": "--scheduler",
    "chunk_size": "--chunk-size",
    "max_starts": "--max-starts",
    # the meshes
    "chord": "--chord",
    "bolt_mesh": "--bolt-mesh",
    "nut_mesh": "--nut-mesh",
    "mesh_units": "--mesh-units",
    "max_faces": "--max-mesh-faces",
    # the network and the recommendation
    "k": "--k",
    "active": "--active",
    "jump_penalty": "--jump-penalty",
    "move_penalty": "--move-penalty",
    "roll_spread": "--roll-spread",
    "partial": "--partial",
    # the design stage
    "turn_margin": "--turn-margin",
    "torque_margin": "--torque-margin",
    "may_exceed": "--may-exceed",
    "ratios": "--ratios",
    "refinements": "--refinements",
    "azimuth_known": "--azimuth-known",
    "pretilt_sizes": "--pretilt-sizes",
    # the parts (threadmate.geometry.with_parts)
    "condition": "--condition",
    "point": "--point",
    "chamfer_angle": "--chamfer-angle",
    "point_diameter": "--point-diameter",
    "round_radius": "--round-radius",
    "countersink": "--countersink",
    "countersink_angle": "--countersink-angle",
    "countersink_diameter": "--countersink-diameter",
    "bolt_length": "--bolt-length",
    "nut_height": "--nut-height",
}
_NAMES = "|".join(sorted(FLAGS, key=len, reverse=True))
#: ``name=value`` (a value the API suggests): ``step=0.01``, ``model='mechanics'``.
_SUGGESTED = re.compile(rf"(?<![\w.])({_NAMES})=(?:'([^']*)'|\"([^\"]*)\"|([^\s,;:)]+))")
#: The name a message starts with: the parameter it is about.
_LEADING = re.compile(rf"^({_NAMES})(?=[\s:(]|$)")
#: A parameter named within a message: only names of two or more words (``max_starts``),
#: which no sentence uses, and not within a path, a dotted key or a quoted mapping's key.
_NAMED = re.compile(rf"(?<![\w/.'\"-])({'|'.join(n for n in FLAGS if '_' in n)})(?![\w/.'\"-]|=)")


def flag_words(message: str) -> str:
    """An API message in the command line's words: each parameter of :data:`FLAGS` named
    as its flag.

    The API names the parameter a message is about first (``step must be within (0,
    10]``), suggests a value as ``name=value`` (``pass max_starts=4000``; ``True`` for a
    flag's) and otherwise names a parameter of two or more words as it is
    (``countersink_diameter``); these, and only these, become ``--step must be ...``,
    ``pass --max-starts 4000``, ``--countersink-diameter``.
    """

    def suggested(m: re.Match[str]) -> str:
        value = next(v for v in m.groups()[1:] if v is not None)
        flag = FLAGS[m[1]]
        return flag if value == "True" else f"{flag} {value}"

    message = _SUGGESTED.sub(suggested, message)
    message = _LEADING.sub(lambda m: FLAGS[m[1]], message)
    return _NAMED.sub(lambda m: FLAGS[m[1]], message)


# -- the compliance --------------------------------------------------------------------------
#: How a grid option is written (sweep's and run's --roll, --pitch and --phase).
RANGE_HELP = (
    "START:STOP:STEP (STOP included when on the grid), a value, or a comma list, in degrees"
)
#: What a polar grid's direction is, in the help's words (the one definition is
#: threadmate.geometry.held_tilt_from_polar's).
DIRECTION_HELP = (
    "the azimuth in the nut's frame F, from +X toward +Y, toward which the bolt's axis "
    "leans (0: a positive held pitch, 90: a negative held roll)"
)


def polar_grid_options(func: Callable[..., Any]) -> Callable[..., Any]:
    """``--tilt RANGE`` and ``--direction RANGE``: a polar grid of misalignment, for every
    command that sweeps one (the library stage refuses them mixed with roll and pitch)."""
    from ..library._grid import DEFAULT_POLAR_RANGES  # light: numpy and the angle rules

    func = click.option(
        "--direction",
        "direction",
        default=None,
        metavar="RANGE",
        help=f"Polar grid: directions of the held tilt, {DIRECTION_HELP}, modulo 360: "
        f"{RANGE_HELP} (default {DEFAULT_POLAR_RANGES['direction']} with --tilt). Not with "
        "--roll/--pitch.",
    )(func)
    return click.option(
        "--tilt",
        "tilt",
        default=None,
        metavar="RANGE",
        help=f"Polar grid: held tilt sizes, the angle between bolt and nut axes, 0 to "
        f"{MAX_TILT:g}: {RANGE_HELP} (default {DEFAULT_POLAR_RANGES['tilt']} with "
        "--direction). Size 0 is one held tilt, upright. Not with --roll/--pitch.",
    )(func)


def envelope_grid_options(
    what: str, tilt: str, direction: str, phase: str, tolerance: float | None
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """``--tilt``, ``--direction``, ``--phase`` and ``--tolerance`` of an envelope's polar
    grid (``envelope``, ``design``): ``what`` names the grid in the help, the other
    arguments give the defaults it states (``tolerance`` None: the option's default is
    None and the API's applies)."""
    options = [
        click.option(
            "--tilt",
            default=None,
            metavar="RANGE",
            help=f"{what}: held tilt sizes: {RANGE_HELP} (default {tilt}).",
        ),
        click.option(
            "--direction",
            default=None,
            metavar="RANGE",
            help=f"{what}: directions, modulo 360: {RANGE_HELP} (default {direction}).",
        ),
        click.option(
            "--phase",
            default=None,
            metavar="RANGE",
            help=f"{what}: start phases, modulo 360: {RANGE_HELP} (default {phase}).",
        ),
        click.option(
            "--tolerance",
            type=float,
            default=tolerance,
            show_default=tolerance is not None,
            help=f"{what}: how closely each envelope is located in tilt size (degrees)"
            + ("." if tolerance is not None else ", default 0.25."),
        ),
    ]

    def decorate(func: Callable[..., Any]) -> Callable[..., Any]:
        for option in reversed(options):
            func = option(func)
        return func

    return decorate


def check_grid_kind(
    roll: str | None, pitch: str | None, tilt: str | None, direction: str | None
) -> None:
    """Refuse a square grid's options mixed with a polar grid's (one message, in flags)."""
    square = [f for f, v in (("--roll", roll), ("--pitch", pitch)) if v is not None]
    polar = [f for f, v in (("--tilt", tilt), ("--direction", direction)) if v is not None]
    if square and polar:
        raise InputError(
            f"{square[0]} and {polar[0]} name two kinds of grid: give --roll/--pitch (a "
            "square grid) or --tilt/--direction (a polar grid), not both"
        )


def held_tilt_from_options(
    roll: float | None, pitch: float | None, tilt: float | None, direction: float | None
) -> tuple[float, float]:
    """The held ``(roll, pitch)`` of one start given as ``--roll/--pitch`` or as
    ``--tilt/--direction`` (InputError when mixed or incomplete)."""
    square, polar = (roll, pitch), (tilt, direction)
    if any(v is not None for v in square) and any(v is not None for v in polar):
        raise InputError(
            "give the held tilt as --roll and --pitch or as --tilt and --direction, not both"
        )
    if all(v is not None for v in polar):
        from ..geometry._frames import held_tilt_from_polar

        t = float(tilt)  # type: ignore[arg-type]
        if not 0 <= t <= MAX_TILT:
            raise InputError(
                f"--tilt {t:g} is out of range: a tilt size lies within 0 and {MAX_TILT:g} deg"
            )
        return held_tilt_from_polar(t, float(direction))  # type: ignore[arg-type]
    if all(v is not None for v in square):
        return float(roll), float(pitch)  # type: ignore[arg-type]
    raise InputError("give the held tilt: --roll and --pitch, or --tilt and --direction")


#: The defaults of the options are those of :class:`Compliance`.
_D = Compliance()

#: The keyword names the compliance options give a command, in order.
COMPLIANCE_PARAMETERS = ("force", "stiffness_text", "lateral_stiffness", "friction", "compliance_z")

DEFAULTS_NOTE = (
    f"Defaults (threadmate.contact.Compliance): {_D.force:g} N is a light hand or "
    f"float-spring push on a small screw; {_D.roll_stiffness:g} N m/rad is the soft end of "
    "remote-centre compliances for small parts (Whitney's k_r = k_t l^2 with about 1.6 N/mm "
    "projected 25 mm); the centre is held laterally at x = y = 0 and sits at the bolt's "
    f"tip; friction {_D.friction:g} is steel on steel in a thread (VDI 2230's 0.08 to 0.20)."
)


def compliance_option_list() -> list[Callable[[Any], Any]]:
    """The click options of the compliance, in help order: ``--force``, ``--stiffness``,
    ``--lateral-stiffness``, ``--friction``, ``--compliance-z``."""
    return [
        click.option(
            "--force",
            type=float,
            default=_D.force,
            show_default=True,
            help="Axial force pressing the bolt down through the compliance "
            "centre, in N (1 lbf = 4.448 N).",
        ),
        click.option(
            "--stiffness",
            "stiffness_text",
            default=f"{_D.roll_stiffness:g}",
            show_default=True,
            metavar="K|ROLL,PITCH",
            help="Rotational stiffness of the compliance about X and Y through "
            "its centre, in N m/rad: one number, or two as ROLL,PITCH for an "
            "anisotropic compliance (0 is a free tilt).",
        ),
        click.option(
            "--lateral-stiffness",
            type=float,
            default=None,
            help="Lateral stiffness of the compliance centre in N/m (default: the "
            "centre is held at x = y = 0).",
        ),
        click.option(
            "--friction",
            type=float,
            default=_D.friction,
            show_default=True,
            help="Coulomb friction coefficient of the thread contacts (enters the "
            "driver's torque and work, not the rest pose).",
        ),
        click.option(
            "--compliance-z",
            type=float,
            default=_D.compliance_z,
            show_default=True,
            help="Compliance centre on the bolt axis, bolt frame, in the spec's "
            "length units (0: the tip centre).",
        ),
    ]


def compliance_options(func: Callable[..., Any]) -> Callable[..., Any]:
    """Decorate a command with the compliance options (see :func:`compliance_option_list`)."""
    for option in reversed(compliance_option_list()):
        func = option(func)
    return func


def parse_stiffness(text: str) -> float | tuple[float, float]:
    """``K`` or ``ROLL,PITCH`` as numbers (their range is the Compliance's to check)."""
    parts = [p.strip() for p in text.split(",")]
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) not in (1, 2):
        raise InputError(
            f"--stiffness {text!r}: give one number or two as ROLL,PITCH (N m/rad), e.g. 1 or 0.5,2"
        )
    return values[0] if len(values) == 1 else (values[0], values[1])


def compliance_from_options(
    force: float,
    stiffness_text: str,
    lateral_stiffness: float | None,
    friction: float,
    compliance_z: float,
) -> Compliance:
    """The :class:`Compliance` the options describe (InputError naming a bad value)."""
    return Compliance(
        force=force,
        stiffness=parse_stiffness(stiffness_text),
        lateral_stiffness=lateral_stiffness,
        compliance_z=compliance_z,
        friction=friction,
    )


class _Condition(click.ParamType):
    """A material condition in any spelling the geometry accepts (max, maximum, mmc; mean,
    mid, middle; min, minimum, lmc; any case), normalised to max, mean or min."""

    name = "condition"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> str:
        try:
            return material_condition(value)
        except InputError as exc:
            self.fail(str(exc), param, ctx)


def condition_option(func: Callable[..., Any]) -> Callable[..., Any]:
    """``--condition``: the same spellings for every command that expands a designation."""
    return click.option(
        "--condition",
        type=_Condition(),
        default="mean",
        show_default=True,
        metavar="max|mean|min",
        help="Material condition at which a designation expands: max (maximum material: "
        "largest bolt, smallest nut; also maximum, mmc), mean (mid-limits; also mid) or "
        "min (also minimum, lmc).",
    )(func)


def chord_option(func: Callable[..., Any]) -> Callable[..., Any]:
    """``--chord``: the meshes' chord tolerance, one help text for every command (the
    range is checked by :func:`threadmate.geometry.check_chord`)."""
    return click.option(
        "--chord",
        type=float,
        default=None,
        help=f"Chord tolerance of the meshes in the spec's length units (default "
        f"{DEFAULT_CHORD['in']:g} in, {DEFAULT_CHORD['mm']:g} mm).",
    )(func)


def workers_option(func: Callable[..., Any]) -> Callable[..., Any]:
    """``--workers N``: the worker processes of every command that sweeps (checked by
    :func:`threadmate._validate.check_workers`)."""
    return click.option(
        "--workers",
        type=int,
        default=None,
        help="Worker processes (default: the CPUs available; 1 runs in-process).",
    )(func)


def max_starts_option(func: Callable[..., Any]) -> Callable[..., Any]:
    """``--max-starts N``: the most configurations a grid may hold, for every command that
    sweeps (the API's limit, :func:`threadmate._validate.check_starts`)."""
    return click.option(
        "--max-starts",
        type=int,
        default=None,
        metavar="N",
        help=f"Most configurations the grid may hold (default {MAX_STARTS:,}; at most "
        f"{MAX_STARTS_CEILING:,}): a larger grid is refused at once, with its count and the "
        "time it would take.",
    )(func)


def roll_spread_option(func: Callable[..., Any]) -> Callable[..., Any]:
    """``--roll-spread DEG``: the largest roll error the recommendation must hold for, the
    same option and range for ``recommend`` and ``run`` (the API checks it,
    :func:`threadmate._validate.check_roll_spread`)."""
    return click.option(
        "--roll-spread",
        type=float,
        default=None,
        help=f"Largest roll error expected, degrees from 0 to {MAX_TILT:g}: starts have |held "
        "roll| <= spread (default: every roll of the grid).",
    )(func)


def parts_option(func: Callable[..., Any]) -> Callable[..., Any]:
    """The bolt's point, the nut's countersink and their lengths, for every command that
    expands a designation or reads a spec: ``--point``, ``--chamfer-angle``,
    ``--point-diameter``, ``--round-radius``, ``--countersink/--no-countersink``,
    ``--countersink-angle``, ``--countersink-diameter``, ``--bolt-length``,
    ``--nut-height``. The command receives them as one keyword argument ``parts``
    (:class:`threadmate.geometry.SpecParts`, for :func:`~threadmate.cli._common.resolve_spec`).
    """
    options: list[Callable[[Any], Any]] = [
        click.option(
            "--point",
            "point",
            type=click.Choice(POINT_FORMS),
            default=None,
            help="The bolt's point: chamfer (ASME B18.2.1, ISO 4753), round (ISO 4753 RN) "
            "or flat (the thesis's). Default: chamfer for a designation, a spec file's own.",
        ),
        click.option(
            "--chamfer-angle",
            "chamfer_angle",
            type=float,
            default=None,
            metavar="DEG",
            help="Chamfer angle from the bolt's axis in degrees (default 45).",
        ),
        click.option(
            "--point-diameter",
            "point_diameter",
            type=float,
            default=None,
            metavar="LEN",
            help="Diameter of the tip face where a chamfer or round ends, in the spec's units "
            "(default 0.1 pitch below the bolt's minor diameter).",
        ),
        click.option(
            "--round-radius",
            "round_radius",
            type=float,
            default=None,
            metavar="LEN",
            help="Radius of a round point in the spec's units (default 1.4 x major diameter).",
        ),
        click.option(
            "--countersink/--no-countersink",
            "countersink",
            default=None,
            help="The nut's countersink, or a flat, sharp-edged bore (the thesis's). Default: "
            "a countersink for a designation, a spec file's own. --point flat "
            "--no-countersink are the thesis's parts.",
        ),
        click.option(
            "--countersink-angle",
            "countersink_angle",
            type=float,
            default=None,
            metavar="DEG",
            help="Included angle of the countersink in degrees (default 120).",
        ),
        click.option(
            "--countersink-diameter",
            "countersink_diameter",
            type=float,
            default=None,
            metavar="LEN",
            help="Diameter of the countersink at the nut's face, in the spec's units "
            "(default: the mean of ASME B18.2.2's or ISO 4032's limits).",
        ),
        click.option(
            "--bolt-length",
            "bolt_length",
            default=None,
            metavar="LEN|Np",
            help="Bolt length in the spec's units or in pitches, e.g. 3p (default: the "
            "point's height and one pitch).",
        ),
        click.option(
            "--nut-height",
            "nut_height",
            default=None,
            metavar="LEN|Np|standard",
            help="Nut height in the spec's units, in pitches (3p), or 'standard': the "
            "standard hex nut's (ASME B18.2.2, B18.6.3, ISO 4032) (default: the "
            "countersink's depth and one pitch).",
        ),
    ]
    names = [f.name for f in fields(SpecParts)]

    @functools.wraps(func)
    def command(*args: Any, **kwargs: Any) -> Any:
        parts = SpecParts(**{name: kwargs.pop(name) for name in names})
        return func(*args, parts=parts, **kwargs)

    wrapped: Callable[..., Any] = command
    for option in reversed(options):
        wrapped = option(wrapped)
    return wrapped


# -- meshes from CAD ---------------------------------------------------------------------
@dataclass(frozen=True)
class MeshFiles:
    """``--bolt-mesh``, ``--nut-mesh``, ``--mesh-units`` and ``--max-mesh-faces`` as one
    keyword argument ``meshes`` of a command."""

    bolt: Path | None = None
    nut: Path | None = None
    units: str | None = None
    max_faces: int | None = None

    @property
    def given(self) -> bool:
        """Whether a mesh file is given."""
        return self.bolt is not None or self.nut is not None

    def arguments(self) -> dict[str, Any]:
        """Keyword arguments of :class:`~threadmate.contact.ContactAnalyzer`,
        :func:`~threadmate.library.sweep` and the pipeline (the paths, as given; the
        API checks the values)."""
        for value, flag in ((self.units, "--mesh-units"), (self.max_faces, "--max-mesh-faces")):
            if value is not None and not self.given:
                raise InputError(f"{flag} needs --bolt-mesh or --nut-mesh")
        return {
            "bolt_mesh": None if self.bolt is None else str(self.bolt),
            "nut_mesh": None if self.nut is None else str(self.nut),
            "mesh_units": self.units,
            "max_faces": self.max_faces,
        }


def mesh_files_option(func: Callable[..., Any]) -> Callable[..., Any]:
    """``--bolt-mesh FILE``, ``--nut-mesh FILE``, ``--mesh-units in|mm`` and
    ``--max-mesh-faces N``: meshes from CAD instead of generated ones. The command receives
    them as one keyword argument ``meshes`` (:class:`MeshFiles`); the API loads and checks
    the files."""
    options: list[Callable[[Any], Any]] = [
        click.option(
            "--bolt-mesh",
            "bolt_mesh",
            type=click.Path(path_type=Path),
            default=None,
            metavar="FILE",
            help="The bolt from CAD (STL, OBJ or PLY) instead of the generated mesh, in its "
            "frame: tip face at z = 0, body in z >= 0, axis +Z toward the head. Regions "
            "and normals still come from the spec; contacts where the mesh leaves the "
            "spec (a point or a head it does not state) are labelled point or other.",
        ),
        click.option(
            "--nut-mesh",
            "nut_mesh",
            type=click.Path(path_type=Path),
            default=None,
            metavar="FILE",
            help="The nut from CAD instead of the generated mesh, in its frame: entry (top) "
            "face at z = 0, body in z <= 0, axis along Z. Contacts where it leaves the "
            "spec (a countersink or flats it does not state) are labelled countersink "
            "or other.",
        ),
        click.option(
            "--mesh-units",
            "mesh_units",
            type=click.Choice(["in", "mm"]),
            default=None,
            help="Length units of the mesh files (STL carries none). Default: the units "
            "a threadmate STL's header declares, else the spec's; a header that disagrees "
            "is refused. A file in other units than the spec's is scaled into them.",
        ),
        click.option(
            "--max-mesh-faces",
            "max_faces",
            type=int,
            default=None,
            metavar="N",
            help=f"Most triangles a mesh file may have (default {MAX_FACES:,}): a larger one "
            "is refused at once, with its count (the contact stages' set-up grows with it); "
            f"above {WARN_FACES:,} one is taken with a warning.",
        ),
    ]

    @functools.wraps(func)
    def command(*args: Any, **kwargs: Any) -> Any:
        meshes = MeshFiles(
            kwargs.pop("bolt_mesh"),
            kwargs.pop("nut_mesh"),
            kwargs.pop("mesh_units"),
            kwargs.pop("max_faces"),
        )
        return func(*args, meshes=meshes, **kwargs)

    wrapped: Callable[..., Any] = command
    for option in reversed(options):
        wrapped = option(wrapped)
    return wrapped


def echo_mesh_notes(info: dict[str, Any] | None, units: str) -> None:
    """On stderr: each CAD mesh scaled into the spec's units, and each warning that much
    of a mesh's contact zone lies off the spec (``mesh_info`` of the analyser, or the
    ``mesh`` entry of a library's metadata)."""
    for kind in ("bolt", "nut"):
        part = (info or {}).get(kind)
        if not isinstance(part, dict) or not part.get("sha256"):
            continue
        scale = part.get("scale")
        if scale is None and part.get("units") not in (None, units):
            scale = unit_scale(part["units"], units)
        if scale is not None and scale != 1.0:
            click.echo(
                f"threadmate: {kind} mesh {part.get('file')}: in {part.get('units')}, "
                f"scaled by {scale:.6g} into the spec's {units}",
                err=True,
            )
        if part.get("warning"):
            click.echo(f"threadmate: warning: {part['warning']}", err=True)


def mesh_summary(info: dict[str, Any], units: str) -> str:
    """One line naming the meshes used (for the text output when a CAD mesh is given)."""
    words = []
    for kind in ("bolt", "nut"):
        part = info.get(kind) or {}
        if part.get("generated"):
            words.append(f"{kind} generated (chord {part['chord']:g} {units})")
            continue
        sha = part.get("sha256")
        facts = [f"sha256 {sha[:12]}", f"units {part.get('units')}"] if sha else []
        facts += [
            f"deviation {part.get('deviation', float('nan')):.3g} {units}",
            f"{part.get('zone_off_spec_share', 0.0):.0%} of its contact zone off the spec",
        ]
        words.append(f"{kind} {part.get('file') or 'from CAD'} ({', '.join(facts)})")
    return "Meshes: " + "; ".join(words)
