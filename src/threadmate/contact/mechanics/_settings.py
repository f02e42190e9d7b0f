"""The settings of a continuation in phase (a search, a screw-in, a sweep's search): their
defaults, their ranges and the one check of each.

Light to import (no mechanics): the command line quotes the defaults and ranges in its
help and checks its options with these functions before any stage loads. Angles in
degrees, torques in N m.
"""

from __future__ import annotations

import math

from ..._errors import InputError
from ..._validate import check_open_range, check_search_steps

__all__ = [
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
    "check_continuation",
    "check_screw",
]

#: The continuation's default step (degrees): the thesis's phase step. Folds and contact
#: changes inside a step are located by bisection; a step this size is what the library's
#: sweep and ``threadmate search`` both take by default, so that they agree.
CONTINUATION_STEP = 5.0
#: Largest step of a continuation (degrees): beyond it a step passes over whole contact
#: changes of a thread's flank.
MAX_STEP = 10.0
#: Longest step of a tightening continuation (degrees): a screw-in proof's walk and a
#: clockwise start's, whatever the continuation's step. Its steps in the thread are
#: predicted along the helix (the lead's share of the turn), and the descent corrects the
#: prediction; but a longer step can carry a tilted landing past where the thread draws
#: it in, onto a ride at its tilt that never descends (docs/mechanics.md, "The snap
#: proved: screwing in").
TIGHTEN_STEP = 5.0
#: Most turns one continuation takes.
MAX_TURNS = 10.0
#: How closely jumps, contact changes and the snap are located in phase (degrees, default;
#: at most the step).
PHASE_TOLERANCE = 0.01
#: How closely the screw-in proof locates a fold that the bolt leaves downward (degrees):
#: where such a jump lies within the turn changes neither whether the turn wedges nor its
#: descent over the second half, only the phase its note quotes; a fold whose landing lies
#: above the branch (a wedge, or none) is located to the phase tolerance as any other.
PROOF_FOLD_TOLERANCE = 1.0
#: Largest angle between bolt axes (degrees) of two rest states taken as one: a
#: continuation that reaches a state already known joins it, for the quasi-static dynamics
#: are deterministic and from there on the paths are one.
JOIN_TILT = 0.05
#: Largest distance between compliance centres, in pitches, of two rest states taken as
#: one (with :data:`JOIN_TILT`).
JOIN_DISTANCE = 1e-3
#: Default turn of the screw-in that proves a snap (degrees).
SCREW_IN = 180.0
#: Longest screw-in that proves a snap (degrees: two turns).
MAX_SCREW_IN = 720.0
#: Longest turn of a proof that goes on while the bolt still rights itself in the thread
#: (degrees): a tilted landing comes upright within a turn, and a turn keeps the proof
#: within the shortest parts' thread (the thesis's bolt and nut are a pitch long).
PROOF_TURN_LIMIT = 360.0


def check_screw(*, screw_in: float = SCREW_IN, torque_limit: float | None = None) -> None:
    """Refuse screw-in settings out of range (InputError naming the setting).

    Parameters
    ----------
    screw_in : float
        Turn of the clockwise continuation that proves a snap, degrees within
        [0, :data:`MAX_SCREW_IN`] (0: none).
    torque_limit : float or None
        Tightening torque past which the bolt counts as jammed (N m, > 0); None: the
        default.
    """
    if not (math.isfinite(screw_in) and 0.0 <= screw_in <= MAX_SCREW_IN):
        raise InputError(f"screw_in must be within [0, {MAX_SCREW_IN:g}] degrees, got {screw_in!r}")
    if torque_limit is not None and not (math.isfinite(torque_limit) and torque_limit > 0):
        raise InputError(f"torque_limit must be a positive torque (N m), got {torque_limit!r}")


def check_continuation(
    *,
    turns: float = 1.0,
    step: float = CONTINUATION_STEP,
    phase_tolerance: float = PHASE_TOLERANCE,
) -> None:
    """Refuse continuation settings out of range (InputError naming the setting).

    Parameters
    ----------
    turns : float
        Turns to continue over, within (0, :data:`MAX_TURNS`].
    step : float
        Step in phase, degrees within (0, :data:`MAX_STEP`].
    phase_tolerance : float
        How closely events are located, degrees within (0, ``step``].

    The steps the turns take at ``step`` are counted too
    (:func:`threadmate._validate.check_search_steps`): one check for every caller.
    """
    for name, value, lo, hi in (
        ("turns", turns, 0.0, MAX_TURNS),
        ("step", step, 0.0, MAX_STEP),
        ("phase_tolerance", phase_tolerance, 0.0, step),
    ):
        check_open_range(name, value, lo, hi)
    check_search_steps(turns, step)
