"""GraphML written and read as a stream: the file networkx's tree writer gave, in memory
that does not grow with the network.

The reference is written here: the network's attributes made plain by the rules of
docs/network.md (lists as JSON text with ``null`` for NaN, NaN and infinity left out,
private keys left out, numpy scalars as Python's), restated below without threadmate,
and written by networkx's own ElementTree writer (:func:`networkx.write_graphml`). Both
files are read with :func:`networkx.read_graphml`, which must give the same nodes, edges
and values; :func:`threadmate.network.read_graphml` must give what networkx reads, with
the lists parsed and the missing floats back as NaN. Memory is measured with
:mod:`tracemalloc`: the writer's and the reader's own peak must not grow with the network.
"""

from __future__ import annotations

import gc
import json
import math
import tracemalloc
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import networkx as nx
import numpy as np
import pandas as pd
import pytest

from _libraries import library_rows, mechanics_library, synthetic_library
from threadmate import InputError
from threadmate.network import (
    GEOMETRY_ATTRIBUTES,
    from_library,
    read_graphml,
    start_outcomes,
    write_graphml,
)

NS = "{http://graphml.graphdrawing.org/xmlns}"
#: Node attributes :func:`read_graphml` parses back from JSON text.
LISTS = ("contact_regions", "contact_forces", *GEOMETRY_ATTRIBUTES)
#: What GraphML type names the reader's value types (networkx's reading).
PYTHON_TYPE = {"boolean": bool, "long": int, "double": float, "string": str}


# -- the reference: the rules restated, written by networkx ---------------------------------
def plain(value: Any) -> Any:
    """A value as the files hold it (None: left out)."""
    if isinstance(value, np.ndarray | list | tuple):
        items = np.asarray(value, dtype=object).tolist()
        return json.dumps(
            [None if isinstance(v, float) and not math.isfinite(v) else v for v in items]
        )
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def cleaned(data: dict[Any, Any]) -> dict[str, Any]:
    out = {}
    for key, value in data.items():
        v = plain(value)
        if not str(key).startswith("_") and v is not None:
            out[str(key)] = v
    return out


def reference_file(graph: nx.DiGraph, path: Path, rows: pd.DataFrame | None = None) -> Path:
    """The network written by networkx's tree writer, after the rules (``rows``: the
    library's, whose geometry each node gets first)."""
    geometry = {}
    if rows is not None:
        for _, row in rows.iterrows():
            geometry[row["state_id"]] = {k: row[k] for k in GEOMETRY_ATTRIBUTES}
    ref: nx.DiGraph[str] = nx.DiGraph()
    ref.graph.update(cleaned(graph.graph))
    for n, d in graph.nodes(data=True):
        ref.add_node(str(n), **cleaned({**geometry.get(str(n), {}), **d}))
    for u, v, d in graph.edges(data=True):
        ref.add_edge(str(u), str(v), **cleaned(d))
    nx.write_graphml(ref, path)
    return path


def assert_same_reading(ours: nx.DiGraph, reference: nx.DiGraph) -> None:
    """The same nodes, edges and values, of the same types, in either networkx reading."""
    assert list(ours.nodes) == list(reference.nodes)
    assert sorted(ours.edges) == sorted(reference.edges)
    assert ours.graph == reference.graph
    for n, d in reference.nodes(data=True):
        assert ours.nodes[n] == d, n
        assert {k: type(v) for k, v in ours.nodes[n].items()} == {
            k: type(v) for k, v in d.items()
        }, n
    for u, v, d in reference.edges(data=True):
        assert ours.edges[u, v] == d and all(
            type(ours.edges[u, v][k]) is type(x) for k, x in d.items()
        ), (u, v)


def keys_of(path: Path) -> dict[tuple[str, str], str]:
    """(for, attr.name) -> attr.type of the file's keys, checked one per pair, and every
    data element's key declared for its element's kind with a value of its type."""
    root = ET.parse(path).getroot()
    keys = {}
    by_id = {}
    for k in root.iter(f"{NS}key"):
        pair = (k.get("for"), k.get("attr.name"))
        assert pair not in keys, f"key {pair} declared twice"
        assert k.get("attr.type") in PYTHON_TYPE, k.attrib
        assert k.get("id") not in by_id
        keys[pair] = k.get("attr.type")
        by_id[k.get("id")] = (k.get("for"), k.get("attr.type"))
    for scope in ("graph", "node", "edge"):
        for element in root.iter(f"{NS}{scope}"):
            for data in element.findall(f"{NS}data"):
                kind, attr_type = by_id[data.get("key")]
                assert kind == scope
                text = data.text or ""
                if attr_type == "boolean":
                    assert text in ("true", "false")
                elif attr_type == "long":
                    int(text)
                elif attr_type == "double":
                    assert math.isfinite(float(text))
    return keys


def assert_read_is_networkx_reading(path: Path) -> None:
    """:func:`read_graphml` gives what networkx reads, lists parsed, missing floats NaN."""
    back, raw = read_graphml(path), nx.read_graphml(path)
    assert list(back.nodes) == list(raw.nodes)
    assert list(back.edges) == list(raw.edges)
    assert back.graph == raw.graph
    for items, raw_items in (
        (back.nodes(data=True), raw.nodes(data=True)),
        (back.edges(data=True), raw.edges(data=True)),
    ):
        for (*_, d), (*_, r) in zip(items, raw_items, strict=True):
            for key, value in r.items():
                if key in LISTS:
                    want = [math.nan if v is None else v for v in json.loads(value)]
                    assert d[key] == want or np.array_equal(d[key], want, equal_nan=True)
                else:
                    assert d[key] == value and type(d[key]) is type(value)
            for key in d.keys() - r.keys():
                assert math.isnan(d[key]), key  # a float the file leaves out


# -- fixtures -------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def real_lib(tmp_path_factory):
    return mechanics_library(tmp_path_factory)


@pytest.fixture(scope="module")
def synth_lib(tmp_path_factory, quarter_20):
    return synthetic_library(tmp_path_factory.mktemp("synthetic") / "lib", quarter_20)


def mixed_graph() -> nx.DiGraph:
    """Values of every kind: numpy and Python scalars, NaN, infinities, None, empty and
    escaped strings, lists with NaN, private keys, and keys whose values mix types."""
    g: nx.DiGraph[str] = nx.DiGraph(
        grid=json.dumps({"phase": [0.0, 90.0]}),
        units="mm",
        active=True,
        count=np.int64(3),
        gone=math.inf,
        _cache=pd.DataFrame({"a": [1]}),  # private: never written, whatever it holds
    )
    g.add_node(
        "a&b <1>",
        phase=np.float64(12.5),
        n=np.int32(2),
        ok=np.bool_(True),
        note='"quoted" & <tagged> \u00d8 6 \u2014 \u00b5m',
        empty="",
        z=math.nan,
        lifted=math.inf,
        sunk=-math.inf,
        nothing=None,
        contact_forces=np.array([6.0, math.nan, 4.0]),
        contact_regions=["base/surface", "+F/surface"],
        rotation=(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        contact_points=[],
        all_nan=math.nan,
        _private=1,
    )
    g.add_node(
        'line\nbreak\t"q"',
        phase=0.1 + 0.2,
        n=7,
        ok=False,
        note="plain",
        empty="",
        z=-1e-300,
        contact_forces=[],
        all_nan=math.nan,
    )
    g.add_node("c", phase=-0.0, n=-(2**62), ok=True, z=1e300, all_nan=math.nan)
    g.add_edge("a&b <1>", 'line\nbreak\t"q"', weight=0.25, active=np.bool_(False), kind="jump")
    g.add_edge('line\nbreak\t"q"', "c", weight=math.nan, active=True, kind="snap & <drop>")
    g.add_edge("c", "a&b <1>", weight=np.float32(0.5), active=False, kind="")
    return g


# -- the file networkx's writer gave --------------------------------------------------------
def test_real_network_loads_in_networkx_as_the_tree_writer_wrote_it(real_lib, tmp_path):
    graph = from_library(real_lib, active=True)
    start_outcomes(graph)  # the caches it keeps on the graph are not written
    path = write_graphml(graph, tmp_path / "net.graphml", library=real_lib)
    reference = reference_file(graph, tmp_path / "ref.graphml", library_rows(real_lib))
    ours = nx.read_graphml(path)
    assert_same_reading(ours, nx.read_graphml(reference))
    assert ours.number_of_nodes() == graph.number_of_nodes() > 100
    assert ours.number_of_edges() == graph.number_of_edges()
    keys = keys_of(path)
    for key in LISTS:
        assert keys[("node", key)] == "string"  # lists as JSON text
    assert keys[("edge", "active")] == keys[("graph", "active")] == "boolean"
    assert keys[("node", "config_id")] == "long" and keys[("node", "phase")] == "double"
    assert_read_is_networkx_reading(path)
    assert sorted(tmp_path.iterdir()) == [path, reference]  # no temporary left behind


def test_synthetic_library_without_geometry(synth_lib, tmp_path):
    graph = from_library(synth_lib)
    path = write_graphml(graph, tmp_path / "net.graphml")
    reference = reference_file(graph, tmp_path / "ref.graphml")
    assert_same_reading(nx.read_graphml(path), nx.read_graphml(reference))
    assert not {("node", k) for k in GEOMETRY_ATTRIBUTES} & keys_of(path).keys()
    assert_read_is_networkx_reading(path)


def test_mixed_values_follow_the_typing_rules(tmp_path):
    graph = mixed_graph()
    path = write_graphml(graph, tmp_path / "mixed.graphml")
    keys = keys_of(path)
    assert keys == {
        ("graph", "grid"): "string",
        ("graph", "units"): "string",
        ("graph", "active"): "boolean",
        ("graph", "count"): "long",
        ("node", "phase"): "double",
        ("node", "n"): "long",
        ("node", "ok"): "boolean",
        ("node", "note"): "string",
        ("node", "empty"): "string",
        ("node", "z"): "double",
        ("node", "contact_forces"): "string",
        ("node", "contact_regions"): "string",
        ("node", "rotation"): "string",
        ("node", "contact_points"): "string",
        ("edge", "weight"): "double",
        ("edge", "active"): "boolean",
        ("edge", "kind"): "string",
    }  # no key for values all missing (all_nan, lifted, nothing) or private
    back = nx.read_graphml(path)
    assert_same_reading(back, nx.read_graphml(reference_file(graph, tmp_path / "ref.graphml")))
    a, b = back.nodes["a&b <1>"], back.nodes['line\nbreak\t"q"']
    assert a["note"] == '"quoted" & <tagged> \u00d8 6 \u2014 \u00b5m' and a["empty"] == ""
    assert a["phase"] == 12.5 and a["n"] == 2 and a["ok"] is True
    assert not {"z", "lifted", "sunk", "nothing", "all_nan", "_private"} & a.keys()
    assert json.loads(a["contact_forces"]) == [6.0, None, 4.0]
    assert json.loads(a["rotation"]) == [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    assert json.loads(a["contact_points"]) == []
    assert b["phase"] == 0.1 + 0.2 and b["z"] == -1e-300 and b["ok"] is False
    c = back.nodes["c"]
    assert c["n"] == -(2**62) and c["z"] == 1e300 and math.copysign(1, c["phase"]) == -1
    assert back.edges["c", "a&b <1>"] == {"weight": 0.5, "active": False, "kind": ""}
    assert "weight" not in back.edges['line\nbreak\t"q"', "c"]
    assert back.graph["count"] == 3 and back.graph["active"] is True
    assert not {"gone", "_cache"} & back.graph.keys()
    assert_read_is_networkx_reading(path)


def test_a_key_of_mixed_types_is_typed_once(tmp_path):
    """Integers and floats make a double key; any other mix, a string key of the texts
    (networkx's writer would declare the name twice, once per type)."""
    g: nx.DiGraph[str] = nx.DiGraph(grid="{}")
    g.add_node("a", number=1, mix=True, label=2)
    g.add_node("b", number=2.5, mix=3, label="two")
    path = write_graphml(g, tmp_path / "m.graphml")
    keys = keys_of(path)
    assert keys[("node", "number")] == "double"
    assert keys[("node", "mix")] == keys[("node", "label")] == "string"
    back = nx.read_graphml(path)
    assert back.nodes["a"] == {"number": 1.0, "mix": "true", "label": "2"}
    assert type(back.nodes["a"]["number"]) is float
    assert back.nodes["b"] == {"number": 2.5, "mix": "3", "label": "two"}


def test_a_value_that_is_no_scalar_leaves_no_file(tmp_path):
    g: nx.DiGraph[str] = nx.DiGraph(grid="{}")
    g.add_node("a", fine=1.0)
    g.add_node("b", bad={"a": 1})
    with pytest.raises(TypeError, match="scalar"):
        write_graphml(g, tmp_path / "bad.graphml")
    assert list(tmp_path.iterdir()) == []


# -- the reading side -----------------------------------------------------------------------
def test_files_networkx_writes_read_as_networkx_reads_them(tmp_path):
    """A file the stream reader does not take (key defaults, parallel edges, an edge id)
    is read by networkx; one it takes gives networkx's reading."""
    g: nx.MultiDiGraph[str] = nx.MultiDiGraph(grid="{}", node_default={"colour": "red"})
    g.add_node("a", colour="blue", phase=1.0)
    g.add_node("b", phase=2.0)
    g.add_edge("a", "b", weight=1.0)
    g.add_edge("a", "b", weight=2.0)
    nx.write_graphml(g, tmp_path / "multi.graphml")
    plain = nx.DiGraph(nx.MultiDiGraph(g))
    plain.graph.pop("node_default")
    nx.write_graphml(plain, tmp_path / "plain.graphml", prettyprint=True)
    for name in ("multi.graphml", "plain.graphml"):
        path = tmp_path / name
        assert type(read_graphml(path)) is type(nx.read_graphml(path))
        assert_read_is_networkx_reading(path)
    assert read_graphml(tmp_path / "multi.graphml").number_of_edges() == 2
    assert read_graphml(tmp_path / "multi.graphml").graph["node_default"] == {"colour": "red"}


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("\n".join(nx.generate_graphml(nx.DiGraph())), "not a threadmate contact-state"),
        ("<nothing/>", "not readable GraphML"),
        ("not xml at all", "not readable GraphML"),
    ],
)
def test_a_file_that_is_no_network_is_refused(tmp_path, text, message):
    path = tmp_path / "x.graphml"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        read_graphml(path)
    with pytest.raises(InputError, match="no network file"):
        read_graphml(tmp_path / "missing.graphml")


def test_a_truncated_file_is_refused(synth_lib, tmp_path):
    path = write_graphml(from_library(synth_lib), tmp_path / "net.graphml")
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(InputError, match="not readable GraphML"):
        read_graphml(path)


# -- bounded memory -------------------------------------------------------------------------
def chain(n: int) -> nx.DiGraph:
    """A network-shaped graph of ``n`` states, each turning to the next."""
    g: nx.DiGraph[str] = nx.DiGraph(grid=json.dumps({"phase": [0.0]}), units="in")
    for i in range(n):
        g.add_node(
            f"r+0_p+0_ph{i % 360:07.3f}_s{i}",
            phase=float(i % 360),
            role="start",
            classification="quasi-stable",
            config_id=i,
            engaged=bool(i % 2),
            centre_z=math.nan if i % 3 else 1e-4 * i,
            potential=i / 7,
            contact_regions=np.array(["base/surface", "+F/surface"], dtype=object),
            contact_forces=np.array([6.0, i / 3]),
            error="",
        )
    ids = list(g.nodes)
    for u, v in zip(ids, ids[1:], strict=False):
        g.add_edge(u, v, kind="turning", label="quasi-stable", weight=0.35, active=False)
    return g


def traced_peak(step: Any) -> tuple[Any, int, int]:
    """What ``step()`` returns, the memory it allocated and kept, and its peak above that
    (bytes, :mod:`tracemalloc`)."""
    gc.collect()
    tracemalloc.start()
    try:
        base = tracemalloc.get_traced_memory()[0]
        result = step()
        current, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return result, current - base, peak - current


def test_write_and_read_memory_does_not_grow_with_the_network(tmp_path):
    """Four times the states: the same peak for the writer and for the reader beyond the
    graph it returns (a document tree grows with the file: networkx's reader is shown to,
    as the check that the measure sees one)."""
    peaks = {}
    for n in (2_000, 8_000):
        path = tmp_path / f"n{n}.graphml"
        graph = chain(n)
        _, _, write_peak = traced_peak(lambda g=graph, p=path: write_graphml(g, p))
        del graph
        back, kept, read_peak = traced_peak(lambda p=path: read_graphml(p))
        assert back.number_of_nodes() == n
        del back
        _, _, tree_peak = traced_peak(lambda p=path: nx.read_graphml(p))
        peaks[n] = write_peak, read_peak, tree_peak, kept, path.stat().st_size
    (w1, r1, t1, kept1, size1), (w4, r4, t4, kept4, size4) = peaks[2_000], peaks[8_000]
    assert size4 > 3.5 * size1 and kept4 > 3.5 * kept1
    mb = 2**20
    assert w4 < w1 + mb and w4 < 4 * mb, (w1, w4)
    assert r4 < r1 + mb and r4 < 4 * mb, (r1, r4)
    assert t4 > 3 * t1 and t4 > 8 * mb, (t1, t4)  # the tree: it grows with the file
