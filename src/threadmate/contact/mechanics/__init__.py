"""The mechanics of the held bolt (docs/mechanics.md).

Rest states with their contact forces (:class:`Mechanics`, :func:`settle`), the
counter-clockwise search as a quasi-static continuation with its jumps and the snap proved
by screwing in (:func:`search`, :class:`Continuation`), clockwise starts (:func:`screw`),
the compliance (:class:`Compliance`), the continuation's settings (:mod:`._settings`) and a
turn's figures (:mod:`._figures`). All on a :class:`threadmate.contact.ContactScene`.
"""

from typing import TYPE_CHECKING

from ..._lazy import lazy_exports

if TYPE_CHECKING:  # the names for type checkers; at run time __getattr__ imports them
    from ._compliance import LIMITS as COMPLIANCE_LIMITS
    from ._compliance import (
        Compliance,
    )
    from ._descent import (
        BALANCE,
        MAX_STEPS,
    )
    from ._figures import (
        plot_screw,
        plot_search,
    )
    from ._lcp import (
        contact_step,
    )
    from ._rest_state import (
        LEAD_TOLERANCE,
        Engagement,
        LoadedContact,
        MechanicalState,
        RestState,
        SearchEvent,
        SearchResult,
        tightening_torque,
        turn_units,
    )
    from ._screw import (
        ENGAGED_TURN,
        ScrewResult,
        screw,
    )
    from ._screw import OUTCOMES as SCREW_OUTCOMES
    from ._search import (
        CLICK_SPAN,
        SENSES,
        Continuation,
        Leg,
        default_torque_limit,
        engagement,
        search,
        sensor_click,
        wedged,
    )
    from ._settings import (
        CONTINUATION_STEP,
        MAX_SCREW_IN,
        MAX_STEP,
        MAX_TURNS,
        PHASE_TOLERANCE,
        SCREW_IN,
        check_continuation,
        check_screw,
    )
    from ._settle import (
        Mechanics,
        mechanics,
        settle,
    )

__all__ = [
    "Compliance",
    "COMPLIANCE_LIMITS",
    "plot_screw",
    "plot_search",
    "contact_step",
    "Engagement",
    "LEAD_TOLERANCE",
    "LoadedContact",
    "MechanicalState",
    "RestState",
    "SearchEvent",
    "SearchResult",
    "tightening_torque",
    "turn_units",
    "ENGAGED_TURN",
    "SCREW_OUTCOMES",
    "screw",
    "ScrewResult",
    "Continuation",
    "default_torque_limit",
    "engagement",
    "Leg",
    "search",
    "SENSES",
    "sensor_click",
    "CLICK_SPAN",
    "wedged",
    "check_continuation",
    "check_screw",
    "CONTINUATION_STEP",
    "MAX_SCREW_IN",
    "MAX_STEP",
    "MAX_TURNS",
    "PHASE_TOLERANCE",
    "SCREW_IN",
    "BALANCE",
    "MAX_STEPS",
    "Mechanics",
    "mechanics",
    "settle",
]

#: The submodule of each public name, imported when the name is first used (PEP 562).
_SOURCES = {
    "._compliance": (
        "Compliance",
        "COMPLIANCE_LIMITS",
    ),
    "._figures": (
        "plot_screw",
        "plot_search",
    ),
    "._lcp": ("contact_step",),
    "._rest_state": (
        "Engagement",
        "LEAD_TOLERANCE",
        "LoadedContact",
        "MechanicalState",
        "RestState",
        "SearchEvent",
        "SearchResult",
        "tightening_torque",
        "turn_units",
    ),
    "._screw": (
        "ENGAGED_TURN",
        "SCREW_OUTCOMES",
        "screw",
        "ScrewResult",
    ),
    "._search": (
        "Continuation",
        "default_torque_limit",
        "engagement",
        "Leg",
        "search",
        "SENSES",
        "sensor_click",
        "CLICK_SPAN",
        "wedged",
    ),
    "._settings": (
        "check_continuation",
        "check_screw",
        "CONTINUATION_STEP",
        "MAX_SCREW_IN",
        "MAX_STEP",
        "MAX_TURNS",
        "PHASE_TOLERANCE",
        "SCREW_IN",
    ),
    "._descent": (
        "BALANCE",
        "MAX_STEPS",
    ),
    "._settle": (
        "Mechanics",
        "mechanics",
        "settle",
    ),
}
_ALIASES: dict[str, str] = {"COMPLIANCE_LIMITS": "LIMITS", "SCREW_OUTCOMES": "OUTCOMES"}
_WHERE = {name: module for module, names in _SOURCES.items() for name in names}


__getattr__, __dir__ = lazy_exports(__name__, globals(), _WHERE, _ALIASES)
