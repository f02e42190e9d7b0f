"""The network on disk: GraphML (networkx, yEd, Gephi, Cytoscape), node-link JSON and the
starts' outcomes as CSV.

GraphML keeps string node ids and scalar attributes only, each key of one type (str, int,
float or boolean, never numpy scalars), as Gephi and yEd type their columns; booleans are
written ``true``/``false`` as the GraphML schema spells them. A list attribute (the
rotation, the contacts' regions, forces, points and normals) is written as its JSON text,
a string. A float the mechanics did not give (NaN in memory) is left out of that element's
data, as GraphML allows for missing values, because NaN is not a number every reader
parses; inside a list's JSON text it is ``null``. The graph's metadata (spec, grid and
compliance as JSON strings, units, cost units, threadmate version, the weight formula) are
graph attributes; private keys (starting with ``_``) are not written. The node-link JSON
is :func:`networkx.node_link_data` with missing values as ``null``.

GraphML is written and read as a stream (:mod:`._graphml`: each node and edge goes to the
file as it is produced, and is dropped once read), so that writing or reading the network
of 10^5 starts needs little memory beyond the network's own, never a document tree.

The network in memory leaves each state's rotation and its contacts' points and normals
(:data:`GEOMETRY_ATTRIBUTES`) in the library, so that it stays small; given the library,
the writers put them on every node of the files. The starts' CSV names each column with
its unit (``turn_deg``, ``work_mJ``, ``click_in``, ...: :data:`START_COLUMN_UNITS`). Every
file is written atomically.
"""

from __future__ import annotations

import itertools
import json
import math
import operator
import os
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any

import networkx as nx
import numpy as np
import pandas as pd

from .._errors import InputError
from .._io import atomic_path, atomic_write_text
from .._json import json_text, to_jsonable
from ..library import load
from ._graphml import EdgeBlock, NodeBlock, read_graphml_stream, write_graphml_stream

__all__ = [
    "GEOMETRY_ATTRIBUTES",
    "LIST_ATTRIBUTES",
    "START_COLUMN_UNITS",
    "read_graphml",
    "start_outcomes_csv",
    "write_graphml",
    "write_node_link",
]

#: Node attributes the files carry from the library (a state's pose and its contacts):
#: ``rotation`` (9 values, row-major), ``contact_points`` (3 values per touching contact,
#: spec units, frame F) and ``contact_normals`` (3 per contact, unit, nut into bolt).
GEOMETRY_ATTRIBUTES = ("rotation", "contact_points", "contact_normals")
#: Node attributes that hold lists (written as JSON text, read back as lists).
LIST_ATTRIBUTES = ("contact_regions", "contact_forces", *GEOMETRY_ATTRIBUTES)
#: Units of the starts' outcome columns (:func:`threadmate.network.start_outcomes`) that
#: have one ("length": the spec's); the CSV names them ``<column>_<unit>``.
START_COLUMN_UNITS = {
    "held_roll": "deg",
    "held_pitch": "deg",
    "held_tilt": "deg",
    "held_direction": "deg",
    "phase": "deg",
    "turn": "deg",
    "work": "mJ",
    "click": "length",
    "snap_phase": "deg",
    "snap_window": "deg",
    "torque_peak": "N_m",
}

Library = str | os.PathLike[str] | pd.DataFrame
#: The types of a GraphML attribute's scalar value.
_SCALARS = (str, bool, int, float, np.bool_, np.integer, np.floating)
#: Nodes or edges written at a time: the writer's memory is a block's text.
_BLOCK = 512


def _scalar(value: Any) -> Any:
    """A plain Python scalar (:func:`~threadmate._json.to_jsonable`: None for missing
    values); lists become their JSON text."""
    if type(value) is str:  # the common case first: this runs once per attribute
        return value
    if isinstance(value, np.ndarray | list | tuple):
        return json_text(value, None, end="")
    if value is None or isinstance(value, _SCALARS):
        return to_jsonable(value)
    raise TypeError(f"attribute value {value!r} is not a scalar")


def _scalars(values: list[Any]) -> list[Any]:
    """:func:`_scalar` of each value of a column. A column of flat arrays (a state's
    forces, regions, rotation, points, normals) is written as one JSON document and cut
    into its rows: the same text at a fraction of the cost of one document per row."""
    if values and all(type(v) is np.ndarray and v.ndim == 1 for v in values):
        numeric = all(v.dtype.kind in "biuf" for v in values)
        try:
            text = json.dumps([v.tolist() for v in values])
        except TypeError:  # a value JSON does not know: each row by to_jsonable
            text = ""
        if text and ("N" in text or "I" in text):
            if not numeric:  # "NaN" may be text inside a string: each row by json_text
                text = ""
            else:  # NaN, Infinity: null, as json_text writes them
                text = text.replace("-Infinity", "null").replace("Infinity", "null")
                text = text.replace("NaN", "null")
        rows = text[1:-1].split("], [")
        if text and len(rows) == len(values):  # else "], [" inside a string
            rows[0], rows[-1] = rows[0][1:], rows[-1][:-1]
            return [f"[{row}]" for row in rows]
    return [_scalar(v) for v in values]


def _public(name: str) -> bool:
    """Whether an attribute is written to the files (private keys start with ``_``)."""
    return not name.startswith("_")


class _Geometry:
    """Each state's :data:`GEOMETRY_ATTRIBUTES`, by state id, read from ``library`` (a
    path, or rows as :func:`threadmate.library.load` gives them); none without one.

    The values stay in the library's columns (one array per cell), found by row, so that
    no dictionary per state is made."""

    def __init__(self, library: Library | None) -> None:
        self.row: dict[str, int] = {}
        self.columns: list[list[Any]] = []
        if library is None:
            return
        columns = ["state_id", *GEOMETRY_ATTRIBUTES]
        rows = library if isinstance(library, pd.DataFrame) else load(library, columns=columns)
        missing = [c for c in columns if c not in rows.columns]
        if missing:
            raise InputError(f"the library rows lack {', '.join(missing)}: not a mechanics library")
        self.row = {sid: i for i, sid in enumerate(rows["state_id"].tolist())}
        self.columns = [rows[c].tolist() for c in GEOMETRY_ATTRIBUTES]

    def items(self, node: str, own: Mapping[Any, Any]) -> list[tuple[str, Any]]:
        """The geometry of state ``node`` that its own attributes ``own`` do not hold."""
        i = self.row.get(node)
        if i is None:
            return []
        return [
            (key, column[i])
            for key, column in zip(GEOMETRY_ATTRIBUTES, self.columns, strict=True)
            if key not in own
        ]


def _nodes(graph: nx.DiGraph, library: Library | None) -> Iterator[tuple[Any, Iterable[Any]]]:
    """The graph's nodes with their attributes as (key, value) pairs, each state's
    geometry from ``library`` first where the node does not hold it."""
    geometry = _Geometry(library)
    for n, d in graph.nodes(data=True):
        yield n, itertools.chain(geometry.items(str(n), d), d.items())


def _columns(dicts: list[dict[Any, Any]], skip: Iterable[Any] = ()) -> list[tuple[Any, list[Any]]]:
    """The attributes of a block of nodes or edges as columns, in the order the block
    first gives them (None where an element has no value)."""
    names = dict.fromkeys(dicts[0]) if dicts else {}
    same = all(d.keys() == names.keys() for d in dicts)  # the common case: one layout
    if not same:
        names = dict.fromkeys(key for d in dicts for key in d)
    for key in skip:
        names.pop(key, None)
    if same:
        return [(key, list(map(operator.itemgetter(key), dicts))) for key in names]
    return [(key, [d.get(key) for d in dicts]) for key in names]


def _node_blocks(graph: nx.DiGraph, library: Library | None) -> Iterator[NodeBlock]:
    """The graph's nodes in blocks of :data:`_BLOCK`, each state's geometry from
    ``library`` first (a node's own value, where it holds one, instead)."""
    geometry = _Geometry(library)
    nodes = iter(graph.nodes(data=True))
    while block := list(itertools.islice(nodes, _BLOCK)):
        ids = [str(n) for n, _ in block]
        dicts = [d for _, d in block]
        columns = []
        if geometry.columns:
            rows = [geometry.row.get(n) for n in ids]
            for key, column in zip(GEOMETRY_ATTRIBUTES, geometry.columns, strict=True):
                values = [
                    d[key] if key in d else (None if i is None else column[i])
                    for d, i in zip(dicts, rows, strict=True)
                ]
                columns.append((key, values))
        yield ids, columns + _columns(dicts, skip=GEOMETRY_ATTRIBUTES if geometry.columns else ())


def _edge_blocks(graph: nx.DiGraph) -> Iterator[EdgeBlock]:
    """The graph's edges in blocks of :data:`_BLOCK`."""
    edges = iter(graph.edges(data=True))
    while block := list(itertools.islice(edges, _BLOCK)):
        yield (
            [str(u) for u, _, _ in block],
            [str(v) for _, v, _ in block],
            _columns([d for _, _, d in block]),
        )


def write_graphml(graph: nx.DiGraph, path: str | Path, *, library: Library | None = None) -> Path:
    """Write the network as GraphML, atomically, a block of nodes and edges at a time.

    Parameters
    ----------
    graph : networkx.DiGraph
        A network from :func:`build_network`.
    path : path-like
        Destination (``.graphml``).
    library : path-like or pandas.DataFrame, optional
        The library the network was built from (its path or its rows): each node then
        also gets its :data:`GEOMETRY_ATTRIBUTES` (JSON text).

    Returns
    -------
    pathlib.Path
    """
    path = Path(path)
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        write_graphml_stream(
            fh,
            graph.graph.items(),
            _node_blocks(graph, library),
            _edge_blocks(graph),
            convert=_scalars,
            keep=_public,
            spool_dir=tmp.parent,
        )
    return path


def write_node_link(graph: nx.DiGraph, path: str | Path, *, library: Library | None = None) -> Path:
    """Write the network as node-link JSON (``networkx.node_link_data``), atomically.

    Missing values are ``null``; read back with ``networkx.node_link_graph(doc,
    edges="edges")``. With ``library`` (as for :func:`write_graphml`) each node also
    gets its :data:`GEOMETRY_ATTRIBUTES`, as lists.
    """
    export: nx.DiGraph[str] = nx.DiGraph()
    export.graph.update({k: v for k, v in graph.graph.items() if _public(str(k))})
    export.add_nodes_from((n, dict(items)) for n, items in _nodes(graph, library))
    export.add_edges_from(graph.edges(data=True))
    doc = nx.node_link_data(export, edges="edges")
    return atomic_write_text(path, json_text(doc, None))  # values made plain by to_jsonable


def read_graphml(path: str | Path) -> nx.DiGraph:
    """Read a network written by :func:`write_graphml` (missing floats back as NaN).

    Raises
    ------
    InputError
        The file is missing, not GraphML, or not a threadmate network.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"no network file at {path}")
    try:
        graph = read_graphml_stream(path)
    except Exception as exc:  # noqa: BLE001 - networkx/lxml raise many kinds on bad files
        raise InputError(f"{path} is not readable GraphML: {exc}") from None
    if "grid" not in graph.graph or not isinstance(graph, nx.DiGraph):
        raise InputError(f"{path} is not a threadmate contact-state network")
    floats = (
        "potential",
        "driver_torque",
        "friction_torque",
        "roll",
        "pitch",
        "origin_x",
        "origin_y",
        "origin_z",
        "centre_x",
        "centre_y",
        "centre_z",
    )
    for _, d in graph.nodes(data=True):
        for key in floats:
            d.setdefault(key, math.nan)
        for key in LIST_ATTRIBUTES:
            if isinstance(d.get(key), str):
                d[key] = json.loads(d[key])
                if key != "contact_regions":  # null in the JSON text of numbers: NaN
                    d[key] = [math.nan if v is None else v for v in d[key]]
    for _, _, d in graph.edges(data=True):
        for key in ("torque_peak", "tilt_change", "drop", "click", "snap_window"):
            d.setdefault(key, math.nan)
    return graph


def start_outcomes_csv(outcomes: pd.DataFrame, path: str | Path, units: str) -> Path:
    """Write the starts' outcomes (:func:`threadmate.network.start_outcomes`) as CSV,
    atomically, each column with a unit named with it (:data:`START_COLUMN_UNITS`;
    ``units``: the spec's length unit, for the click)."""
    names = {
        col: f"{col}_{units if unit == 'length' else unit}"
        for col, unit in START_COLUMN_UNITS.items()
    }
    return atomic_write_text(path, outcomes.rename(columns=names).to_csv(index=False))
