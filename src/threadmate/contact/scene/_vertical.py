"""How far a bolt triangle comes down before it meets a nut triangle (exact, vectorised).

Lowering the bolt by ``d`` along -Z brings a bolt point ``a`` onto a nut point ``b`` when
``a_xy = b_xy`` and ``d = a_z - b_z``. Over the overlap of two triangles' projections on
the XY plane, ``a_z - b_z`` is a linear function, so its least value, the drop at which
the two first touch, sits at a vertex of the overlap polygon: a vertex of one triangle
inside the other's projection, or a crossing of two edges' projections. Every candidate
is evaluated and the least kept. A pair whose projections do not overlap never touches
(``inf``).

This turns one enumeration of the crossing pairs below a collision-free pose into the exact
drop at which the meshes first touch, and the vertical gap of every other contact within
that depth, without bisection.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ._kernels import vertical_touch as _kernel

__all__ = ["vertical_rise", "vertical_touch"]


def vertical_touch(
    bolt_tris: NDArray[np.float64], nut_tris: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Drop at which each bolt triangle first meets its nut triangle, and where.

    Parameters
    ----------
    bolt_tris, nut_tris : (n, 3, 3) arrays
        Paired triangles in the fixed frame, the bolt's at the pose lowering starts from.

    Returns
    -------
    drop : (n,) array
        Least downward translation of the bolt triangle that makes it touch the nut
        triangle (``inf`` when their projections do not overlap; negative when they
        already cross at the starting pose).
    point : (n, 3) array
        The touching point on the nut triangle (fixed frame; NaN with an ``inf`` drop).
    """
    # Compiled (the lowering asks a few pairs at a time, thousands of times): every
    # candidate in the order bolt vertices, nut vertices, then the nine edge pairs bolt
    # edge (i, i+1) by nut edge (k, k+1) row-major; the first least wins a tie.
    return _kernel(bolt_tris, nut_tris)


def vertical_rise(
    bolt_tris: NDArray[np.float64], nut_tris: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rise at which each bolt triangle first meets its nut triangle above it, and where:
    :func:`vertical_touch` of the pair mirrored in the XY plane (a rise is a drop there)."""
    flip = np.array([1.0, 1.0, -1.0])
    rise, point = vertical_touch(
        np.asarray(bolt_tris, dtype=float) * flip, np.asarray(nut_tris, dtype=float) * flip
    )
    return rise, point * flip
