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

if TYPE_CHECKING:  # the names for type checkers; at run time __getattr__ imports them
    from ._analyzer import (
        ContactAnalyzer,
        analyze,
    )
    from ._result import (
        STAGES,
        Contact,
        ContactResult,
        StageResult,
        record_schema,
    )
    from ._stability import (
        classify,
        interference_depth,
        is_rolling,
        pivot_offset,
    )
    from ._stages import (
        Cluster,
        Search,
        StageOutcome,
        TurnOutcome,
        clusters_at,
        first_contact,
        lowering_direction,
        turn_to_new_contact,
    )

__all__ = [
    "analyze",
    "ContactAnalyzer",
    "Contact",
    "ContactResult",
    "record_schema",
    "StageResult",
    "STAGES",
    "classify",
    "interference_depth",
    "is_rolling",
    "pivot_offset",
    "Cluster",
    "clusters_at",
    "first_contact",
    "lowering_direction",
    "Search",
    "StageOutcome",
    "turn_to_new_contact",
    "TurnOutcome",
]

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
_ALIASES: dict[str, str] = {}
_WHERE = {name: module for module, names in _SOURCES.items() for name in names}


__getattr__, __dir__ = lazy_exports(__name__, globals(), _WHERE, _ALIASES)
