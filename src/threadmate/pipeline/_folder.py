"""The output folder of a run: new, empty, or a previous run's (to resume and refresh).

A run writes its library (or one per compliance) and its files into one folder. Like the
sweep, which refuses to write a library into a folder that holds something else, a run
refuses a folder that holds anything a run does not write: it would mix its files with
the user's, or replace them. A previous run's folder (a library in it, and nothing a run
does not write) is resumed: its library is reused or finished, its files are written
again. Hidden entries (a name starting with ``.``) are ignored, as the sweep ignores them.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from .._errors import InputError

__all__ = ["RUN_FILES", "check_run_folder"]

#: What a run writes into its folder, besides its libraries (``library``, or
#: ``library-F<force>-k<roll>-<pitch>`` each with several compliances).
RUN_FILES = (
    "network.graphml",
    "network.json",
    "starts.csv",
    "recommendation.json",
    "envelope.json",
    "sensor.json",
    "program.json",
    "figures",
    "report.md",
    "report.html",
    "views",
)
_LIBRARY = re.compile(r"library(-F.+-k.+)?")


def check_run_folder(out: str | os.PathLike[str]) -> Path:
    """``out`` if a run may write into it: missing, empty, or a previous run's folder.

    Raises
    ------
    InputError
        ``out`` exists, is not empty and is not a previous run's folder (named entries
        a run does not write, or no library among them).
    """
    from ..library import METADATA_FILE  # the library's own marker file

    out = Path(out)
    if not out.is_dir():
        return out  # missing (created), or a file (the writers refuse it)
    entries = sorted(p for p in out.iterdir() if not p.name.startswith("."))
    if not entries:
        return out
    libraries = [p for p in entries if _LIBRARY.fullmatch(p.name)]
    foreign = [p.name for p in entries if p.name not in RUN_FILES and p not in libraries]
    if foreign or not any((p / METADATA_FILE).is_file() for p in libraries):
        shown = foreign or [p.name for p in entries]
        holds = ", ".join(repr(n) for n in shown[:3]) + (", ..." if len(shown) > 3 else "")
        raise InputError(
            f"{out} exists, is not empty and is not a threadmate run's folder (it holds "
            f"{holds}): give a new or empty folder, or a previous run's folder to resume it"
        )
    return out
