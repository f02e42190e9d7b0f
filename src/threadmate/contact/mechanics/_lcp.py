"""The small contact problem of one descent step: a convex QP by a primal active set.

A step ``x`` of the bolt's free coordinates (three, or five with lateral freedom)
minimises ``1/2 x'Hx + c'x`` subject to the linearised non-penetration
``G x + gap >= 0`` (one row per contact, ``gap >= 0``). The multipliers of the rows are
the contact forces. ``x = 0`` is feasible, so the primal active-set method (Nocedal and
Wright, *Numerical Optimization*, algorithm 16.3) starts there: solve the equality
problem on the working set, step until a row blocks, add it, drop the row whose
multiplier turns negative. With at most five coordinates the working set holds at most
five linearly independent rows; a flat face resting on a face gives many rows with
dependent normals, which this handles where a dual pivoting (or Gauss-Seidel) solver
stalls.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import minimize, nnls

__all__ = ["contact_step"]

_MAX_ITERATIONS = 200


def _independent(rows: NDArray[np.float64], candidate: NDArray[np.float64]) -> bool:
    """Whether ``candidate`` is not (nearly) a combination of ``rows``."""
    if len(rows) == 0:
        return bool(np.linalg.norm(candidate) > 0)
    stack = np.vstack([rows, candidate])
    s = np.linalg.svd(stack, compute_uv=False)
    return bool(s[-1] > 1e-6 * s[0])


def contact_step(
    H: NDArray[np.float64],
    c: NDArray[np.float64],
    G: NDArray[np.float64],
    gap: NDArray[np.float64],
    first: tuple[int, ...] = (),
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The step ``x`` and contact forces ``lambda`` of the QP (see the module docstring).

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
    first : tuple of int
        Rows to try in the working set first (the previous step's active rows).
    """
    H = np.diag(H) if np.ndim(H) == 1 else np.asarray(H, dtype=float)
    m = len(c)
    n = len(gap)
    G = np.asarray(G, dtype=float).reshape(n, m)
    # The coordinates differ in scale by many orders (metres against radians, a proximal
    # weight of 1e5 N/m against a stiffness of 1 N m/rad): solve in y = D x, D^2 = diag H.
    d = np.sqrt(np.maximum(np.diag(H), 1e-300))
    y, lam = _solve(
        H / np.outer(d, d),
        np.asarray(c, dtype=float) / d,
        G / d,
        np.asarray(gap, dtype=float),
        first,
    )
    return y / d, lam


def _solve(
    H: NDArray[np.float64],
    c: NDArray[np.float64],
    G: NDArray[np.float64],
    gap: NDArray[np.float64],
    first: tuple[int, ...],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """:func:`contact_step` on a well-scaled problem."""
    m, n = len(c), len(gap)
    gap = np.maximum(np.asarray(gap, dtype=float), 0.0)
    x = np.zeros(m)
    lam = np.zeros(n)
    tol = 1e-12 * max(float(np.abs(gap).max(initial=0.0)), 1e-300)
    working: list[int] = []
    # Start with the touching rows of the previous support that are independent.
    for i in list(first) + [i for i in range(n) if gap[i] <= tol]:
        if (
            i < n
            and gap[i] <= tol
            and i not in working
            and len(working) < m
            and _independent(G[working], G[i])
        ):
            working.append(i)
    # The metric is small (at most 5 x 5) and positive definite: its inverse once, and
    # each equality problem by its Schur complement on the working rows, avoid a
    # least-squares solve of the whole KKT matrix per iteration.
    h_inv = np.linalg.inv(H)
    # After a full step ``x`` minimises the model on the working set: the step there is nil
    # in exact arithmetic, and only the multipliers are still to be read. Testing the
    # computed step against a threshold instead lets rounding (G's rows are small against
    # H) pass for a step, and the iteration wanders.
    stationary = False
    for _ in range(_MAX_ITERATIONS):
        g = H @ x + c
        k = len(working)
        p, mult = _equality_step(h_inv, G[working], g)
        # Nil when its force, H p, is rounding against the forces acting, g.
        if stationary or float(np.abs(H @ p).max()) <= 1e-12 * max(float(np.abs(g).max()), 1e-300):
            stationary = False
            if k == 0 or mult.min() >= -1e-12 * max(float(np.abs(mult).max()), 1e-300):
                lam[:] = 0.0
                lam[working] = np.maximum(mult, 0.0)
                return x, lam
            # Bland's rule against cycling at degenerate vertices (more touching rows than
            # coordinates): drop the first row, by index, whose multiplier is negative.
            negative = [
                r
                for r, v in zip(working, mult, strict=True)
                if v < -1e-12 * max(float(np.abs(mult).max()), 1e-300)
            ]
            working.remove(min(negative))
            continue
        # Step along p until a row outside the working set blocks.
        rate = G @ p
        slack = G @ x + gap
        alpha, block = 1.0, -1
        # A row whose rate is nil against its own size is parallel to the step (a
        # duplicate of a working row, as the corners of a flat contact are): not blocking.
        norms = np.linalg.norm(G, axis=1) * float(np.linalg.norm(p))
        for row in np.flatnonzero(rate < -1e-7 * norms):
            if row in working:
                continue
            a = max(float(slack[row]), 0.0) / float(-rate[row])
            if a < alpha:  # ties keep the first row by index (Bland)
                alpha, block = a, int(row)
        x = x + alpha * p
        if block >= 0:
            working.append(block)
        else:
            stationary = True
    # Cycling at a degenerate vertex (a flat face on a face: more touching rows than
    # coordinates): a general solver on the scaled problem, the forces by non-negative
    # least squares on the rows it leaves touching. (scipy-stubs types a constraint's
    # "fun" as scalar-valued and its "jac" as 1-D: SLSQP takes a vector inequality with
    # its Jacobian matrix, as here.)
    res = minimize(  # type: ignore[call-overload]
        lambda v: 0.5 * v @ H @ v + c @ v,
        x,
        jac=lambda v: H @ v + c,
        constraints=[{"type": "ineq", "fun": lambda v: G @ v + gap, "jac": lambda v: G}],
        method="SLSQP",
        options={"ftol": 1e-16, "maxiter": 1000},
    )
    x = res.x
    slack = G @ x + gap
    active = np.flatnonzero(
        slack
        <= 1e-9 * (float(np.abs(G @ x).max(initial=0.0)) + float(gap.max(initial=0.0))) + 1e-15
    )
    lam[:] = 0.0
    if len(active):
        lam[active] = nnls(G[active].T, H @ x + c)[0]
    return x, lam


def _equality_step(
    h_inv: NDArray[np.floating], A: NDArray[np.float64], g: NDArray[np.float64]
) -> tuple[NDArray[np.floating], NDArray[np.floating]]:
    """Step ``p`` and multipliers of ``min 1/2 p'Hp + g'p`` subject to ``A p = 0``.

    ``H p - A' mult = -g`` and ``A p = 0`` give ``(A H^-1 A') mult = A H^-1 g`` and
    ``p = H^-1 (A' mult - g)``. The working rows are independent, so the Schur complement
    is positive definite; should rounding make it singular, least squares decides.
    """
    if len(A) == 0:
        return -(h_inv @ g), np.empty(0)
    ha = h_inv @ A.T
    schur = A @ ha
    rhs = ha.T @ g
    try:
        mult = np.linalg.solve(schur, rhs)
    except np.linalg.LinAlgError:
        mult = np.linalg.lstsq(schur, rhs, rcond=None)[0]
    return ha @ mult - h_inv @ g, mult
