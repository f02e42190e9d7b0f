"""Where the bolt sits: in phase on the helices, or seated upright on its end.

In phase (engaged, docs/mechanics.md): every contact that carries the load lies on the
helices (:func:`._contact_set.on_helix`: a bolt flank on the nut's thread or on the edge
where it meets the nut's entry, or the bolt's end on a nut flank), so that turning moves
the bolt along the helix (:meth:`_Seat.engaged`). Decided from what carries the bolt,
never from its tilt or where it is.

Seated: a bolt within :data:`SEAT_TILT` of upright that touches the nut's entry with its
end only is tipping into a seat (:meth:`_Seat._seating`). A face landing on a face, or a
point centring in a countersink, is where the descent's linearised contacts serve worst;
the seated pose is known but for its height, so the descent tries it once, as a step
(:meth:`_Seat._seat`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ._contact_set import _ContactSet, _Near
from ._forces import _Forces
from ._lowering import _Drop

__all__ = ["SEAT_BOLT_REGIONS", "SEAT_NUT_REGIONS", "SEAT_TILT"]

#: Tilt (degrees) within which a bolt touching the nut's entry with its end only is tried
#: seated upright (:meth:`Mechanics._seat`), and the regions of such contacts.
SEAT_TILT = 3.0
# (``point``: a CAD bolt's end where it does not follow the spec, _exact.off_spec_region.)
SEAT_BOLT_REGIONS = frozenset({"base", "chamfer", "round", "point"})
SEAT_NUT_REGIONS = frozenset({"surface", "countersink"})


class _Seat(_ContactSet, _Forces):
    """Where the bolt sits (module docstring): a layer of :class:`Mechanics`, on the
    contact set and the forces."""

    def engaged(self, near: list[_Near], forces: NDArray[np.float64] | None = None) -> bool:
        """Whether the bolt's thread is in the nut's (in phase, mechanics.md): every
        contact that carries the load lies on a helix (:func:`._contact_set.on_helix`),
        so that turning moves the bolt along the helix.

        With ``forces`` (a rest state's), the contacts carrying more than
        :data:`._held_bolt.LOAD_CARRYING` times the load; without (a pose on the way),
        the touching ones. Nothing here depends on the tilt or on where the bolt is: only
        on what carries it.
        """
        if forces is None:
            carrying = [c for c in near if c.gap <= self.touching]
        else:
            floor = self.load_carrying
            carrying = [c for c, f in zip(near, forces, strict=True) if f > floor]
        return bool(carrying) and all(c.helical for c in carrying)

    def _seating(self, near: list[_Near], tilt: NDArray[np.float64]) -> bool:
        """Whether the bolt is tipping into a seat: within ``SEAT_TILT`` of upright, it
        touches the nut's entry (top face, countersink) with its end only (tip face,
        point), and no thread touches."""
        touching = [c for c in near if c.gap <= self.touching]
        return (
            bool(touching)
            and all(
                c.bolt_region in SEAT_BOLT_REGIONS and c.nut_region in SEAT_NUT_REGIONS
                for c in touching
            )
            and float(np.hypot(*tilt)) <= math.radians(SEAT_TILT)
        )

    def _seat(
        self,
        d: _Drop,
        tilt: NDArray[np.float64],
        phase: float,
        held: NDArray[np.float64],
        u_most: float,
    ) -> tuple[_Drop, list[_Near], NDArray[np.float64], float] | None:
        """The bolt seated upright in the nut's entry (the tip face flat on the top face,
        the point in the countersink), if it lies below the potential ``u_most``, lowered
        onto the nut there and touching end on entry only.

        A face landing on a face, or a point centring in a countersink, is where the
        descent's linearised contacts serve worst (the support jumps from a rim point to a
        patch, or runs round a ring); the seated pose is known but for its height, so it
        is tried once, as a step. The descent goes on from it: it is a rest state when its
        contacts balance the load and the spring (the KKT conditions), and the descent
        leaves it (a touch off upright, where coplanar meshes miss pairs) when not.
        """
        upright = np.zeros(2)
        rotation = self._rotation(upright, phase)
        # Turning upright moves no bolt point farther than this: the seat's height is
        # within it of the present one.
        reach = float(np.hypot(*tilt)) * (self.radius + self.scene.bolt.z_max)
        # The seat lies below ``u_most`` only if it lies below this height. Where the bolt
        # collides there, the seat (the first touch from above, so no lower) does not:
        # one yes/no query, cheap where it collides, spares the lowering (a face landing
        # on a face meets a thousand triangle pairs). Most seats tried fail so.
        highest = (u_most - self.potential(0.0, upright, d.xy, held)) / (
            self.compliance.force * self.metres
        )
        if highest <= d.zc + reach - self.near and self.engine.collides(
            self._pose(rotation, d.xy, highest)
        ):
            return None
        seat = self.drop(rotation, d.xy, d.zc, span=reach + 4 * self.tolerance)
        if seat is None:
            return None
        u = self.potential(seat.zc, upright, seat.xy, held)
        if u >= u_most:
            return None
        near = self.contacts(seat)
        if not self._seating(near, upright):
            return None
        return seat, near, upright, u
