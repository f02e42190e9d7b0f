"""SRCC pitch recommendation: which pitch setting of the compliance makes the snap easiest.

For each pitch value of the grid, the starts are the states at that pitch whose roll lies
within the expected spread (``|roll| <= roll_spread``) at every phase (``error`` states
left out). Over them:

- ``expected_cost``: mean least-resistance cost to the snap over the starts that reach it;
- ``worst_cost``: the largest of those costs;
- ``share_reachable``: share of starts with any path to the snap;
- ``share_safe``: share of starts with a path that enters no unstable state.

The recommended setting is the first in the order (largest ``share_reachable``, smallest
``expected_cost``, smallest ``worst_cost``, largest ``share_safe``); the margin is the
next setting's expected cost minus the pick's. At the pick, the roll with the smallest
expected cost is named, and roll *matters* when the expected costs of the rolls spread by
more than 10 % of the pick's expected cost. Sensitivity: the ranking is recomputed with
the friction, the unstable penalty and the compliance stiffness each halved and doubled
(six variants) and the report says whether the pick changes.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import networkx as nx
import numpy as np

from .._errors import InputError, NoPathError
from .._io import atomic_path, atomic_write_text
from ._cost import variant_weight
from ._paths import Weight, _safe_reach, cost_to_snap

__all__ = [
    "PitchSetting",
    "Recommendation",
    "format_recommendation",
    "plot_recommendation",
    "recommend_pitch",
    "write_recommendation",
]

#: Roll matters when its expected costs spread by more than this share of the pick's cost.
ROLL_MATTERS = 0.10
#: (parameter, edge term scaled, factor) of the sensitivity study.
SENSITIVITY = (("friction", "friction", 0.5), ("friction", "friction", 2.0),
               ("unstable_penalty", "penalty", 0.5), ("unstable_penalty", "penalty", 2.0),
               ("rotational_stiffness", "stiffness", 0.5),
               ("rotational_stiffness", "stiffness", 2.0))
_TOL = 1e-9


@dataclass
class PitchSetting:
    """Figures of one pitch setting over its starts (costs in mJ)."""

    pitch: float
    starts: int
    reachable: int
    expected_cost: float
    worst_cost: float
    share_reachable: float
    share_safe: float
    roll_costs: dict[float, float] = field(default_factory=dict)

    def key(self) -> tuple[float, float, float, float]:
        """Ranking key: smaller is better."""
        return (-self.share_reachable, self.expected_cost, self.worst_cost, -self.share_safe)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready mapping (infinite costs as None)."""
        return {"pitch": self.pitch, "starts": self.starts, "reachable": self.reachable,
                "expected_cost": _num(self.expected_cost), "worst_cost": _num(self.worst_cost),
                "share_reachable": self.share_reachable, "share_safe": self.share_safe,
                "roll_expected_cost": [{"roll": r, "expected_cost": _num(c)}
                                       for r, c in sorted(self.roll_costs.items())]}


@dataclass
class Recommendation:
    """The recommended SRCC pitch setting and the figures behind it.

    Attributes
    ----------
    pitch : float
        Recommended pitch setting (degrees).
    roll : float
        Roll with the smallest expected cost at that pitch (degrees).
    roll_matters : bool
        Whether the roll changes the expected cost by more than 10 %.
    next_pitch : float or None
        The second-best setting.
    margin : float
        Next setting's expected cost minus the pick's (mJ; inf when the next one reaches
        fewer starts or none).
    settings : list of PitchSetting
        Every pitch setting, in pitch order.
    sensitivity : list of dict
        ``parameter``, ``factor``, ``pick``, ``changed`` for each variant.
    """

    pitch: float
    roll: float
    roll_matters: bool
    next_pitch: float | None
    margin: float
    settings: list[PitchSetting]
    roll_spread: float | None
    sensitivity: list[dict[str, Any]]
    parameters: dict[str, Any]
    units: str
    cost_units: str

    @property
    def best(self) -> PitchSetting:
        """The figures of the recommended setting."""
        return next(s for s in self.settings if s.pitch == self.pitch)

    @property
    def robust(self) -> bool:
        """True when no sensitivity variant changes the pick."""
        return not any(v["changed"] for v in self.sensitivity)

    @property
    def margin_relative(self) -> float:
        """The margin as a share of the pick's expected cost."""
        best = self.best.expected_cost
        return self.margin / best if best > 0 else math.inf

    def note(self) -> str:
        """One paragraph on the pick, its margin and its sensitivity."""
        b = self.best
        text = (f"Recommended SRCC pitch {self.pitch:g} deg: expected {b.expected_cost:.3g} "
                f"{self.cost_units}, worst {b.worst_cost:.3g} {self.cost_units}, "
                f"{100 * b.share_safe:.0f}% of starts reach the snap without an unstable "
                f"transition.")
        if self.next_pitch is not None:
            margin = ("the pick reaches the snap from more starts" if math.isinf(self.margin)
                      else f"the pick is {self.margin:.3g} {self.cost_units} cheaper on "
                           f"average ({100 * self.margin_relative:.2g}% of its own cost)")
            text += f" Next best pitch {self.next_pitch:g} deg: {margin}."
        text += (f" Roll {'matters' if self.roll_matters else 'matters little'}: best roll "
                 f"{self.roll:g} deg.")
        changed = [v for v in self.sensitivity if v["changed"]]
        if not self.sensitivity:
            pass
        elif not changed:
            text += (" The pick holds with the friction, the unstable penalty and the "
                     "compliance stiffness each halved or doubled.")
        else:
            text += " The pick changes with " + "; ".join(
                f"{v['parameter']} x{v['factor']:g} (-> {v['pick']:g} deg)" for v in changed) \
                + "."
        return text

    def to_dict(self) -> dict[str, Any]:
        """The JSON document of ``threadmate recommend --json``."""
        return {
            "recommended_pitch": self.pitch, "recommended_roll": self.roll,
            "roll_matters": self.roll_matters, "next_best_pitch": self.next_pitch,
            "margin": _num(self.margin), "margin_relative": _num(self.margin_relative),
            "roll_spread": self.roll_spread, "robust": self.robust,
            "sensitivity": self.sensitivity, "note": self.note(),
            "settings": [s.to_dict() for s in self.settings],
            "parameters": self.parameters, "units": self.units,
            "cost_units": self.cost_units, "angle_units": "deg",
        }


def _num(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def _settings(graph: nx.DiGraph, starts: list[str], costs: dict[str, float],
              safe: set[str]) -> list[PitchSetting]:
    nodes = graph.nodes
    by_pitch: dict[float, list[str]] = {}
    for n in starts:
        by_pitch.setdefault(nodes[n]["pitch"], []).append(n)
    out = []
    for pitch in sorted(by_pitch):
        group = by_pitch[pitch]
        c = np.array([costs[n] for n in group])
        ok = np.isfinite(c)
        rolls = np.array([nodes[n]["roll"] for n in group])
        roll_costs = {}
        for r in np.unique(rolls):
            sel = (rolls == r) & ok
            roll_costs[float(r)] = float(c[sel].mean()) if sel.any() else math.inf
        out.append(PitchSetting(
            pitch=float(pitch), starts=len(group), reachable=int(ok.sum()),
            expected_cost=float(c[ok].mean()) if ok.any() else math.inf,
            worst_cost=float(c[ok].max()) if ok.any() else math.inf,
            share_reachable=float(ok.mean()),
            share_safe=float(np.mean([n in safe for n in group])),
            roll_costs=roll_costs))
    return out


def _pick(settings: list[PitchSetting]) -> list[PitchSetting]:
    return sorted(settings, key=lambda s: (*s.key(), abs(s.pitch)))


def recommend_pitch(graph: nx.DiGraph, roll_spread: float | None = None, *,
                    sensitivity: bool = True) -> Recommendation:
    """Recommend the SRCC pitch setting that makes the snap cheapest and safest.

    Parameters
    ----------
    graph : networkx.DiGraph
        A network from :func:`build_network`.
    roll_spread : float, optional
        Largest roll error expected (degrees): starts have ``|roll| <= roll_spread``.
        Default: every roll of the grid.
    sensitivity : bool
        Recompute the pick with friction, penalty and stiffness halved and doubled.

    Returns
    -------
    Recommendation

    Raises
    ------
    InputError
        A negative or non-finite spread, or one that holds no roll of the grid.
    NoPathError
        No start at any pitch reaches the snap.
    """
    if roll_spread is not None:
        if isinstance(roll_spread, bool) or not isinstance(roll_spread, int | float) \
                or not math.isfinite(roll_spread) or roll_spread < 0:
            raise InputError(f"--roll-spread {roll_spread!r}: give a non-negative number of "
                             "degrees")
        roll_spread = float(roll_spread)
    starts = [n for n, d in graph.nodes(data=True) if d["classification"] != "error"
              and (roll_spread is None or abs(d["roll"]) <= roll_spread + _TOL)]
    if not starts:
        rolls = sorted({d["roll"] for _, d in graph.nodes(data=True)})
        raise InputError(f"--roll-spread {roll_spread:g} holds no roll of the library's grid "
                         f"(rolls {rolls[0]:g}..{rolls[-1]:g} deg)" if rolls else
                         "the network holds no states")
    safe = _safe_reach(graph)
    settings = _settings(graph, starts, cost_to_snap(graph), safe)
    ranked = _pick(settings)
    best = ranked[0]
    if best.reachable == 0:
        raise NoPathError("no start state at any pitch setting reaches the snap (no in-phase "
                          "state is reachable)")
    nxt = ranked[1] if len(ranked) > 1 else None
    if nxt is None:
        margin = math.inf
    elif nxt.share_reachable < best.share_reachable:
        margin = math.inf
    else:
        margin = nxt.expected_cost - best.expected_cost
    finite = [c for c in best.roll_costs.values() if math.isfinite(c)]
    best_roll = min(best.roll_costs, key=lambda r: (best.roll_costs[r], abs(r)))
    roll_matters = bool(len(finite) > 1 and (max(finite) - min(finite))
                        > ROLL_MATTERS * best.expected_cost)
    variants = []
    if sensitivity:
        for parameter, term, factor in SENSITIVITY:
            weight: Weight = variant_weight(**{term: factor})
            alt = _pick(_settings(graph, starts, cost_to_snap(graph, weight), safe))[0]
            variants.append({"parameter": parameter, "factor": factor, "pick": alt.pitch,
                             "changed": alt.pitch != best.pitch})
    return Recommendation(
        pitch=best.pitch, roll=best_roll, roll_matters=roll_matters,
        next_pitch=nxt.pitch if nxt is not None else None, margin=margin,
        settings=sorted(settings, key=lambda s: s.pitch), roll_spread=roll_spread,
        sensitivity=variants, parameters=json.loads(graph.graph.get("parameters", "{}")),
        units=str(graph.graph.get("units", "")),
        cost_units=str(graph.graph.get("cost_units", "mJ")))


def format_recommendation(rec: Recommendation) -> str:
    """The recommendation as a plain-text table with its note."""
    u = rec.cost_units
    head = (f"{'pitch':>7}  {'starts':>6}  {'expected ' + u:>12}  {'worst ' + u:>10}  "
            f"{'reach':>6}  {'safe':>6}")
    lines = [head, "-" * len(head)]
    for s in rec.settings:
        mark = "  <- recommended" if s.pitch == rec.pitch else ""
        lines.append(f"{s.pitch:>7g}  {s.starts:>6d}  {s.expected_cost:>12.4g}  "
                     f"{s.worst_cost:>10.4g}  {100 * s.share_reachable:>5.0f}%  "
                     f"{100 * s.share_safe:>5.0f}%{mark}")
    spread = "all rolls" if rec.roll_spread is None else f"|roll| <= {rec.roll_spread:g} deg"
    lines += ["", f"starts: {spread}, every phase", rec.note()]
    return "\n".join(lines)


def write_recommendation(rec: Recommendation, path: str | Path) -> Path:
    """Write the recommendation's JSON document atomically."""
    return atomic_write_text(path, json.dumps(rec.to_dict(), indent=2) + "\n")


def plot_recommendation(rec: Recommendation, path: str | Path) -> Path:
    """Draw cost to the snap against the pitch setting (expected and worst), with the share
    of safe starts on a twin axis; written atomically (format from the suffix)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    path = Path(path)
    fmt = path.suffix.lstrip(".").lower() or "png"
    if fmt not in ("png", "pdf", "svg", "jpg", "jpeg", "eps", "ps", "tif", "tiff", "webp"):
        raise InputError(f"--plot {path}: unknown figure format {fmt!r} (use .png, .pdf "
                         "or .svg)")
    pitches = [s.pitch for s in rec.settings]
    expected = [s.expected_cost if math.isfinite(s.expected_cost) else np.nan
                for s in rec.settings]
    worst = [s.worst_cost if math.isfinite(s.worst_cost) else np.nan for s in rec.settings]
    safe = [100 * s.share_safe for s in rec.settings]
    fig = Figure(figsize=(7, 4.2), layout="constrained")
    ax = fig.add_subplot()
    ax.plot(pitches, expected, "o-", color="C0", label="expected cost")
    ax.plot(pitches, worst, "s--", color="C3", label="worst cost")
    ax.axvline(rec.pitch, color="0.5", lw=1, ls=":", label=f"recommended {rec.pitch:g} deg")
    ax.set_xlabel("SRCC pitch setting [deg]")
    ax.set_ylabel(f"least-resistance cost to the snap [{rec.cost_units}]")
    twin = ax.twinx()
    twin.plot(pitches, safe, "^-", color="C2", label="safe starts")
    twin.set_ylabel("starts with a safe path to the snap [%]")
    twin.set_ylim(-5, 105)
    spread = "all rolls" if rec.roll_spread is None else f"|roll| <= {rec.roll_spread:g} deg"
    ax.set_title(f"SRCC pitch recommendation ({spread}, all phases)")
    handles = ax.get_legend_handles_labels()
    handles2 = twin.get_legend_handles_labels()
    ax.legend(handles[0] + handles2[0], handles[1] + handles2[1], loc="best", fontsize=8)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=fmt, dpi=120)
    return path
