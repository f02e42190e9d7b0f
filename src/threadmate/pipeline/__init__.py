"""The main job end to end: sweep (or reuse) a library, build the network, recommend the
SRCC setting, write GraphML, figures and the report."""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # the names for type checkers; at run time __getattr__ imports them
    from ._defaults import DEFAULT_DESIGNATION, RUN_GRID
    from ._folder import RUN_FILES, check_run_folder
    from ._run import RunResult, run_pipeline

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
    "._defaults": ("DEFAULT_DESIGNATION", "RUN_GRID"),
    "._folder": ("RUN_FILES", "check_run_folder"),
    "._run": ("RunResult", "run_pipeline"),
}
#: Public names that differ from their submodule's.
_ALIASES: dict[str, str] = {}
_WHERE = {name: module for module, names in _SOURCES.items() for name in names}


__getattr__, __dir__ = lazy_exports(__name__, globals(), _WHERE, _ALIASES)
