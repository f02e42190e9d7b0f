"""Results of the contact stages: plain frozen objects, a JSON document, a flat record.

:meth:`ContactResult.to_record` produces exactly the columns of the contact record in
docs/architecture.md, with the types of :func:`record_schema`; missing values are NaN
(floats), 0 (ints) and "" (strings), so every chunk of a library has one Arrow schema.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import pyarrow as pa

from ...geometry import Pose
from ..scene import RegionPair, Vec, as_vec

if TYPE_CHECKING:
    pass

__all__ = ["Contact", "StageResult", "ContactResult", "record_schema", "STAGES"]

#: Stage names, in order.
STAGES = ("first", "second", "third")
#: Contact slots per stage in the flat record.
SLOTS = 3

_NAN = float("nan")


@dataclass(frozen=True)
class Contact(RegionPair):
    """One distinct contact between the bolt and the nut.

    Attributes
    ----------
    point : (x, y, z)
        Location in the fixed frame F (spec units).
    normal : (nx, ny, nz)
        Common normal in F: unit, from the nut into the bolt.
    pairs : int
        Bolt/nut triangle pairs that make up the contact.
    bolt_region, nut_region : str
        Regions of the exact profiles in contact (conventions.md names).
    bolt_feature, nut_feature : str
        ``rim``, ``cap``, ``corner`` or ``thread`` (see :mod:`threadmate.contact`).
    """

    point: Vec
    normal: Vec
    pairs: int
    bolt_region: str
    nut_region: str
    bolt_feature: str = ""
    nut_feature: str = ""


@dataclass(frozen=True)
class StageResult:
    """One contact stage.

    Attributes
    ----------
    name : {"first", "second", "third"}
    found : bool
        Whether the stage reached a contact (within its search range).
    angle : float
        Turn of the stage in degrees (first: 0; NaN when not found).
    origin : (x, y, z) or None
        Bolt origin in F at the stage's contact (None when not found).
    rotation : 3 x 3 nested tuple or None
        Bolt rotation matrix in F (``x_F = R x_B + origin``).
    contacts : tuple of Contact
        Every distinct contact at the stage, earlier ones first.
    axis_point, axis_direction : (x, y, z) or None
        The line the bolt turned about (second and third stages).
    queries : int
        Collision queries the stage spent.
    """

    name: str
    found: bool
    angle: float = _NAN
    origin: Vec | None = None
    rotation: tuple[Vec, Vec, Vec] | None = None
    contacts: tuple[Contact, ...] = ()
    axis_point: Vec | None = None
    axis_direction: Vec | None = None
    queries: int = 0

    @classmethod
    def at(
        cls,
        name: str,
        pose: Pose,
        contacts: tuple[Contact, ...],
        angle: float,
        queries: int,
        axis: tuple[Any, Any] | None = None,
    ) -> StageResult:
        """A found stage at ``pose``."""
        rot = (as_vec(pose.rotation[0]), as_vec(pose.rotation[1]), as_vec(pose.rotation[2]))
        return cls(
            name,
            True,
            float(angle),
            as_vec(pose.origin),
            rot,
            tuple(contacts),
            None if axis is None else as_vec(axis[0]),
            None if axis is None else as_vec(axis[1]),
            int(queries),
        )

    @property
    def pose(self) -> Pose | None:
        """The bolt pose at the stage (None when not found)."""
        if self.origin is None or self.rotation is None:
            return None
        return Pose(np.array(self.rotation, dtype=float), np.array(self.origin, dtype=float))

    @property
    def found_pose(self) -> Pose:
        """The bolt pose at a found stage's contact."""
        pose = self.pose
        assert pose is not None, f"the {self.name} stage found no contact"
        return pose

    @property
    def found_origin(self) -> Vec:
        """The bolt origin at a found stage's contact."""
        assert self.origin is not None, f"the {self.name} stage found no contact"
        return self.origin

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping for JSON (None where not found)."""
        return {
            "found": self.found,
            "angle": self.angle if self.found else None,
            "origin": None if self.origin is None else list(self.origin),
            "rotation": None if self.rotation is None else [list(r) for r in self.rotation],
            "contacts": [c.to_dict() for c in self.contacts],
            "axis": None
            if self.axis_point is None or self.axis_direction is None
            else {"point": list(self.axis_point), "direction": list(self.axis_direction)},
            "queries": self.queries,
        }


@dataclass(frozen=True)
class ContactResult:
    """The three contact stages of one configuration and their classification.

    Attributes
    ----------
    units : str
        Length units of every length here.
    roll, pitch, phase : float
        The configuration (degrees, conventions.md).
    classification : str
        One of :data:`CLASSIFICATIONS` (rules in :mod:`threadmate.contact`).
    first, second, third : StageResult
    interference : float
        Depth of interference at the third stage (NaN when not reached).
    origin_drop : float
        Drop of the bolt origin from the second to the third stage (positive down).
    pivot_offset : float
        Distance from the compliance centre to the pivot axis (NaN without two contacts).
    rolling : bool
        The thesis's rolling axis (4.2): a pivot contact (one of the second stage's two)
        has more triangle pairs at the third stage than at the second. False when the
        third stage did not turn.
    compliance_z : float
        Compliance centre on the bolt axis (bolt frame).
    queries : int
        Collision queries spent on the configuration.
    tolerances : dict
        ``travel`` (bisection), ``separation`` (distinct contacts), ``interference``
        and ``quasi`` (stability), in ``units``.
    """

    units: str
    roll: float
    pitch: float
    phase: float
    classification: str
    first: StageResult
    second: StageResult
    third: StageResult
    interference: float = _NAN
    origin_drop: float = _NAN
    pivot_offset: float = _NAN
    rolling: bool = False
    compliance_z: float = 0.0
    queries: int = 0
    tolerances: dict[str, float] = field(default_factory=dict)

    @property
    def stages(self) -> tuple[StageResult, StageResult, StageResult]:
        """The three stages in order."""
        return (self.first, self.second, self.third)

    @property
    def last_stage(self) -> StageResult | None:
        """The last stage that reached a contact (None if none did)."""
        found = [s for s in self.stages if s.found]
        return found[-1] if found else None

    @property
    def n_contacts(self) -> int:
        """Distinct contacts at the last stage reached."""
        last = self.last_stage
        return 0 if last is None else len(last.contacts)

    @property
    def region_combination(self) -> str:
        """``bolt/nut`` regions of each contact at the last stage, joined by `` + ``."""
        last = self.last_stage
        return "" if last is None else " + ".join(c.regions for c in last.contacts)

    @property
    def final_pose(self) -> Pose | None:
        """The bolt pose at the last stage reached."""
        last = self.last_stage
        return None if last is None else last.pose

    def to_dict(self) -> dict[str, Any]:
        """The JSON document of ``threadmate contact --json``."""
        final = self.final_pose
        return {
            "units": self.units,
            "roll": self.roll,
            "pitch": self.pitch,
            "phase": self.phase,
            "compliance_z": self.compliance_z,
            "classification": self.classification,
            "n_contacts": self.n_contacts,
            "region_combination": self.region_combination,
            "stages": {s.name: s.to_dict() for s in self.stages},
            "interference": self.interference,
            "origin_drop": self.origin_drop,
            "pivot_offset": self.pivot_offset,
            "rolling": bool(self.rolling),
            "final": None
            if final is None
            else {
                "origin": final.origin.tolist(),
                "angles": list(final.angles()),
            },
            "queries": self.queries,
            "tolerances": dict(self.tolerances),
        }

    def to_record(self) -> dict[str, Any]:
        """One flat row with exactly the columns of :func:`record_schema`."""
        final = self.final_pose
        angles = final.angles() if final is not None else (_NAN, _NAN, _NAN)
        rec: dict[str, Any] = {
            "roll": float(self.roll),
            "pitch": float(self.pitch),
            "phase": float(self.phase),
            "classification": self.classification,
            "n_contacts": int(self.n_contacts),
            "region_combination": self.region_combination,
            "interference": float(self.interference),
            "origin_drop": float(self.origin_drop),
            "pivot_offset": float(self.pivot_offset),
            "rolling": bool(self.rolling),
            "final_roll": float(angles[0]),
            "final_pitch": float(angles[1]),
            "final_phase": float(angles[2]),
            "final_origin_z": float(final.origin[2]) if final is not None else _NAN,
            "queries": int(self.queries),
        }
        for stage in self.stages:
            s = stage.name
            rec[f"{s}_found"] = bool(stage.found)
            rec[f"{s}_angle"] = float(stage.angle) if stage.found else _NAN
            origin = stage.origin if stage.origin is not None else (_NAN,) * 3
            for k, axis in enumerate("xyz"):
                rec[f"{s}_origin_{axis}"] = float(origin[k])
            rot = stage.rotation if stage.rotation is not None else ((_NAN,) * 3,) * 3
            for i in range(3):
                for j in range(3):
                    rec[f"{s}_r{i}{j}"] = float(rot[i][j])
            for i in range(1, SLOTS + 1):
                c = stage.contacts[i - 1] if i <= len(stage.contacts) else None
                p = c.point if c is not None else (_NAN,) * 3
                n = c.normal if c is not None else (_NAN,) * 3
                for k, axis in enumerate("xyz"):
                    rec[f"{s}_c{i}_{axis}"] = float(p[k])
                for k, axis in enumerate("xyz"):
                    rec[f"{s}_c{i}_n{axis}"] = float(n[k])
                rec[f"{s}_c{i}_pairs"] = int(c.pairs) if c is not None else 0
                rec[f"{s}_c{i}_bolt_region"] = c.bolt_region if c is not None else ""
                rec[f"{s}_c{i}_nut_region"] = c.nut_region if c is not None else ""
        return rec


def record_schema() -> pa.Schema:
    """The Arrow schema of :meth:`ContactResult.to_record` (fixed column order and types).

    Floats are float64, counts int64, flags bool, names string.
    """
    f64, i64, b, s = pa.float64(), pa.int64(), pa.bool_(), pa.string()
    fields: list[pa.Field] = [
        pa.field("roll", f64),
        pa.field("pitch", f64),
        pa.field("phase", f64),
        pa.field("classification", s),
        pa.field("n_contacts", i64),
        pa.field("region_combination", s),
        pa.field("interference", f64),
        pa.field("origin_drop", f64),
        pa.field("pivot_offset", f64),
        pa.field("rolling", b),
        pa.field("final_roll", f64),
        pa.field("final_pitch", f64),
        pa.field("final_phase", f64),
        pa.field("final_origin_z", f64),
        pa.field("queries", i64),
    ]
    for st in STAGES:
        fields.append(pa.field(f"{st}_found", b))
        fields.append(pa.field(f"{st}_angle", f64))
        fields += [pa.field(f"{st}_origin_{a}", f64) for a in "xyz"]
        fields += [pa.field(f"{st}_r{i}{j}", f64) for i in range(3) for j in range(3)]
        for i in range(1, SLOTS + 1):
            fields += [pa.field(f"{st}_c{i}_{a}", f64) for a in "xyz"]
            fields += [pa.field(f"{st}_c{i}_n{a}", f64) for a in "xyz"]
            fields.append(pa.field(f"{st}_c{i}_pairs", i64))
            fields.append(pa.field(f"{st}_c{i}_bolt_region", s))
            fields.append(pa.field(f"{st}_c{i}_nut_region", s))
    return pa.schema(fields)
