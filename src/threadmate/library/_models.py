"""The models a library can hold, and the one check of a model's name.

Light to import (no pandas): the command line offers the models as its ``--model``
choices before any stage loads.
"""

from __future__ import annotations

from typing import Any

from .._errors import InputError

__all__ = ["MODELS", "check_model"]

#: The models a library can hold: the mechanics' states, or the thesis's fixed-pivot rows.
MODELS = ("mechanics", "thesis")


def check_model(model: Any) -> str:
    """``model`` if it is one of :data:`MODELS`, else an :class:`InputError` naming them."""
    if model not in MODELS:
        raise InputError(f"model must be one of {', '.join(MODELS)}, got {model!r}")
    return str(model)
