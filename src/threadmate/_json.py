"""numpy-to-JSON conversion: the one place that turns results into plain JSON types.

Every JSON document threadmate writes (``--json`` output, result files, GraphML and
node-link attributes) goes through :func:`to_jsonable`, so that numpy scalars and arrays,
tuples and paths come out the same everywhere and a NaN or infinity becomes ``null``
(strict JSON has no such numbers).
"""

from __future__ import annotations

import json
import math
from pathlib import PurePath
from typing import Any

import numpy as np

__all__ = ["to_jsonable", "json_text", "parse_json"]


def to_jsonable(obj: Any) -> Any:
    """``obj`` with numpy scalars/arrays, tuples, sets and paths made plain JSON types.

    Mappings get string keys; lists, tuples and arrays become lists; numpy booleans,
    integers and floats become ``bool``/``int``/``float``; a non-finite float becomes
    ``None``; a path becomes its text. Anything else is returned unchanged.
    """
    if type(obj) is float:  # the commonest value first: a network writes one per attribute
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, set | frozenset):
        return [to_jsonable(v) for v in sorted(obj, key=str)]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, bool | np.bool_):
        return bool(obj)
    if isinstance(obj, int | np.integer):
        return int(obj)
    if isinstance(obj, float | np.floating):
        value = float(obj)
        return value if math.isfinite(value) else None
    if isinstance(obj, PurePath):
        return str(obj)
    return obj


def json_text(obj: Any, indent: int | None = 2, *, sort_keys: bool = False, end: str = "\n") -> str:
    """``obj`` as one strict JSON document (via :func:`to_jsonable`), ending in ``end`` (a
    newline; ``""`` for JSON kept inside another format: a GraphML attribute, a Parquet
    schema's metadata)."""
    if isinstance(obj, np.ndarray) and obj.dtype.kind in "biufU":
        try:  # plain finite numbers or strings: to_jsonable would give the same list
            return json.dumps(obj.tolist(), indent=indent, allow_nan=False) + end
        except ValueError:  # a NaN or an infinity: null, by to_jsonable
            pass
    return json.dumps(to_jsonable(obj), indent=indent, sort_keys=sort_keys, allow_nan=False) + end


class _Object(dict[str, Any]):
    """A JSON object as parsed, with the first key it gave twice (None: none)."""

    twice: str | None = None


def _object(pairs: list[tuple[str, Any]]) -> _Object:
    obj = _Object()
    for key, value in pairs:
        if key in obj and obj.twice is None:
            obj.twice = key
        obj[key] = value
    return obj


def _key_twice(value: Any, path: tuple[str, ...] = ()) -> str | None:
    """The dotted path of the first key given twice in a parsed document (None: none)."""
    if isinstance(value, _Object):
        if value.twice is not None:
            return ".".join((*path, value.twice))
        children: Any = value.items()
    elif isinstance(value, list):
        children = ((f"[{i}]", v) for i, v in enumerate(value))
    else:
        return None
    for key, inner in children:
        found = _key_twice(inner, (*path, key))
        if found is not None:
            return found
    return None


def parse_json(text: str) -> Any:
    """``text`` as JSON, refusing a key given twice in one object (plain :func:`json.loads`
    keeps the last silently: a ``pitch`` given twice would pass for one).

    Raises
    ------
    ValueError
        Invalid JSON (:class:`json.JSONDecodeError`), or a key given twice: the message
        names its dotted path, ``'bolt.major'``.
    RecursionError
        Brackets nested deeper than the interpreter's recursion limit.
    """
    doc = json.loads(text, object_pairs_hook=_object)
    twice = _key_twice(doc)
    if twice is not None:
        raise ValueError(f"key '{twice}' is given twice (give each key once)")
    return doc
