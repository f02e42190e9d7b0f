"""Numbers as the reports and commands print them: the one module that owns the rule."""

from __future__ import annotations

import math
from typing import Any

__all__ = ["number_text"]


def number_text(value: Any, fmt: str = ".6f") -> str:
    """``value`` formatted with ``fmt``, or ``-`` where there is no number (None, NaN or
    an infinity)."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return format(value, fmt)
