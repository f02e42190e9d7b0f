"""The design stage: what a designer sets, what it tolerates, and what to program.

- :func:`envelope`: the capture envelope of a compliance: for each direction of
  misalignment relative to the nut's thread start, the largest held tilt at which every
  start phase (and 95 %, 50 % of them) snaps within one turn, located by bisection in tilt
  size along the direction; the tolerated misalignment is its worst direction. It reads a
  polar library (``threadmate sweep --tilt ... --direction ...``) or sweeps a spec's held
  tilts on demand, with the library's own machinery (docs/design.md, "The capture
  envelope"). :func:`grid_envelope` reads the same off any mechanics library's grid,
  with no new search (the lead of ``threadmate run``'s report).
- :func:`best_compliance`: the force and stiffness within the designer's bounds that
  tolerate the most misalignment, by a coarse-to-fine search over the ratio k/F (on which
  alone the envelope depends), with the settings evaluated, the fall-off around the
  optimum and its :func:`robustness` over the parts' material conditions and the friction
  range (docs/design.md, "The design search", "Robust to what varies").
- :func:`snap_detection`: from a library's network, with no new search, whether a sensor
  can tell the snap from the other jumps of the same searches (the click, the tilt
  spring's moment, the driver's torque, the lateral force), with the threshold that
  separates them or the statement that none does (docs/design.md, "The snap a sensor
  sees").
- :func:`controller_program`: what to program on the controller: the turn limit, the
  torque limit, what to do for starts that never snap, and the snap as a sensor threshold
  (docs/design.md, "What to program").

Lengths in the spec's units, angles in degrees, forces in N, stiffness in N m/rad, torques
and moments in N m, work in mJ.

Example
-------
>>> from threadmate.geometry import spec_from_designation
>>> from threadmate.contact import Compliance
>>> from threadmate import design, network
>>> spec = spec_from_designation("1/4-20 UNC-2A/2B")
>>> env = design.envelope(spec, compliance=Compliance(force=10, stiffness=1))  # doctest: +SKIP
>>> env.tolerated_tilt, env.to_dict()["units"]                                 # doctest: +SKIP
>>> design.plot_envelope(env, "envelope.png")                                  # doctest: +SKIP
>>> g = network.from_library("lib-1-4-20", active=True)               # doctest: +SKIP
>>> det = design.snap_detection(g)                                     # doctest: +SKIP
>>> design.controller_program(g, det).to_dict()                        # doctest: +SKIP
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from ._best import (
        COARSE as COARSE,
        ComplianceDesign as ComplianceDesign,
        DesignProgress as DesignProgress,
        best_compliance as best_compliance,
        format_compliance_design as format_compliance_design,
        plot_compliance_design as plot_compliance_design,
    )
    from ._controller import (
        ControllerProgram as ControllerProgram,
        controller_program as controller_program,
        format_controller_program as format_controller_program,
    )
    from ._envelope import (
        ENVELOPE_PHASES as ENVELOPE_PHASES,
        LEVELS as LEVELS,
        SAME_DIRECTION as SAME_DIRECTION,
        TOLERANCE as TOLERANCE,
        Envelope as Envelope,
        EnvelopeProgress as EnvelopeProgress,
        envelope as envelope,
        grid_envelope as grid_envelope,
    )
    from ._figures import plot_envelope as plot_envelope
    from ._robust import (
        FRICTION_RANGE as FRICTION_RANGE,
        Robustness as Robustness,
        format_robustness as format_robustness,
        material_specs as material_specs,
        most_robust as most_robust,
        robustness as robustness,
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
    "._best": (
        "COARSE",
        "ComplianceDesign",
        "DesignProgress",
        "best_compliance",
        "format_compliance_design",
        "plot_compliance_design",
    ),
    "._controller": ("ControllerProgram", "controller_program", "format_controller_program"),
    "._envelope": (
        "ENVELOPE_PHASES",
        "LEVELS",
        "SAME_DIRECTION",
        "TOLERANCE",
        "Envelope",
        "EnvelopeProgress",
        "envelope",
        "grid_envelope",
    ),
    "._figures": ("plot_envelope",),
    "._robust": (
        "FRICTION_RANGE",
        "Robustness",
        "format_robustness",
        "material_specs",
        "most_robust",
        "robustness",
    ),
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
