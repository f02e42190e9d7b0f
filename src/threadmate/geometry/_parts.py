"""The parts of a thread pair beyond its thread: the bolt's point, the nut's countersink and
the two lengths, applied to a designation, a spec or a spec file (:func:`with_parts`).

A designation expands with a chamfered point and the standard nut's countersink unless
told otherwise (:func:`spec_from_designation`); a spec keeps its own parts unless told
otherwise. Lengths are in the spec's units or in pitches (``"3p"``); angles in degrees.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Callable
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

from .._errors import InputError, SpecError
from ._designation import Designation, parse_designation, spec_from_designation
from ._ends import BoltPoint, Countersink
from ._nuts import standard_countersink_diameter, standard_nut_height
from ._spec import ThreadSpec, load_spec, parse_length

__all__ = ["SpecParts", "with_parts"]

#: The spec key each parameter of :func:`with_parts` sets: a refusal of that key names the
#: parameter first.
_PART_KEYS = {
    "point": "bolt.point.form",
    "chamfer_angle": "bolt.point.angle",
    "point_diameter": "bolt.point.diameter",
    "round_radius": "bolt.point.radius",
    "countersink_angle": "nut.countersink.angle",
    "countersink_diameter": "nut.countersink.diameter",
    "bolt_length": "bolt.length",
    "nut_height": "nut.height",
}
#: The point forms each of the point's values applies to.
_POINT_VALUES = {
    "chamfer_angle": ("chamfer",),
    "round_radius": ("round",),
    "point_diameter": ("chamfer", "round"),
}
#: A spec file's suffixes (a text ending otherwise is a designation).
_SPEC_SUFFIXES = (".json", ".toml")


def with_parts(
    spec: ThreadSpec | Designation | str | os.PathLike[str],
    *,
    condition: str = "mean",
    point: str | None = None,
    chamfer_angle: float | None = None,
    point_diameter: float | None = None,
    round_radius: float | None = None,
    countersink: bool | None = None,
    countersink_angle: float | None = None,
    countersink_diameter: float | None = None,
    bolt_length: float | str | None = None,
    nut_height: float | str | None = None,
) -> ThreadSpec:
    """A thread pair with the bolt's point, the nut's countersink and the lengths given.

    Parameters
    ----------
    spec : ThreadSpec, Designation, str or path-like
        A spec; a designation (``"1/4-20 UNC-2A/2B"``, ``"M6"``); or a spec file (a path,
        or text ending in ``.json`` or ``.toml``).
    condition : {"mean", "max", "min"}
        Material condition at which a designation expands (a spec has its diameters).
    point : {"chamfer", "round", "flat"}, optional
        The bolt's point. Default: a chamfer for a designation, a spec's own.
    chamfer_angle : float, optional
        Chamfer angle from the bolt's axis, degrees (a chamfer only; default 45, or the
        spec's).
    point_diameter : float, optional
        Diameter of the tip face where a chamfer or round ends (default 0.1 pitch below
        the bolt's minor diameter, or the spec's).
    round_radius : float, optional
        Radius of a round point (a round only; default 1.4 x major diameter, or the
        spec's).
    countersink : bool, optional
        The nut's countersink (True) or a flat, sharp-edged bore (False). Default: the
        standard's for a designation; a spec's own, or one when its angle or diameter is
        given.
    countersink_angle : float, optional
        Included angle of the countersink, degrees (default 120, or the spec's).
    countersink_diameter : float, optional
        Diameter of the countersink at the nut's face (default: the standard's for the
        designation, or the spec's).
    bolt_length, nut_height : float or str, optional
        A length, or text: a number, pitches such as ``"3p"``, and for ``nut_height``
        ``"standard"``, the standard hex nut's height (of a designation, or of the one a
        spec names). Default: the point's height and one pitch; the countersink's depth
        and one pitch. A spec's own lengths stay unless they are these defaults, which
        follow new ends.

    Returns
    -------
    ThreadSpec
        The thread pair with its parts, lengths in its units.

    Raises
    ------
    DesignationError
        A designation that names no standard thread.
    SpecError
        A spec file that cannot be read, or parts that do not fit the thread: the
        message names the parameter first, then the spec key it sets.
    InputError
        A value that does not apply to the point's form or to a flat bore, or a standard
        value asked of a spec that names no designation.

    Examples
    --------
    >>> from threadmate.geometry import with_parts
    >>> spec = with_parts("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    >>> spec.bolt.length == spec.nut.height == spec.pitch    # the thesis's parts
    True
    >>> with_parts(spec, point="chamfer", bolt_length="3p").bolt.length == 3 * spec.pitch
    True
    """
    parts = SpecParts(
        point,
        chamfer_angle,
        point_diameter,
        round_radius,
        countersink,
        countersink_angle,
        countersink_diameter,
        bolt_length,
        nut_height,
    )
    if isinstance(spec, os.PathLike) or (
        isinstance(spec, str) and spec.strip().lower().endswith(_SPEC_SUFFIXES)
    ):
        spec = load_spec(Path(spec))
    if isinstance(spec, ThreadSpec):
        if not parts.given:
            return spec
        return parts.naming(functools.partial(_parts_of_spec, spec, parts))
    des = parse_designation(spec)
    if not parts.given:
        return spec_from_designation(des, condition)
    return parts.naming(functools.partial(_parts_of_designation, des, condition, parts))


@dataclass(frozen=True)
class SpecParts:
    """The bolt's point, the nut's countersink and the two lengths as :func:`with_parts`
    takes them, its keyword arguments (None: not given; their meaning is its).

    Examples
    --------
    >>> from threadmate.geometry import SpecParts, with_parts
    >>> parts = SpecParts(point="flat", countersink=False)
    >>> spec = with_parts("1/4-20 UNC-2A/2B", **parts.arguments())
    >>> spec.bolt.point.form, spec.nut.countersink
    ('flat', None)
    """

    point: str | None = None
    chamfer_angle: float | None = None
    point_diameter: float | None = None
    round_radius: float | None = None
    countersink: bool | None = None
    countersink_angle: float | None = None
    countersink_diameter: float | None = None
    bolt_length: float | str | None = None
    nut_height: float | str | None = None

    def arguments(self) -> dict[str, Any]:
        """The keyword arguments of :func:`with_parts`, one per field."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    @property
    def given(self) -> bool:
        """Whether any part is given."""
        return any(getattr(self, f.name) is not None for f in fields(self))

    def naming(self, build: Callable[[], ThreadSpec]) -> ThreadSpec:
        """``build()``, a refusal of a spec key that a given part sets prefixed with the
        part's parameter."""
        try:
            return build()
        except SpecError as exc:
            message = str(exc)
            for name, key in _PART_KEYS.items():
                if getattr(self, name) is not None and f"'{key}'" in message:
                    raise SpecError(f"{name}: {message}") from None
            raise

    def check_applies(self, form: str, countersink: bool) -> None:
        """Refuse a value that does not apply to the point's form or to a flat bore."""
        for name, forms in _POINT_VALUES.items():
            if getattr(self, name) is not None and form not in forms:
                raise InputError(
                    f"{name} applies to a {' or '.join(forms)} point, not to a {form} one"
                )
        if not countersink:
            for name in ("countersink_angle", "countersink_diameter"):
                if getattr(self, name) is not None:
                    raise InputError(
                        f"{name} applies to a countersink, not to a flat bore (no countersink)"
                    )


def _length_value(value: float | str | None) -> float | str | None:
    """A length given as text that is a number, as that number (pitches and
    ``"standard"`` stay text)."""
    if isinstance(value, str):
        try:
            return float(value)
        except ValueError:
            return value
    return value


def _parts_of_designation(des: Designation, condition: str, parts: SpecParts) -> ThreadSpec:
    form = parts.point or "chamfer"
    wanted = True if parts.countersink is None else parts.countersink
    parts.check_applies(form, wanted)
    sink: Countersink | bool = False
    if wanted:
        angle = parts.countersink_angle
        sink = (
            Countersink(diameter=parts.countersink_diameter)
            if angle is None
            else Countersink(angle, parts.countersink_diameter)
        )
    return spec_from_designation(
        des,
        condition,
        point=BoltPoint(form, parts.chamfer_angle, parts.point_diameter, parts.round_radius),
        countersink=sink,
        bolt_length=_length_value(parts.bolt_length),
        nut_height=_length_value(parts.nut_height),
    )


def _length(value: float | str | None, name: str, spec: ThreadSpec) -> float | None:
    """``bolt_length`` or ``nut_height`` of a spec in its units (None: not given)."""
    value = _length_value(value)
    if value is None:
        return None
    if name == "nut_height" and isinstance(value, str) and value.strip().lower() == "standard":
        if spec.designation is None:
            raise InputError(
                f"nut_height='standard' needs a designation and the spec names none; give "
                f"the height in {spec.units} or in pitches (e.g. 3p)"
            )
        try:
            return standard_nut_height(spec.designation)
        except InputError as exc:  # a size the tables lack, a spec's unreadable designation
            raise SpecError(f"nut_height='standard': {exc}") from None
    return parse_length(value, spec.pitch, name, spec.units)


def _parts_of_spec(spec: ThreadSpec, parts: SpecParts) -> ThreadSpec:
    """``spec`` with the parts given replaced. A length that is the spec's default (the
    point's height or the countersink's depth, and one pitch) stays the default: it
    follows new ends."""
    old_point, old_sink = spec.bolt.point, spec.nut.countersink
    form = parts.point or old_point.form
    wanted = parts.countersink
    if wanted is None:  # a countersink's angle or diameter asks for one
        wanted = old_sink is not None or (
            parts.countersink_angle is not None or parts.countersink_diameter is not None
        )
    parts.check_applies(form, wanted)
    keep = old_point if form == old_point.form else BoltPoint(form)
    point = BoltPoint(
        form,
        keep.angle if parts.chamfer_angle is None else parts.chamfer_angle,
        keep.diameter if parts.point_diameter is None else parts.point_diameter,
        keep.radius if parts.round_radius is None else parts.round_radius,
    )
    sink: Countersink | None = None
    if wanted:
        angle = parts.countersink_angle
        diameter = parts.countersink_diameter
        if old_sink is not None:
            angle = old_sink.angle if angle is None else angle
            diameter = old_sink.diameter if diameter is None else diameter
        if diameter is None:
            if spec.designation is None:
                raise InputError(
                    "countersink: the spec has no countersink and names no designation to "
                    "take the standard's from; give countersink_diameter"
                )
            try:
                diameter = standard_countersink_diameter(spec.designation, spec.nut.major)
            except InputError as exc:  # the spec's designation is unreadable
                raise InputError(f"countersink: {exc}") from None
        sink = Countersink(diameter=diameter) if angle is None else Countersink(angle, diameter)
    length = _length(parts.bolt_length, "bolt_length", spec)
    height = _length(parts.nut_height, "nut_height", spec)
    old_length, old_height = spec.bolt.length, spec.nut.height
    assert old_length is not None and old_height is not None  # filled in by the spec
    tol = 1e-9 * spec.pitch
    if length is None and abs(old_length - spec.point_height - spec.pitch) > tol:
        length = old_length  # its own length; the default follows the new point
    if height is None and abs(old_height - spec.countersink_depth - spec.pitch) > tol:
        height = old_height
    return replace(
        spec,
        bolt=replace(spec.bolt, point=point, length=length),
        nut=replace(spec.nut, countersink=sink, height=height),
    )
