"""The ends that meet: the bolt's point and the nut's countersink (conventions.md, "Ends").

The thesis's bodies end in flat faces: a flat tip on the bolt, a flat, sharp-edged bore
on the nut. Real fasteners have a *point* (a chamfer or a rounded end) and a
*countersink*. Both are surfaces of revolution about the body's axis, so each is one
curve ``r = envelope(z)`` in the meridian plane that trims the helical thread:

- the bolt is material where ``r <= min(R_b(t), envelope(z))``;
- the nut is material where ``max(R_n(t), envelope(z)) <= r <= outer_radius``.

Forms (angles in degrees, lengths in the spec's units):

- ``BoltPoint("flat")``: no envelope (the thesis's bolt).
- ``BoltPoint("chamfer", angle, diameter)``: a cone at ``angle`` from the axis, from the
  tip face's circle of ``diameter`` up to the major diameter. Defaults: 45 degrees and a
  diameter 0.1 pitch below the bolt's minor diameter. ASME B18.2.1 (hex bolts and cap
  screws) and ISO 4753 (ends of parts with external ISO metric thread, end "CH") make the
  point a chamfer of about 45 degrees down to a diameter at or slightly below the
  thread's minor diameter; the 0.1 pitch is our choice of "slightly".
- ``BoltPoint("round", radius=..., diameter=...)``: a sphere of ``radius`` centred on the
  axis, through the tip face's circle of ``diameter``. Default radius 1.4 x the major
  diameter, ISO 4753's rounded end "RN" (``r_e ~ 1.4 d``); the same default diameter.
- ``Countersink(angle, diameter)``: a cone of included ``angle`` (90 to 120 degrees in
  ASME B18.2.2 and ISO 4032 nuts) from the entry face's circle of ``diameter`` down into
  the bore. Defaults: 120 degrees and, for Unified nuts, the mean of ASME B18.2.2's
  limits (the basic major diameter, and that plus 0.030 in up to 3/8 in, 1.08 times it
  above); for ISO nuts the mean of ISO 4032's ``d_a`` limits (``d`` and ``d_a max``).

A point's tip circle lies inside the bolt's minor diameter and a countersink's face
circle outside the nut's major diameter, so the end faces stay full discs and annuli
whose edges are circles.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._errors import SpecError

__all__ = [
    "POINT_FORMS",
    "BoltPoint",
    "Countersink",
    "Envelope",
    "point_envelope",
    "countersink_envelope",
]

#: Forms of the bolt's point.
POINT_FORMS = ("flat", "chamfer", "round")
#: Default chamfer angle from the axis, degrees (ASME B18.2.1, ISO 4753 "CH").
CHAMFER_ANGLE = 45.0
#: Default rounded-end radius, in major diameters (ISO 4753 "RN": r_e ~ 1.4 d).
ROUND_RADIUS = 1.4
#: Default tip diameter below the bolt's minor diameter, in pitches.
TIP_BELOW_MINOR = 0.1
#: Default countersink included angle, degrees (ASME B18.2.2 and ISO 4032: 90 to 120).
COUNTERSINK_ANGLE = 120.0


@dataclass(frozen=True)
class BoltPoint:
    """The bolt's point: ``flat``, ``chamfer`` or ``round`` (see the module docstring).

    Attributes
    ----------
    form : {"flat", "chamfer", "round"}
    angle : float or None
        Chamfer angle from the axis, degrees (chamfer only; default 45).
    diameter : float or None
        Diameter of the tip face where the chamfer or round meets it, spec units
        (default 0.1 pitch below the bolt's minor diameter).
    radius : float or None
        Radius of a round point's sphere, spec units (round only; default 1.4 x major).
    """

    form: str = "flat"
    angle: float | None = None
    diameter: float | None = None
    radius: float | None = None

    def to_dict(self) -> dict[str, Any]:
        """The point as a spec table (only the keys its form uses)."""
        out: dict[str, Any] = {"form": self.form}
        for key in ("angle", "diameter", "radius"):
            value = getattr(self, key)
            if value is not None:
                out[key] = value
        return out

    def describe(self, units: str) -> str:
        """The point in words, e.g. ``chamfer 45 deg from the axis to a 4.635 mm tip``."""
        if self.form == "chamfer":
            return f"chamfer {self.angle:g} deg from the axis to a {self.diameter:.6g} {units} tip"
        if self.form == "round":
            return f"round, radius {self.radius:.6g} {units}, to a {self.diameter:.6g} {units} tip"
        return self.form


@dataclass(frozen=True)
class Countersink:
    """A countersink on the nut's entry face (see the module docstring).

    Attributes
    ----------
    angle : float
        Included angle, degrees (default 120).
    diameter : float or None
        Diameter at the entry face, spec units (default from the nut standards for a
        designation; required in a spec).
    """

    angle: float = COUNTERSINK_ANGLE
    diameter: float | None = None

    def to_dict(self) -> dict[str, Any]:
        """The countersink as a spec table."""
        return {"angle": self.angle, "diameter": self.diameter}

    def describe(self, units: str) -> str:
        """The countersink in words, e.g. ``120 deg, 6.375 mm at the face``."""
        return f"{self.angle:g} deg, {self.diameter:.6g} {units} at the face"


@dataclass(frozen=True)
class Envelope:
    """The meridian curve ``r = radius(z)`` of a point or countersink, in the body frame.

    ``kind`` ``"cone"``: ``r = r0 + slope_rz * z``; ``"sphere"``: ``r^2 + (z - z0)^2 =
    rho^2`` (its lower half). ``side`` is +1 for the bolt (material inside, ``r <=
    radius``) and -1 for the nut (material outside). ``z_lo <= z <= z_hi`` is where it
    can trim the thread (beyond, it lies outside the thread's radial band).
    """

    region: str
    kind: str
    side: int
    r0: float
    slope_rz: float = 0.0
    z0: float = 0.0
    rho: float = 0.0
    z_lo: float = 0.0
    z_hi: float = 0.0

    @overload
    def radius(self, z: float) -> np.float64: ...
    @overload
    def radius(self, z: ArrayLike) -> NDArray[np.float64]: ...

    def radius(self, z: ArrayLike) -> NDArray[np.float64] | np.float64:
        """Envelope radius at heights ``z``; +inf (bolt) or -inf (nut) outside its span."""
        if isinstance(z, float):  # the contact code's root finding asks one height at a time
            return np.float64(self._radius_at(z))
        z = np.asarray(z, dtype=float)
        if self.kind == "cone":
            r = self.r0 + self.slope_rz * z
        else:
            r = np.sqrt(np.maximum(self.rho * self.rho - (z - self.z0) ** 2, 0.0))
        far = np.inf * self.side
        return np.where((z >= self.z_lo) & (z <= self.z_hi), r, far)

    def _radius_at(self, z: float) -> float:
        """:meth:`radius` at one height (the same formulas in plain floats)."""
        if not self.z_lo <= z <= self.z_hi:
            return math.inf * self.side
        if self.kind == "cone":
            return self.r0 + self.slope_rz * z
        return math.sqrt(max(self.rho * self.rho - (z - self.z0) ** 2, 0.0))

    def slope(self, z: ArrayLike) -> NDArray[np.float64]:
        """``d radius / dz`` at heights ``z`` (inside its span)."""
        z = np.asarray(z, dtype=float)
        if self.kind == "cone":
            return np.full_like(z, self.slope_rz)
        r = np.sqrt(np.maximum(self.rho * self.rho - (z - self.z0) ** 2, 1e-300))
        return (self.z0 - z) / r

    def signed_distance(self, r: ArrayLike, z: ArrayLike) -> NDArray[np.float64]:
        """Distance in the meridian plane to the envelope surface, positive on the air
        side (exact: the surface is one of revolution)."""
        if isinstance(r, float) and isinstance(z, float):  # (as :meth:`radius`)
            if self.kind == "cone":
                at = (r - self.r0 - self.slope_rz * z) / math.hypot(1.0, self.slope_rz)
            else:
                at = float(np.hypot(r, z - self.z0)) - self.rho
            return np.float64(self.side * at)
        r = np.asarray(r, dtype=float)
        z = np.asarray(z, dtype=float)
        if self.kind == "cone":
            d = (r - self.r0 - self.slope_rz * z) / math.hypot(1.0, self.slope_rz)
        else:
            d = np.hypot(r, z - self.z0) - self.rho
        return self.side * d

    def normal(self, r: float, z: float) -> tuple[float, float]:
        """Outward unit normal of the body's material on the envelope, ``(n_r, n_z)``."""
        if self.kind == "cone":
            k = math.hypot(1.0, self.slope_rz)
            return self.side / k, -self.side * self.slope_rz / k
        h = math.hypot(r, z - self.z0) or 1.0
        return self.side * r / h, self.side * (z - self.z0) / h

    @cached_property
    def face_radius(self) -> float:
        """Radius of the envelope's circle on the end face at ``z = 0``."""
        return float(self.radius(0.0))

    @property
    def depth(self) -> float:
        """Axial extent of the envelope from the end face (its height or depth)."""
        return self.z_hi - self.z_lo


def point_envelope(point: BoltPoint, r_major: float, r_minor: float) -> Envelope | None:
    """The envelope of a filled-in bolt point (None for a flat one)."""
    if point.form == "flat":
        return None
    assert point.diameter is not None
    a = point.diameter / 2.0
    if point.form == "chamfer":
        assert point.angle is not None
        k = math.tan(math.radians(point.angle))
        return Envelope("chamfer", "cone", +1, a, slope_rz=k, z_lo=0.0, z_hi=(r_major - a) / k)
    assert point.radius is not None
    rho = point.radius
    z0 = math.sqrt(rho * rho - a * a)
    z_hi = z0 - math.sqrt(rho * rho - r_major * r_major)
    return Envelope("round", "sphere", +1, a, z0=z0, rho=rho, z_lo=0.0, z_hi=z_hi)


def countersink_envelope(sink: Countersink, r_minor: float) -> Envelope:
    """The envelope of a filled-in countersink: a cone narrowing into the bore from the
    entry face down to the nut's minor diameter."""
    assert sink.diameter is not None
    b = sink.diameter / 2.0
    k = math.tan(math.radians(sink.angle / 2.0))
    return Envelope("countersink", "cone", -1, b, slope_rz=k, z_lo=-(b - r_minor) / k, z_hi=0.0)


# -- spec tables -------------------------------------------------------------------------


def fill_point(point: BoltPoint, pitch: float, major: float, minor: float) -> BoltPoint:
    """``point`` with its defaults filled in and checked against the bolt's diameters."""
    if point.form not in POINT_FORMS:
        raise SpecError(
            f"spec key 'bolt.point.form' must be one of {', '.join(POINT_FORMS)}; "
            f"got {point.form!r}"
        )
    if point.form == "flat":
        for key in ("angle", "diameter", "radius"):
            if getattr(point, key) is not None:
                raise SpecError(f"spec key 'bolt.point.{key}' does not apply to a flat point")
        return point
    diameter = point.diameter if point.diameter is not None else minor - TIP_BELOW_MINOR * pitch
    if not 0 < diameter < minor:
        raise SpecError(
            f"spec key 'bolt.point.diameter' ({diameter:g}) must lie between 0 and the bolt's "
            f"minor diameter ({minor:g}): the tip face is a disc inside the thread"
        )
    if point.form == "chamfer":
        if point.radius is not None:
            raise SpecError("spec key 'bolt.point.radius' applies to a round point only")
        angle = point.angle if point.angle is not None else CHAMFER_ANGLE
        if not 10.0 <= angle <= 80.0:
            raise SpecError(
                f"spec key 'bolt.point.angle' ({angle:g} deg from the axis) must lie within "
                f"10 to 80 degrees"
            )
        return BoltPoint("chamfer", angle=float(angle), diameter=float(diameter))
    if point.angle is not None:
        raise SpecError("spec key 'bolt.point.angle' applies to a chamfered point only")
    radius = point.radius if point.radius is not None else ROUND_RADIUS * major
    if not radius > major / 2.0:
        raise SpecError(
            f"spec key 'bolt.point.radius' ({radius:g}) must exceed half the bolt's major "
            f"diameter ({major / 2:g}): the round must reach the thread's crest"
        )
    return BoltPoint("round", diameter=float(diameter), radius=float(radius))


def check_countersink(sink: Countersink, major: float, outer_radius: float) -> Countersink:
    """``sink`` checked against the nut's diameters."""
    if sink.diameter is None:
        raise SpecError("spec key 'nut.countersink.diameter' is missing")
    if not 60.0 <= sink.angle <= 150.0:
        raise SpecError(
            f"spec key 'nut.countersink.angle' ({sink.angle:g} deg included) must lie "
            f"within 60 to 150 degrees (nuts use 90 to 120)"
        )
    if not major < sink.diameter < 2.0 * outer_radius:
        raise SpecError(
            f"spec key 'nut.countersink.diameter' ({sink.diameter:g}) must lie between the "
            f"nut's major diameter ({major:g}) and its outer diameter ({2 * outer_radius:g})"
        )
    return Countersink(float(sink.angle), float(sink.diameter))
