"""The thesis's fixed-pivot procedure: first, second and third contact, classified by its
own criteria (its chapter 3 and section 4.2).

:class:`ContactAnalyzer` (on a :class:`threadmate.contact.ContactScene`) lowers the bolt at a
fixed tilt until it first touches, turns it about the nut's tangent there until a second
contact, then about the pivot axis through the two until a third (:mod:`._stages`), and
classifies the state (:mod:`._stability`); the results and their flat record are in
:mod:`._result`.
"""

from typing import TYPE_CHECKING

from ..._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from ._analyzer import ContactAnalyzer as ContactAnalyzer, analyze as analyze
    from ._result import (
        STAGES as STAGES,
        Contact as Contact,
        ContactResult as ContactResult,
        StageResult as StageResult,
        record_schema as record_schema,
    )
    from ._stability import (
        classify as classify,
        interference_depth as interference_depth,
        is_rolling as is_rolling,
        pivot_offset as pivot_offset,
    )
    from ._stages import (
        Cluster as Cluster,
        Search as Search,
        StageOutcome as StageOutcome,
        TurnOutcome as TurnOutcome,
        clusters_at as clusters_at,
        first_contact as first_contact,
        lowering_direction as lowering_direction,
        turn_to_new_contact as turn_to_new_contact,
    )


#: The submodule of each public name, imported when the name is first used (PEP 562).
_SOURCES = {
    "._analyzer": (
        "analyze",
        "ContactAnalyzer",
    ),
    "._result": (
        "Contact",
        "ContactResult",
        "record_schema",
        "StageResult",
        "STAGES",
    ),
    "._stability": (
        "classify",
        "interference_depth",
        "is_rolling",
        "pivot_offset",
    ),
    "._stages": (
        "Cluster",
        "clusters_at",
        "first_contact",
        "lowering_direction",
        "Search",
        "StageOutcome",
        "turn_to_new_contact",
        "TurnOutcome",
    ),
}


__getattr__, __dir__, __all__ = lazy_exports(__name__, globals(), _SOURCES)
