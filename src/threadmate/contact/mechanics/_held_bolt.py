"""The held bolt in its scene: what every part of :class:`Mechanics` stands on.

:class:`Mechanics` is composed by concern, each layer standing on the ones before it:
this one (the thread pair, the compliance, the scene of exact bodies, meshes and
collision queries, the tolerances of the descent), lowering (:mod:`._lowering`), the
contact set (:mod:`._contact_set`), the potential and the forces (:mod:`._forces`),
where the bolt sits (:mod:`._seat`) and the descent (:mod:`._descent`). Here too is the
bolt's pose from its free coordinates: the compliance centre's position and the tilt
(docs/conventions.md).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..._errors import InputError
from ..._units import METRES_PER_UNIT
from ..._validate import check_open_range
from ...geometry import Pose, ThreadSpec, bolt_rotation
from ..scene import ContactScene, scene_for
from ._compliance import Compliance

__all__ = ["LOAD_CARRYING", "STALL_STEPS"]

#: Descent steps over which a continued descent (one leaving a rest state at a nearby
#: phase) that neither lowered the potential by more than the mesh's noise nor its least
#: equilibrium residual by 1 % has stalled. It stops there: at the thread starts, where
#: both bodies' run-outs meet edge to edge, such descents would run on to ``MAX_STEPS``
#: without moving. (Not while tipping into a seat, nor from first contact: an upright
#: point settling on the countersink's ring of edges can wander that long before it finds
#: its support.)
STALL_STEPS = 20
#: Force above which a contact carries the load (relative to the axial load): one below it
#: touches without load, or hovers at the touching threshold, and changes nothing a driver
#: or a sensor sees.
LOAD_CARRYING = 1e-4


class _HeldBolt:
    """The thread pair, compliance, scene and tolerances of a :class:`Mechanics`, and the
    bolt's pose from its free coordinates: the first layer of :class:`Mechanics`, whose
    constructor this is (its parameters are documented there)."""

    def __init__(
        self,
        spec: ThreadSpec,
        compliance: Compliance | None = None,
        *,
        chord: float | None = None,
        bolt_mesh: object = None,
        nut_mesh: object = None,
        mesh_units: str | None = None,
        tolerance: float | None = None,
        scene: ContactScene | None = None,
        max_faces: int | None = None,
    ) -> None:
        if compliance is None:
            compliance = Compliance()
        if not isinstance(compliance, Compliance):
            raise InputError(f"compliance must be a Compliance, got {type(compliance).__name__}")
        if not isinstance(spec, ThreadSpec):
            raise InputError(f"spec must be a ThreadSpec, got {type(spec).__name__}")
        compliance.check_for(spec.pitch)
        scene = scene_for(
            spec,
            scene,
            chord=chord,
            bolt_mesh=bolt_mesh,
            nut_mesh=nut_mesh,
            mesh_units=mesh_units,
            max_faces=max_faces,
        )
        self.spec = spec
        self.units = spec.units
        self.compliance = compliance
        #: The exact bodies, meshes, collision pair and tolerances (:class:`ContactScene`).
        self.scene = scene
        self.engine = scene.engine
        self.metres = METRES_PER_UNIT[spec.units]
        travel = scene.travel
        if tolerance is not None:
            travel = check_open_range(
                "tolerance", tolerance, 0.0, spec.pitch / 100, units=spec.units
            )
        self.tolerance = travel
        #: Depth below the touching pose within which contacts are known to the descent.
        self.near = spec.pitch / 5000
        #: Spacing of the yes/no queries with which a lowering looks for material it passed
        #: whole above its touch (:meth:`verified`).
        self.probe = spec.pitch / 256
        #: Gap below which a contact counts as touching (carries force at rest).
        self.touching = 20 * travel
        #: Margin of a stable state's support (see the module docstring).
        self.support_margin = spec.pitch / 100
        #: Descent steps without progress after which a descent has stalled (STALL_STEPS).
        self.stall_steps = STALL_STEPS
        self.separation = spec.pitch / 4
        self.radius = 0.5 * spec.bolt.major  # moment scale (spec units)
        self._floor = scene.nut.z_min - 2 * scene.bolt.z_max - spec.pitch
        # Vertices that can pass whole into the other body: the nut's in its top pitch,
        # the bolt's in its first (the thread's run-outs on the end faces are wedges),
        # counted from where the full thread begins.
        nv, bv = self.engine.nut_vertices, self.engine.bolt_vertices
        self._nut_top = nv[nv[:, 2] >= -spec.pitch - spec.countersink_depth]
        self._bolt_tip = bv[bv[:, 2] <= spec.pitch + spec.point_height]
        #: Where meshes from CAD do not follow the spec (None: generated meshes).
        self._off = scene.off_spec

    @property
    def tolerances(self) -> dict[str, float]:
        """Tolerances in force (spec units): the descent's travel, the feature tolerance
        of the exact contact geometry, the touching gap, the contacts' grouping distance
        and the meshes' deviation."""
        return {
            "travel": self.tolerance,
            "feature": self.scene.feature_tolerance,
            "touching": self.touching,
            "separation": self.separation,
            "mesh_deviation": self.scene.deviation,
        }

    @property
    def load_carrying(self) -> float:
        """Force (N) above which a contact carries the load: :data:`LOAD_CARRYING` times
        the axial load. The one threshold of the descent, the search and the sweep."""
        return LOAD_CARRYING * self.compliance.force

    # -- poses ----------------------------------------------------------------------------
    def _pose(self, rotation: NDArray[np.float64], xy: NDArray[np.float64], zc: float) -> Pose:
        """The bolt pose with its rotation and its compliance centre at ``(x, y, zc)``
        (the descent's coordinates are the centre's; a pose is the tip centre's)."""
        # (Per coordinate, as ``centre - rotation[:, 2] * compliance_z`` would be: asked
        # at every probe of a lowering, where numpy's per-call cost is most of it.)
        cz = self.compliance.compliance_z
        origin = [
            xy[0] - rotation[0, 2] * cz,
            xy[1] - rotation[1, 2] * cz,
            zc - rotation[2, 2] * cz,
        ]
        return Pose(rotation, np.array(origin, dtype=float))

    def _rotation(self, tilt: NDArray[np.float64], phase: float) -> NDArray[np.float64]:
        """The bolt's rotation at ``tilt`` (roll, pitch in radians) and ``phase`` (degrees)."""
        return bolt_rotation(math.degrees(tilt[0]), math.degrees(tilt[1]), phase)

    def _clear_of_top(self, rotation: NDArray[np.float64]) -> float:
        """Height of the compliance centre at which the bolt's lowest point lies on the
        nut's top face."""
        return -self.engine.lowest_bolt_z(rotation) + self.compliance.compliance_z * rotation[2, 2]
