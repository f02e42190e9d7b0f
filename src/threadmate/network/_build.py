"""The contact-state network of a mechanics library (docs/mechanics.md, "The network").

**Nodes** are the library's states, one per row of the state record
(``threadmate.contact.STATE_COLUMNS``): the rest states each start reaches, the unstable
states passed on the way (first contact, new contacts, rolling), the states the
continuation reaches at each grid phase, and both sides of every jump. Their ids
(``r+1_p-2_ph135.000_s7``) carry the held tilt, the phase and a serial; continuations from
different starts that reach the same state (same load-carrying contacts, pose within the
library's join tolerances) share one node, which the sweep decides.

**Passive edges** are the transitions the state record names (each state has at most one:
the quasi-static dynamics are deterministic): ``settling`` (first contact to rest, same
phase), ``turning`` (a continuous branch, to the next grid phase or to a fold), ``jump``
and ``snap``. Each keeps its label (``stable``, ``quasi-stable``, ``unstable``) and the
work the library measured. None changes the held tilt.

**Active edges** (``active=True``, marked ``active``): what a robot can do beyond turning.
From every rest state at a grid phase, change the held tilt by one grid step (in roll or
pitch; on a polar grid in size or direction, ``Grid.neighbours``): lift the bolt clear
and drop it again at the new held tilt, arriving at that
tilt's first contact at the same phase; then it settles passively.

Weights are in mJ (:data:`WEIGHT_FORMULA`); never negative.
"""

from __future__ import annotations

import json
import math
import os
from typing import Any

import networkx as nx
import numpy as np
import pandas as pd

from .._angles import wrap_phase
from .._errors import InputError, LibraryError
from .._json import json_text
from .._units import MJ_PER_J, to_metres
from .._validate import check_range
from ..contact import ERROR_CLASS, IN_PHASE, STATE_COLUMNS, TRANSITIONS, UNSTABLE
from ..library import load, progress, read_grid

__all__ = [
    "COST_UNITS",
    "EDGE_KINDS",
    "NODE_ATTRIBUTES",
    "WEIGHT_FORMULA",
    "build_network",
    "from_library",
    "start_node",
    "starts",
]

COST_UNITS = "mJ"
#: Kinds of edge: the passive transitions, then the active move.
EDGE_KINDS = (*TRANSITIONS, "tilt-step")
#: The weight of each kind of edge (mJ).
WEIGHT_FORMULA = (
    "turning: max(0, work_friction + work_potential), the driver's work along the branch "
    "(friction: the trapezoid of its friction torque over the phase turned; potential: the "
    "rise of the potential F z_C + k/2 |tilt - held|^2 from the branch's start to its end; "
    "clipped at 0 where the potential falls faster than friction takes, since the driver "
    "is not paid back); "
    "settling: 0 (the driver holds the phase; the load does the work); "
    "jump: jump_penalty (default 0: a jump releases energy); snap: 0; "
    "tilt-step (active): F * max(0, z_C at the new tilt's first contact - z_C now) + "
    "move_penalty (the lift against the load, and a stated price per robot move, default "
    "F x one thread pitch)"
)
_EDGE_COLUMNS = (
    "transition",
    "transition_label",
    "transition_turn",
    "work_friction",
    "work_potential",
    "torque_peak",
    "drop",
    "click",
    "tilt_change",
    "snap_window",
)
#: Node attributes kept from the state record. The transition columns go to the edges;
#: the rotation is ``Rx(roll) Ry(pitch) Rz(phase)`` of the attributes kept, and the contact
#: points and normals stay in the library (one row per node, by ``state_id``), so that a
#: network of 10^5 starts stays small.
NODE_ATTRIBUTES = tuple(
    c.name
    for c in STATE_COLUMNS
    if c.name
    not in (*_EDGE_COLUMNS, "next_id", "state_id", "rotation", "contact_points", "contact_normals")
)
_REST_ROLES = ("start", "continued")


def _finite_nonnegative(name: str, value: float) -> float:
    return check_range(f"{name} (mJ)", value, 0.0, math.inf)


def build_network(
    rows: pd.DataFrame,
    *,
    active: bool = False,
    jump_penalty: float = 0.0,
    move_penalty: float | None = None,
) -> nx.DiGraph:
    """The network of a mechanics library's rows (see the module docstring).

    Parameters
    ----------
    rows : pandas.DataFrame
        The library's rows as :func:`threadmate.library.load` gives them (with the
        library's metadata in ``rows.attrs["threadmate"]``).
    active : bool
        Add the active tilt-step moves.
    jump_penalty : float
        Weight of a jump (mJ, >= 0; the snap costs nothing).
    move_penalty : float, optional
        Price of one active move (mJ, >= 0; default the axial force times one thread
        pitch).

    Returns
    -------
    networkx.DiGraph
        Node and edge attributes as in the module docstring; graph attributes ``units``,
        ``cost_units``, ``weight_formula``, ``spec``, ``grid``, ``compliance`` (JSON
        strings), ``active``, ``jump_penalty``, ``move_penalty``, and how far the
        library's sweep got: ``done`` (starts), ``configurations`` (the grid's) and
        ``complete``.
    """
    meta = rows.attrs.get("threadmate")
    if not meta:
        raise InputError("rows without library metadata (load them with threadmate.library.load)")
    if meta.get("model") != "mechanics":
        raise LibraryError(
            "the network stands on the mechanics: this library holds the "
            "thesis's fixed-pivot rows (sweep it again with model='mechanics', "
            "the default)"
        )
    jump_penalty = _finite_nonnegative("jump_penalty", jump_penalty)
    force = float(meta["compliance"]["force"])
    thread_pitch_mj = MJ_PER_J * force * to_metres(float(meta["spec"]["pitch"]), meta["units"])
    move_penalty = (
        thread_pitch_mj
        if move_penalty is None
        else _finite_nonnegative("move_penalty", move_penalty)
    )
    graph: nx.DiGraph[str] = nx.DiGraph(
        units=meta["units"],
        cost_units=COST_UNITS,
        weight_formula=WEIGHT_FORMULA,
        model="mechanics",
        spec=json_text(meta["spec"], None, sort_keys=True, end=""),
        grid=json_text(meta["grid"], None, sort_keys=True, end=""),
        compliance=json_text(meta["compliance"], None, sort_keys=True, end=""),
        threadmate_version=str(meta.get("threadmate_version", "")),
        active=bool(active),
        jump_penalty=jump_penalty,
        move_penalty=move_penalty,
    )
    ids = rows["state_id"].tolist()
    graph.add_nodes_from(zip(ids, _records(rows, NODE_ATTRIBUTES), strict=True))

    linked = rows[rows["next_id"] != ""]
    missing = sorted(set(linked["next_id"]) - set(ids))
    if missing:
        raise LibraryError(
            f"the library's transitions name {len(missing)} state(s) it does "
            f"not hold (first: {missing[0]}): it is incomplete or mixed"
        )
    kind = linked["transition"].to_numpy()
    work = (linked["work_friction"] + linked["work_potential"]).to_numpy()
    weight = np.where(
        kind == "turning", np.maximum(work, 0.0), np.where(kind == "jump", jump_penalty, 0.0)
    )
    weight = np.where(np.isfinite(weight), weight, 0.0)
    edge_attrs = _records(
        linked,
        _EDGE_COLUMNS,
        {"transition": "kind", "transition_label": "label", "transition_turn": "turn"},
    )
    for d, w in zip(edge_attrs, weight.tolist(), strict=True):
        d["weight"] = w
        d["active"] = False
    graph.add_edges_from(
        zip(linked["state_id"].tolist(), linked["next_id"].tolist(), edge_attrs, strict=True)
    )
    if active:
        _add_tilt_steps(graph, rows, meta, force, move_penalty)
    graph.graph.update(progress(rows))  # done, configurations, complete
    return graph


def _records(
    rows: pd.DataFrame, columns: tuple[str, ...], rename: dict[str, str] | None = None
) -> list[dict[str, Any]]:
    """Rows as plain dicts, column by column (much faster than ``DataFrame.to_dict``)."""
    names = [(rename or {}).get(c, c) for c in columns]
    values = [rows[c].tolist() for c in columns]
    return [dict(zip(names, row, strict=True)) for row in zip(*values, strict=True)]


def _phase_key(phase: float) -> float:
    """A phase to match states at one grid phase by (a continuation that summed its turns
    may land a hair below 360 for phase 0)."""
    return wrap_phase(round(phase, 6)) + 0.0


def _add_tilt_steps(
    graph: nx.DiGraph, rows: pd.DataFrame, meta: dict[str, Any], force: float, move_penalty: float
) -> None:
    """Active moves: from each rest state at a grid phase to the first contact of a
    neighbouring held tilt at that phase."""
    grid = read_grid(meta["grid"])
    first = rows[rows["role"] == "first-contact"]
    arrive = {
        (r, p, _phase_key(ph)): (sid, z)
        for sid, r, p, ph, z in zip(
            first["state_id"],
            first["held_roll"],
            first["held_pitch"],
            first["phase"],
            first["centre_z"],
            strict=True,
        )
    }
    metres = to_metres(1.0, meta["units"])
    rest = rows[
        rows["role"].isin(_REST_ROLES) & ~rows["classification"].isin([IN_PHASE, ERROR_CLASS])
    ]
    # The held tilts one grid step away from each (in roll or pitch on a square grid; in
    # size or direction on a polar one): the grid's own rule.
    near: dict[tuple[float, float], list[tuple[float, float]]] = {}
    for here, there in grid.neighbours():
        near.setdefault(here, []).append(there)
    steps = []
    for sid, r, p, ph, z in zip(
        rest["state_id"],
        rest["held_roll"],
        rest["held_pitch"],
        rest["phase"],
        rest["centre_z"],
        strict=True,
    ):
        for tilt in near.get((r, p), ()):
            target = arrive.get((tilt[0], tilt[1], _phase_key(ph)))
            if target is None:
                continue
            lift = max(0.0, target[1] - z) * metres
            steps.append(
                (
                    sid,
                    target[0],
                    {
                        "kind": "tilt-step",
                        "label": UNSTABLE,
                        "turn": 0.0,
                        "work_friction": 0.0,
                        "work_potential": MJ_PER_J * force * lift,
                        "torque_peak": math.nan,
                        "drop": z - target[1],
                        "tilt_change": math.nan,
                        "weight": MJ_PER_J * force * lift + move_penalty,
                        "active": True,
                    },
                )
            )
    graph.add_edges_from(steps)


def from_library(
    path: str | os.PathLike[str],
    *,
    active: bool = False,
    jump_penalty: float = 0.0,
    move_penalty: float | None = None,
) -> nx.DiGraph:
    """The network of the mechanics library at ``path`` (:func:`build_network`)."""
    return build_network(
        load(path), active=active, jump_penalty=jump_penalty, move_penalty=move_penalty
    )


def starts(graph: nx.DiGraph) -> dict[tuple[float, float, float], str]:
    """The start states, keyed by (held roll, held pitch, phase) in degrees (cached on the
    graph under a private key that the writers skip)."""
    cached = graph.graph.get("_starts")
    if cached is None:
        cached = {
            (d["held_roll"], d["held_pitch"], d["phase"]): n
            for n, d in graph.nodes(data=True)
            if d["role"] == "start"
        }
        graph.graph["_starts"] = cached
    return cached


def start_node(
    graph: nx.DiGraph, roll: float, pitch: float, phase: float, *, nearest: bool = False
) -> tuple[str, bool]:
    """The start state of a configuration: ``(node id, moved_to_grid)``.

    Without ``nearest`` a configuration that is not on the library's grid is refused with
    the nearest grid configurations named; with it, the nearest is taken and ``moved_to_grid`` is
    True.
    """
    grid = read_grid(json.loads(graph.graph["grid"]))
    _, on_grid, moved_to_grid = grid.locate(roll, pitch, phase, nearest=nearest)
    node = starts(graph).get(on_grid)
    if node is None:
        raise InputError(
            f"the library has no start at roll {on_grid[0]:g}, pitch "
            f"{on_grid[1]:g}, phase {on_grid[2]:g}: its sweep is unfinished or "
            "that configuration failed"
        )
    return node, moved_to_grid
