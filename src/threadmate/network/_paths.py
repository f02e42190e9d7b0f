"""Least-resistance paths to the snap, and the outcome of every start at once.

The targets are the in-phase states. Without active moves a state has at most one
successor, so the path from a start is the passive search itself, and
:func:`start_outcomes` follows every start's path once, sharing the common tails. With
active moves (:func:`~threadmate.network.build_network` with ``active=True``) the
least-resistance path is a Dijkstra search to a virtual sink joined to every target
(:func:`least_resistance_path`); :func:`k_best_paths` gives the next best by
:func:`networkx.shortest_simple_paths`. Costs in mJ, turns in degrees.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from typing import Any

import networkx as nx
import numpy as np
import pandas as pd

from .._angles import FULL_TURN
from .._errors import InputError, NoPathError
from .._validate import MAX_K, check_whole
from ..contact import ERROR_CLASS, IN_PHASE, UNSTABLE
from ..geometry import polar_from_held_tilt
from ._build import start_node, starts

__all__ = [
    "PathResult",
    "k_best_paths",
    "least_resistance_path",
    "no_path_document",
    "snap_click",
    "snap_targets",
    "start_outcomes",
]

_SINK = ("threadmate", "snap")  # a node no string id can equal


def _passive(u: str, v: str, d: dict[str, Any]) -> float | None:
    """Edge weight with the active moves hidden (networkx skips None)."""
    return None if d.get("active") else d["weight"]


def _any(u: str, v: str, d: dict[str, Any]) -> float:
    return d["weight"]


@dataclass
class PathResult:
    """One path from a start to the snap.

    Attributes
    ----------
    start : str
        Node id of the start (the rest state the drop at the configuration reaches).
    requested : dict
        The configuration asked for (``roll``, ``pitch``, ``phase``, degrees).
    moved_to_grid : bool
        True when the request was off the grid and the nearest start was taken.
    path : list of str
        Node ids, start to the in-phase state.
    kinds, labels : list of str
        Kind (``turning``, ``jump``, ``snap``, ``settling``, ``tilt-step``) and label
        (``stable``, ``quasi-stable``, ``unstable``) of each edge.
    weights : list of float
        Weight of each edge (mJ); their sum is :attr:`cost`.
    turn : float
        Phase turned along the path (degrees).
    snap : dict
        ``phase``, ``turn``, ``drop`` (the fall across the jump) and ``click`` (the fall
        a sensor sees within the last degree of turn; spec units; 0 where the bolt passed
        into phase without a jump) of the snap.
    active : bool
        Whether active moves were allowed.
    """

    start: str
    requested: dict[str, float]
    moved_to_grid: bool
    path: list[str]
    kinds: list[str]
    labels: list[str]
    weights: list[float]
    turn: float
    snap: dict[str, float]
    active: bool
    units: str = "in"
    alternatives: list[PathResult] = field(default_factory=list)

    @property
    def cost(self) -> float:
        """Total weight (mJ)."""
        return float(sum(self.weights))

    @property
    def passes_unstable(self) -> bool:
        """True when a transition before the snap is labelled unstable."""
        return any(
            lab == UNSTABLE for lab, k in zip(self.labels, self.kinds, strict=True) if k != "snap"
        )

    @property
    def moves(self) -> int:
        """Active moves on the path."""
        return sum(k == "tilt-step" for k in self.kinds)

    def to_dict(self) -> dict[str, Any]:
        """The JSON document of ``threadmate path --json``."""
        return {
            "units": _units(self.units),
            "start": _start(self.start, self.requested, self.moved_to_grid),
            "path": list(self.path),
            "kinds": list(self.kinds),
            "labels": list(self.labels),
            "weights": list(self.weights),
            "cost": self.cost,
            "turn": self.turn,
            "within_one_turn": self.turn <= FULL_TURN + 1e-9,
            "passes_unstable": self.passes_unstable,
            "active": self.active,
            "active_moves": self.moves,
            "snap": dict(self.snap),
            "alternatives": [a.to_dict() for a in self.alternatives],
        }


def _units(length: str) -> dict[str, str]:
    return {"length": length, "angle": "deg", "cost": "mJ", "work": "mJ"}


def _start(node: str, requested: dict[str, float], moved_to_grid: bool) -> dict[str, Any]:
    return {"node": node, **requested, "moved_to_grid": moved_to_grid}


def no_path_document(
    graph: nx.DiGraph,
    roll: float,
    pitch: float,
    phase: float,
    error: NoPathError,
    *,
    active: bool = False,
    nearest: bool = False,
) -> dict[str, Any]:
    """The JSON document of ``threadmate path --json`` for a start from which no path
    reaches the snap (``error``, as :func:`least_resistance_path` raised it): the keys of
    :meth:`PathResult.to_dict`, with no path, cost, turn or snap, and the ``reason``."""
    start, moved_to_grid = start_node(graph, roll, pitch, phase, nearest=nearest)
    return {
        "units": _units(graph.graph.get("units", "in")),
        "start": _start(
            start,
            {"roll": float(roll), "pitch": float(pitch), "phase": float(phase)},
            moved_to_grid,
        ),
        "path": None,
        "kinds": [],
        "labels": [],
        "weights": [],
        "cost": None,
        "turn": None,
        "within_one_turn": False,
        "passes_unstable": None,
        "active": active,
        "active_moves": 0,
        "snap": None,
        "alternatives": [],
        "reason": str(error),
    }


def is_snapped(node: dict[str, Any]) -> bool:
    """Whether a node's state ends a search: in phase and proved by screwing in."""
    return node.get("classification") == IN_PHASE and bool(node.get("engaged"))


def snap_targets(graph: nx.DiGraph) -> list[str]:
    """The in-phase states proved by screwing in."""
    return [n for n, d in graph.nodes(data=True) if is_snapped(d)]


def snap_click(edge: dict[str, Any]) -> float:
    """The click of a snap edge (its attributes): the fall a sensor sees (spec units), or
    its drop where the library holds no click; NaN where the bolt passed into phase
    without a jump (a snap edge not labelled unstable): there is no click to see."""
    if edge["label"] != UNSTABLE:
        return math.nan
    click = float(edge.get("click", math.nan))
    return click if math.isfinite(click) else float(edge["drop"])


def _result(
    graph: nx.DiGraph,
    path: list[str],
    start: str,
    requested: dict[str, float],
    moved_to_grid: bool,
    active: bool,
) -> PathResult:
    edges = [graph.edges[u, v] for u, v in itertools.pairwise(path)]
    turn = float(sum(e["turn"] for e in edges))
    last = graph.nodes[path[-1]]
    snap_edges = [e for e in edges if e["kind"] == "snap"]
    drop = float(snap_edges[-1]["drop"]) if snap_edges else 0.0
    click = snap_click(snap_edges[-1]) if snap_edges else 0.0
    if not math.isfinite(click):
        click = 0.0  # into phase without a jump: no click, as for a start in phase
    return PathResult(
        start,
        requested,
        moved_to_grid,
        path,
        [e["kind"] for e in edges],
        [e["label"] for e in edges],
        [float(e["weight"]) for e in edges],
        turn,
        {"phase": float(last["phase"]), "turn": turn, "drop": drop, "click": click},
        active,
        graph.graph.get("units", "in"),
    )


def _no_path(graph: nx.DiGraph, start: str, active: bool) -> NoPathError:
    d = graph.nodes[start]
    if d.get("classification") == ERROR_CLASS:
        return NoPathError(f"the library failed at start {start}: {d.get('error')}")
    how = "with active moves" if active else "passively (no active moves asked)"
    return NoPathError(
        f"no path from {start} reaches the snap {how}: the search from it "
        "never snaps within the library's horizon"
    )


def least_resistance_path(
    graph: nx.DiGraph,
    roll: float,
    pitch: float,
    phase: float,
    *,
    active: bool = False,
    nearest: bool = False,
) -> PathResult:
    """The least-resistance path from the start at (roll, pitch, phase) to the snap.

    Parameters
    ----------
    graph : networkx.DiGraph
        From :func:`~threadmate.network.build_network`.
    roll, pitch, phase : float
        The start: held tilt and phase (degrees).
    active : bool
        Allow the active moves (the graph must have been built with them).
    nearest : bool
        Take the nearest start when the request is off the grid (else refuse).

    Raises
    ------
    NoPathError
        No path reaches the snap.
    """
    if active and not graph.graph.get("active"):
        raise InputError(
            "active=True asks for active moves, but the network was built without "
            "them (build it with active=True)"
        )
    start, moved_to_grid = start_node(graph, roll, pitch, phase, nearest=nearest)
    requested = {"roll": float(roll), "pitch": float(pitch), "phase": float(phase)}
    if is_snapped(graph.nodes[start]):
        return _result(graph, [start], start, requested, moved_to_grid, active)
    weight = _any if active else _passive
    targets = snap_targets(graph)
    graph.add_node(_SINK)
    try:
        graph.add_edges_from((t, _SINK, {"weight": 0.0}) for t in targets)
        try:
            path = nx.dijkstra_path(graph, start, _SINK, weight=weight)
        except nx.NetworkXNoPath:
            raise _no_path(graph, start, active) from None
    finally:
        graph.remove_node(_SINK)
    return _result(graph, path[:-1], start, requested, moved_to_grid, active)


def k_best_paths(
    graph: nx.DiGraph,
    k: int,
    roll: float,
    pitch: float,
    phase: float,
    *,
    active: bool = False,
    nearest: bool = False,
) -> PathResult:
    """The least-resistance path with up to ``k - 1`` next-best alternatives (in
    :attr:`PathResult.alternatives`); ``k`` is at most ``threadmate._validate.MAX_K``.

    Passively there is one path (the dynamics are deterministic); alternatives come from
    active moves.
    """
    check_whole(
        "k",
        k,
        1,
        MAX_K,
        why=" (the alternatives are Yen's k shortest paths, whose cost grows with k)",
    )
    best = least_resistance_path(graph, roll, pitch, phase, active=active, nearest=nearest)
    if k == 1 or len(best.path) == 1:
        return best
    view = (
        graph
        if active
        else nx.subgraph_view(graph, filter_edge=lambda u, v: not graph.edges[u, v].get("active"))
    )
    work: nx.DiGraph[Any] = nx.DiGraph(view)
    work.add_edges_from((t, _SINK, {"weight": 0.0}) for t in snap_targets(graph))
    paths = nx.shortest_simple_paths(work, best.start, _SINK, weight="weight")
    # Yen's first path may be another of equal cost than Dijkstra's: skip the best by
    # identity, not by rank, so that no path is listed twice.
    others = (p for p in paths if p[:-1] != best.path)
    for path in itertools.islice(others, k - 1):
        best.alternatives.append(
            _result(graph, path[:-1], best.start, best.requested, best.moved_to_grid, active)
        )
    return best


def _larger(a: float, b: float) -> float:
    """The larger of two torques, NaN meaning none."""
    if not math.isfinite(b):
        return a
    return b if not math.isfinite(a) else max(a, b)


def start_outcomes(graph: nx.DiGraph) -> pd.DataFrame:
    """The passive search from every start at once (computed once per graph and kept).

    Returns
    -------
    pandas.DataFrame
        One row per start: ``node``, ``held_roll``, ``held_pitch``, ``held_tilt`` and
        ``held_direction`` (the held tilt's size and direction, degrees:
        :func:`threadmate.geometry.polar_from_held_tilt`; direction NaN upright), ``phase``,
        ``classification`` (of the rest state reached), ``snapped`` (reaches the snap
        within one turn), ``reaches`` (at all, within the library's horizon), ``turn``
        (degrees to the snap, NaN if never), ``work`` (mJ: the sum of the passive edge
        weights), ``click`` (the snap's drop, spec units), ``snap_phase``, ``snap_window``
        (degrees before the snap within which the drop may already come), ``torque_peak``
        (largest driver torque on the way, N m), ``passes_unstable`` (a jump or an
        unstable transition before the snap), ``failed`` (the start's drop raised).
    """
    cached = graph.graph.get("_outcomes")
    if cached is not None:
        return cached.copy()
    memo: dict[str, tuple[Any, ...]] = {}
    nan = math.nan

    def passive_next(n: str) -> tuple[str, dict[str, Any]] | None:
        for _, v, d in graph.out_edges(n, data=True):
            if not d.get("active"):
                return v, d
        return None

    def outcome(node: str) -> tuple[Any, ...]:
        # (reaches, turn, work, click, snap_phase, torque_peak, unstable, window); an
        # iterative walk.
        trail: list[tuple[str, dict[str, Any]]] = []
        seen: set[str] = set()
        n = node
        while n not in memo:
            d = graph.nodes[n]
            if is_snapped(d):
                memo[n] = (True, 0.0, 0.0, 0.0, float(d["phase"]), nan, False, 0.0)
                break
            if n in seen:
                # A cycle: never snaps, and the driver meets every edge of it, whichever
                # of its states the walk entered first.
                ring = [e for m, e in trail[[m for m, _ in trail].index(n) :]]
                peak = nan
                for e in ring:
                    peak = _larger(peak, e["torque_peak"])
                memo[n] = (
                    False,
                    nan,
                    nan,
                    nan,
                    nan,
                    peak,
                    any(e["label"] == UNSTABLE and e["kind"] != "snap" for e in ring),
                    nan,
                )
                break
            step = passive_next(n)
            if step is None:  # horizon or failure: never snaps
                memo[n] = (False, nan, nan, nan, nan, nan, False, nan)
                break
            seen.add(n)
            trail.append((n, step[1]))
            n = step[0]
        for m, e in reversed(trail):
            reaches, turn, work, click, ph, peak, unstable, window = memo[n]
            if e["kind"] == "snap":
                click = snap_click(e)
                window = float(e.get("snap_window", nan))
            peak = _larger(peak, e["torque_peak"])
            unstable = unstable or (e["label"] == UNSTABLE and e["kind"] != "snap")
            memo[m] = (
                reaches,
                turn + e["turn"],
                work + e["weight"],
                click,
                ph,
                peak,
                unstable,
                window,
            )
            n = m
        return memo[node]

    rows = []
    for (roll, pitch, phase), node in sorted(starts(graph).items()):
        d = graph.nodes[node]
        reaches, turn, work, click, snap_phase, peak, unstable, window = outcome(node)
        peak = _larger(peak, d["driver_torque"])
        rows.append(
            {
                "node": node,
                "held_roll": roll,
                "held_pitch": pitch,
                "phase": phase,
                "classification": d["classification"],
                "snapped": bool(reaches and turn <= FULL_TURN + 1e-9),
                "reaches": bool(reaches),
                "turn": turn,
                "work": work,
                "click": click,
                "snap_phase": snap_phase,
                "snap_window": window,
                "torque_peak": peak,
                "passes_unstable": bool(unstable),
                "failed": d["classification"] == ERROR_CLASS,
            }
        )
    table = pd.DataFrame(
        rows,
        columns=[
            "node",
            "held_roll",
            "held_pitch",
            "held_tilt",
            "held_direction",
            "phase",
            "classification",
            "snapped",
            "reaches",
            "turn",
            "work",
            "click",
            "snap_phase",
            "snap_window",
            "torque_peak",
            "passes_unstable",
            "failed",
        ],
    )
    # The held tilt's size and direction (docs/design.md), derived from roll and pitch by
    # the one rule that owns them.
    size, direction = polar_from_held_tilt(table["held_roll"], table["held_pitch"])
    table["held_tilt"], table["held_direction"] = np.round(size, 9), np.round(direction, 9)
    graph.graph["_outcomes"] = table  # private key: the writers skip it
    return table.copy()
