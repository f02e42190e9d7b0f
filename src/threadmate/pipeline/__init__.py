"""The main job end to end: sweep (or reuse) a library, build the network, recommend the
SRCC setting, write GraphML, figures and the report."""

from ._run import DEFAULT_DESIGNATION, RUN_GRID, RunResult, run_pipeline

__all__ = ["DEFAULT_DESIGNATION", "RUN_GRID", "RunResult", "run_pipeline"]
