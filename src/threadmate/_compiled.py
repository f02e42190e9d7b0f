"""Compiled kernels' decorator: numba's ``njit`` with its on-disk cache, or plain Python.

The contact code's innermost loops (the exact contact geometry, the lowering's vertical
touch, the grouping of contact points) are asked a few numbers at a time, thousands of
times per rest state, where Python's and numpy's per-call overhead is most of the cost.
They are written as plain loops over floats and arrays and compiled by numba on first
use, once per machine: ``cache=True`` keeps the machine code in the package's
``__pycache__`` (or numba's user cache where that is not writable, or
``NUMBA_CACHE_DIR``). Where numba is not installed the same functions run as Python,
slower, with the same results but for the last bit of a fused multiply-add (:data:`fma`,
which Python rounds twice).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar, cast

__all__ = ["COMPILED", "compiled", "fma", "inlined"]

_F = TypeVar("_F", bound=Callable[..., Any])


def _compiler() -> Any:
    """numba's ``njit``, or None where numba is not installed."""
    try:
        from numba import njit
    except ImportError:  # pragma: no cover - numba is a dependency
        return None
    return njit


_njit = _compiler()
#: Whether the kernels run compiled.
COMPILED = _njit is not None


def compiled(func: _F) -> _F:
    """``func`` compiled (releasing the GIL) and cached on disk; as Python without numba."""
    if _njit is None:  # pragma: no cover
        return func
    return cast("_F", _njit(cache=True, nogil=True)(func))


def inlined(func: _F) -> _F:
    """``func`` compiled into each compiled caller (numba's ``inline="always"``): a small
    function asked at every step of a compiled loop, which a call would cost more than
    its arithmetic; as Python without numba."""
    if _njit is None:  # pragma: no cover
        return func
    return cast("_F", _njit(cache=True, nogil=True, inline="always")(func))


def _fused_in_python(x: float, y: float, z: float) -> float:
    return x * y + z  # two roundings: the last bit may differ from ``fma``'s


def _fused() -> Callable[[float, float, float], float]:
    """``x * y + z`` rounded once (the C library's ``fma``), for compiled code: numba has no
    ``math.fma`` before Python 3.13, and compiles ``x * y + z`` as two roundings."""
    if _njit is None:  # pragma: no cover
        return _fused_in_python
    from numba import types
    from numba.extending import intrinsic

    @intrinsic
    def fused(typingctx: Any, x: Any, y: Any, z: Any) -> Any:
        def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
            return builder.fma(*args)

        return types.float64(types.float64, types.float64, types.float64), codegen

    return cast("Callable[[float, float, float], float]", fused)


#: ``fma(x, y, z)``: ``x * y + z`` rounded once, in compiled code (LLVM's ``llvm.fma``: the
#: processor's instruction, or the C library's ``fma`` where it has none); as Python
#: without numba, rounded twice. The BLAS that numpy calls multiplies a few points by a
#: 3 x 3 matrix by such chains (``contact.scene._kernels.placed_in_fixed`` reproduces it).
fma = _fused()
