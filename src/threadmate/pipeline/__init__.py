"""The main job end to end: sweep (or reuse) a library, build the network, recommend the
SRCC setting, write GraphML, figures and the report."""

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # the names for type checkers; at run time __getattr__ imports them
    from ._folder import RUN_FILES, check_run_folder
    from ._run import DEFAULT_DESIGNATION, RUN_GRID, RunResult, run_pipeline

__all__ = [
    "DEFAULT_DESIGNATION",
    "RUN_FILES",
    "RUN_GRID",
    "RunResult",
    "check_run_folder",
    "run_pipeline",
]

#: The submodule of each public name, imported when the name is first used (PEP 562):
#: importing the package loads none of them, so that a command that does not need
#: a stage's heavy dependencies (scipy, trimesh, fcl, pandas, matplotlib) never
#: imports them. tests/test_cli_contract.py checks it against the imports above.
_SOURCES = {
    "._folder": ("RUN_FILES", "check_run_folder"),
    "._run": ("DEFAULT_DESIGNATION", "RUN_GRID", "RunResult", "run_pipeline"),
}
#: Public names that differ from their submodule's.
_ALIASES: dict[str, str] = {}
_WHERE = {name: module for module, names in _SOURCES.items() for name in names}


def __getattr__(name: str) -> Any:
    """Import the submodule that holds ``name`` on first use (PEP 562)."""
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(module, __name__), _ALIASES.get(name, name))
    globals()[name] = value  # later uses find it without this hook
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
