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

__all__ = ["to_jsonable", "json_text"]


def to_jsonable(obj: Any) -> Any:
    """``obj`` with numpy scalars/arrays, tuples, sets and paths made plain JSON types.

    Mappings get string keys; lists, tuples and arrays become lists; numpy booleans,
    integers and floats become ``bool``/``int``/``float``; a non-finite float becomes
    ``None``; a path becomes its text. Anything else is returned unchanged.
    """
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


def json_text(obj: Any, indent: int | None = 2) -> str:
    """``obj`` as one strict JSON document (via :func:`to_jsonable`), ending in a newline."""
    return json.dumps(to_jsonable(obj), indent=indent, allow_nan=False) + "\n"
