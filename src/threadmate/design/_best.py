"""The compliance that tolerates the most misalignment (docs/design.md, "The design
search"; docs/mechanics.md, "Recommendations").

Within the designer's bounds on the axial force F (N) and the rotational stiffness k
(N m/rad), the best compliance maximises the tolerated misalignment (the capture
envelope's 100 % level in its worst direction), ties broken by the mean turn to the snap,
then the mean work, then the peak driver torque.

The search is one-dimensional. A rest state minimises ``U = F z_C + k/2 |tilt - held|^2``
(the equilibrium is frictionless; friction enters only the driver's torque and work), and
``U / F`` depends on F and k only through ``k / F``: the rest states, their folds, the snap
phase, the click and so the envelope depend on the ratio alone, while the contact forces,
the torque and the work scale with F. At one ratio the least force within the bounds is
therefore best (least work and torque; with a torque limit the only one that can be best,
since the torque grows with F). The box ``[F_lo, F_hi] x [k_lo, k_hi]`` reduces to the
ratios ``r`` in ``[k_lo / F_hi, k_hi / F_lo]``, each evaluated at
``F = max(F_lo, k_lo / r)``, ``k = r F``.

The tolerated tilt is known only to the envelope's bisection tolerance: a step-like,
quantised objective that scipy.optimize's scalar methods (which assume a smooth or at
least continuous function) do not serve. The ratio is searched on a log-spaced grid, and
the grid step then halved around the best, its two neighbours evaluated at each step
(coarse to fine). A best at the edge of the ratios evaluated is walked outward, beyond the
bounds as far as ``may_exceed`` allows (the force stays at its bound, the stiffness goes
beyond its own), and a pick at a bound is said to be one.

Each setting is evaluated with a coarse envelope (few directions and phases, a coarse
tolerance), which ranks the settings; the optimum is then measured again at the envelope's
own grid (``confirm``), the figure the design leads with: a worst direction or phase
between the coarse grid's can tolerate less. ``fine=True`` measures the robustness cases
at that grid too.
The compliance centre ``compliance_z`` is geometric and not reduced: given several, each
is searched and the best kept.

Angles in degrees, forces in N, stiffness in N m/rad, work in mJ, torque in N m.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .._errors import InputError
from .._units import json_units
from .._validate import check_range
from ..contact import Compliance
from ..geometry import ThreadSpec
from ._envelope import TOLERANCE, Envelope, envelope
from ._robust import FRICTION_RANGE

__all__ = [
    "COARSE",
    "ComplianceDesign",
    "DesignProgress",
    "best_compliance",
    "format_compliance_design",
    "plot_compliance_design",
]

#: The coarse envelope each setting of the search is evaluated with: the polar grid's
#: sizes, directions and start phases (degrees, as :func:`threadmate.design.envelope`
#: takes them) and the bisection's tolerance (degrees).
COARSE: Mapping[str, Any] = {
    "tilt": "0:4:1",
    "direction": "0:360:45",
    "phase": "0:340:40",
    "tolerance": 0.25,
}
#: The optimum's envelope (``confirm``, and the robustness's with ``fine=True``): the
#: envelope's own defaults.
FINE: Mapping[str, Any] = {"tilt": None, "direction": None, "phase": None, "tolerance": TOLERANCE}
#: Ratios of the first, log-spaced grid (the bounds included).
RATIOS = 5
#: Halvings of the grid step around the best.
REFINEMENTS = 4
#: Log-ratios ``log(k/F)`` closer than this are one setting, evaluated once.
SAME_RATIO = 1e-9
#: ``progress(text)``: the search says what it evaluates next.
DesignProgress = Callable[[str], None]


@dataclass
class _Setting:
    """One setting evaluated: its compliance and coarse envelope."""

    ratio: float
    force: float
    stiffness: float
    compliance_z: float
    beyond: bool
    envelope: Envelope

    @property
    def tolerated(self) -> float:
        return self.envelope.tolerated_tilt

    def key(self) -> tuple[float, float, float, float]:
        """Order of merit, smallest best: the tolerated tilt (larger better), then the
        mean turn, mean work and peak torque of the starts inside (smaller better)."""
        inside = self.envelope.inside

        def worst_if_none(value: float | None) -> float:
            return math.inf if value is None else float(value)

        return (
            -self.tolerated,
            worst_if_none(inside["turn_mean"]),
            worst_if_none(inside["work_mean"]),
            worst_if_none(inside["torque_peak"]),
        )

    def row(self) -> dict[str, Any]:
        inside = self.envelope.inside
        return {
            "ratio": self.ratio,
            "force": self.force,
            "stiffness": self.stiffness,
            "compliance_z": self.compliance_z,
            "beyond_bounds": self.beyond,
            "tolerated_tilt": self.tolerated,
            "tolerated_beyond_range": bool(self.envelope.tolerated["100%"]["beyond_range"]),
            "turn_mean": inside["turn_mean"],
            "work_mean": inside["work_mean"],
            "torque_peak": inside["torque_peak"],
            "probes": self.envelope.probes,
            "seconds": self.envelope.seconds,
        }


@dataclass
class ComplianceDesign:
    """The compliance that tolerates the most misalignment (module docstring).

    Attributes
    ----------
    optimum : dict
        The setting chosen: ``force`` (N), ``stiffness`` (N m/rad), ``ratio`` (k/F, m/rad),
        ``compliance_z``, ``tolerated_tilt`` (degrees), turn, work and torque of the
        starts inside, ``at_bound`` (None, or which bound it lies at), ``beyond_bounds``.
    settings : list of dict
        Every setting evaluated (the table), in ascending ratio.
    falloff : dict
        The tolerated tilt one final refinement step either side of the optimum in ratio
        (``lower``, ``higher``: a setting's row, None beyond what may be searched), and
        the step (a factor in ratio).
    envelope : Envelope
        The optimum's coarse envelope.
    fine : Envelope or None
        The optimum's envelope at the envelope's own grid (:data:`FINE`), the figure the
        lead gives; None when not measured (``confirm=False``).
    robustness : Robustness or None
        The optimum re-evaluated over the parts' tolerance band and the friction range.
    bounds : dict
        The bounds given, the ratios they span and how far beyond them the search may go.
    held : str
        What the tool holds: upright (the nut's thread-start azimuth is unknown), or the
        pre-tilt recommended (``azimuth_known``).
    resolution : dict
        The coarse envelope's grid and tolerance.
    torque_limit : float or None
        N m; a start whose peak driver torque passes it counts as not snapping.
    notes : list of str
        The pick at a bound, the reduction to the ratio, what the figures do not say.
    seconds : float
        Wall time of the whole design.
    pretilt : dict or None
        The pre-tilt recommended (``size``, ``direction``, degrees, and its envelope's
        figures), None when held upright.
    pretilts : list of dict
        Every pre-tilt evaluated (``azimuth_known``).
    robust_setting : dict or None
        Where the optimum does not hold over what varies: the setting evaluated whose
        worst case tolerates the most (:func:`threadmate.design.most_robust`), None
        when none tolerates more than the optimum's worst case or it was not looked for.
    fine_cases : bool
        Whether the robustness cases were measured at the envelope's own grid
        (``fine=True``) rather than the coarse one.
    """

    optimum: dict[str, Any]
    settings: list[dict[str, Any]]
    falloff: dict[str, Any]
    envelope: Envelope
    fine: Envelope | None
    robustness: Any
    bounds: dict[str, Any]
    held: str
    resolution: dict[str, Any]
    torque_limit: float | None
    units: str
    seconds: float
    notes: list[str] = field(default_factory=list)
    pretilt: dict[str, Any] | None = None
    pretilts: list[dict[str, Any]] = field(default_factory=list)
    robust_setting: dict[str, Any] | None = None
    fine_cases: bool = False

    def summary_line(self) -> str:
        """What to buy and set, and what it tolerates; where that does not hold over what
        varies, what the worst case tolerates (the lead must not promise more)."""
        o = self.optimum
        tolerated = o["tolerated_tilt"] if self.pretilt is None else self.pretilt["tolerated_tilt"]
        turn, beyond = o["turn_mean"], o["tolerated_beyond_range"]
        if self.fine is not None:
            tolerated, turn = self.fine.tolerated_tilt, self.fine.inside.get("turn_mean")
            beyond = bool(self.fine.tolerated["100%"].get("beyond_range"))
        turn_words = "" if turn is None else f"; snaps after {turn:.0f} deg of turn on average"
        bound = f" (at the {o['at_bound']})" if o["at_bound"] else ""
        least = "at least " if beyond else ""
        worst = None if self.robustness is None else self.robustness.worst_case()
        caveat = ""
        if worst is not None:
            r = self.robust_setting
            instead = (
                ""
                if r is None
                else f"; over it F = {r['force']:.3g} N, k = {r['stiffness']:.3g} N m/rad "
                f"tolerates {r['tolerated_tilt']:.2f} deg"
            )
            # The cases measured at the coarse grid, beside a figure at the envelope's own.
            coarse = " at the coarse grid" if self.fine is not None and not self.fine_cases else ""
            caveat = (
                f" with the nominal parts and friction, {worst['tolerated_tilt']:.2f} deg "
                f"with {worst['case']}{coarse} (the recommendation does not hold over what "
                f"varies{instead})"
            )
        return (
            f"F = {o['force']:.3g} N, k = {o['stiffness']:.3g} N m/rad{bound}, held "
            f"{self.held}: tolerates {least}{tolerated:.2f} deg of misalignment "
            f"{self._where()}{caveat}{turn_words}"
        )

    def _where(self) -> str:
        """Where the lead's figure holds (:meth:`Envelope.where`): as the envelope it comes
        from, the fine one when measured, else the coarse one."""
        env = self.fine if self.fine is not None else self.envelope
        return "in each direction evaluated" if env is None else env.where()

    def to_dict(self) -> dict[str, Any]:
        """The JSON document (``threadmate design --json``)."""
        return {
            "units": json_units(
                self.units,
                "angle",
                "force",
                "stiffness",
                "work",
                "torque",
                "seconds",
                ratio="m/rad (stiffness over force)",
            ),
            "summary": self.summary_line(),
            "optimum": self.optimum,
            "held": self.held,
            "pretilt": self.pretilt,
            "pretilts": self.pretilts,
            "settings": self.settings,
            "falloff": self.falloff,
            "bounds": self.bounds,
            "resolution": self.resolution,
            "torque_limit": self.torque_limit,
            "envelope": self.envelope.to_dict(),
            "fine_envelope": None if self.fine is None else self.fine.to_dict(),
            "robustness": None if self.robustness is None else self.robustness.to_dict(),
            "robust_setting": self.robust_setting,
            "seconds": self.seconds,
            "notes": list(self.notes),
        }


def _bounds(name: str, value: Sequence[float], units: str, lo: float) -> tuple[float, float]:
    if isinstance(value, str) or len(value) != 2:
        raise InputError(f"{name} bounds: give two numbers (low, high) in {units}")
    a = check_range(f"{name} (low bound)", value[0], lo, 1e9, units=units)
    b = check_range(f"{name} (high bound)", value[1], lo, 1e9, units=units)
    if a > b:
        raise InputError(f"{name} bounds {a:g}:{b:g} are reversed: give the low bound first")
    return a, b


def _centres(compliance_z: float | str | Sequence[float]) -> tuple[float, ...]:
    from ..library import parse_range

    if isinstance(compliance_z, int | float):
        return (float(compliance_z),)
    try:
        values = parse_range(compliance_z, "compliance_z")
    except InputError as exc:
        raise InputError(str(exc).replace("phase", "compliance_z")) from None
    return tuple(float(v) for v in values)


class _RatioSearch:
    """The coarse-to-fine search in ``log(k/F)`` at one compliance centre."""

    def __init__(
        self,
        evaluate: Callable[[float, float, float, bool], _Setting],
        force: tuple[float, float],
        stiffness: tuple[float, float],
        may_exceed: float,
        compliance_z: float,
    ) -> None:
        self.evaluate_setting = evaluate
        self.force, self.stiffness, self.z = force, stiffness, compliance_z
        self.r_lo = stiffness[0] / force[1]
        self.r_hi = stiffness[1] / force[0]
        self.x_lo = math.log(self.r_lo / may_exceed)
        self.x_hi = math.log(self.r_hi * may_exceed)
        self.done: dict[float, _Setting] = {}

    def known(self, x: float) -> _Setting | None:
        """The setting evaluated at ``log(ratio)`` x, if any: a refinement's neighbour,
        a sum of halved steps, meets a ratio evaluated before only to rounding."""
        return next((s for k, s in self.done.items() if abs(k - x) <= SAME_RATIO), None)

    def setting(self, x: float) -> _Setting:
        """The setting of ``log(ratio)`` x: the least force within the bounds; beyond
        them the force stays at its bound and the stiffness goes beyond its own."""
        found = self.known(x)
        if found is not None:
            return found
        x = round(x, 12) + 0.0
        r = math.exp(x)
        for bound in (self.r_lo, self.r_hi):  # the bounds exactly, not through the log
            if abs(x - math.log(bound)) < 1e-11:
                r = bound
        f_lo, f_hi = self.force
        if r < self.r_lo * (1 - 1e-12):
            force, beyond = f_hi, True
        elif r > self.r_hi * (1 + 1e-12):
            force, beyond = f_lo, True
        else:
            force, beyond = min(max(f_lo, self.stiffness[0] / r), f_hi), False
        stiffness = r * force
        if not beyond:
            stiffness = min(max(stiffness, self.stiffness[0]), self.stiffness[1])
        found = self.evaluate_setting(r, force, stiffness, beyond)
        self.done[x] = found
        return found

    def best(self) -> tuple[float, _Setting]:
        x, s = min(self.done.items(), key=lambda item: item[1].key())
        return x, s

    def run(self, ratios: int, refinements: int) -> float:
        """Search; return the final step in ``log(ratio)``."""
        a, b = math.log(self.r_lo), math.log(self.r_hi)
        n = 1 if b - a < 1e-12 else max(2, ratios)
        grid = [a + (b - a) * i / (n - 1) for i in range(n)] if n > 1 else [a]
        for x in grid:
            self.setting(x)
        h = (b - a) / (n - 1) if n > 1 else math.log(2.0)
        # Walk outward while the best lies at the edge of what was evaluated and the
        # search may go further.
        while True:
            x, _ = self.best()
            known = sorted(self.done)
            if x == known[0] and x > self.x_lo + 1e-12:
                self.setting(max(x - h, self.x_lo))
            elif x == known[-1] and x < self.x_hi - 1e-12:
                self.setting(min(x + h, self.x_hi))
            else:
                break
        for _ in range(refinements):
            h /= 2
            while True:
                x, _ = self.best()
                for nx in (x - h, x + h):
                    if self.x_lo - 1e-12 <= nx <= self.x_hi + 1e-12:
                        self.setting(nx)
                if self.best()[0] == x:
                    break
        return h


def best_compliance(
    spec: ThreadSpec,
    *,
    force: Sequence[float] = (2.0, 40.0),
    stiffness: Sequence[float] = (0.1, 10.0),
    compliance_z: float | str | Sequence[float] = 0.0,
    friction: float | None = None,
    lateral_stiffness: float | None = None,
    torque_limit: float | None = None,
    may_exceed: float = 1.0,
    ratios: int = RATIOS,
    refinements: int = REFINEMENTS,
    tilt: Any = COARSE["tilt"],
    direction: Any = COARSE["direction"],
    phase: Any = COARSE["phase"],
    tolerance: float = COARSE["tolerance"],
    confirm: bool = True,
    fine: bool = False,
    robust: bool = True,
    azimuth_known: bool = False,
    pretilt_sizes: Any = "1,2",
    pretilt_directions: Any = None,
    material: Mapping[str, ThreadSpec] | None = None,
    workers: int | None = None,
    chord: float | None = None,
    progress: DesignProgress | None = None,
) -> ComplianceDesign:
    """The force and stiffness within bounds that tolerate the most misalignment
    (module docstring).

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair.
    force, stiffness : (float, float)
        Bounds on the axial force (N, > 0) and the rotational stiffness (N m/rad, > 0).
    compliance_z : float, str or sequence of float
        Compliance centre on the bolt axis (spec units, bolt frame); a range or list
        (``"0:0.1:0.05"``) is searched value by value.
    friction, lateral_stiffness : float, optional
        As :class:`threadmate.contact.Compliance` (its defaults when None).
    torque_limit : float, optional
        Driver torque limit (N m): a start whose peak torque passes it counts as not
        snapping. The reduction to the ratio still holds (torque grows with F, so the
        least force at a ratio is still best).
    may_exceed : float
        How far (a factor >= 1 on the ratio k/F) the search may go beyond the bounds when
        the best lies at one; 1: never.
    ratios : int
        Ratios of the first log-spaced grid over the bounds (>= 2).
    refinements : int
        Halvings of the grid step around the best (>= 0).
    tilt, direction, phase, tolerance
        The coarse envelope of every setting (:data:`COARSE`), as
        :func:`threadmate.design.envelope` takes them.
    confirm : bool
        Measure the optimum again at the envelope's own grid (:data:`FINE`: 16
        directions, 18 start phases, its tolerance), the figure the lead gives ("in any
        direction"). False leaves the lead at the coarse envelope, which holds only in
        the directions it evaluates (minutes less).
    fine : bool
        Measure the robustness cases at the envelope's own grid too (implies
        ``confirm``; two full envelopes more, the material conditions).
    robust : bool
        Re-evaluate the optimum at maximum and minimum material and at friction 0.08 and
        0.20 (:func:`threadmate.design.robustness`).
    azimuth_known : bool
        The nut's thread-start azimuth is known to the robot: search a pre-tilt at the
        optimum compliance (sizes ``pretilt_sizes`` by directions ``pretilt_directions``,
        default the coarse envelope's, degrees), each judged by its envelope measured
        around it; recommended only when it tolerates more than upright. Otherwise the
        bolt is held upright.
    pretilt_sizes, pretilt_directions : str or sequence of float
        The pre-tilts searched (degrees).
    material : mapping, optional
        ``{"max": spec, "min": spec}`` for the robustness; default from the spec's
        designation, keeping its point and countersink.
    workers, chord
        As :func:`threadmate.design.envelope`.
    progress : callable, optional
        ``progress(text)`` before each envelope.

    Returns
    -------
    ComplianceDesign

    Raises
    ------
    InputError
        Reversed or non-positive bounds, a bad factor, count or grid.
    """
    start = time.perf_counter()
    if not isinstance(spec, ThreadSpec):
        raise InputError(f"spec must be a ThreadSpec, got {type(spec).__name__}")
    f_bounds = _bounds("force", force, "N", 1e-6)
    k_bounds = _bounds("stiffness", stiffness, "N m/rad", 1e-9)
    may_exceed = check_range("may_exceed (factor on k/F)", may_exceed, 1.0, 1e3)
    if not isinstance(ratios, int) or ratios < 2:
        raise InputError(f"ratios must be a whole number >= 2, got {ratios!r}")
    if not isinstance(refinements, int) or not 0 <= refinements <= 8:
        raise InputError(f"refinements must be a whole number in [0, 8], got {refinements!r}")
    centres = _centres(compliance_z)
    base = Compliance() if friction is None else Compliance(friction=friction)
    # The grid, tolerance and compliance checked before any work.
    from ..library import PolarGrid

    PolarGrid.parse(tilt, direction, phase)
    if azimuth_known:
        PolarGrid.parse(
            pretilt_sizes, direction if pretilt_directions is None else pretilt_directions, "0"
        )
    check_range("tolerance (degrees)", tolerance, 1e-3, 1.0)
    for z in centres:
        Compliance(compliance_z=z, lateral_stiffness=lateral_stiffness, friction=base.friction)
    coarse = {"tilt": tilt, "direction": direction, "phase": phase, "tolerance": tolerance}
    count = 0
    # The friction cases of the robustness, located with each setting in the same pass
    # (little more than the nominal alone): the optimum's robustness and the look for
    # the setting that holds best then need no envelope of their own at them. Without
    # friction the torques tell no proportion, and each held tilt would be walked at
    # each friction: the robustness then locates them for the optimum alone.
    frictions = FRICTION_RANGE if robust and base.friction > 0 else ()

    def evaluate(z: float) -> Callable[[float, float, float, bool], _Setting]:
        def one(r: float, f: float, k: float, beyond: bool) -> _Setting:
            nonlocal count
            count += 1
            if progress is not None:
                progress(f"setting {count}: F {f:.4g} N, k {k:.4g} N m/rad (k/F {r:.4g})")
            comp = Compliance(
                force=f,
                stiffness=k,
                lateral_stiffness=lateral_stiffness,
                compliance_z=z,
                friction=base.friction,
            )
            env = envelope(
                spec,
                compliance=comp,
                workers=workers,
                chord=chord,
                torque_limit=torque_limit,
                frictions=frictions,
                **coarse,
            )
            return _Setting(r, f, k, z, beyond, env)

        return one

    searches = []
    for z in centres:
        s = _RatioSearch(evaluate(z), f_bounds, k_bounds, may_exceed, z)
        h = s.run(ratios, refinements)
        searches.append((s, h))
    search, h = min(searches, key=lambda sh: sh[0].best()[1].key())
    x, best = search.best()
    notes: list[str] = []
    at_bound = _at_bound(search, x, best, may_exceed, notes)
    if lateral_stiffness is not None:
        notes.append(
            "with a lateral stiffness the envelope depends on its ratio to the force too, "
            "which the search does not hold fixed: the least force at a ratio is then not "
            "proved best"
        )
    if best.envelope.tolerated["100%"]["beyond_range"]:
        notes.append(
            "every start phase snaps up to the largest tilt size searched in every "
            "direction: the optimum tolerates at least that; search larger sizes (tilt)"
        )
    if len(centres) > 1:
        notes.append(
            "compliance centres searched: "
            + ", ".join(f"{z:g}" for z in centres)
            + f" {spec.units}; the best is at {best.compliance_z:g} {spec.units}"
        )
    notes.append(
        "the envelope depends on force and stiffness only through k/F (the rest states "
        "minimise U/F); at each ratio the least force within the bounds is taken, as it "
        "needs the least work and torque"
    )
    settings = sorted(
        (s.row() for sr, _ in searches for s in sr.done.values()),
        key=lambda r: (r["compliance_z"], r["ratio"]),
    )
    falloff = {
        "step": math.exp(h),
        "lower": _row_or_none(search, x - h),
        "higher": _row_or_none(search, x + h),
    }
    optimum = {**best.row(), "at_bound": at_bound}
    fine_env = None
    comp = _compliance_of(best, base, lateral_stiffness)
    pretilt = None
    pretilts: list[dict[str, Any]] = []
    if azimuth_known:
        pretilt, pretilts = _pretilt_search(
            spec,
            comp,
            best,
            sizes=pretilt_sizes,
            directions=direction if pretilt_directions is None else pretilt_directions,
            progress=progress,
            envelope_settings={
                "workers": workers,
                "chord": chord,
                "torque_limit": torque_limit,
                **coarse,
            },
        )
    held = "upright"
    if pretilt is not None:
        held = (
            f"pre-tilted {pretilt['size']:g} deg toward {pretilt['direction']:g} deg "
            "(azimuth from the nut's thread start)"
        )
    elif azimuth_known:
        held = "upright (no pre-tilt searched tolerates more)"
    at = None if pretilt is None else (pretilt["size"], pretilt["direction"])
    if confirm or fine:
        if progress is not None:
            progress("the optimum at the envelope's own grid")
        fine_env = envelope(
            spec,
            compliance=comp,
            workers=workers,
            chord=chord,
            torque_limit=torque_limit,
            pretilt=at,
            frictions=frictions,
            **FINE,
        )
    robustness = None
    if robust:
        from ._robust import robustness as robust_of

        grid = FINE if fine else coarse
        robustness = robust_of(
            spec,
            comp,
            nominal=fine_env if fine else (best.envelope if pretilt is None else None),
            pretilt=at,
            material=material,
            torque_limit=torque_limit,
            workers=workers,
            chord=chord,
            progress=progress,
            **grid,
        )
    robust_setting = None
    worst = None if robustness is None else robustness.worst_case()
    if worst is not None:
        if fine or pretilt is not None:
            notes.append(
                "the setting that holds best over what varies is looked for upright at the "
                "coarse resolution only"
            )
        else:
            from ._robust import most_robust

            ranked = sorted(
                (s for sr, _ in searches for s in sr.done.values() if s is not best),
                key=_Setting.key,
            )
            robust_setting = most_robust(
                spec,
                [(s.row(), _compliance_of(s, base, lateral_stiffness), s.envelope) for s in ranked],
                min(best.tolerated, worst["tolerated_tilt"]),
                material=material,
                torque_limit=torque_limit,
                workers=workers,
                chord=chord,
                progress=progress,
                **coarse,
            )
    return ComplianceDesign(
        optimum=optimum,
        settings=settings,
        falloff=falloff,
        envelope=best.envelope,
        fine=fine_env,
        robustness=robustness,
        bounds={
            "force": list(f_bounds),
            "stiffness": list(k_bounds),
            "ratio": [search.r_lo, search.r_hi],
            "may_exceed": may_exceed,
            "compliance_z": list(centres),
        },
        held=held,
        pretilt=pretilt,
        pretilts=pretilts,
        resolution=dict(coarse),
        torque_limit=torque_limit,
        units=spec.units,
        seconds=time.perf_counter() - start,
        notes=notes,
        robust_setting=robust_setting,
        fine_cases=fine and robustness is not None,
    )


def _compliance_of(s: _Setting, base: Compliance, lateral_stiffness: float | None) -> Compliance:
    """The compliance of a setting evaluated."""
    return Compliance(
        force=s.force,
        stiffness=s.stiffness,
        lateral_stiffness=lateral_stiffness,
        compliance_z=s.compliance_z,
        friction=base.friction,
    )


def _row_or_none(search: _RatioSearch, x: float) -> dict[str, Any] | None:
    found = search.known(x)
    return None if found is None else found.row()


def _at_bound(
    search: _RatioSearch, x: float, best: _Setting, may_exceed: float, notes: list[str]
) -> str | None:
    """Which bound the pick lies at (None: inside), with the note that says so."""
    r = best.ratio
    where = None
    if best.beyond:
        limit = abs(x - search.x_lo) < 1e-9 or abs(x - search.x_hi) < 1e-9
        where = "limit of may_exceed" if limit else "outside the bounds"
        notes.append(
            f"the pick lies beyond the bounds (k/F {r:.4g} m/rad against "
            f"{search.r_lo:.4g} to {search.r_hi:.4g})"
            + (
                f", at the limit of may_exceed {may_exceed:g}: the best may lie further out"
                if limit
                else ""
            )
        )
    elif abs(r - search.r_lo) <= 1e-9 * r:
        where = "low bound of k/F (stiffness low, force high)"
    elif abs(r - search.r_hi) <= 1e-9 * r:
        where = "high bound of k/F (stiffness high, force low)"
    if where is not None and not best.beyond:
        notes.append(
            f"the pick lies at the {where}: the best may lie beyond it"
            + (
                "; allow the search beyond the bounds (may_exceed) to look"
                if may_exceed <= 1.0
                else ""
            )
        )
    return where


def format_compliance_design(design: ComplianceDesign) -> str:
    """The design as text: the sentence, the settings evaluated, the fall-off, the
    robustness, the notes."""
    lines = [design.summary_line() + "."]
    if not design.pretilts:
        lines.append(
            "The nut's thread-start azimuth is unknown to the robot: hold the bolt upright "
            "(no pre-tilt)."
        )
    res = design.resolution
    lines.append(
        f"Each setting evaluated with a coarse envelope (directions {res['direction']}, "
        f"phases {res['phase']}, sizes {res['tilt']} deg, bisected to {res['tolerance']:g} "
        "deg)."
    )
    if design.fine is None:
        lines.append(
            "A worst direction or phase between those evaluated can tolerate less: without "
            "--no-confirm the optimum is measured at the envelope's own grid, the figure "
            "to rely on."
        )
    else:
        lines.append(
            f"At the envelope's own grid the optimum {design.fine.summary_line()}; the "
            "figure above."
        )
    lines += [
        "",
        "| k/F m/rad | F N | k N m/rad | tolerated deg | turn mean deg | work mean mJ "
        "| peak torque N m |",
        "|---|---|---|---|---|---|---|",
    ]
    o = design.optimum
    for r in design.settings:
        mark = (
            " (best)" if r["ratio"] == o["ratio"] and r["compliance_z"] == o["compliance_z"] else ""
        )
        mark += " (beyond bounds)" if r["beyond_bounds"] else ""
        lines.append(
            f"| {r['ratio']:.4g}{mark} | {r['force']:.4g} | {r['stiffness']:.4g} | "
            f"{'>=' if r['tolerated_beyond_range'] else ''}{r['tolerated_tilt']:.2f} | "
            f"{_num(r['turn_mean'], '.0f')} | "
            f"{_num(r['work_mean'], '.3g')} | {_num(r['torque_peak'], '.3g')} |"
        )
    if design.pretilts:
        up = design.optimum["tolerated_tilt"]
        lines += [
            "",
            f"Pre-tilts at the optimum (the nut's azimuth known; upright tolerates {up:.2f} "
            "deg), each envelope measured around the pre-tilt:",
            "",
            "| pre-tilt deg | toward deg | tolerated deg | turn mean deg | work mean mJ |",
            "|---|---|---|---|---|",
        ]
        for p in design.pretilts:
            lines.append(
                f"| {p['size']:g} | {p['direction']:g} | {p['tolerated_tilt']:.2f} | "
                f"{_num(p['turn_mean'], '.0f')} | {_num(p['work_mean'], '.3g')} |"
            )
    f = design.falloff
    sides = []
    for side in ("lower", "higher"):
        row = f[side]
        sides.append(
            f"{side} k/F: not searched"
            if row is None
            else f"{side} k/F ({row['ratio']:.4g}): {row['tolerated_tilt']:.2f} deg"
        )
    lines += [
        "",
        f"Fall-off one step (x{f['step']:.3g} in k/F) either side of the optimum "
        f"({o['tolerated_tilt']:.2f} deg): " + "; ".join(sides) + ".",
    ]
    if design.robustness is not None:
        from ._robust import format_robustness

        lines += ["", format_robustness(design.robustness)]
    rs = design.robust_setting
    if rs is not None:
        cases = "; ".join(f"{c['case']} {c['tolerated_tilt']:.2f} deg" for c in rs["cases"])
        lines += [
            "",
            f"Of the settings evaluated, the one that holds best over what varies: "
            f"F = {rs['force']:.4g} N, k = {rs['stiffness']:.4g} N m/rad "
            f"(k/F {rs['ratio']:.4g}): {rs['tolerated_tilt']:.2f} deg in its worst case "
            f"({rs['nominal_tolerated_tilt']:.2f} nominal; {cases}).",
        ]
    lines += [f"note: {n}" for n in design.notes]
    lines.append(f"{len(design.settings)} settings evaluated in {design.seconds:.0f} s.")
    return "\n".join(lines)


def _num(value: float | None, fmt: str) -> str:
    from .._text import number_text

    return number_text(value, fmt)


def plot_compliance_design(design: ComplianceDesign, path: str | os.PathLike[str]) -> Path:
    """Tolerated tilt (degrees) against the ratio k/F (log axis) of every setting
    evaluated, the optimum marked and the bounds drawn. Written atomically (.png, .pdf or
    .svg by the suffix)."""
    from .._figures import new_figure, save_figure

    fig = new_figure((6.4, 4.2))
    ax: Any = fig.add_subplot()
    for z in sorted({r["compliance_z"] for r in design.settings}):
        rows = [r for r in design.settings if r["compliance_z"] == z]
        ax.plot(
            [r["ratio"] for r in rows],
            [r["tolerated_tilt"] for r in rows],
            "o-",
            ms=4,
            label=f"compliance centre {z:g} {design.units}",
        )
    o = design.optimum
    ax.plot([o["ratio"]], [o["tolerated_tilt"]], "*", ms=14, color="C3", label="optimum")
    for r in design.bounds["ratio"]:
        ax.axvline(r, color="0.5", lw=0.8, ls="--")
    ax.set_xscale("log")
    ax.set_xlabel("k/F (m/rad): stiffness over force")
    ax.set_ylabel("tolerated misalignment (deg)")
    beyond = [r for r in design.settings if r["tolerated_beyond_range"]]
    if beyond:
        ax.plot(
            [r["ratio"] for r in beyond],
            [r["tolerated_tilt"] for r in beyond],
            "^",
            ms=9,
            mfc="none",
            color="0.3",
            label="at least (largest size searched)",
        )
    ax.set_title(
        f"optimum F {o['force']:.3g} N, k {o['stiffness']:.3g} N m/rad: "
        f"{o['tolerated_tilt']:.2f} deg (coarse envelopes)\ndashed: the bounds of k/F",
        fontsize="medium",
    )
    ax.legend(fontsize=8)
    return save_figure(fig, path)


def _pretilt_search(
    spec: ThreadSpec,
    compliance: Compliance,
    upright: _Setting,
    *,
    sizes: Any,
    directions: Any,
    progress: DesignProgress | None,
    envelope_settings: dict[str, Any],
) -> tuple[dict[str, Any] | None, list[dict[str, Any]]]:
    """The pre-tilt that tolerates the most (by the settings' order of merit), each
    judged by its envelope measured around it, and the table of those evaluated; None
    when none beats upright."""
    from ..library import parse_range

    sizes_deg = [s for s in parse_range(sizes, "tilt") if s > 0]
    directions_deg = sorted({d % 360.0 for d in parse_range(directions, "direction")})
    rows = []
    best, best_key = None, upright.key()
    for size in sizes_deg:
        for d in directions_deg:
            if progress is not None:
                progress(f"pre-tilt {size:g} deg toward {d:g} deg")
            env = envelope(spec, compliance=compliance, pretilt=(size, d), **envelope_settings)
            s = _Setting(
                upright.ratio, upright.force, upright.stiffness, upright.compliance_z, False, env
            )
            row = {
                "size": size,
                "direction": d,
                "tolerated_tilt": env.tolerated_tilt,
                "turn_mean": env.inside["turn_mean"],
                "work_mean": env.inside["work_mean"],
                "torque_peak": env.inside["torque_peak"],
            }
            rows.append(row)
            if s.key() < best_key:
                best, best_key = row, s.key()
    return best, rows
