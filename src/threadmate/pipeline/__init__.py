"""The main job end to end: sweep (or reuse) a library, build the network, recommend the
SRCC pitch, write GraphML, figures and a short report."""

from ._run import DEFAULT_DESIGNATION, RunResult, run_pipeline

__all__ = ["DEFAULT_DESIGNATION", "RunResult", "run_pipeline"]
