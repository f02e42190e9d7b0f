"""The classes of a contact state, declared once (docs/mechanics.md, "Classes"; the
thesis's in :mod:`._stability`).

Every row, result and figure names a state's class with one of these strings; the lists
below are built from them. The mechanics give a state one of :data:`REST_CLASSES`, the
thesis's fixed-pivot stages one of :data:`CLASSIFICATIONS`; a library row whose
computation failed carries :data:`ERROR_CLASS` (its ``error`` column says why). A passive
transition is labelled by its stability, one of :data:`TRANSITION_LABELS`.
"""

from __future__ import annotations

__all__ = [
    "CLASSIFICATIONS",
    "ERROR_CLASS",
    "IN_PHASE",
    "NO_CONTACT",
    "QUASI_STABLE",
    "REST_CLASSES",
    "STABLE",
    "TRANSITION_LABELS",
    "UNSTABLE",
]

#: The contacts alone hold the load.
STABLE = "stable"
#: A rest state that needs the compliance.
QUASI_STABLE = "quasi-stable"
#: Not a rest state.
UNSTABLE = "unstable"
#: Engaged: every load-carrying contact lies on the helices.
IN_PHASE = "in-phase"
#: The thesis's stages found no first, second or third contact.
NO_CONTACT = "no-contact"
#: A configuration whose computation failed (a library row).
ERROR_CLASS = "error"

#: Classes of a mechanical state.
REST_CLASSES = (STABLE, QUASI_STABLE, UNSTABLE, IN_PHASE)
#: Every classification a result can carry (the library adds :data:`ERROR_CLASS`).
CLASSIFICATIONS = (*REST_CLASSES, NO_CONTACT)
#: Labels of a transition, by its stability (docs/network.md, "The network").
TRANSITION_LABELS = (STABLE, QUASI_STABLE, UNSTABLE)
