"""The capture envelope of a compliance (docs/design.md; docs/mechanics.md,
"Recommendations").

For each direction of misalignment relative to the nut's thread start (the azimuth in F,
from +X toward +Y, toward which the bolt's axis leans: a polar grid's direction), the
envelope at level L is the largest held tilt size s such that at every size up to s the
share L of the start phases snaps within one turn (the first crossing, from upright
outward). The *tolerated misalignment* is the smallest 100 % envelope over the
directions: the tilt a compliance tolerates whatever the direction.

The envelope is located by a search along each direction, not read off a grid: the grid's
sizes are evaluated outward until the share falls below the lowest level, and then, for
each level, the size is bisected between the last grid size where the level holds and
the first where it does not, until the bracket is no wider than the tolerance. Each size
probed is one held tilt with every phase of the grid, computed by the library's sweep
machinery (:class:`threadmate.library.HeldTiltProbe`) and read as the network reads a
library (:func:`threadmate.network.start_outcomes`). A start whose drop failed, or whose
search does not snap within one turn for any reason, counts as not snapping; so does,
when a torque limit is given, a start whose driver torque passes it on the way (the
driver would stop it).

Angles in degrees, forces in N, stiffness in N m/rad, work in mJ, torque in N m, lengths
in the spec's units.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .._errors import InputError
from .._units import json_units
from .._validate import check_range
from ..contact import CONTINUATION_STEP, PHASE_TOLERANCE, Compliance
from ..geometry import ThreadSpec, polar_from_held_tilt
from ..library import (
    DEFAULT_POLAR_RANGES,
    METADATA_FILE,
    Grid,
    HeldTiltProbe,
    PolarGrid,
    info,
    load,
    read_grid,
)

__all__ = [
    "ENVELOPE_PHASES",
    "LEVELS",
    "SAME_DIRECTION",
    "TOLERANCE",
    "Envelope",
    "EnvelopeProgress",
    "envelope",
    "grid_envelope",
]

#: The shares of start phases whose envelopes are located: every phase, 95 %, 50 %.
LEVELS = (1.0, 0.95, 0.5)
#: How closely each envelope is located in tilt size (degrees): the bisection stops when
#: the last size where the level holds and the first where it does not are this close.
TOLERANCE = 0.05
#: The default start phases of an envelope from a spec (degrees): every 20, as
#: ``threadmate run``'s grid.
ENVELOPE_PHASES = "0:340:20"
#: Narrowest tolerance accepted (degrees).
MIN_TOLERANCE = 1e-3
#: Directions of misalignment, at the least, over which an envelope's figure is said to hold
#: in any direction: the default polar grid's (every 22.5 degrees). Measured over fewer, it
#: holds in those it evaluates: a worst direction between them can tolerate less.
ANY_DIRECTION = len(PolarGrid.parse().direction)
#: ``progress(held_tilts_done, held_tilts_asked)``, cumulative over the search's rounds.
EnvelopeProgress = Callable[[int, int], None]

_UP = None  # the direction key of the upright held tilt, shared by every direction


def _level_key(level: float) -> str:
    return f"{100 * level:g}%"


def _figures(out: pd.DataFrame) -> dict[str, Any]:
    """Turn, work, click and peak torque of starts (rows of ``start_outcomes``) that snap;
    the torque over every start."""
    snapped = out[out["snapped"] & ~out["failed"]]
    clicks = snapped.loc[snapped["turn"] > 0, "click"].dropna()

    def stat(series: pd.Series, how: str) -> float | None:
        series = series.dropna()
        if series.empty:
            return None
        return float(getattr(series, how)())

    return {
        "starts": len(out),
        "snapped": len(snapped),
        "failed": int(out["failed"].sum()),
        "turn_mean": stat(snapped["turn"], "mean"),
        "turn_worst": stat(snapped["turn"], "max"),
        "work_mean": stat(snapped["work"], "mean"),
        "work_worst": stat(snapped["work"], "max"),
        "click_mean": stat(clicks, "mean"),
        "click_min": stat(clicks, "min"),
        "torque_peak": stat(out["torque_peak"], "max"),
    }


def _share(out: pd.DataFrame) -> float:
    """Share of the starts that snap within one turn (a failed start does not)."""
    if out.empty:
        return 0.0
    return float((out["snapped"] & ~out["failed"]).sum() / len(out))


@dataclass
class Envelope:
    """The capture envelope of one compliance (module docstring).

    Attributes
    ----------
    directions : list of dict
        One per direction (degrees): ``direction``; ``tilt`` (per level, "100%", "95%",
        "50%": the envelope in degrees); ``first_failure`` (per level: the smallest size
        probed above it where the level fails, None when none did); ``beyond_range`` (per
        level: no size searched failed, the envelope is at least the largest);
        ``shares`` (``[size, share]`` of every size evaluated, ascending); ``inside``
        (turn, work, click and peak torque of the starts at the sizes evaluated up to the
        100 % envelope).
    tolerated : dict
        Per level, the smallest envelope over the directions (``tilt``) and the
        direction(s) where it lies (``worst_directions``).
    inside : dict
        Turn (deg), work (mJ), click (spec units) and peak torque (N m) of the starts at
        every size evaluated up to the tolerated misalignment, in every direction.
    compliance : dict
        Force (N), stiffness (N m/rad), lateral stiffness, friction and centre.
    spec, grid : dict
        The thread pair and the polar grid searched.
    tolerance : float
        The bisection's tolerance (degrees).
    units : str
        Length units of the spec.
    probes : int
        Held tilts computed for this envelope (the library's own not counted).
    seconds : float
        Wall time.
    notes : list of str
        What the figures do not say by themselves.
    located : bool
        True: each envelope is bisected to ``tolerance``; False: read off a library's
        grid (:func:`grid_envelope`), each between the sizes the grid holds in its
        direction.
    torque_limit : float or None
        The driver's torque limit (N m) past which a start counts as not snapping; None:
        none.
    pretilt : (float, float) or None
        The pre-tilt ``(size, direction)`` (degrees) around which the misalignment is
        measured; None: upright.
    friction_cases : dict
        ``{friction: Envelope}``: the envelope of the same compliance at each other
        friction coefficient asked (:func:`envelope`'s ``frictions``), located in the same
        pass; empty when none was asked. Not in :meth:`to_dict`.
    floor : float or None
        The floor :func:`envelope` was given (degrees): the search stopped once the
        tolerated tilt was known to be no more than it, and a note says when it did.
    """

    directions: list[dict[str, Any]]
    tolerated: dict[str, Any]
    inside: dict[str, Any]
    compliance: dict[str, Any]
    spec: dict[str, Any]
    grid: dict[str, Any]
    tolerance: float
    units: str
    probes: int
    seconds: float
    source: str
    notes: list[str] = field(default_factory=list)
    located: bool = True
    torque_limit: float | None = None
    pretilt: tuple[float, float] | None = None
    friction_cases: dict[float, Envelope] = field(default_factory=dict)
    floor: float | None = None

    @property
    def tolerated_tilt(self) -> float:
        """The tolerated misalignment: every start phase snaps within one turn up to this
        tilt (degrees) in any direction."""
        return float(self.tolerated[_level_key(1.0)]["tilt"])

    def to_dict(self) -> dict[str, Any]:
        """The JSON document (``threadmate envelope --json``)."""
        return {
            "units": json_units(
                self.units,
                "angle",
                "force",
                "stiffness",
                "lateral_stiffness",
                "work",
                "torque",
                "share",
            ),
            "definition": (
                "per direction (azimuth in F from +X toward +Y toward which the bolt's axis "
                "leans) and level L: the largest held tilt size up to which, at every size, "
                "the share L of start phases snaps within one turn; tolerated: the smallest "
                "over directions"
            ),
            "tolerated_tilt": self.tolerated_tilt,
            "tolerated": self.tolerated,
            "inside": self.inside,
            "directions": self.directions,
            "compliance": self.compliance,
            "spec": self.spec,
            "grid": self.grid,
            "tolerance": self.tolerance,
            "located": self.located,
            "torque_limit": self.torque_limit,
            "pretilt": None
            if self.pretilt is None
            else {"size": self.pretilt[0], "direction": self.pretilt[1]},
            "levels": [_level_key(v) for v in LEVELS],
            "source": self.source,
            "probes": self.probes,
            "seconds": self.seconds,
            "notes": list(self.notes),
        }

    def summary_line(self) -> str:
        """One sentence: what the compliance tolerates."""
        t = self.tolerated[_level_key(1.0)]
        worst = ", ".join(f"{d:g}" for d in t["worst_directions"])
        if not self.located:
            return (
                f"every start phase snaps within one turn up to {t['tilt']:.2f} deg of "
                f"misalignment in each of the {len(self.directions)} directions the grid "
                f"holds (worst direction {worst} deg; read off the grid, not located)"
            )
        return (
            f"tolerates {t['tilt']:.2f} deg of misalignment {self.where()} (every start "
            f"phase snaps within one turn; worst direction {worst} deg)"
        )

    def where(self) -> str:
        """Where the tolerated tilt holds, in words: in any direction when the envelope
        evaluates :data:`ANY_DIRECTION` directions or more, else in each of those it
        evaluates."""
        n = len(self.directions)
        if n >= ANY_DIRECTION:
            return "in any direction"
        return (
            "in the one direction evaluated"
            if n == 1
            else f"in each of the {n} directions evaluated"
        )


class _Search:
    """The evaluated held tilts and the bisection's brackets, direction by direction."""

    def __init__(
        self, sizes: Sequence[float], tolerance: float, upright_alone: bool = False
    ) -> None:
        self.tolerance = tolerance
        #: Ask the upright held tilt before any other (see :meth:`needed`).
        self.upright_alone = upright_alone
        #: The grid's tilted sizes, walked outward along each direction.
        self.sizes = [t for t in sizes if t > 0]
        self.outcomes: dict[tuple[float, float | None], pd.DataFrame] = {}

    @staticmethod
    def key(size: float, direction: float) -> tuple[float, float | None]:
        size = round(size, 9) + 0.0
        return (0.0, _UP) if size == 0 else (size, direction)

    def evaluated(self, direction: float) -> list[tuple[float, float]]:
        """``(size, share)`` of the sizes evaluated in ``direction``, ascending."""
        out = []
        for (size, d), rows in self.outcomes.items():
            if d is _UP or d == direction:
                out.append((size, _share(rows)))
        return sorted(out)

    @staticmethod
    def bracket(known: list[tuple[float, float]], level: float) -> tuple[float, float | None]:
        """The last size up to which the level holds at every size evaluated, and the
        next size evaluated (where it fails; None when none does)."""
        lo = 0.0
        for size, share in known:
            if share + 1e-12 < level:
                return lo, size
            lo = size
        return lo, None

    def needed(self, direction: float) -> set[float]:
        """The sizes to evaluate next in ``direction`` (empty: located)."""
        known = self.evaluated(direction)
        if not known or known[0][0] != 0:
            # Upright first, and the grid's first size with it: it is almost always
            # needed, and the upright tilt alone would leave every worker but one idle;
            # alone where its failure would end the search (a floor).
            return {0.0} if self.upright_alone else {0.0, *self.sizes[:1]}
        done = {s for s, _ in known}
        lowest = min(LEVELS)
        need = set()
        if all(share + 1e-12 >= lowest for _, share in known):
            # The walk outward along the grid's sizes, beside the bisections below (a
            # bracket holds whatever lies further out).
            need.update(next(([s] for s in self.sizes if s not in done), []))
        for level in LEVELS:
            lo, hi = self.bracket(known, level)
            if hi is not None and hi - lo > self.tolerance and lo != hi:
                need.add(round(0.5 * (lo + hi), 9) + 0.0)
        return need

    def at_most(self, directions: Sequence[float], floor: float) -> bool:
        """Whether the tolerated tilt is known to be no more than ``floor``: in some
        direction a size no larger than it fails at the 100 % level (the envelope lies
        below that size)."""
        for d in directions:
            _, hi = self.bracket(self.evaluated(d), 1.0)
            if hi is not None and hi <= floor + 1e-12:
                return True
        return False


def _library_source(path: Path) -> tuple[ThreadSpec, dict[str, Any], PolarGrid, pd.DataFrame]:
    """A polar mechanics library: its spec, metadata, grid and rows."""
    doc = info(path)
    meta = doc["metadata"]
    if meta["model"] != "mechanics":
        raise InputError(
            f"{path} holds the thesis's fixed-pivot rows: the envelope stands on the "
            "mechanics (sweep again with the mechanics model, the default)"
        )
    grid = read_grid(meta["grid"])
    if not isinstance(grid, PolarGrid):
        raise InputError(
            f"{path} holds a roll/pitch grid: the envelope searches along directions; sweep "
            "a polar grid (tilt and direction), or give the spec"
        )
    if meta["mesh"].get("bolt") or meta["mesh"].get("nut"):
        raise InputError(
            f"{path} was swept with meshes from CAD, which the envelope's probes would need "
            "again: give the spec and the mesh files"
        )
    return ThreadSpec.from_dict(meta["spec"]), meta, grid, load(path)


def _outcomes(rows: pd.DataFrame, torque_limit: float | None = None) -> pd.DataFrame:
    """Every start's passive search (the network's reading of a library's rows); with a
    torque limit (N m), a start whose peak driver torque passes it does not snap."""
    from ..network import build_network, start_outcomes

    out = start_outcomes(build_network(rows))
    if torque_limit is not None and not out.empty:
        out = out.copy()
        out.loc[out["torque_peak"] > torque_limit, "snapped"] = False
    return out


def envelope(
    source: ThreadSpec | str | os.PathLike[str],
    *,
    compliance: Compliance | None = None,
    tilt: Any = None,
    direction: Any = None,
    phase: Any = None,
    tolerance: float = TOLERANCE,
    workers: int | None = None,
    scheduler: str | None = None,
    chord: float | None = None,
    step: float = CONTINUATION_STEP,
    phase_tolerance: float = PHASE_TOLERANCE,
    torque_limit: float | None = None,
    pretilt: tuple[float, float] | None = None,
    frictions: Sequence[float] = (),
    floor: float | None = None,
    progress: EnvelopeProgress | None = None,
) -> Envelope:
    """The capture envelope of a compliance (module docstring).

    Parameters
    ----------
    source : ThreadSpec or path-like
        A thread pair (swept along the directions on demand), or a mechanics library of a
        polar grid (``threadmate sweep --tilt ... --direction ...``), whose held tilts are
        read and whose compliance, phases and settings the probes between its sizes use.
    compliance : Compliance, optional
        From a spec: the compliance (default :class:`~threadmate.contact.Compliance()`).
        A library's is its own.
    tilt, direction, phase : str, float or sequence, optional
        From a spec: the polar grid's sizes (default ``0:4:0.5``), directions (default
        ``0:360:22.5``) and start phases (default :data:`ENVELOPE_PHASES`), degrees, as
        :class:`threadmate.library.PolarGrid` takes them. A library's are its own.
    tolerance : float
        Width in tilt size to which each envelope is bisected (degrees, default
        :data:`TOLERANCE`).
    workers, scheduler, chord, step, phase_tolerance
        As :func:`threadmate.library.sweep` (a library's chord and continuation settings
        are its own).
    torque_limit : float, optional
        The driver's torque limit (N m, > 0): a start whose peak driver torque passes it
        counts as not snapping (the driver stops it). None: no limit.
    pretilt : (float, float), optional
        From a spec: a deliberate pre-tilt, as a polar held tilt ``(size, direction)``
        (degrees), around which the misalignment is measured: each held tilt probed is the
        misalignment's rotation (in F) applied to the pre-tilted axis
        (:func:`compose_tilts`). None: upright.
    frictions : sequence of float, optional
        From a spec: other friction coefficients at which to locate the envelope of the
        same compliance in the same pass (:attr:`Envelope.friction_cases`). The rest
        states are frictionless; each held tilt is walked once and its rows scaled to the
        other coefficients wherever its snaps' proofs judge alike there
        (:func:`threadmate.library.HeldTiltProbe`), and each envelope is located by its
        own bisection, exactly as :func:`envelope` alone at that coefficient would.
    floor : float, optional
        Degrees: stop as soon as the tolerated tilt is known to be no more than this (a
        search that must beat a figure needs no more); the upright held tilt is then
        asked first, alone, as its failure settles it. The tolerated tilt returned is
        then at most ``floor`` and the other figures are those of the held tilts computed
        so far (a note says so; the friction cases stop with it). Above the floor the
        envelope is the one located without it. None: locate it whole.
    progress : callable, optional
        ``progress(done, asked)``: held tilts computed and asked for so far.

    Returns
    -------
    Envelope

    Raises
    ------
    InputError
        A bad grid or value, grid or compliance arguments with a library, a library of the
        thesis's model, of a roll/pitch grid or of CAD meshes.
    """
    start = time.perf_counter()
    tolerance = check_range("tolerance (degrees)", tolerance, MIN_TOLERANCE, 1.0)
    if torque_limit is not None:
        torque_limit = check_range("torque_limit", torque_limit, 1e-9, 1e6, units="N m")
    if floor is not None:
        floor = check_range("floor (degrees)", floor, 0.0, 90.0)
    if isinstance(source, ThreadSpec):
        spec = source
        grid = PolarGrid.parse(
            DEFAULT_POLAR_RANGES["tilt"] if tilt is None else tilt,
            DEFAULT_POLAR_RANGES["direction"] if direction is None else direction,
            ENVELOPE_PHASES if phase is None else phase,
        )
        compliance = Compliance() if compliance is None else compliance
        base_meta = None
        rows = None
        where = "spec"
    elif isinstance(source, str | os.PathLike):
        if pretilt is not None:
            raise InputError("pretilt: an envelope from a library is measured around upright")
        path = Path(source)
        if not (path / METADATA_FILE).is_file():
            raise InputError(f"{path} is not a threadmate library (no {METADATA_FILE})")
        given = [
            n
            for n, v in (("tilt", tilt), ("direction", direction), ("phase", phase))
            if v is not None
        ]
        if compliance is not None:
            given.insert(0, "compliance")
        if chord is not None:
            given.append("chord")
        if given:
            raise InputError(
                f"{given[0]} is the library's own: an envelope from a library keeps its "
                "grid, compliance and mesh (give the spec to choose them)"
            )
        spec, base_meta, grid, rows = _library_source(path)
        compliance = Compliance.from_dict(base_meta["compliance"])
        chord = float(base_meta["mesh"]["chord"])
        cont = base_meta.get("continuation") or {}
        step = float(cont.get("step", step))
        phase_tolerance = float(cont.get("phase_tolerance", phase_tolerance))
        where = str(path)
    else:
        raise InputError(
            f"source must be a ThreadSpec or a library directory, got {type(source).__name__}"
        )
    if frictions and rows is not None:
        raise InputError("frictions: an envelope from a library is at the library's friction")
    directions = [float(d) for d in grid.direction]
    with HeldTiltProbe(
        spec,
        grid.phase,
        compliance=compliance,
        chord=chord,
        step=step,
        phase_tolerance=phase_tolerance,
        workers=workers,
        scheduler=scheduler,
        base_metadata=base_meta,
        frictions=frictions,
    ) as probe:
        # One search per friction coefficient, each asking the held tilts its own
        # bisection needs; a held tilt comes back at every coefficient.
        searches = {
            mu: _Search(grid.tilt, tolerance, upright_alone=floor is not None)
            for mu in probe.frictions
        }
        if rows is not None and not rows.empty:
            outcomes = _outcomes(rows, torque_limit)
            polar = dict(zip(grid.held_tilts, grid.polar_tilts, strict=True))
            for (r, p), group in outcomes.groupby(["held_roll", "held_pitch"], sort=False):
                size, d = polar[(float(r), float(p))]  # type: ignore[arg-type]
                own = searches[compliance.friction]
                own.outcomes[own.key(size, d)] = group
        computed: dict[float, dict[tuple[float, float | None], pd.DataFrame]] = {
            mu: {} for mu in probe.frictions
        }
        used: dict[float, int] = dict.fromkeys(probe.frictions, 0)
        asked = done = 0
        # Each direction's next size is asked as soon as the sizes it depends on are in:
        # the workers stay busy while directions bisect at their own pace. A held tilt
        # goes to each search that asked for it as it comes back, as it would alone.
        in_flight: dict[tuple[float, float | None], tuple[float, float]] = {}
        wanted: dict[tuple[float, float | None], set[float]] = {}
        nominal = searches[probe.frictions[0]]

        def settled() -> bool:
            return floor is not None and nominal.at_most(directions, floor)

        while True:
            found_one = True
            # A held tilt already computed may settle what comes next; past the floor
            # nothing more is asked (those in flight still come back and count).
            while found_one and not settled():
                found_one = False
                for mu, search in searches.items():
                    for d in directions:
                        for size in sorted(search.needed(d)):
                            k = search.key(size, d)
                            if k in search.outcomes or mu in wanted.get(k, ()):
                                continue
                            if k in computed[mu]:
                                search.outcomes[k] = computed[mu][k]
                                used[mu] += 1
                                found_one = True
                                continue
                            wanted.setdefault(k, set()).add(mu)
                            if k in in_flight:
                                continue
                            at = (k[0], d if k[1] is not _UP else directions[0])
                            in_flight[k] = at if pretilt is None else compose_tilts(pretilt, at)
                            probe.submit(*in_flight[k])
                            asked += 1
            if not in_flight:
                break
            if progress is not None:
                progress(done, asked)
            at, each = probe.next_done_each()
            k = next(key for key, value in in_flight.items() if value == at)
            del in_flight[k]
            for mu, found in each.items():
                computed[mu][k] = _outcomes(found, torque_limit)
            for mu in wanted.pop(k):
                searches[mu].outcomes[k] = computed[mu][k]
                used[mu] += 1
            done += 1
        if progress is not None:
            progress(done, asked)
        mu0 = probe.frictions[0]
    out = {}
    for mu, search in searches.items():
        c = replace(compliance, friction=mu)
        out[mu] = _result(search, directions, spec, c, grid, where, used[mu], start)
        out[mu].torque_limit = torque_limit
        out[mu].floor = floor
        if settled():
            out[mu].notes.append(
                f"stopped once the tolerated tilt was known to be no more than the floor, "
                f"{floor:g} deg: the other figures are those of the held tilts computed so far"
            )
        if pretilt is not None:
            out[mu].pretilt = (float(pretilt[0]), float(pretilt[1]))
        if mu != mu0:
            out[mu].notes.append(
                f"located in one pass with the envelope at friction {mu0:g}: the rest states "
                "are frictionless, and each held tilt's rows were scaled to this friction "
                "where every snap's proof judges alike at it, else walked again"
            )
    env = out.pop(mu0)
    env.friction_cases = out
    return env


def compose_tilts(
    pretilt: tuple[float, float], misalignment: tuple[float, float]
) -> tuple[float, float]:
    """The held tilt ``(size, direction)`` (degrees) of a pre-tilted hold misaligned by
    ``misalignment`` ``(size, direction)``: the pre-tilted bolt axis rotated by the
    misalignment's size about the horizontal axis of F perpendicular to its direction
    (the rotation that leans an upright axis toward that direction by that size). Upright
    pre-tilt: the misalignment itself."""
    t, d = np.radians(misalignment[0]), np.radians(misalignment[1])
    pt, pd = np.radians(pretilt[0]), np.radians(pretilt[1])
    axis = np.array([np.sin(pt) * np.cos(pd), np.sin(pt) * np.sin(pd), np.cos(pt)])
    u = np.array([-np.sin(d), np.cos(d), 0.0])  # Rodrigues' rotation about u by t
    axis = axis * np.cos(t) + np.cross(u, axis) * np.sin(t) + u * (u @ axis) * (1 - np.cos(t))
    size = float(np.degrees(np.arccos(np.clip(axis[2], -1.0, 1.0))))
    direction = float(np.degrees(np.arctan2(axis[1], axis[0]))) % 360.0 if size > 1e-12 else 0.0
    return round(size, 12) + 0.0, round(direction, 12) + 0.0


#: Held tilts of a grid whose directions differ by less than this (degrees) lie on one
#: direction: a square grid's diagonal tilts (1, 1) and (2, 2) lean toward directions
#: a hundredth of a degree apart.
SAME_DIRECTION = 0.1


def grid_envelope(library: str | os.PathLike[str]) -> Envelope:
    """The capture envelope as a mechanics library's grid shows it, with no new search.

    Every held tilt of the library (a polar grid's, or a roll/pitch grid's turned into
    size and direction by :func:`threadmate.geometry.polar_from_held_tilt`, directions
    within :data:`SAME_DIRECTION` taken as one) is read as :func:`envelope` reads its
    probes; each envelope then lies between the last size the grid holds in its direction
    where the level holds and the next (``first_failure``), not located by bisection
    (``located`` False). A square grid holds few sizes per direction, and none between its
    directions: :func:`envelope` locates the envelope from the spec.

    Raises
    ------
    InputError
        Not a library, or a library of the thesis's fixed-pivot model.
    """
    start = time.perf_counter()
    path = Path(library)
    if not (path / METADATA_FILE).is_file():
        raise InputError(f"{path} is not a threadmate library (no {METADATA_FILE})")
    meta = info(path)["metadata"]
    if meta["model"] != "mechanics":
        raise InputError(
            f"{path} holds the thesis's fixed-pivot rows: the envelope stands on the "
            "mechanics (sweep again with the mechanics model, the default)"
        )
    grid = read_grid(meta["grid"])
    outcomes = _outcomes(load(path))
    search = _Search((), 0.0)
    keyed: list[tuple[float, float, pd.DataFrame]] = []
    for held, group in outcomes.groupby(["held_roll", "held_pitch"], sort=False):
        tilt, azimuth = polar_from_held_tilt(*np.asarray(held, dtype=float))
        keyed.append((float(tilt), float(azimuth), group))
    directions: list[float] = []
    for _, d, _ in sorted(keyed, key=lambda k: (np.isnan(k[1]), k[1])):
        if not np.isnan(d) and not any(abs(d - x) < SAME_DIRECTION for x in directions):
            # To a thousandth of a degree: computed from a grid's roll and pitch.
            directions.append(round(d, 3) + 0.0)
    for size, d, group in keyed:
        if search.key(size, 0.0)[1] is _UP or np.isnan(d):
            search.outcomes[(0.0, _UP)] = group
        else:
            at = next(x for x in directions if abs(d - x) < SAME_DIRECTION)
            search.outcomes[search.key(size, at)] = group
    if not directions:
        raise InputError(f"{path} holds no tilted start: the envelope needs directions")
    env = _result(
        search,
        directions,
        ThreadSpec.from_dict(meta["spec"]),
        Compliance.from_dict(meta["compliance"]),
        grid,
        str(path),
        0,
        start,
        located=False,
    )
    env.notes.append(
        "read off the library's grid: each envelope lies between the last size the grid "
        "holds in its direction where its level holds and the next (first_failure); the "
        "directions between are not computed (threadmate envelope locates it)"
    )
    return env


def _result(
    search: _Search,
    directions: list[float],
    spec: ThreadSpec,
    compliance: Compliance,
    grid: PolarGrid | Grid,
    source: str,
    probes: int,
    start: float,
    *,
    located: bool = True,
) -> Envelope:
    """The envelope from the evaluated sizes."""
    # In order of size and direction, not of arrival: the figures' sums then do not hang
    # on which worker finished first.
    held = sorted(search.outcomes.items(), key=lambda kv: (kv[0][0], kv[0][1] or 0.0))
    per_direction: list[dict[str, Any]] = []
    notes: list[str] = []
    for d in directions:
        known = search.evaluated(d)
        tilts: dict[str, float] = {}
        failures: dict[str, float | None] = {}
        beyond: dict[str, bool] = {}
        for level in LEVELS:
            lo, hi = search.bracket(known, level)
            tilts[_level_key(level)] = lo
            failures[_level_key(level)] = hi
            beyond[_level_key(level)] = hi is None
        lo100 = tilts[_level_key(1.0)]
        inside = [
            rows for (size, dd), rows in held if (dd is _UP or dd == d) and size <= lo100 + 1e-12
        ]
        per_direction.append(
            {
                "direction": d,
                "tilt": tilts,
                "first_failure": failures,
                "beyond_range": beyond,
                "shares": [[s, sh] for s, sh in known],
                "inside": _figures(pd.concat(inside)) if inside else _figures(_empty()),
            }
        )
    tolerated = {}
    for level in LEVELS:
        k = _level_key(level)
        low = min(x["tilt"][k] for x in per_direction)
        tolerated[k] = {
            "tilt": low,
            "worst_directions": [x["direction"] for x in per_direction if x["tilt"][k] == low],
            "beyond_range": all(x["beyond_range"][k] for x in per_direction),
        }
    limit = tolerated[_level_key(1.0)]["tilt"]
    inside_all = [
        rows
        for (size, dd), rows in held
        if size <= limit + 1e-12 and (dd is _UP or dd in directions)
    ]
    phases = len(grid.phase)
    # A level that one phase short already misses asks every phase, as the 100 % one.
    strict = [lv for lv in LEVELS if lv < 1.0 and (phases - 1) / phases + 1e-12 < lv]
    if strict:
        one = len(strict) == 1
        notes.append(
            f"with {phases} start phase{'s' if phases > 1 else ''} the "
            + " and ".join(f"{100 * lv:g} %" for lv in strict)
            + (" level asks" if one else " levels ask")
            + f" every phase (one short is {100 * (phases - 1) / phases:.1f} %): "
            + ("its envelope is" if one else "their envelopes are")
            + " the 100 % one"
        )
    upright = search.outcomes.get(search.key(0.0, 0.0))
    if upright is not None and _share(upright) < 1.0:
        notes.append(
            f"even upright only {_share(upright):.0%} of start phases snap within one turn: "
            "the compliance tolerates no misalignment"
        )
    wide = [x for x in per_direction if x["beyond_range"][_level_key(1.0)]]
    if wide:
        largest = min(x["shares"][-1][0] for x in wide)
        notes.append(
            f"in {len(wide)} direction(s) every start phase snaps up to the largest size "
            f"searched there ({largest:g} deg or more): the envelope lies beyond it; search "
            "larger sizes"
        )
    rises = [
        x["direction"]
        for x in per_direction
        if x["first_failure"]["100%"] is not None
        and any(s > x["first_failure"]["100%"] and sh >= 1.0 for s, sh in x["shares"])
    ]
    if rises:
        notes.append(
            "in direction(s) "
            + ", ".join(f"{d:g}" for d in rises)
            + " every phase snaps again at a size above the first failure: the envelope is "
            "the first crossing from upright outward"
        )
    return Envelope(
        directions=per_direction,
        tolerated=tolerated,
        inside=_figures(pd.concat(inside_all)) if inside_all else _figures(_empty()),
        compliance=compliance.to_dict(),
        spec=spec.to_dict(),
        grid=grid.to_dict(),
        tolerance=search.tolerance,
        units=spec.units,
        probes=probes,
        seconds=time.perf_counter() - start,
        source=source,
        notes=notes,
        located=located,
    )


def _empty() -> pd.DataFrame:
    return pd.DataFrame(
        {
            "snapped": pd.Series(dtype=bool),
            "failed": pd.Series(dtype=bool),
            "turn": pd.Series(dtype=float),
            "work": pd.Series(dtype=float),
            "click": pd.Series(dtype=float),
            "torque_peak": pd.Series(dtype=float),
        }
    )


def directions_of(env: Envelope) -> np.ndarray:
    """The directions of an envelope (degrees), in order."""
    return np.asarray([x["direction"] for x in env.directions], dtype=float)


def levels_of(env: Envelope, level: float) -> np.ndarray:
    """The envelope at one level, direction by direction (degrees)."""
    return np.asarray([x["tilt"][_level_key(level)] for x in env.directions], dtype=float)
