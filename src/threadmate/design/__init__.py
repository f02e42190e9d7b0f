"""The design stage: what a designer sets, and what it tolerates.

The capture envelope of a compliance (:func:`envelope`): for each direction of
misalignment relative to the nut's thread start, the largest held tilt at which every
start phase (and 95 %, 50 % of them) snaps within one turn, located by bisection in tilt
size along the direction; the tolerated misalignment is its worst direction
(docs/design.md). It reads a polar library (``threadmate sweep --tilt ... --direction
...``) or sweeps a spec's held tilts on demand, with the library's own machinery.

Example
-------
>>> from threadmate.geometry import spec_from_designation
>>> from threadmate.contact import Compliance
>>> from threadmate import design
>>> spec = spec_from_designation("1/4-20 UNC-2A/2B")
>>> env = design.envelope(spec, compliance=Compliance(force=10, stiffness=1))  # doctest: +SKIP
>>> env.tolerated_tilt, env.to_dict()["units"]                                 # doctest: +SKIP
>>> design.plot_envelope(env, "envelope.png")                                  # doctest: +SKIP
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from ._envelope import (
        ENVELOPE_PHASES as ENVELOPE_PHASES,
        LEVELS as LEVELS,
        TOLERANCE as TOLERANCE,
        Envelope as Envelope,
        EnvelopeProgress as EnvelopeProgress,
        envelope as envelope,
    )
    from ._figures import plot_envelope as plot_envelope

#: The submodule of each public name, imported when first used (PEP 562).
_SOURCES = {
    "._envelope": (
        "ENVELOPE_PHASES",
        "LEVELS",
        "TOLERANCE",
        "Envelope",
        "EnvelopeProgress",
        "envelope",
    ),
    "._figures": ("plot_envelope",),
}


__getattr__, __dir__, __all__ = lazy_exports(__name__, globals(), _SOURCES)
