"""The compliance that holds the bolt: load, stiffness, friction (docs/mechanics.md).

The tool holds the compliance centre C laterally (or against a lateral stiffness), holds
the tilt ``(roll0, pitch0)`` through a rotational stiffness about C, spins the bolt to the
phase and presses it down with a constant axial force. One :class:`Compliance` carries
those parameters, validated once here, and every mechanics result stores it.

Defaults, and where they come from:

- ``force`` 10 N: "pressed lightly". A 1/4-20 (M6) screw is started by hand or by a
  nutrunner's float spring with a few newtons to a few tens; 10 N is also the axial load
  the network's costs used so far.
- ``stiffness`` 1 N m/rad about X and Y: the soft end of remote-centre compliances made
  for small parts. Whitney's rule for an RCC (Whitney 1982, "Quasi-static assembly of
  compliantly supported rigid parts") ties the rotational stiffness to the lateral one by
  ``k_r = k_t l^2`` with ``l`` the projection of the compliance centre; a small device
  with ``k_t`` of about 1.6 N/mm projecting its centre 25 mm gives 1 N m/rad. With it the
  load's moment on a 1/4-20 tip (10 N x 3 mm) tips the bolt by about 2 degrees: the
  compliance and the contacts both matter.
- ``lateral_stiffness`` None: the compliance centre is held at x = y = 0 (the RCC corrects
  the lateral error before the thread starts; mechanics.md's default).
- ``compliance_z`` 0: the centre at the bolt's tip, as in the thesis (spec units, bolt
  frame).
- ``friction`` 0.15: steel on steel in a thread, within the 0.08 to 0.20 range of thread
  friction coefficients used for bolted joints (VDI 2230).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any, cast

from ..._errors import InputError
from ..._validate import check_number

__all__ = ["Compliance", "COMPLIANCE_LIMITS"]

#: Allowed range of each parameter (inclusive), with its unit: beyond these the numbers are
#: not a bolt held by a compliance but a typing error.
COMPLIANCE_LIMITS: dict[str, tuple[float, float, str]] = {
    "force": (1e-6, 1e5, "N"),
    "stiffness": (0.0, 1e9, "N m/rad"),
    "lateral_stiffness": (1e-6, 1e12, "N/m"),
    "friction": (0.0, 2.0, ""),
}


def _in_range(name: str, value: Any, key: str | None = None) -> float:
    value = check_number(name, value)
    lo, hi, unit = COMPLIANCE_LIMITS[key or name]
    if not lo <= value <= hi:
        raise InputError(
            f"{name} {value:g} {unit} is out of range: give a value within "
            f"[{lo:g}, {hi:g}] {unit}".rstrip().replace("  ", " ")
        )
    return value


@dataclass(frozen=True)
class Compliance:
    """Load, stiffness and friction of the compliance holding the bolt.

    Parameters
    ----------
    force : float
        Axial force pressing the bolt down through the compliance centre (N, > 0).
    stiffness : float or (float, float)
        Rotational stiffness about X (roll) and Y (pitch) through the compliance centre
        (N m/rad, >= 0); one number for an isotropic compliance.
    lateral_stiffness : float or None
        Lateral stiffness of the compliance centre (N/m); None holds it at x = y = 0.
    compliance_z : float
        Compliance centre on the bolt axis (bolt frame, spec units; 0 is the tip centre).
    friction : float
        Coulomb friction coefficient of the thread contacts (enters the driver's torque).

    Raises
    ------
    InputError
        A value that is not a finite number within :data:`COMPLIANCE_LIMITS`.
    """

    force: float = 10.0
    stiffness: float | tuple[float, float] = 1.0
    lateral_stiffness: float | None = None
    compliance_z: float = 0.0
    friction: float = 0.15

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "force", _in_range("force", self.force))
        k = self.stiffness
        if isinstance(k, list | tuple):
            if len(k) != 2:
                raise InputError(f"stiffness must be one number or (roll, pitch), got {k!r}")
            pair = (
                _in_range("stiffness (roll)", k[0], "stiffness"),
                _in_range("stiffness (pitch)", k[1], "stiffness"),
            )
        else:
            value = _in_range("stiffness", k)
            pair = (value, value)
        set_(self, "stiffness", pair)
        if self.lateral_stiffness is not None:
            set_(self, "lateral_stiffness", _in_range("lateral_stiffness", self.lateral_stiffness))
        set_(self, "compliance_z", check_number("compliance_z", self.compliance_z))
        set_(self, "friction", _in_range("friction", self.friction))

    @property
    def roll_stiffness(self) -> float:
        """Rotational stiffness about X (N m/rad)."""
        return cast("tuple[float, float]", self.stiffness)[0]  # a pair once constructed

    @property
    def pitch_stiffness(self) -> float:
        """Rotational stiffness about the pitch axis (N m/rad)."""
        return cast("tuple[float, float]", self.stiffness)[1]

    @property
    def held_laterally(self) -> bool:
        """Whether the compliance centre is held at x = y = 0."""
        return self.lateral_stiffness is None

    def check_for(self, thread_pitch: float) -> None:
        """Refuse a compliance centre absurdly far from a thread of ``thread_pitch``
        (spec units): beyond 1000 pitches from the tip it is no longer the bolt's."""
        if abs(self.compliance_z) > 1000 * thread_pitch:
            raise InputError(
                f"compliance_z {self.compliance_z:g} is out of range: give a "
                f"height within +/-{1000 * thread_pitch:g} (1000 pitches) of the tip"
            )

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping with units, for JSON and library metadata."""
        d = asdict(self)
        d["stiffness"] = {"roll": self.roll_stiffness, "pitch": self.pitch_stiffness}
        d["units"] = {
            "force": "N",
            "stiffness": "N m/rad",
            "lateral_stiffness": "N/m",
            "compliance_z": "spec length unit",
            "friction": "1",
        }
        return d

    @classmethod
    def from_dict(cls, doc: dict[str, Any]) -> Compliance:
        """The compliance of a :meth:`to_dict` mapping (a result's or a library's)."""
        k = doc["stiffness"]
        return cls(
            force=doc["force"],
            stiffness=(k["roll"], k["pitch"]),
            lateral_stiffness=doc.get("lateral_stiffness"),
            compliance_z=doc["compliance_z"],
            friction=doc["friction"],
        )

    def describe(self, units: str) -> str:
        """One line with units, for reports: force, stiffness, lateral, centre, friction."""
        lateral = (
            "held laterally at x = y = 0"
            if self.lateral_stiffness is None
            else f"lateral stiffness {self.lateral_stiffness:g} N/m"
        )
        return (
            f"axial force {self.force:g} N, rotational stiffness {self.roll_stiffness:g}/"
            f"{self.pitch_stiffness:g} N m/rad (roll/pitch), {lateral}, compliance centre "
            f"z = {self.compliance_z:g} {units} (bolt frame), friction {self.friction:g}"
        )
