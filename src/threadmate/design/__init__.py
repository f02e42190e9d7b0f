"""The design stage: what a robot integrator sets and programs, from a library.

From a library's network (:mod:`threadmate.network`), with no new search:

- :func:`snap_detection`: whether a sensor can tell the snap from the other jumps of the
  same searches (the click, the tilt spring's moment, the driver's torque), with the
  threshold that separates them or the statement that none does (docs/design.md, "The
  snap a sensor sees");
- :func:`controller_program`: what to program on the controller: the turn limit, the
  torque limit, what to do for starts that never snap, and the snap as a sensor threshold
  (docs/design.md, "What to program").

Lengths in the spec's units, angles in degrees, forces in N, torques and moments in N m.

Example
-------
>>> from threadmate import design, network
>>> g = network.from_library("lib-1-4-20", active=True)               # doctest: +SKIP
>>> det = design.snap_detection(g)                                     # doctest: +SKIP
>>> det.click.statement(det.units)                                     # doctest: +SKIP
>>> design.controller_program(g, det).to_dict()                        # doctest: +SKIP
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from ._controller import (
        ControllerProgram as ControllerProgram,
        controller_program as controller_program,
        format_controller_program as format_controller_program,
    )
    from ._searches import (
        EVENT_SIGNALS as EVENT_SIGNALS,
        SearchEvents as SearchEvents,
        search_events as search_events,
    )
    from ._sensor import (
        Separation as Separation,
        SnapDetection as SnapDetection,
        format_snap_detection as format_snap_detection,
        plot_snap_detection as plot_snap_detection,
        separation as separation,
        snap_detection as snap_detection,
    )


#: The submodule of each public name, imported when the name is first used (PEP 562);
#: __all__ is made from it. tests/test_cli_contract.py checks it against the re-exports
#: above.
_SOURCES = {
    "._controller": ("ControllerProgram", "controller_program", "format_controller_program"),
    "._searches": ("EVENT_SIGNALS", "SearchEvents", "search_events"),
    "._sensor": (
        "Separation",
        "SnapDetection",
        "format_snap_detection",
        "plot_snap_detection",
        "separation",
        "snap_detection",
    ),
}


__getattr__, __dir__, __all__ = lazy_exports(__name__, globals(), _SOURCES)
