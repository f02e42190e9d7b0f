"""What every contact record shares: its region pair, and vectors as plain tuples."""

from __future__ import annotations

from dataclasses import fields
from typing import TYPE_CHECKING, Any, cast

import numpy as np

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

__all__ = ["RegionPair", "Vec", "as_vec"]

#: A point or a direction in a record: three floats.
Vec = tuple[float, float, float]


def as_vec(v: Any) -> Vec:
    """A 3-vector as a tuple of floats (the records' form of points and normals)."""
    a = np.asarray(v, dtype=float).reshape(3)
    return (float(a[0]), float(a[1]), float(a[2]))


class RegionPair:
    """What every contact record shares: its regions and its JSON form (its fields in
    order, vectors as lists)."""

    bolt_region: str
    nut_region: str

    @property
    def regions(self) -> str:
        """``bolt/nut`` region pair, e.g. ``base/surface``."""
        return f"{self.bolt_region}/{self.nut_region}"

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping for JSON."""
        return {
            f.name: list(v) if isinstance(v, tuple) else v
            for f in fields(cast("DataclassInstance", self))  # every subclass is one
            for v in [getattr(self, f.name)]
        }
