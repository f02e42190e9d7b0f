"""The thesis's chapter 2: the bolt flush on the nut at any phase.

Contact points where the bolt's tip outline crosses the nut's top outline, the contact
angle, the pivot axis, the in-phase window, the critical phases at which a contact changes
regions, and the figures of one turn of phase (the contact-region combination disk, the
thesis's Figure 2.6, and the pivot axes, its Figure 2.9). Angles are degrees in the fixed
frame F, measured from +X toward +Y; lengths are in the spec's units (conventions.md).
"""

from ._analysis import (
    CriticalPhase,
    PlanarContact,
    PlanarState,
    critical_phases,
    in_phase_window,
    phase_sweep,
    planar_state,
)
from ._plots import FIGURE_SUFFIXES, figure_format, plot_pivot_axes, plot_region_disk

__all__ = [
    "FIGURE_SUFFIXES",
    "CriticalPhase",
    "PlanarContact",
    "PlanarState",
    "critical_phases",
    "figure_format",
    "in_phase_window",
    "phase_sweep",
    "planar_state",
    "plot_pivot_axes",
    "plot_region_disk",
]
