"""Least-resistance paths to the snap (the in-phase states) on a contact-state network.

Every in-phase state is a target. One Dijkstra on the reversed graph, started from all
targets at once, gives each state's cost to its cheapest snap (:func:`cost_to_snap`); a
single path stops as soon as its start is settled (:func:`least_resistance_path`); the k
best alternatives run :func:`networkx.shortest_simple_paths` to a virtual sink joined to
every target by a zero-weight edge (:func:`k_best_paths`). Costs are in the graph's
``cost_units`` (mJ).
"""

from __future__ import annotations

import itertools
import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import networkx as nx
import numpy as np

from .._errors import InputError, NoPathError
from ._build import node_id

__all__ = [
    "PathResult",
    "cost_to_snap",
    "k_best_paths",
    "least_resistance_path",
    "resolve_start",
    "snap_targets",
    "unsafe_starts",
]

_SINK = ("threadmate", "snap")  # a node no string id can equal
Weight = str | Callable[[str, str, dict[str, Any]], float]


@dataclass
class PathResult:
    """One path from a start state to the snap.

    Attributes
    ----------
    start : str
        Node id of the start state (the grid state nearest the request).
    requested : dict
        The requested ``roll``, ``pitch``, ``phase`` (degrees).
    snapped : bool
        True when the request was not a grid state and was moved to the nearest one.
    message : str
        What was done (the snapping, or that the start is already in phase).
    path : list of str
        Node ids, start to snap (the last is an in-phase state).
    labels, kinds : list of str
        Label (``stable``/``quasi-stable``/``unstable``) and kind (``turning``/
        ``settling``) of each edge, ``len(path) - 1`` of each.
    weights : list of float
        Weight of each edge (mJ).
    cost : float
        Sum of the weights (mJ).
    """

    start: str
    requested: dict[str, float]
    snapped: bool
    message: str
    path: list[str]
    labels: list[str] = field(default_factory=list)
    kinds: list[str] = field(default_factory=list)
    weights: list[float] = field(default_factory=list)
    cost: float = 0.0

    @property
    def target(self) -> str:
        """The in-phase state the path ends in."""
        return self.path[-1]

    @property
    def safe(self) -> bool:
        """True when no edge of the path is labelled unstable."""
        return "unstable" not in self.labels

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready mapping (the ``threadmate path --json`` document)."""
        return {"start": self.start, "requested": dict(self.requested),
                "snapped": self.snapped, "message": self.message, "path": list(self.path),
                "labels": list(self.labels), "kinds": list(self.kinds),
                "weights": list(self.weights), "cost": self.cost, "target": self.target,
                "steps": len(self.path) - 1, "safe": self.safe}


def snap_targets(graph: nx.DiGraph) -> list[str]:
    """Node ids of the in-phase states (the snap targets)."""
    return [n for n, d in graph.nodes(data=True) if d.get("in_phase")]


def _grid(graph: nx.DiGraph) -> dict[str, np.ndarray]:
    try:
        doc = json.loads(graph.graph["grid"])
        return {k: np.asarray(doc[k], dtype=float) for k in ("roll", "pitch", "phase")}
    except (KeyError, TypeError, ValueError):
        raise InputError("the graph carries no grid: build it with build_network") from None


def _finite(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating) \
            or not math.isfinite(value):
        raise InputError(f"--{name}: {value!r} is not a finite number of degrees")
    return float(value)


def resolve_start(graph: nx.DiGraph, roll: float, pitch: float, phase: float
                  ) -> tuple[str, bool, str]:
    """The grid state nearest a requested configuration.

    Roll and pitch snap to their nearest grid values and phase to the nearest grid phase
    modulo 360. A roll or pitch farther than one grid step outside the grid is refused.

    Returns
    -------
    node : str
        Node id of the state.
    snapped : bool
        True when the state differs from the request.
    message : str
        Says which state is used and why.

    Raises
    ------
    InputError
        A non-finite angle, a tilt beyond the grid, or a nearest state the library lacks.
    """
    roll, pitch, phase = _finite("roll", roll), _finite("pitch", pitch), _finite("phase", phase)
    grid = _grid(graph)
    picked = []
    for name, value in (("roll", roll), ("pitch", pitch)):
        values = grid[name]
        step = float(np.min(np.diff(values))) if len(values) > 1 else 1.0
        if value < values[0] - step - 1e-9 or value > values[-1] + step + 1e-9:
            raise InputError(f"--{name} {value:g} lies outside the library's grid "
                             f"({values[0]:g}..{values[-1]:g} deg); nearest states: "
                             f"{_nearest_list(graph, grid, roll, pitch, phase)}")
        picked.append(float(values[int(np.argmin(np.abs(values - value)))]))
    d_phase = np.abs((grid["phase"] - phase + 180.0) % 360.0 - 180.0)
    picked.append(float(grid["phase"][int(np.argmin(d_phase))]))
    node = node_id(*picked)
    if node not in graph:
        raise InputError(f"the library has no state {node} (an unfinished sweep?); nearest "
                         f"states: {_nearest_list(graph, grid, roll, pitch, phase)}")
    snapped = node != node_id(roll, pitch, phase)
    if snapped:
        message = (f"({roll:g}, {pitch:g}, {phase:g}) is not a state of the grid: using the "
                   f"nearest state {node} (roll {picked[0]:g}, pitch {picked[1]:g}, "
                   f"phase {picked[2]:g} deg)")
    else:
        message = f"start {node} is a state of the grid"
    return node, snapped, message


def _nearest_list(graph: nx.DiGraph, grid: dict[str, np.ndarray], roll: float, pitch: float,
                  phase: float, n: int = 3) -> str:
    out = []
    rolls = sorted(grid["roll"], key=lambda v: abs(v - roll))[:2]
    pitches = sorted(grid["pitch"], key=lambda v: abs(v - pitch))[:2]
    phases = sorted(grid["phase"], key=lambda v: abs((v - phase + 180.0) % 360.0 - 180.0))[:2]
    for r, p, ph in itertools.product(rolls, pitches, phases):
        if node_id(r, p, ph) in graph:
            out.append(node_id(r, p, ph))
        if len(out) == n:
            break
    return ", ".join(out) if out else "none"


def _start(graph: nx.DiGraph, start: str | None, roll: float | None, pitch: float | None,
           phase: float | None) -> tuple[str, dict[str, float], bool, str]:
    if start is not None:
        if start not in graph:
            raise InputError(f"no state {start!r} in the network (ids look like "
                             f"{next(iter(graph.nodes), 'r+0.0_p+0.0_ph0.0')})")
        d = graph.nodes[start]
        requested = {"roll": d["roll"], "pitch": d["pitch"], "phase": d["phase"]}
        return start, requested, False, f"start {start} is a state of the grid"
    if roll is None or pitch is None or phase is None:
        raise InputError("give a start state: its node id, or roll, pitch and phase")
    node, snapped, message = resolve_start(graph, roll, pitch, phase)
    return node, {"roll": float(roll), "pitch": float(pitch), "phase": float(phase)}, \
        snapped, message


def _result(graph: nx.DiGraph, path: list[str], start: str, requested: dict[str, float],
            snapped: bool, message: str) -> PathResult:
    edges = [graph.edges[u, v] for u, v in itertools.pairwise(path)]
    weights = [float(e["weight"]) for e in edges]
    return PathResult(start=start, requested=requested, snapped=snapped, message=message,
                      path=list(path), labels=[e["label"] for e in edges],
                      kinds=[e["kind"] for e in edges], weights=weights,
                      cost=float(math.fsum(weights)))


def _no_path(graph: nx.DiGraph, start: str) -> NoPathError:
    d = graph.nodes[start]
    if not snap_targets(graph):
        return NoPathError("no state of the library is in phase: there is no snap to reach")
    if d.get("classification") == "error":
        return NoPathError(f"state {start} has no contact analysis (its sweep recorded an "
                           "error), so no transition leaves it")
    return NoPathError(f"no sequence of turning and settling transitions leads from {start} "
                       f"({d.get('classification')}) to an in-phase state")


def least_resistance_path(graph: nx.DiGraph, start: str | None = None, *,
                          roll: float | None = None, pitch: float | None = None,
                          phase: float | None = None) -> PathResult:
    """The cheapest path from a start state to any in-phase state.

    Parameters
    ----------
    graph : networkx.DiGraph
        A network from :func:`build_network`.
    start : str, optional
        Node id of the start; otherwise give ``roll``, ``pitch`` and ``phase`` (degrees),
        which snap to the nearest grid state (``PathResult.snapped`` and ``message`` say so).

    Returns
    -------
    PathResult

    Raises
    ------
    InputError
        A start that is not in the network or off the grid.
    NoPathError
        No path from the start reaches an in-phase state.
    """
    node, requested, snapped, message = _start(graph, start, roll, pitch, phase)
    if graph.nodes[node].get("in_phase"):
        return _result(graph, [node], node, requested, snapped,
                       message + "; it is already in phase (the snap)")
    targets = snap_targets(graph)
    if not targets:
        raise _no_path(graph, node)
    try:
        _, path = nx.multi_source_dijkstra(graph.reverse(copy=False), targets, target=node,
                                           weight="weight")
    except nx.NetworkXNoPath:
        raise _no_path(graph, node) from None
    return _result(graph, path[::-1], node, requested, snapped, message)


def k_best_paths(graph: nx.DiGraph, k: int, start: str | None = None, *,
                 roll: float | None = None, pitch: float | None = None,
                 phase: float | None = None) -> list[PathResult]:
    """The ``k`` cheapest loopless paths from a start state to the snap, cheapest first.

    Each path ends at its first in-phase state (in-phase states are absorbing). Fewer than
    ``k`` come back when fewer exist. Arguments as :func:`least_resistance_path`.

    Yen's algorithm (:func:`networkx.shortest_simple_paths`, to a virtual sink joined to
    every target) runs on the states that a path of cost at most ``B`` can visit: those
    with (cost from the start) + (cost to the snap) <= ``B``. Every path of cost <= ``B``
    lies in that subgraph, so the paths found there up to ``B`` are the best overall;
    ``B`` starts 1e-6 above the cheapest cost (ties) and grows tenfold until ``k`` paths
    fit, so that the search stays near the cheapest path.
    """
    if isinstance(k, bool) or not isinstance(k, int | np.integer) or k < 1:
        raise InputError(f"--k {k!r}: give a whole number of paths, at least 1")
    node, requested, snapped, message = _start(graph, start, roll, pitch, phase)
    if graph.nodes[node].get("in_phase"):
        return [_result(graph, [node], node, requested, snapped,
                        message + "; it is already in phase (the snap)")]
    targets = snap_targets(graph)
    if not targets:
        raise _no_path(graph, node)
    to_snap = cost_to_snap(graph)
    best = to_snap[node]
    if math.isinf(best):
        raise _no_path(graph, node)
    from_start = nx.single_source_dijkstra_path_length(graph, node, weight="weight")
    through = {v: d + to_snap[v] for v, d in from_start.items() if math.isfinite(to_snap[v])}
    widest = max(through.values())
    slack = max(1e-6 * best, 1e-9)
    while True:
        bound = best + slack
        # a hair of tolerance so that rounding in the sums never drops a path at the bound
        keep = {v for v, c in through.items() if c <= bound * (1 + 1e-12) + 1e-12}
        paths = _yen(graph, node, keep, k, bound)
        if len(paths) >= k or bound >= widest:
            break
        slack *= 10.0
    if len(paths) < k:  # every reachable state is in: the paths past the bound count too
        paths = _yen(graph, node, set(through), k, math.inf)
    return [_result(graph, p, node, requested, snapped, message) for p in paths]


def _yen(graph: nx.DiGraph, start: str, keep: set[str], k: int, bound: float
         ) -> list[list[str]]:
    """Up to ``k`` cheapest simple paths from ``start`` to a target inside ``keep``, of cost
    at most ``bound``."""
    search = nx.DiGraph()
    search.add_node(start)
    succ = graph.succ
    search.add_weighted_edges_from((u, v, d["weight"]) for u in keep
                                   for v, d in succ[u].items() if v in keep)
    nodes = graph.nodes
    search.add_weighted_edges_from((t, _SINK, 0.0) for t in keep if nodes[t].get("in_phase"))
    out = []
    for path in nx.shortest_simple_paths(search, start, _SINK, "weight"):
        cost = math.fsum(search.succ[u][v]["weight"] for u, v in itertools.pairwise(path))
        if cost > bound * (1 + 1e-12) + 1e-12:
            break
        out.append(path[:-1])
        if len(out) == k:
            break
    return out


def cost_to_snap(graph: nx.DiGraph, weight: Weight = "weight") -> dict[str, float]:
    """Least-resistance cost from every state to the snap, in one Dijkstra.

    Parameters
    ----------
    graph : networkx.DiGraph
    weight : str or callable
        Edge attribute or networkx weight function (e.g.
        :func:`~threadmate.network.variant_weight` for a sensitivity study).

    Returns
    -------
    dict
        Node id -> cost (mJ); 0 for in-phase states, ``math.inf`` where no path exists.
    """
    out = dict.fromkeys(graph.nodes, math.inf)
    targets = snap_targets(graph)
    if targets:
        out.update(nx.multi_source_dijkstra_path_length(graph.reverse(copy=False), targets,
                                                        weight=weight))
    return out


def _safe_reach(graph: nx.DiGraph) -> set[str]:
    """States with a path to the snap that enters no unstable state (targets included)."""
    targets = snap_targets(graph)
    if not targets:
        return set()
    succ = graph.succ
    safe = nx.subgraph_view(graph, filter_edge=lambda u, v: succ[u][v]["label"] != "unstable")
    return set(nx.multi_source_dijkstra_path_length(safe.reverse(copy=False), targets,
                                                    weight=lambda u, v, d: 1))


def unsafe_starts(graph: nx.DiGraph) -> list[str]:
    """States from which no snap is reachable without an unstable transition.

    ``error`` states (no analysis) are left out; in-phase states are safe.
    """
    reach = _safe_reach(graph)
    return [n for n, d in graph.nodes(data=True)
            if n not in reach and d.get("classification") != "error"]
