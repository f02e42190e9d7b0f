"""The built-in default of ``threadmate run``: its thread pair and its grid.

Light to import (no stage): the command line quotes them in its help.
"""

from __future__ import annotations

__all__ = ["DEFAULT_DESIGNATION", "RUN_GRID"]

#: The built-in default of ``threadmate run``: the thesis's thread pair.
DEFAULT_DESIGNATION = "1/4-20 UNC-2A/2B"
#: The default grid of ``threadmate run``: held roll and pitch -2..2 by 1 degree (a square
#: grid, so that the azimuth-proof pick exists) and start phases every 20 degrees. The
#: thesis's grid (-4..4 by 1, phases by 5) is ``roll="-4:4:1", pitch="-4:4:1",
#: phase="0:355:5"``.
RUN_GRID = {"roll": "-2:2:1", "pitch": "-2:2:1", "phase": "0:340:20"}
