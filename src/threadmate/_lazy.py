"""Public names loaded on first use (PEP 562), for the packages' ``__init__`` modules.

A package lists which private submodule holds each public name; importing the package
loads none of them, so that a command that does not need a stage's heavy dependencies
(scipy, trimesh, numba, pandas, matplotlib) never imports them.

Each public ``__init__`` names an export twice: once in its ``TYPE_CHECKING`` block, as
an explicit re-export (``from ._x import name as name``) that type checkers read, also
under ``--no-implicit-reexport``; once in its ``_SOURCES`` table, which the loader reads
at run time. ``__all__`` is derived from the table here, and
tests/test_cli_contract.py checks that table and block agree.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any

__all__ = ["lazy_exports"]


def lazy_exports(
    package: str,
    namespace: dict[str, Any],
    sources: Mapping[str, tuple[str, ...]],
) -> tuple[Callable[[str], Any], Callable[[], list[str]], list[str]]:
    """The module-level ``__getattr__``, ``__dir__`` and ``__all__`` of ``package``.

    Parameters
    ----------
    package
        The package's ``__name__``.
    namespace
        The package's ``globals()``, where a name once loaded is kept (later uses find it
        without the hook).
    sources
        Each submodule (relative to ``package``) and the public names it holds, under
        the same names there.

    Raises
    ------
    ValueError
        If a name is listed under two submodules.
    """
    where: dict[str, str] = {}
    for module, names in sources.items():
        for name in names:
            if name in where:
                raise ValueError(f"{package}: {name!r} is listed under {where[name]} and {module}")
            where[name] = module

    def __getattr__(name: str) -> Any:
        module = where.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module, package), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted({*namespace, *where})

    return __getattr__, __dir__, list(where)
