"""The contact-state network: one node per library state, turning and settling edges.

Nodes
    One per library row, with the string id :func:`node_id` (``r{roll}_p{pitch}_ph{phase}``,
    each angle in degrees rounded to 1e-6 and written as Python writes a float, roll and
    pitch signed: ``r+1.0_p-2.0_ph135.0``, ``r-0.5_p+0.0_ph3.0``). Attributes are scalars:
    ``roll``, ``pitch``, ``phase``, ``classification``, ``in_phase`` (the snap targets),
    ``n_contacts``, ``region_combination``, ``interference``, ``origin_drop``,
    ``pivot_offset``, ``final_roll``, ``final_pitch``, ``final_origin_z``,
    ``first_origin_z``, ``second_origin_z``, ``third_origin_z``, ``rest_height`` (the
    compliance centre's height at the last stage reached) and ``contact_radius`` (mean
    distance of that stage's contacts from the nut axis); lengths in the spec's units,
    angles in degrees, NaN where the contact stages gave no value.

Edges (``kind``)
    ``turning``: to the state one phase step further counter-clockwise (the next phase of
    the grid, wrapping at 360) at the same roll and pitch: the motion of the snap heuristic.

    ``settling``: to the neighbouring roll/pitch of the grid, at the same phase, toward the
    bolt's resting orientation. The contact stages turn the bolt about its contacts in the
    sense that lowers the compliance centre, i.e. along the moment of the axial load (along
    -Z through the compliance centre) about the contacts; they end at ``final_roll`` and
    ``final_pitch``. The compliance holding the bolt yields the same way, so its held
    orientation relaxes toward that rest: along each tilt axis the edge steps one grid value
    in the sign of ``final - held`` when the rest lies at least half of that grid step away
    (a diagonal step when both do); no edge when the rest is within half a step on both.

    In-phase states are absorbing (the bolt has dropped into the thread: the search ends
    there) and ``error`` states have no edges.

Labels (``label``)
    The classification of the destination state: ``stable``, ``quasi-stable`` or
    ``unstable``; entering an in-phase state is ``stable`` (the bolt is seated) and entering
    a ``no-contact`` state is ``unstable`` (nothing known holds the bolt there).

Weights (``weight``, mJ)
    See :mod:`threadmate.network._cost`; the four terms are kept on each edge (``work``,
    ``elastic``, ``friction``, ``penalty``) with the geometry they come from (``rise``,
    ``tilt_change``, ``turn``, lengths in the spec's units and angles in degrees).
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import networkx as nx
import numpy as np
import pandas as pd

from .._errors import LibraryError
from .._version import __version__
from ._cost import COST_UNITS, MM_PER_UNIT, WEIGHT_FORMULA, ResistanceParams, edge_costs

__all__ = [
    "CLASSIFICATIONS",
    "EDGE_LABELS",
    "NETWORK_COLUMNS",
    "NODE_ID_FORMAT",
    "build_network",
    "from_library",
    "node_id",
]

#: Classifications a library row may carry.
CLASSIFICATIONS = ("stable", "quasi-stable", "unstable", "in-phase", "no-contact", "error")
#: Labels an edge may carry.
EDGE_LABELS = ("stable", "quasi-stable", "unstable")
#: How node ids are written.
NODE_ID_FORMAT = "r{roll:+}_p{pitch:+}_ph{phase}  (degrees rounded to 1e-6)"
#: Label of an edge by the classification of its destination.
_LABEL_OF = {"stable": "stable", "quasi-stable": "quasi-stable", "unstable": "unstable",
             "in-phase": "stable", "no-contact": "unstable"}
_STAGES = ("first", "second", "third")
_SLOTS = 3
_FLOAT_ATTRS = ("interference", "origin_drop", "pivot_offset", "final_roll", "final_pitch",
                "final_origin_z", "first_origin_z", "second_origin_z", "third_origin_z")
#: Library columns the network reads (pass to ``threadmate.library.load(columns=...)``).
NETWORK_COLUMNS = [
    "roll", "pitch", "phase", "classification", "n_contacts", "region_combination",
    *_FLOAT_ATTRS, "error",
    *[f"{s}_found" for s in _STAGES],
    *[f"{s}_r22" for s in _STAGES],
    *[f"{s}_c{i}_{a}" for s in _STAGES for i in range(1, _SLOTS + 1) for a in "xy"],
]
_ROUND = 6
_TOL = 1e-6


def _angle(value: float) -> float:
    return round(float(value), _ROUND) + 0.0  # + 0.0 turns -0.0 into 0.0


def node_id(roll: float, pitch: float, phase: float) -> str:
    """The node id of a state, e.g. ``node_id(1, -2, 135) == "r+1.0_p-2.0_ph135.0"``.

    Angles in degrees, rounded to 1e-6; phase taken modulo 360.
    """
    ph = _angle(float(phase) % 360.0)
    if ph >= 360.0:
        ph = 0.0
    return f"r{_angle(roll):+}_p{_angle(pitch):+}_ph{ph}"


def _grid_values(meta: dict[str, Any], df: pd.DataFrame) -> tuple[np.ndarray, ...]:
    grid = meta.get("grid") if isinstance(meta.get("grid"), dict) else None
    out = []
    for name in ("roll", "pitch", "phase"):
        if grid is not None and name in grid:
            values = np.asarray(grid[name], dtype=float)
        else:
            col = df[name].to_numpy(float)
            values = np.unique(np.round(col % 360.0 if name == "phase" else col, _ROUND))
        out.append(np.sort(values))
    return tuple(out)


def _indices(values: np.ndarray, grid: np.ndarray, name: str, phase: bool = False
             ) -> np.ndarray:
    if phase:
        values = np.mod(values, 360.0)
    pos = np.clip(np.searchsorted(grid, values - _TOL), 0, len(grid) - 1)
    bad = np.abs(grid[pos] - values) > _TOL
    if phase:  # 359.9999999 is phase 0
        wrap = bad & (np.abs(values - 360.0 - grid[0]) <= _TOL)
        pos[wrap], bad = 0, bad & ~wrap
    if np.any(bad):
        v = values[np.argmax(bad)]
        raise LibraryError(f"a library row has {name} {v:g}, which is not on the library's "
                           f"grid")
    return pos


def _column(df: pd.DataFrame, name: str, default: Any, dtype: Any) -> np.ndarray:
    if name in df.columns:
        col = df[name]
        if dtype is str:
            return col.fillna(default).astype(str).to_numpy()
        return col.to_numpy(dtype=dtype, na_value=default)
    return np.full(len(df), default, dtype=object if dtype is str else dtype)


def _contact_radius(df: pd.DataFrame, fallback: float) -> np.ndarray:
    """Mean distance from the nut axis of the last stage's contacts (fallback: pitch radius)."""
    n = len(df)
    radius = np.full(n, np.nan)
    for stage in _STAGES:  # later stages overwrite earlier ones where they found contacts
        xs = [f"{stage}_c{i}_x" for i in range(1, _SLOTS + 1)]
        ys = [f"{stage}_c{i}_y" for i in range(1, _SLOTS + 1)]
        if not all(c in df.columns for c in xs + ys):
            continue
        r = np.hypot(df[xs].to_numpy(float), df[ys].to_numpy(float))
        count = np.isfinite(r).sum(axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = np.where(np.isfinite(r), r, 0.0).sum(axis=1) / count
        found = _column(df, f"{stage}_found", True, bool)
        take = found & np.isfinite(mean)
        radius[take] = mean[take]
    radius[~np.isfinite(radius)] = fallback
    return radius


def _rest_height(df: pd.DataFrame, compliance_z: float) -> np.ndarray:
    """Height of the compliance centre at the last stage reached (spec units)."""
    z = _column(df, "final_origin_z", np.nan, float)
    if compliance_z == 0.0:
        return z
    r22 = np.full(len(df), np.nan)
    for stage in _STAGES:
        col = _column(df, f"{stage}_r22", np.nan, float)
        found = _column(df, f"{stage}_found", False, bool)
        r22 = np.where(found & np.isfinite(col), col, r22)
    return z + compliance_z * np.nan_to_num(r22, nan=1.0)


def _metadata(df: pd.DataFrame, metadata: dict[str, Any] | None) -> dict[str, Any]:
    meta = dict(df.attrs.get("threadmate") or {}) if metadata is None else dict(metadata)
    spec = meta.get("spec") if isinstance(meta.get("spec"), dict) else {}
    units = meta.get("units") or spec.get("units")
    if units not in MM_PER_UNIT:
        raise LibraryError("the library table does not say its length units ('in' or 'mm'): "
                           "expected df.attrs['threadmate']['units'] as threadmate.library."
                           "load gives")
    meta["units"] = units
    meta["spec"] = spec
    return meta


def build_network(library: pd.DataFrame, params: ResistanceParams | None = None, *,
                  metadata: dict[str, Any] | None = None) -> nx.DiGraph:
    """The contact-state network of a library table.

    Parameters
    ----------
    library : pandas.DataFrame
        Rows of a contact-state library (:func:`threadmate.library.load`; the columns of
        docs/architecture.md). ``roll``, ``pitch``, ``phase`` and ``classification`` are
        required; other missing columns count as missing values.
    params : ResistanceParams, optional
        Parameters of the edge weight (defaults: :class:`ResistanceParams`).
    metadata : dict, optional
        The library's metadata (spec, grid, units, ...); default ``library.attrs
        ["threadmate"]``. ``units`` is required; the spec gives the pitch (default
        penalty) and the pitch radius (friction radius where a state has no contacts).

    Returns
    -------
    networkx.DiGraph
        Nodes, edges, labels and weights as described in this module's docstring. Graph
        attributes (scalars, ready for GraphML): ``units``, ``cost_units``, ``spec``,
        ``grid`` and ``parameters`` (JSON strings), ``threadmate_version``,
        ``node_id_format``, ``weight_formula``, ``compliance_z``, ``pitch_mm``.

    Raises
    ------
    LibraryError
        A table without the required columns or units, with no rows, with a row off the
        grid, with a configuration twice or with an unknown classification.
    """
    params = ResistanceParams() if params is None else params
    if not isinstance(library, pd.DataFrame):
        raise LibraryError(f"expected a library table (pandas.DataFrame), got "
                           f"{type(library).__name__}")
    missing = [c for c in ("roll", "pitch", "phase", "classification")
               if c not in library.columns]
    if missing:
        raise LibraryError(f"not a contact-state library table: no column {missing[0]!r}")
    if len(library) == 0:
        raise LibraryError("the library holds no states: sweep it first")
    meta = _metadata(library, metadata)
    units, spec = meta["units"], meta["spec"]
    mm = MM_PER_UNIT[units]
    df = library.reset_index(drop=True)
    cls = df["classification"].fillna("error").astype(str).to_numpy()
    unknown = sorted(set(cls) - set(CLASSIFICATIONS))
    if unknown:
        raise LibraryError(f"unknown classification {unknown[0]!r} in the library")

    rolls, pitches, phases = _grid_values(meta, df)
    ir = _indices(df["roll"].to_numpy(float), rolls, "roll")
    ip = _indices(df["pitch"].to_numpy(float), pitches, "pitch")
    ik = _indices(df["phase"].to_numpy(float), phases, "phase", phase=True)
    shape = (len(rolls), len(pitches), len(phases))
    flat = np.ravel_multi_index((ir, ip, ik), shape)
    if len(np.unique(flat)) != len(flat):
        raise LibraryError("the library holds a configuration twice")
    where = np.full(shape, -1, dtype=np.int64)
    where[ir, ip, ik] = np.arange(len(df))

    pitch_len = float(spec.get("pitch", math.nan))
    pitch_mm = pitch_len * mm if math.isfinite(pitch_len) else math.nan
    pitch_radius = float((spec.get("bolt") or {}).get("pitch_diameter", math.nan)) / 2.0
    compliance_z = float((meta.get("contact") or {}).get("compliance_z", 0.0) or 0.0)
    radius = _contact_radius(df, pitch_radius)
    height = _rest_height(df, compliance_z)
    held_roll, held_pitch = rolls[ir], pitches[ip]
    f_roll = _column(df, "final_roll", np.nan, float)
    f_pitch = _column(df, "final_pitch", np.nan, float)
    rest_roll = np.where(np.isfinite(f_roll), f_roll, held_roll)
    rest_pitch = np.where(np.isfinite(f_pitch), f_pitch, held_pitch)

    ids = [node_id(r, p, ph) for r, p, ph in zip(held_roll, held_pitch, phases[ik],
                                                  strict=True)]
    # --- edges -------------------------------------------------------------------------
    active = (cls != "in-phase") & (cls != "error")  # in-phase absorbs, error is unknown
    src_parts, dst_parts, kind_parts, turn_parts = [], [], [], []
    if len(phases) > 1:
        nxt = (ik + 1) % len(phases)
        dst = where[ir, ip, nxt]
        ok = active & (dst >= 0)
        step = np.mod(phases[nxt] - phases[ik], 360.0)
        src_parts.append(np.flatnonzero(ok))
        dst_parts.append(dst[ok])
        kind_parts.append(np.full(ok.sum(), "turning", dtype=object))
        turn_parts.append(step[ok])
    di = _settle_step(f_roll - held_roll, ir, rolls)
    dj = _settle_step(f_pitch - held_pitch, ip, pitches)
    moves = active & np.isfinite(f_roll) & np.isfinite(f_pitch) & ((di != 0) | (dj != 0))
    dst = np.full(len(df), -1, dtype=np.int64)
    dst[moves] = where[ir[moves] + di[moves], ip[moves] + dj[moves], ik[moves]]
    ok = moves & (dst >= 0)
    src_parts.append(np.flatnonzero(ok))
    dst_parts.append(dst[ok])
    kind_parts.append(np.full(ok.sum(), "settling", dtype=object))
    turn_parts.append(np.zeros(ok.sum()))
    src = np.concatenate(src_parts)
    dst = np.concatenate(dst_parts)
    kind = np.concatenate(kind_parts)
    turn_deg = np.concatenate(turn_parts)
    keep = cls[dst] != "error"
    src, dst, kind, turn_deg = src[keep], dst[keep], kind[keep], turn_deg[keep]

    label = np.array([_LABEL_OF[c] for c in cls[dst]], dtype=object)
    rise = height[dst] - height[src]
    tilt_deg = np.hypot(rest_roll[dst] - rest_roll[src], rest_pitch[dst] - rest_pitch[src])
    if np.any(label == "unstable") and not math.isfinite(pitch_mm) \
            and params.unstable_penalty is None:
        raise LibraryError("the library's spec gives no pitch for the default unstable "
                           "penalty: pass ResistanceParams(unstable_penalty=...)")
    if not np.all(np.isfinite(radius[src][kind == "turning"])):
        raise LibraryError("states without contact points and a spec without a pitch "
                           "diameter: cannot size the friction torque of turning")
    costs = edge_costs(rise * mm, np.radians(tilt_deg), np.radians(turn_deg), radius[src] * mm,
                       label == "unstable", params, pitch_mm)

    # --- graph ---------------------------------------------------------------------------
    graph = nx.DiGraph()
    graph.graph.update(_graph_attributes(meta, params, (rolls, pitches, phases), pitch_mm,
                                         compliance_z))
    n_contacts = _column(df, "n_contacts", 0, np.int64)
    regions = _column(df, "region_combination", "", str)
    node_cols: dict[str, Sequence[Any]] = {
        "roll": held_roll.tolist(), "pitch": held_pitch.tolist(),
        "phase": phases[ik].tolist(), "classification": cls.tolist(),
        "in_phase": (cls == "in-phase").tolist(),
        "n_contacts": [int(v) for v in n_contacts], "region_combination": list(map(str, regions)),
    }
    for name in _FLOAT_ATTRS:
        node_cols[name] = _column(df, name, np.nan, float).tolist()
    node_cols["rest_height"] = height.tolist()
    node_cols["contact_radius"] = radius.tolist()
    if "config_id" in df.columns:
        node_cols["config_id"] = [int(v) for v in df["config_id"].to_numpy()]
    names = list(node_cols)
    graph.add_nodes_from(zip(ids, (dict(zip(names, values, strict=True))
                                   for values in zip(*node_cols.values(), strict=True)),
                             strict=True))
    edge_cols = {
        "kind": kind.tolist(), "label": label.tolist(),
        "weight": costs["weight"].tolist(), "work": costs["work"].tolist(),
        "elastic": costs["elastic"].tolist(), "friction": costs["friction"].tolist(),
        "penalty": costs["penalty"].tolist(),
        "rise": np.nan_to_num(rise, nan=0.0).tolist(), "tilt_change": tilt_deg.tolist(),
        "turn": turn_deg.tolist(),
    }
    enames = list(edge_cols)
    graph.add_edges_from(
        (ids[u], ids[v], dict(zip(enames, values, strict=True)))
        for u, v, *values in zip(src.tolist(), dst.tolist(), *edge_cols.values(), strict=True))
    return graph


def _settle_step(delta: np.ndarray, index: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """-1, 0 or +1 grid step toward the rest: at least half the step to that neighbour."""
    n = len(grid)
    up_gap = np.where(index + 1 < n, grid[np.minimum(index + 1, n - 1)] - grid[index], np.inf)
    down_gap = np.where(index > 0, grid[index] - grid[np.maximum(index - 1, 0)], np.inf)
    with np.errstate(invalid="ignore"):
        step = np.where(delta >= 0.5 * up_gap - _TOL, 1,
                        np.where(-delta >= 0.5 * down_gap - _TOL, -1, 0))
    return np.where(np.isfinite(delta), step, 0).astype(np.int64)


def _graph_attributes(meta: dict[str, Any], params: ResistanceParams,
                      grid: tuple[np.ndarray, ...], pitch_mm: float, compliance_z: float
                      ) -> dict[str, Any]:
    rolls, pitches, phases = grid
    return {
        "name": "threadmate contact-state network",
        "units": meta["units"],
        "angle_units": "deg",
        "cost_units": COST_UNITS,
        "spec": json.dumps(meta["spec"], sort_keys=True),
        "grid": json.dumps({"roll": rolls.tolist(), "pitch": pitches.tolist(),
                            "phase": phases.tolist()}),
        "parameters": json.dumps(params.to_dict(), sort_keys=True),
        "axial_force_N": params.axial_force,
        "rotational_stiffness_Nm_per_rad": params.rotational_stiffness,
        "friction": params.friction,
        "unstable_penalty_mJ": float(params.penalty_mj(pitch_mm)) if (
            params.unstable_penalty is not None or math.isfinite(pitch_mm)) else -1.0,
        "pitch_mm": float(pitch_mm) if math.isfinite(pitch_mm) else -1.0,
        "compliance_z": compliance_z,
        "threadmate_version": __version__,
        "library_version": str(meta.get("threadmate_version", "")),
        "node_id_format": NODE_ID_FORMAT,
        "weight_formula": WEIGHT_FORMULA,
        "label_rule": "label = classification of the destination state (in-phase -> stable, "
                      "no-contact -> unstable)",
        "settling_rule": "one grid step in roll and/or pitch at the same phase toward "
                         "(final_roll, final_pitch) when it lies at least half a step away",
        "conventions": "frames, poses and regions per threadmate conventions.md",
    }


def from_library(path: str | Path, params: ResistanceParams | None = None) -> nx.DiGraph:
    """Load a library directory (reading only the columns the network needs) and build
    its network: ``build_network(threadmate.library.load(path, NETWORK_COLUMNS), params)``.
    """
    from ..library import load

    return build_network(load(path, columns=NETWORK_COLUMNS), params)
