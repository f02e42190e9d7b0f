"""Options shared by the commands that run the mechanics (``settle``, ``search``, ``sweep``):
the compliance's parameters, declared once.

The defaults are those of :class:`threadmate.contact.Compliance`; the values are checked by
it (one message naming the parameter and its range).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import click

from .._errors import InputError
from ..contact import Compliance
from ..geometry import DEFAULT_CHORD, material_condition

__all__ = [
    "COMPLIANCE_PARAMETERS",
    "DEFAULTS_NOTE",
    "compliance_from_options",
    "chord_option",
    "compliance_option_list",
    "compliance_options",
    "condition_option",
    "parse_stiffness",
]

#: The defaults of the options are those of :class:`Compliance`.
_D = Compliance()

#: The keyword names the compliance options give a command, in order.
COMPLIANCE_PARAMETERS = ("force", "stiffness_text", "lateral_stiffness", "friction", "compliance_z")

DEFAULTS_NOTE = (
    "Defaults (threadmate.contact.Compliance): 10 N is a light hand or float-spring push "
    "on a small screw; 1 N m/rad is the soft end of remote-centre compliances for small "
    "parts (Whitney's k_r = k_t l^2 with about 1.6 N/mm projected 25 mm); the centre is "
    "held laterally at x = y = 0 and sits at the bolt's tip; friction 0.15 is steel on "
    "steel in a thread (VDI 2230's 0.08 to 0.20)."
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
