"""The meshes' chord tolerance: its default per unit and the one check of a chord given.

Light to import (no trimesh): the command line quotes the default in its help and checks
``--chord`` with :func:`check_chord` before any mesh is built.
"""

from __future__ import annotations

from .._errors import InputError
from .._units import unit_scale
from .._validate import check_number
from ._spec import ThreadSpec

__all__ = ["DEFAULT_CHORD", "check_chord"]

#: Default chord tolerance per unit: 5e-6 in (the thesis's CAD models used 1e-4 in).
DEFAULT_CHORD: dict[str, float] = {"in": 5e-6, "mm": 5e-6 * unit_scale("in", "mm")}
# Finest and coarsest chord, in pitches: finer would make meshes of millions of triangles,
# coarser would no longer resemble a thread.
_FINEST_CHORD = 1e-6
_COARSEST_CHORD = 0.02


def check_chord(spec: ThreadSpec, chord: float | None, name: str = "chord") -> float:
    """The chord tolerance to mesh ``spec`` with: ``chord`` checked (a positive length
    within the finest and coarsest the meshes accept, in pitches), or the default of the
    spec's units.

    The one check of a chord: the meshes, the sweep and the commands use it.

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair (the range is in its pitches, the message in its units).
    chord : float or None
        The chord tolerance in the spec's units; None: :data:`DEFAULT_CHORD`.
    name : str
        The parameter's name in the messages.

    Returns
    -------
    float
        The chord tolerance, spec units.

    Raises
    ------
    InputError
        Naming the chord and the range it must lie in.
    """
    if not isinstance(spec, ThreadSpec):
        raise InputError(f"spec must be a ThreadSpec, got {type(spec).__name__}")
    if chord is None:
        return DEFAULT_CHORD[spec.units]
    chord = check_number(name, chord)
    if chord <= 0:
        raise InputError(f"{name} must be a positive length, got {chord!r}")
    if chord < spec.pitch * _FINEST_CHORD:
        raise InputError(
            f"{name} {chord:g} {spec.units} is too fine (the meshes would have "
            f"many millions of triangles): give at least "
            f"{spec.pitch * _FINEST_CHORD:g}"
        )
    if chord > spec.pitch * _COARSEST_CHORD:
        raise InputError(
            f"{name} {chord:g} {spec.units} is too coarse for a pitch of "
            f"{spec.pitch:g} {spec.units}: give at most "
            f"{spec.pitch * _COARSEST_CHORD:g}"
        )
    return float(chord)
