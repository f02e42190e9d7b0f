"""The record contract: the columns of a contact state, declared once.

Two kinds of row leave :mod:`threadmate.contact` for the library and the network:

- a **state record** of the mechanics (:data:`STATE_COLUMNS`): one contact state of the
  compliance-held bolt (a rest state, an unstable state passed on the way, either side of
  a jump) with the one passive transition that leaves it (settling, turning, jump or snap:
  the quasi-static dynamics are deterministic, so each state has at most one successor);
- a **thesis record** (:func:`thesis_schema`): one configuration through the thesis's
  fixed-pivot stages, :meth:`ContactResult.to_record` plus ``config_id`` and ``error``.

Everything that writes, reads or checks these rows (the sweep, the library readers, the
network, the GraphML writer, the tests, the benchmarks) takes the names, types, units and
classes from here. Lengths are in the spec's units, angles in degrees, forces in N, torques
in N m, potentials and work in mJ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pyarrow as pa

from .._angles import wrap_phase
from .mechanics import MechanicalState
from .scene import REST_CLASSES, TRANSITION_LABELS
from .thesis import record_schema

__all__ = [
    "Column",
    "ROLES",
    "STATE_COLUMNS",
    "TRANSITIONS",
    "blank_row",
    "state_id",
    "state_row",
    "state_schema",
    "thesis_schema",
]

#: What a state is on the way (the ``role`` column).
ROLES = (
    "first-contact",  # the fresh drop's first touch (unstable)
    "passed",  # a new contact or a rolling pivot on the way to rest (unstable)
    "start",  # the rest state a fresh drop at a grid phase reaches
    "continued",  # the continuation's rest state at a grid phase (not a start's)
    "before-jump",  # the last rest state before a fold
    "after-jump",  # where a jump lands (the in-phase state after the snap)
)
#: Kinds of passive transition (the ``transition`` column; "" for none).
TRANSITIONS = ("settling", "turning", "jump", "snap")


@dataclass(frozen=True)
class Column:
    """One column of a record: name, Arrow type, unit and meaning."""

    name: str
    type: pa.DataType
    unit: str
    meaning: str


_F, _I, _S, _B = pa.float64(), pa.int64(), pa.string(), pa.bool_()
_LF, _LS = pa.list_(pa.float64()), pa.list_(pa.string())

#: The columns of a state record, in order.
STATE_COLUMNS: tuple[Column, ...] = (
    Column(
        "config_id",
        _I,
        "",
        "grid configuration (held tilt, start phase) whose drop or "
        "continuation first reached the state",
    ),
    Column("state_id", _S, "", "unique id: held tilt, phase and a serial within the tilt"),
    Column("held_roll", _F, "deg", "roll the tool holds"),
    Column("held_pitch", _F, "deg", "pitch the tool holds"),
    Column("phase", _F, "deg", "phase the driver holds, in [0, 360)"),
    Column("role", _S, "", "what the state is on the way: " + ", ".join(ROLES)),
    Column("classification", _S, "", "class from the mechanics: " + ", ".join(REST_CLASSES)),
    Column("roll", _F, "deg", "actual roll of the bolt"),
    Column("pitch", _F, "deg", "actual pitch of the bolt"),
    Column("origin_x", _F, "length", "bolt origin (tip centre) in F"),
    Column("origin_y", _F, "length", "bolt origin in F"),
    Column("origin_z", _F, "length", "bolt origin in F"),
    Column("rotation", _LF, "", "bolt rotation matrix in F, 9 values row-major"),
    Column("centre_x", _F, "length", "compliance centre in F"),
    Column("centre_y", _F, "length", "compliance centre in F"),
    Column("centre_z", _F, "length", "compliance centre in F (its height over the nut)"),
    Column("potential", _F, "mJ", "F z_C + k/2 |tilt - held|^2 (+ k_t/2 |xy|^2)"),
    Column("driver_torque", _F, "N m", "torque to keep turning (NaN away from rest)"),
    Column("friction_torque", _F, "N m", "the part of driver_torque that is friction"),
    Column("n_contacts", _I, "", "touching contacts"),
    Column("region_combination", _S, "", "bolt/nut regions of the touching contacts"),
    Column("contact_regions", _LS, "", "bolt/nut regions, one per touching contact"),
    Column("contact_forces", _LF, "N", "normal force of each touching contact"),
    Column("contact_points", _LF, "length", "contact points in F, 3 values each"),
    Column("contact_normals", _LF, "", "unit normals (nut into bolt), 3 values each"),
    Column("next_id", _S, "", "state_id of the passive successor ('' for none)"),
    Column("transition", _S, "", "kind of the transition to it: " + ", ".join(TRANSITIONS)),
    Column("transition_label", _S, "", "its stability: " + ", ".join(TRANSITION_LABELS)),
    Column("transition_turn", _F, "deg", "phase turned along it"),
    Column("work_friction", _F, "mJ", "driver's work against friction along it"),
    Column("work_potential", _F, "mJ", "driver's work against the potential along it"),
    Column("torque_peak", _F, "N m", "largest driver torque along it (NaN: none)"),
    Column("drop", _F, "length", "fall of the compliance centre along it"),
    Column(
        "click",
        _F,
        "length",
        "at a jump or a snap: the fall a sensor sees, from the highest the bolt stands "
        "within the last degree of turn to the landing (NaN: neither)",
    ),
    Column("tilt_change", _F, "deg", "angle between the bolt axes at its ends"),
    Column(
        "snap_window",
        _F,
        "deg",
        "at a snap: how far before it the bolt may already drop into the thread (0: at the "
        "snap alone; NaN: not a snap)",
    ),
    Column(
        "engaged",
        _B,
        "",
        "an in-phase state proved by screwing in: turned clockwise it descends at the lead",
    ),
    Column("screw_descent", _F, "length", "descent per turn when screwed in from it (NaN: none)"),
    Column("screw_tilt", _F, "deg", "angle between bolt and nut axes at the screw-in's end"),
    Column("screw_note", _S, "", "why an in-phase state is not engaged ('' else)"),
    Column(
        "clockwise",
        _S,
        "",
        "a start turned clockwise directly: engaged, riding or jammed ('' not asked)",
    ),
    Column("clockwise_phase", _F, "deg", "where the clockwise start is decided (NaN: riding)"),
    Column("error", _S, "", "the message when the configuration failed, else ''"),
)


def state_schema(metadata: dict[bytes | str, bytes | str] | None = None) -> pa.Schema:
    """The Arrow schema of a state record (with ``metadata`` attached)."""
    return pa.schema([pa.field(c.name, c.type) for c in STATE_COLUMNS], metadata=metadata)


def thesis_schema(metadata: dict[bytes | str, bytes | str] | None = None) -> pa.Schema:
    """``config_id``, the thesis record (:func:`record_schema`), then ``error``."""
    fields = [pa.field("config_id", _I), *record_schema(), pa.field("error", _S)]
    return pa.schema(fields, metadata=metadata)


def blank_row(schema: pa.Schema) -> dict[str, Any]:
    """Missing values per the contract: NaN, 0, False, "" and empty lists."""
    out: dict[str, Any] = {}
    for f in schema:
        if pa.types.is_floating(f.type):
            out[f.name] = math.nan
        elif pa.types.is_integer(f.type):
            out[f.name] = 0
        elif pa.types.is_boolean(f.type):
            out[f.name] = False
        elif pa.types.is_list(f.type):
            out[f.name] = []
        else:
            out[f.name] = ""
    return out


def state_id(held_roll: float, held_pitch: float, phase: float, serial: int) -> str:
    """The id of a state: ``r+1_p-2_ph135.000_s7`` (held tilt, phase, serial in the tilt)."""
    return f"r{held_roll:+g}_p{held_pitch:+g}_ph{wrap_phase(phase):07.3f}_s{serial}"


def state_row(
    state: MechanicalState,
    *,
    config_id: int,
    state_id: str,
    held_roll: float,
    held_pitch: float,
    role: str,
) -> dict[str, Any]:
    """A state record for ``state`` without its transition (fill it with the successor's)."""
    touching = state.touching
    row = blank_row(state_schema())
    row.update(
        config_id=int(config_id),
        state_id=state_id,
        held_roll=float(held_roll),
        held_pitch=float(held_pitch),
        phase=float(wrap_phase(state.phase)),
        role=role,
        classification=state.classification,
        roll=float(state.roll),
        pitch=float(state.pitch),
        origin_x=float(state.origin[0]),
        origin_y=float(state.origin[1]),
        origin_z=float(state.origin[2]),
        rotation=[float(v) for v in np.asarray(state.rotation, dtype=float).ravel()],
        centre_x=float(state.centre[0]),
        centre_y=float(state.centre[1]),
        centre_z=float(state.centre[2]),
        potential=float(state.potential),
        driver_torque=float(state.driver_torque),
        friction_torque=float(state.friction_torque),
        n_contacts=len(touching),
        region_combination=state.region_combination,
        contact_regions=[c.regions for c in touching],
        contact_forces=[float(c.force) for c in touching],
        contact_points=[float(v) for c in touching for v in c.point],
        contact_normals=[float(v) for c in touching for v in c.normal],
    )
    proof = state.engagement
    if proof is not None:
        row.update(
            engaged=proof.engaged,
            screw_descent=float(proof.descent),
            screw_tilt=float(proof.tilt),
            screw_note=proof.reason,
        )
    return row
