"""Compiled search along an exact edge: where it comes closest to, or deepest into, the
other body's exact surface (the refinement of an edge-on-face contact,
:func:`threadmate.contact.scene.refine_on_edge`).

The search samples the edge (:class:`._kernels.EdgeCurve`) at 17 polar angles about the
best so far, takes the least signed distance of the other body there and a parabola
through it and its neighbours, and shrinks the window eightfold, three times. Asked a
few thousand times per held tilt, its numpy form spent most of its time in numpy's
per-call overhead; compiled, it keeps numpy's results to the last bit: the points by the
same arithmetic (:func:`._kernels._on_curve`), the bolt's pose applied as the BLAS numpy
calls applies it to a few points (:func:`._kernels.placed_in_fixed`,
:func:`._kernels.placed_in_bolt`), the signed distance by the same kernel
(:func:`._kernels.signed_distance`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..._compiled import compiled
from ._kernels import EdgeCurve, _on_curve, _signed_distance, placed_in_bolt, placed_in_fixed

__all__ = ["SAMPLES", "closest_on_edge", "edge_points", "least_on_grid", "window_grid"]

#: Angles sampled per window, the window's ends included.
SAMPLES = 17


@compiled
def _grid(best: float, half: float, out: NDArray[np.float64]) -> None:
    """``best + np.linspace(-half, half, SAMPLES)`` by numpy's arithmetic: the sample's
    number times the spacing, minus ``half``, the last sample ``half`` itself."""
    step = (half - -half) / (SAMPLES - 1)
    for i in range(SAMPLES - 1):
        out[i] = best + (float(i) * step + -half)
    out[SAMPLES - 1] = best + half


@compiled
def _points(curve: EdgeCurve, angles: NDArray[np.float64], out: NDArray[np.float64]) -> None:
    """The points of ``curve`` at ``angles`` (a kink followed from ``curve.height``, each
    root from the one before)."""
    last = curve.height
    for i in range(len(angles)):
        out[i, 0], out[i, 1], out[i, 2], last = _on_curve(curve, angles[i], last)


@compiled
def _least(angles: NDArray[np.float64], values: NDArray[np.float64]) -> float:
    """The angle of the least value (numpy's ``argmin``: the first, or the first NaN),
    moved to the vertex of the parabola through it and its neighbours where one opens
    upward."""
    j = 0
    for i in range(len(values)):
        if math.isnan(values[i]):
            j = i
            break
        if values[i] < values[j]:
            j = i
    best = angles[j]
    if 0 < j < len(values) - 1:
        a, b, c = values[j - 1], values[j], values[j + 1]
        den = a - 2 * b + c
        if den > 0:
            best += 0.5 * (a - c) / den * (angles[1] - angles[0])
    return best


@compiled
def _closest(
    curve: EdgeCurve,
    prof: NDArray[np.float64],
    env: NDArray[np.float64],
    shape: NDArray[np.float64],
    rotation: NDArray[np.float64],
    origin: NDArray[np.float64],
    into_bolt: bool,
    best: float,
    half: float,
    out: NDArray[np.float64],
) -> None:
    angles = np.empty(SAMPLES)
    points = np.empty((SAMPLES, 3))
    moved = np.empty((SAMPLES, 3))
    theta = np.empty(SAMPLES)
    values = np.empty(SAMPLES)
    for _ in range(3):
        _grid(best, half, angles)
        _points(curve, angles, points)
        for i in range(SAMPLES):
            x, y, z = points[i, 0], points[i, 1], points[i, 2]
            if into_bolt:  # the nut's edge, the bolt's face
                moved[i, 0], moved[i, 1], moved[i, 2] = placed_in_bolt(x, y, z, rotation, origin)
            else:  # the bolt's edge, the nut's face
                moved[i, 0], moved[i, 1], moved[i, 2] = placed_in_fixed(x, y, z, rotation, origin)
            theta[i] = math.atan2(moved[i, 1], moved[i, 0])
        _signed_distance(prof, env, shape, moved, theta, values)
        best = _least(angles, values)
        half /= 8
    out[0], out[1], out[2], _ = _on_curve(curve, best, curve.height)


def window_grid(best: float, half: float) -> NDArray[np.float64]:
    """The :data:`SAMPLES` polar angles (radians) of a window of half-width ``half``
    about ``best``."""
    out = np.empty(SAMPLES)
    _grid(float(best), float(half), out)
    return out


def edge_points(curve: EdgeCurve, angles: NDArray[np.float64]) -> NDArray[np.float64]:
    """The points of ``curve`` at polar ``angles`` (radians, in order; its body's frame),
    ``(n, 3)``."""
    angles = np.ascontiguousarray(angles, dtype=float)
    out = np.empty((len(angles), 3))
    _points(curve, angles, out)
    return out


def least_on_grid(angles: NDArray[np.float64], values: NDArray[np.float64]) -> float:
    """The angle of a window's least value, refined by the parabola through its
    neighbours (see the module docstring)."""
    return float(_least(angles, np.ascontiguousarray(values, dtype=float)))


def closest_on_edge(
    curve: EdgeCurve,
    face: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    rotation: NDArray[np.float64],
    origin: NDArray[np.float64],
    into_bolt: bool,
    angle: float,
    half: float,
) -> NDArray[np.float64]:
    """The point of ``curve`` (its body's frame) where it comes closest to, or deepest
    into, the other body's exact surface, searched from the polar ``angle`` in a window of
    half-width ``half`` (radians); ``face``: the other body's profile, envelope and shape
    arrays (:func:`._kernels._arrays`); ``into_bolt``: the edge is the nut's and the face
    the bolt's (else the reverse), the bolt at ``(rotation, origin)``."""
    out = np.empty(3)
    _closest(
        curve,
        *face,
        np.ascontiguousarray(rotation, dtype=float),
        np.ascontiguousarray(origin, dtype=float),
        into_bolt,
        float(angle),
        float(half),
        out,
    )
    return out
