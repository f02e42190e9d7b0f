"""The thesis's chapter 2: the bolt flush on the nut at any phase.

Contact points where the bolt's tip outline crosses the nut's top outline, the contact
angle, the pivot axis, the in-phase window, the critical phases at which a contact changes
regions, and the figures of one turn of phase (the contact-region combination disk, the
thesis's Figure 2.6, and the pivot axes, its Figure 2.9). Angles are degrees in the fixed
frame F, measured from +X toward +Y; lengths are in the spec's units (conventions.md).
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # the names for type checkers; at run time __getattr__ imports them
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

#: The submodule of each public name, imported when the name is first used (PEP 562):
#: importing the package loads none of them, so that a command that does not need
#: a stage's heavy dependencies (scipy, trimesh, fcl, pandas, matplotlib) never
#: imports them. tests/test_cli_contract.py checks it against the imports above.
_SOURCES = {
    "._analysis": (
        "CriticalPhase",
        "PlanarContact",
        "PlanarState",
        "critical_phases",
        "in_phase_window",
        "phase_sweep",
        "planar_state",
    ),
    "._plots": ("FIGURE_SUFFIXES", "figure_format", "plot_pivot_axes", "plot_region_disk"),
}
#: Public names that differ from their submodule's.
_ALIASES: dict[str, str] = {}
_WHERE = {name: module for module, names in _SOURCES.items() for name in names}


__getattr__, __dir__ = lazy_exports(__name__, globals(), _WHERE, _ALIASES)
