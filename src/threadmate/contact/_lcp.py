"""The small contact problem of one descent step: a convex QP solved through its LCP.

A step ``x`` of the bolt's free coordinates minimises ``1/2 x'Hx + c'x`` subject to the
linearised non-penetration ``G x + gap >= 0`` (one row per contact). Its multipliers are
the contact forces ``lambda >= 0``; with ``Q = G H^-1 G'`` and ``b = gap - G H^-1 c`` they
solve the linear complementarity problem ``w = Q lambda + b >= 0``, ``lambda >= 0``,
``lambda' w = 0`` (``w`` is each contact's gap after the step). ``Q`` is positive
semi-definite, so any solution of the LCP is optimal. With a handful of contacts the
supports are enumerated (smallest first, the previous step's first); many contacts (a
flat face resting on a face) fall back to projected Gauss-Seidel.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["solve_lcp", "contact_step"]

#: Largest contact count whose supports are enumerated.
ENUMERATE = 9


def _check(Q: NDArray[np.float64], b: NDArray[np.float64], lam: NDArray[np.float64],
           tol: float) -> bool:
    w = Q @ lam + b
    return bool(lam.min(initial=0.0) >= -tol and w.min(initial=0.0) >= -tol)


def solve_lcp(Q: NDArray[np.float64], b: NDArray[np.float64],
              first: tuple[int, ...] = ()) -> NDArray[np.float64]:
    """A solution ``lambda`` of the LCP ``(Q, b)`` (see the module docstring).

    Parameters
    ----------
    Q : (n, n) array
        Positive semi-definite.
    b : (n,) array
    first : tuple of int
        A support to try before the others (the previous step's).
    """
    n = len(b)
    lam = np.zeros(n)
    if n == 0 or b.min() >= 0:
        return lam
    scale = max(float(np.abs(Q).max(initial=0.0)), 1e-300)
    tol = 1e-9 * max(float(np.abs(b).max()), 1e-300)
    if n <= ENUMERATE:
        tried = [tuple(first)] if first else []
        supports = itertools.chain(tried, (s for k in range(1, n + 1)
                                           for s in itertools.combinations(range(n), k)))
        for s in supports:
            idx = list(s)
            if not idx or max(idx) >= n:
                continue
            sub = Q[np.ix_(idx, idx)]
            sol, *_ = np.linalg.lstsq(sub + 1e-14 * scale * np.eye(len(idx)), -b[idx],
                                      rcond=None)
            if sol.min() < -tol / scale * 1e3 and sol.min() < 0:
                continue
            trial = np.zeros(n)
            trial[idx] = np.clip(sol, 0.0, None)
            if _check(Q, b, trial, tol):
                return trial
    # Projected Gauss-Seidel (convergent for positive semi-definite Q with a solution).
    diag = np.maximum(np.diag(Q), 1e-12 * scale)
    for _ in range(20_000):
        delta = 0.0
        for i in range(n):
            new = max(0.0, lam[i] - (Q[i] @ lam + b[i]) / diag[i])
            delta = max(delta, abs(new - lam[i]))
            lam[i] = new
        if delta * scale <= tol or not math.isfinite(delta):
            break
    return lam


def contact_step(H: NDArray[np.float64], c: NDArray[np.float64], G: NDArray[np.float64],
                 gap: NDArray[np.float64], first: tuple[int, ...] = ()
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The step ``x`` and contact forces ``lambda`` of the QP.

    Parameters
    ----------
    H : (m,) or (m, m) array
        The (positive definite) step metric, or its diagonal.
    c : (m,) array
        Gradient of the potential.
    G : (n, m) array
        Rows: each contact's gap rate per unit of each coordinate.
    gap : (n,) array
        Each contact's gap now (>= 0).
    """
    hinv = np.diag(1.0 / H) if np.ndim(H) == 1 else np.linalg.inv(H)
    if len(gap) == 0:
        return -hinv @ c, np.zeros(0)
    Q = G @ hinv @ G.T
    b = gap - G @ (hinv @ c)
    lam = solve_lcp(0.5 * (Q + Q.T), b, first)
    return hinv @ (G.T @ lam - c), lam
