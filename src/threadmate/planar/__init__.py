"""The thesis's chapter 2: the bolt flush on the nut at any phase.

Contact points where the bolt's tip outline crosses the nut's top outline, the contact
angle, the pivot axis, the in-phase window, the critical phases at which a contact changes
regions, and the figures of one turn of phase (the contact-region combination disk, the
thesis's Figure 2.6, and the pivot axes, its Figure 2.9). Angles are degrees in the fixed
frame F, measured from +X toward +Y; lengths are in the spec's units (conventions.md).
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from ._analysis import (
        CriticalPhase as CriticalPhase,
        PlanarContact as PlanarContact,
        PlanarState as PlanarState,
        critical_phases as critical_phases,
        in_phase_window as in_phase_window,
        phase_sweep as phase_sweep,
        planar_state as planar_state,
    )
    from ._plots import (
        FIGURE_SUFFIXES as FIGURE_SUFFIXES,
        figure_format as figure_format,
        plot_pivot_axes as plot_pivot_axes,
        plot_region_disk as plot_region_disk,
    )


#: The submodule of each public name, imported when the name is first used (PEP 562):
#: importing the package loads none of them, so that a command that does not need
#: a stage's heavy dependencies (scipy, trimesh, numba, pandas, matplotlib) never
#: imports them; __all__ is made from it. tests/test_cli_contract.py checks it against
#: the re-exports above.
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


__getattr__, __dir__, __all__ = lazy_exports(__name__, globals(), _SOURCES)
