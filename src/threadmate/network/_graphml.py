"""GraphML as a stream: written a block and read one element at a time, in bounded memory.

The writer puts the nodes and edges in the file a block at a time, each attribute of a
block converted as a column (the per-value work is then a comprehension over one type);
the whole document is never held. GraphML declares its keys
(``<key for="node" attr.name=... attr.type=...>``) before the graph, as Gephi and yEd
read them, but a key's type is known only once every value of it has been seen: so the
graph's body is written first to an anonymous temporary file beside the destination, and
the file is then its header, the keys and that body.

One type per key, as Gephi and yEd type their columns (:data:`KEY_TYPES`): a key whose
values are all booleans is ``boolean``, all integers ``long``, integers and floats
``double``; any other mix, or any string, makes it ``string`` (each value its text). A key
that no element gives a value is not declared. Booleans are spelled ``true``/``false``,
floats as Python's shortest text that reads back the same number.

The reader takes back what the writer writes (keys, one directed graph, its nodes and
edges, their data) element by element, dropping each once read, and gives the graph that
:func:`networkx.read_graphml` gives; a file with anything else (key defaults, yEd's
extensions, ports, nested graphs, hyperedges, parallel or undirected edges, edge ids) is
read by :func:`networkx.read_graphml` itself.
"""

from __future__ import annotations

import io
import shutil
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import IO, Any

import networkx as nx

__all__ = ["KEY_TYPES", "EdgeBlock", "NodeBlock", "read_graphml_stream", "write_graphml_stream"]

_NS = "http://graphml.graphdrawing.org/xmlns"
_HEADER = (
    "<?xml version='1.0' encoding='utf-8'?>\n"
    f'<graphml xmlns="{_NS}" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" '
    f'xsi:schemaLocation="{_NS} {_NS}/1.0/graphml.xsd">\n'
)
_BUFFER = 1 << 20  # bytes of file buffer: a few thousand nodes per system call

# The kinds of value seen for a key, as bits: the key's type is their combination's.
_BOOL, _INT, _FLOAT, _STRING = 1, 2, 4, 8
#: The GraphML type of a key from the kinds of its values (bits: boolean 1, integer 2,
#: float 4, string 8); any combination not listed is ``string``.
KEY_TYPES = {_BOOL: "boolean", _INT: "long", _FLOAT: "double", _INT | _FLOAT: "double"}
_BOOLEANS = {"true": True, "false": False, "0": False, "1": True}  # networkx's reading
# What the reader makes of each GraphML type (networkx's table).
_PARSE: dict[str, Callable[[str], Any]] = {
    "string": str,
    "int": int,
    "integer": int,
    "long": int,
    "float": float,
    "double": float,
    "boolean": lambda text: _BOOLEANS[text.lower()],
}


def _text(value: str) -> str:
    """``value`` escaped for an element's text."""
    return value.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def _attribute(value: str) -> str:
    """``value`` escaped for a double-quoted attribute (line breaks and tabs kept)."""
    return (
        _text(value)
        .replace('"', "&quot;")
        .replace("\n", "&#10;")
        .replace("\r", "&#13;")
        .replace("\t", "&#9;")
    )


def _texts(values: list[str]) -> list[str]:
    """:func:`_text` of each value; the values themselves when none needs escaping (one
    scan of the whole column instead of three per value)."""
    whole = "".join(values)
    if "&" in whole or "<" in whole or ">" in whole:
        return [_text(v) for v in values]
    return values


def _attributes(values: list[str]) -> list[str]:
    """:func:`_attribute` of each value, as :func:`_texts`."""
    whole = "".join(values)
    if any(c in whole for c in '&<>"\n\r\t'):
        return [_attribute(v) for v in values]
    return values


def _plain(value: Any) -> tuple[str, int] | None:
    """The text and kind of a plain value (str, bool, int, finite float, or a subclass
    of one); None for a missing one (None, NaN, infinity)."""
    t = type(value)
    if t is str:
        return _text(value), _STRING
    if t is bool:
        return ("true" if value else "false"), _BOOL
    if t is int:
        return str(value), _INT
    if t is float:
        return (repr(value), _FLOAT) if value - value == 0.0 else None
    if value is None:
        return None
    for base in (bool, int, float, str):
        if isinstance(value, base):  # an enum, numpy's str_: as its base type
            return _plain(base(value))
    raise TypeError(f"attribute value {value!r} is not a str, bool, int or float")


_NEW: Any = object()  # an attribute not seen before


class _Keys:
    """The keys of one scope (graph, node or edge): each attribute's id and the kinds of
    its values, gathered as the body is written."""

    def __init__(self, scope: str, keep: Callable[[str], bool], ids: list[str]) -> None:
        self.scope = scope
        self.keep = keep
        self.ids = ids  # every key's id, shared by the scopes: d0, d1, ...
        # attribute -> [open tag '<data key="dN">', kinds seen, name, id], or None: the
        # attribute is not written
        self.slots: dict[Any, list[Any] | None] = {}

    def slot(self, key: Any) -> list[Any] | None:
        name = str(key)
        slot = None
        if self.keep(name):
            key_id = f"d{len(self.ids)}"
            self.ids.append(key_id)
            slot = [f'<data key="{key_id}">', 0, name, key_id]
        self.slots[key] = slot
        return slot

    def declarations(self) -> str:
        lines = []
        for slot in self.slots.values():
            if slot is not None and slot[1]:  # a key no element gives a value: left out
                _, kinds, name, key_id = slot
                lines.append(
                    f'<key id="{key_id}" for="{self.scope}" attr.name="{_attribute(name)}" '
                    f'attr.type="{KEY_TYPES.get(kinds, "string")}"/>\n'
                )
        return "".join(lines)


def _column(
    keys: _Keys, key: Any, values: list[Any], convert: Callable[[list[Any]], list[Any]]
) -> list[str] | None:
    """The ``<data>`` element of one attribute for each element of a block ("" where the
    value is missing); None when the attribute is not written.

    A whole column at a time, because the per-value work is then a comprehension over one
    type: the writer's cost is this loop."""
    slot = keys.slots.get(key, _NEW)
    if slot is _NEW:
        slot = keys.slot(key)
    if slot is None:
        return None
    tag = slot[0]
    types = set(map(type, values))
    if not types <= {float, str, bool, int}:
        values = convert(values)
        types = set(map(type, values))
    if types == {float}:
        kind = _FLOAT
        texts = [f"{tag}{v!r}</data>" if v - v == 0.0 else "" for v in values]
    elif types == {str}:
        kind = _STRING
        texts = [f"{tag}{v}</data>" for v in _texts(values)]
    elif types == {bool}:
        kind = _BOOL
        texts = [f"{tag}true</data>" if v else f"{tag}false</data>" for v in values]
    elif types == {int}:
        kind = _INT
        texts = [f"{tag}{v}</data>" for v in values]
    else:  # a mix, missing values, numpy's scalars: one by one
        kind = 0
        texts = []
        for value in values:
            plain = _plain(value)
            if plain is None:
                texts.append("")
            else:
                texts.append(f"{tag}{plain[0]}</data>")
                kind |= plain[1]
    if any(texts):
        slot[1] |= kind
    return texts


def _elements(
    keys: _Keys,
    opening: list[str],
    columns: Iterable[tuple[Any, list[Any]]],
    closing: str,
    convert: Callable[[list[Any]], list[Any]],
) -> str:
    """A block of elements: each opening tag, its ``<data>`` elements, the closing tag."""
    texts = [t for key, values in columns if (t := _column(keys, key, values, convert)) is not None]
    rows = zip(*texts, strict=True) if texts else [()] * len(opening)
    return "".join(
        f"{head}{''.join(data)}{closing}" for head, data in zip(opening, rows, strict=True)
    )


#: A block of nodes: their ids, and each attribute's values in that order (None:
#: missing).
NodeBlock = tuple[list[str], list[tuple[Any, list[Any]]]]
#: A block of edges: their sources, targets, and each attribute's values.
EdgeBlock = tuple[list[str], list[str], list[tuple[Any, list[Any]]]]


def write_graphml_stream(
    out: IO[bytes],
    graph: Iterable[tuple[Any, Any]],
    nodes: Iterable[NodeBlock],
    edges: Iterable[EdgeBlock],
    *,
    convert: Callable[[list[Any]], list[Any]],
    keep: Callable[[str], bool],
    spool_dir: str | Path,
) -> None:
    """Write a directed graph as GraphML to ``out``, a block of nodes or edges at a time.

    Parameters
    ----------
    out : binary file
        Destination, open for writing.
    graph : iterable of (key, value)
        The graph's attributes.
    nodes : iterable of :data:`NodeBlock`
        Blocks of nodes in the order they are to be written: their ids and their
        attributes as columns (None where a node has no value).
    edges : iterable of :data:`EdgeBlock`
        Blocks of edges: their end nodes and their attributes as columns.
    convert : callable
        Makes each value of a column that is not a str, bool, int or finite float one of
        those, or None (missing: left out of the element's data); given and giving a
        list.
    keep : callable
        Whether an attribute of this name is written.
    spool_dir : path-like
        Folder of the temporary file that holds the body until the keys are known (the
        destination's, so that the body takes room on disk, never in memory).
    """
    ids: list[str] = []
    scopes = [_Keys(s, keep, ids) for s in ("graph", "node", "edge")]
    graph_keys, node_keys, edge_keys = scopes
    with tempfile.TemporaryFile(buffering=_BUFFER, dir=spool_dir) as raw:
        body = io.TextIOWrapper(raw, encoding="utf-8")
        write = body.write
        own = [(key, [value]) for key, value in graph]
        write(_elements(graph_keys, ['<graph edgedefault="directed">'], own, "\n", convert))
        for node_ids, columns in nodes:
            heads = [f'<node id="{n}">' for n in _attributes(node_ids)]
            write(_elements(node_keys, heads, columns, "</node>\n", convert))
        for sources, targets, columns in edges:
            heads = [
                f'<edge source="{u}" target="{v}">'
                for u, v in zip(_attributes(sources), _attributes(targets), strict=True)
            ]
            write(_elements(edge_keys, heads, columns, "</edge>\n", convert))
        write("</graph>\n</graphml>\n")
        body.detach()  # flushed into raw, which stays open
        out.write(_HEADER.encode("utf-8"))
        out.write("".join(keys.declarations() for keys in scopes).encode("utf-8"))
        raw.seek(0)
        shutil.copyfileobj(raw, out, _BUFFER)


class _NotPlain(Exception):
    """The file holds what the stream reader leaves to networkx."""


_ROOT, _KEY, _GRAPH, _NODE, _EDGE, _DATA = (
    f"{{{_NS}}}{t}" for t in ("graphml", "key", "graph", "node", "edge", "data")
)


def read_graphml_stream(path: str | Path) -> nx.Graph:
    """The graph in a GraphML file, as :func:`networkx.read_graphml` reads it.

    A file as :func:`write_graphml_stream` writes it is parsed one element at a time, each
    dropped once read, so that the document is never held whole; any other is read by
    :func:`networkx.read_graphml` (which may give a multigraph, or an undirected
    graph). Its errors (:class:`xml.etree.ElementTree.ParseError`,
    :class:`networkx.NetworkXError`, a value its key's type does not parse) pass on.
    """
    try:
        return _read_plain(path)
    except _NotPlain:
        return nx.read_graphml(path)


def _read_plain(path: str | Path) -> nx.DiGraph:
    graph: nx.DiGraph[str] = nx.DiGraph()
    graph.graph.update(node_default={}, edge_default={})
    add_node, add_edge, has_edge = graph.add_node, graph.add_edge, graph.has_edge
    keys: dict[str | None, tuple[str, Callable[[str], Any]]] = {}
    graph_data: dict[str, Any] = {}
    parent = ET.Element(_GRAPH)  # the graph element, whose children are dropped once read
    depth, graphs = 0, 0

    def decode(children: Iterable[ET.Element]) -> dict[str, Any]:
        data = {}
        for child in children:
            if child.tag != _DATA or len(child):
                raise _NotPlain
            try:
                name, parse = keys[child.get("key")]
            except KeyError:
                raise _NotPlain from None  # networkx names the key that is missing
            text = child.text
            data[name] = "" if text is None else parse(text)  # empty: "", as networkx
        return data

    # Depth: 1 the root, 2 its keys and the graph, 3 nodes, edges and the graph's data,
    # 4 their data. "start" events check the structure; "end" events read an element.
    for event, element in ET.iterparse(path, events=("start", "end")):
        if event == "start":
            depth += 1
            tag = element.tag
            if depth == 1 and tag != _ROOT:
                raise _NotPlain
            if depth == 2 and tag == _GRAPH:
                graphs += 1
                if graphs > 1 or element.get("edgedefault") != "directed":
                    raise _NotPlain
                parent = element
            elif (depth == 3 and tag not in (_NODE, _EDGE, _DATA)) or (depth == 4 and tag != _DATA):
                raise _NotPlain
            elif depth > 4:
                raise _NotPlain
            continue
        depth -= 1
        if depth == 2:  # an element of the graph
            tag = element.tag
            if tag == _NODE:
                if element.attrib.keys() - {"id"}:
                    raise _NotPlain
                add_node(str(element.get("id")), **decode(element))
            elif tag == _EDGE:
                if element.attrib.keys() - {"source", "target"}:
                    raise _NotPlain
                u, v = str(element.get("source")), str(element.get("target"))
                if has_edge(u, v):
                    raise _NotPlain  # networkx makes a multigraph
                add_edge(u, v, **decode(element))
            else:
                graph_data.update(decode((element,)))
            parent.remove(element)  # its last child: dropped, read
        elif depth == 1 and element.tag == _KEY:
            name, kind = element.get("attr.name"), element.get("attr.type")
            if name is None or kind not in _PARSE or len(element) or element.get("yfiles.type"):
                raise _NotPlain
            keys[element.get("id")] = (name, _PARSE[kind])
    if graphs != 1:
        raise _NotPlain
    graph.graph.update(graph_data)  # after the nodes and edges, as networkx
    return graph
