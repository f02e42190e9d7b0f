"""Public names loaded on first use (PEP 562), for the packages' ``__init__`` modules.

A package lists which private submodule holds each public name; importing the package
loads none of them, so that a command that does not need a stage's heavy dependencies
(scipy, trimesh, fcl, pandas, matplotlib) never imports them.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Any

__all__ = ["lazy_exports"]


def lazy_exports(
    package: str,
    namespace: dict[str, Any],
    where: dict[str, str],
    aliases: dict[str, str],
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The module-level ``__getattr__`` and ``__dir__`` of ``package``.

    ``where`` maps each public name to its submodule (relative to ``package``),
    ``aliases`` a public name to the submodule's own where they differ; ``namespace`` is
    the package's ``globals()``, where a name once loaded is kept (later uses find it
    without the hook).
    """

    def __getattr__(name: str) -> Any:
        module = where.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module, package), aliases.get(name, name))
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted({*namespace, *where})

    return __getattr__, __dir__
