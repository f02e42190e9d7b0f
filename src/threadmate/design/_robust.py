"""Whether a compliance's envelope holds over what varies (docs/design.md, "Robust to
what varies"; docs/mechanics.md, "Recommendations").

The chosen compliance is re-evaluated on the parts at the designation's maximum and
minimum material condition (the same point and countersink) and at the ends of the
thread friction range of VDI 2230 (0.08 and 0.20). Each case is a capture envelope at the
same grid and tolerance as the nominal one. The recommendation holds when every case
tolerates at least the nominal tolerated misalignment less the envelope's tolerance (the
resolution to which it is known).

Friction enters only the driver's torque and work (the equilibrium is frictionless), so
the friction cases have the nominal rest states. Their envelope differs only where the
torque decides: a screw-in whose tightening torque passes its limit (by default the load
times the major radius, reached only when the bolt wedges) is no snap, and with a torque
limit given a higher friction can stop more starts. So the friction cases are located in
the nominal envelope's pass (:func:`threadmate.design.envelope`'s ``frictions``): each
held tilt walked once, its rows scaled to another friction wherever its proofs judge
alike there; an envelope that carries them (:attr:`Envelope.friction_cases`) is not
located again.

Where the recommendation does not hold, :func:`most_robust` finds, among the settings the
design evaluated, the one whose worst case tolerates the most.

Angles in degrees, work in mJ, torque in N m.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

from .._errors import InputError
from .._units import json_units
from ..contact import Compliance
from ..geometry import BoltPoint, Countersink, ThreadSpec, spec_from_designation
from ._envelope import Envelope, envelope

if TYPE_CHECKING:
    from ._best import DesignProgress

__all__ = [
    "FRICTION_RANGE",
    "Robustness",
    "format_robustness",
    "material_specs",
    "most_robust",
    "robustness",
]

#: The thread friction coefficients of VDI 2230's range, its low and high end.
FRICTION_RANGE = (0.08, 0.20)
#: The material conditions and their names in the cases.
_CONDITIONS = (("max", "maximum material"), ("min", "minimum material"))


@dataclass
class Robustness:
    """A compliance's envelope over the parts' tolerance band and the friction range.

    Attributes
    ----------
    nominal : Envelope
        The envelope of the spec and friction given.
    cases : list of dict
        One per case: ``case`` (e.g. ``"maximum material"``, ``"friction 0.08"``),
        ``condition``, ``friction``, ``tolerated_tilt`` (degrees), the turn, work and
        torque of the starts inside, and ``envelope`` (the :class:`Envelope`).
    holds : bool
        Every case tolerates at least the nominal tolerated tilt less the tolerance.
    verdict : str
        The plain sentence.
    notes : list of str
        Cases not evaluated and why.
    """

    nominal: Envelope
    cases: list[dict[str, Any]]
    holds: bool
    verdict: str
    notes: list[str] = field(default_factory=list)

    def worst_case(self) -> dict[str, Any] | None:
        """The case that tolerates least, when the recommendation does not hold (one of
        :attr:`cases`); None when it holds."""
        return None if self.holds or not self.cases else _least(self.cases)

    def to_dict(self) -> dict[str, Any]:
        """The JSON part (``robustness`` of ``threadmate design --json``)."""
        return {
            "units": json_units(None, "angle", "work", "torque"),
            "nominal_tolerated_tilt": self.nominal.tolerated_tilt,
            "tolerance": self.nominal.tolerance,
            "holds": self.holds,
            "verdict": self.verdict,
            "cases": [
                {
                    **{k: v for k, v in c.items() if k != "envelope"},
                    "envelope": c["envelope"].to_dict(),
                }
                for c in self.cases
            ],
            "notes": list(self.notes),
        }


def material_specs(spec: ThreadSpec) -> dict[str, ThreadSpec]:
    """The spec's designation at maximum and minimum material (``{"max": ..., "min":
    ...}``), with the same point form (and chamfer angle) and the same countersink choice
    (and angle); the lengths and the diameters of tip and countersink the designation's
    defaults at that condition. Empty when the spec names no designation."""
    if not spec.designation:
        return {}
    p = spec.bolt.point
    point = BoltPoint(form=p.form, angle=p.angle if p.form == "chamfer" else None)
    sink = spec.nut.countersink
    countersink: bool | Countersink = False if sink is None else Countersink(angle=sink.angle)
    return {
        c: spec_from_designation(spec.designation, c, point=point, countersink=countersink)
        for c in ("max", "min")
    }


def _row(case: str, condition: str, friction: float, env: Envelope) -> dict[str, Any]:
    inside = env.inside
    return {
        "case": case,
        "condition": condition,
        "friction": friction,
        "tolerated_tilt": env.tolerated_tilt,
        "turn_mean": inside["turn_mean"],
        "work_mean": inside["work_mean"],
        "torque_peak": inside["torque_peak"],
        "envelope": env,
    }


def robustness(
    spec: ThreadSpec,
    compliance: Compliance,
    *,
    nominal: Envelope | None = None,
    material: Mapping[str, ThreadSpec] | None = None,
    frictions: Sequence[float] = FRICTION_RANGE,
    torque_limit: float | None = None,
    pretilt: tuple[float, float] | None = None,
    workers: int | None = None,
    chord: float | None = None,
    progress: DesignProgress | None = None,
    **grid: Any,
) -> Robustness:
    """The envelope of ``compliance`` at maximum and minimum material and at each friction
    (module docstring).

    Parameters
    ----------
    spec : ThreadSpec
        The nominal thread pair (its designation gives the material conditions).
    compliance : Compliance
        The compliance chosen.
    nominal : Envelope, optional
        Its envelope on ``spec`` at the same grid (computed when None, with the friction
        cases in its pass); the friction cases it carries are taken as they are.
    material : mapping, optional
        ``{"max": spec, "min": spec}``; default :func:`material_specs`.
    frictions : sequence of float
        Friction coefficients (default :data:`FRICTION_RANGE`).
    pretilt : (float, float), optional
        The pre-tilt ``(size, direction)`` (degrees) around which every envelope is
        measured (:func:`threadmate.design.envelope`); None: upright.
    torque_limit, workers, chord, progress
        As :func:`threadmate.design.best_compliance`.
    **grid
        ``tilt``, ``direction``, ``phase``, ``tolerance`` of every envelope, as
        :func:`threadmate.design.envelope` takes them.

    Returns
    -------
    Robustness
    """
    if not isinstance(compliance, Compliance):
        raise InputError(f"compliance must be a Compliance, got {type(compliance).__name__}")
    unknown = set(grid) - {"tilt", "direction", "phase", "tolerance"}
    if unknown:
        raise InputError(f"robustness: unknown grid setting {sorted(unknown)[0]!r}")
    grid = {k: v for k, v in grid.items() if v is not None}
    common = {
        "workers": workers,
        "chord": chord,
        "torque_limit": torque_limit,
        "pretilt": pretilt,
        **grid,
    }

    def run(label: str, s: ThreadSpec, c: Compliance, **more: Any) -> Envelope:
        if progress is not None:
            progress(f"robustness: {label}")
        return envelope(s, compliance=c, **common, **more)

    if nominal is None:
        nominal = run("nominal", spec, compliance, frictions=frictions)
    notes: list[str] = []
    specs = material_specs(spec) if material is None else dict(material)
    if not specs:
        notes.append(
            "the spec names no designation: the maximum and minimum material conditions "
            "are not evaluated"
        )
    cases = []
    for condition, words in _CONDITIONS:
        if condition in specs:
            env = run(words, specs[condition], compliance)
            cases.append(_row(words, condition, compliance.friction, env))
    for mu in frictions:
        known = _friction_case(nominal, float(mu))
        env = known or run(f"friction {mu:g}", spec, replace(compliance, friction=float(mu)))
        cases.append(_row(f"friction {mu:g}", "nominal", float(mu), env))
    holds, verdict = _verdict(nominal, cases)
    return Robustness(nominal=nominal, cases=cases, holds=holds, verdict=verdict, notes=notes)


def most_robust(
    spec: ThreadSpec,
    candidates: Sequence[tuple[dict[str, Any], Compliance, Envelope]],
    to_beat: float,
    *,
    material: Mapping[str, ThreadSpec] | None = None,
    torque_limit: float | None = None,
    workers: int | None = None,
    chord: float | None = None,
    progress: DesignProgress | None = None,
    **grid: Any,
) -> dict[str, Any] | None:
    """Of settings already evaluated at nominal, the one whose worst case over what
    varies tolerates the most, when that is more than ``to_beat`` (degrees: the worst
    case of the setting chosen at nominal); None when none does.

    ``candidates`` are ``(row, compliance, nominal envelope)`` in their order of merit at
    nominal. A setting's worst case is its nominal tolerated tilt or less, so once a
    candidate's nominal figure is no more than the best worst case found, no later one
    can beat it and the search stops; a candidate's cases stop likewise as soon as one
    falls to the best worst case, and each case's envelope as soon as it is known to
    (:func:`threadmate.design.envelope`'s ``floor``: the upright held tilt first, alone).
    The cases are those of :func:`robustness`: the maximum and minimum material
    conditions, then the frictions of :data:`FRICTION_RANGE` (they change the driver's
    torque, and a screw-in whose torque passes its limit is no snap), every envelope at
    the same ``grid`` as the nominal ones.

    Returns
    -------
    dict or None
        The setting's ``row`` (ratio, force, stiffness, ...) with ``nominal_tolerated_tilt``,
        ``tolerated_tilt`` (its worst case, degrees) and ``cases`` (each ``case`` and
        ``tolerated_tilt``).
    """
    specs = material_specs(spec) if material is None else dict(material)
    best: dict[str, Any] | None = None
    best_worst = to_beat
    for row, compliance, nominal in candidates:
        if nominal.tolerated_tilt <= best_worst + 1e-12:
            break
        worst, cases = nominal.tolerated_tilt, []
        plan: list[tuple[str, ThreadSpec, Compliance, Envelope | None]] = [
            (words, specs[c], compliance, None) for c, words in _CONDITIONS if c in specs
        ]
        plan += [
            (
                f"friction {mu:g}",
                spec,
                replace(compliance, friction=mu),
                _friction_case(nominal, mu),
            )
            for mu in FRICTION_RANGE
        ]
        for words, s, c, env in plan:
            if env is None:
                if progress is not None:
                    progress(f"most robust: k/F {row['ratio']:.4g}, {words}")
                env = envelope(
                    s,
                    compliance=c,
                    workers=workers,
                    chord=chord,
                    torque_limit=torque_limit,
                    floor=best_worst,
                    **grid,
                )
            cases.append({"case": words, "tolerated_tilt": env.tolerated_tilt})
            worst = min(worst, env.tolerated_tilt)
            if worst <= best_worst + 1e-12:
                break
        if worst > best_worst + 1e-12:
            best_worst = worst
            best = {
                **row,
                "nominal_tolerated_tilt": nominal.tolerated_tilt,
                "tolerated_tilt": worst,
                "cases": cases,
            }
    return best


def _friction_case(nominal: Envelope, friction: float) -> Envelope | None:
    """The envelope at ``friction`` of ``nominal``'s compliance, when known already: the
    nominal itself at its own friction, or one located in its pass
    (:attr:`Envelope.friction_cases`); None otherwise."""
    if friction == nominal.compliance["friction"]:
        return nominal
    return nominal.friction_cases.get(friction)


def _least(cases: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """The case that tolerates least (the first of equals)."""
    return min(cases, key=lambda c: c["tolerated_tilt"])


def _verdict(nominal: Envelope, cases: list[dict[str, Any]]) -> tuple[bool, str]:
    """Whether every case tolerates the nominal tilt (to the tolerance), in one sentence."""
    want = nominal.tolerated_tilt
    tol = nominal.tolerance
    short = [c for c in cases if c["tolerated_tilt"] < want - tol - 1e-9]
    if not cases:
        return True, "No case beside the nominal one was evaluated."
    if not short:
        low = min(c["tolerated_tilt"] for c in cases)
        return True, (
            f"The recommendation holds: every case tolerates at least {low:.2f} deg against "
            f"{want:.2f} deg nominal (known to {tol:g} deg)."
        )
    worst = _least(short)
    names = ", ".join(f"{c['case']} ({c['tolerated_tilt']:.2f} deg)" for c in short)
    return False, (
        f"The recommendation does not hold over what varies: {names} against {want:.2f} deg "
        f"nominal; count on {worst['tolerated_tilt']:.2f} deg."
    )


def format_robustness(rob: Robustness) -> str:
    """The robustness as text: the sentence and the table of cases."""
    lines = [
        rob.verdict,
        "",
        "| case | tolerated deg | turn mean deg | work mean mJ | peak torque N m |",
        "|---|---|---|---|---|",
        f"| nominal (friction {rob.nominal.compliance['friction']:g}) | "
        f"{rob.nominal.tolerated_tilt:.2f} | {_num(rob.nominal.inside['turn_mean'], '.0f')} | "
        f"{_num(rob.nominal.inside['work_mean'], '.3g')} | "
        f"{_num(rob.nominal.inside['torque_peak'], '.3g')} |",
    ]
    for c in rob.cases:
        lines.append(
            f"| {c['case']} | {c['tolerated_tilt']:.2f} | {_num(c['turn_mean'], '.0f')} | "
            f"{_num(c['work_mean'], '.3g')} | {_num(c['torque_peak'], '.3g')} |"
        )
    lines += [f"note: {n}" for n in rob.notes]
    return "\n".join(lines)


def _num(value: float | None, fmt: str) -> str:
    from .._text import number_text

    return number_text(value, fmt)
