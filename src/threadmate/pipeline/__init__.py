"""The main job end to end: sweep (or reuse) a library, build the network, recommend the
SRCC setting, write GraphML, figures and the report."""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from ._defaults import DEFAULT_DESIGNATION as DEFAULT_DESIGNATION, RUN_GRID as RUN_GRID
    from ._folder import RUN_FILES as RUN_FILES, check_run_folder as check_run_folder
    from ._run import RunResult as RunResult, run_pipeline as run_pipeline


#: The submodule of each public name, imported when the name is first used (PEP 562):
#: importing the package loads none of them, so that a command that does not need
#: a stage's heavy dependencies (scipy, trimesh, numba, pandas, matplotlib) never
#: imports them; __all__ is made from it. tests/test_cli_contract.py checks it against
#: the re-exports above.
_SOURCES = {
    "._defaults": ("DEFAULT_DESIGNATION", "RUN_GRID"),
    "._folder": ("RUN_FILES", "check_run_folder"),
    "._run": ("RunResult", "run_pipeline"),
}


__getattr__, __dir__, __all__ = lazy_exports(__name__, globals(), _SOURCES)
