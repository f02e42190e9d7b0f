"""Small vector arithmetic asked one pair of 3-vectors at a time, without numpy's per-call
overhead (its axis handling costs more than the products)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["cross3"]


def cross3(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """``np.cross`` of two 3-vectors by its formula: the same products and differences,
    rounded alike, so the same numbers to the last bit."""
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )
