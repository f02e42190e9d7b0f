"""The mechanics of the held bolt (docs/mechanics.md).

Rest states with their contact forces (:class:`Mechanics`, :func:`settle`), the
counter-clockwise search as a quasi-static continuation with its jumps and the snap proved
by screwing in (:func:`search`, :class:`Continuation`), clockwise starts (:func:`screw`),
the compliance (:class:`Compliance`), the continuation's settings (:mod:`._settings`) and a
turn's figures (:mod:`._figures`). All on a :class:`threadmate.contact.ContactScene`.
"""

from typing import TYPE_CHECKING

from ..._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from ._compliance import COMPLIANCE_LIMITS as COMPLIANCE_LIMITS, Compliance as Compliance
    from ._descent import BALANCE as BALANCE, MAX_STEPS as MAX_STEPS
    from ._figures import plot_screw as plot_screw, plot_search as plot_search
    from ._lcp import contact_step as contact_step
    from ._rest_state import (
        LEAD_TOLERANCE as LEAD_TOLERANCE,
        Engagement as Engagement,
        LoadedContact as LoadedContact,
        MechanicalState as MechanicalState,
        RestState as RestState,
        SearchEvent as SearchEvent,
        SearchResult as SearchResult,
        tightening_torque as tightening_torque,
        turn_units as turn_units,
    )
    from ._screw import (
        ENGAGED_TURN as ENGAGED_TURN,
        SCREW_OUTCOMES as SCREW_OUTCOMES,
        ClockwiseStarts as ClockwiseStarts,
        ScrewResult as ScrewResult,
        screw as screw,
    )
    from ._search import (
        CLICK_SPAN as CLICK_SPAN,
        SENSES as SENSES,
        Continuation as Continuation,
        Leg as Leg,
        default_torque_limit as default_torque_limit,
        engagement as engagement,
        same_pose as same_pose,
        search as search,
        sensor_click as sensor_click,
        wedged as wedged,
    )
    from ._settings import (
        CONTINUATION_STEP as CONTINUATION_STEP,
        JOIN_DISTANCE as JOIN_DISTANCE,
        JOIN_TILT as JOIN_TILT,
        MAX_SCREW_IN as MAX_SCREW_IN,
        MAX_STEP as MAX_STEP,
        MAX_TURNS as MAX_TURNS,
        PHASE_TOLERANCE as PHASE_TOLERANCE,
        PROOF_FOLD_TOLERANCE as PROOF_FOLD_TOLERANCE,
        PROOF_TURN_LIMIT as PROOF_TURN_LIMIT,
        SCREW_IN as SCREW_IN,
        TIGHTEN_STEP as TIGHTEN_STEP,
        check_continuation as check_continuation,
        check_screw as check_screw,
    )
    from ._settle import Mechanics as Mechanics, mechanics as mechanics, settle as settle


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
        "ClockwiseStarts",
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
        "same_pose",
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
        "JOIN_DISTANCE",
        "JOIN_TILT",
        "MAX_SCREW_IN",
        "MAX_STEP",
        "MAX_TURNS",
        "PHASE_TOLERANCE",
        "PROOF_FOLD_TOLERANCE",
        "PROOF_TURN_LIMIT",
        "SCREW_IN",
        "TIGHTEN_STEP",
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


__getattr__, __dir__, __all__ = lazy_exports(__name__, globals(), _SOURCES)
