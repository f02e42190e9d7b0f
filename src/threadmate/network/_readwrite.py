"""The network on disk: GraphML (networkx, yEd, Gephi, Cytoscape) and node-link JSON.

GraphML keeps string node ids and scalar attributes only, each key of one type (str, int,
float or bool as Python types, never numpy scalars). A float the contact stages did not
give (NaN in memory) is left out of that node's data, as GraphML allows for missing values,
because NaN is not a number every reader parses. The graph's metadata (spec, grid and
parameters as JSON strings, units, cost units, threadmate version, the weight formula) are
graph attributes. The node-link JSON is :func:`networkx.node_link_data` with missing values
as ``null``. Both files are written atomically.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import networkx as nx
import numpy as np

from .._errors import InputError
from .._io import atomic_path, atomic_write_text

__all__ = ["read_graphml", "write_graphml", "write_node_link"]


def _scalar(value: Any) -> Any:
    """A plain Python scalar (None for missing values); refuses containers."""
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if isinstance(value, int | np.integer):
        return int(value)
    if isinstance(value, float | np.floating):
        value = float(value)
        return value if math.isfinite(value) else None
    if isinstance(value, str):
        return value
    if value is None:
        return None
    raise TypeError(f"attribute value {value!r} is not a scalar")


def _clean(data: dict[str, Any]) -> dict[str, Any]:
    out = {}
    for key, value in data.items():
        v = _scalar(value)
        if v is not None:
            out[str(key)] = v
    return out


def _export_graph(graph: nx.DiGraph) -> nx.DiGraph:
    out = nx.DiGraph()
    out.graph.update(_clean(graph.graph))
    out.add_nodes_from((str(n), _clean(d)) for n, d in graph.nodes(data=True))
    out.add_edges_from((str(u), str(v), _clean(d)) for u, v, d in graph.edges(data=True))
    return out


def write_graphml(graph: nx.DiGraph, path: str | Path) -> Path:
    """Write the network as GraphML, atomically.

    Parameters
    ----------
    graph : networkx.DiGraph
        A network from :func:`build_network`.
    path : path-like
        Destination (``.graphml``).

    Returns
    -------
    pathlib.Path
    """
    path = Path(path)
    export = _export_graph(graph)
    with atomic_path(path) as tmp:
        nx.write_graphml(export, tmp, encoding="utf-8", prettyprint=False)
    return path


def write_node_link(graph: nx.DiGraph, path: str | Path) -> Path:
    """Write the network as node-link JSON (``networkx.node_link_data``), atomically.

    Missing values are ``null``; read back with ``networkx.node_link_graph(doc,
    edges="edges")``.
    """
    export = nx.DiGraph()
    export.graph.update({k: _scalar(v) for k, v in graph.graph.items()})
    export.add_nodes_from((n, {k: _scalar(v) for k, v in d.items()})
                          for n, d in graph.nodes(data=True))
    export.add_edges_from((u, v, {k: _scalar(x) for k, x in d.items()})
                          for u, v, d in graph.edges(data=True))
    doc = nx.node_link_data(export, edges="edges")
    return atomic_write_text(path, json.dumps(doc, allow_nan=False) + "\n")


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
        graph = nx.read_graphml(path)
    except Exception as exc:  # noqa: BLE001 - networkx/lxml raise many kinds on bad files
        raise InputError(f"{path} is not readable GraphML: {exc}") from None
    if "grid" not in graph.graph or not isinstance(graph, nx.DiGraph):
        raise InputError(f"{path} is not a threadmate contact-state network")
    floats = ("interference", "origin_drop", "pivot_offset", "final_roll", "final_pitch",
              "final_origin_z", "first_origin_z", "second_origin_z", "third_origin_z",
              "rest_height", "contact_radius")
    for _, d in graph.nodes(data=True):
        for key in floats:
            d.setdefault(key, math.nan)
    return graph
