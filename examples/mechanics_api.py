"""The mechanics from Python: a rest state of the compliance-held bolt, and the search.

Run:  python examples/mechanics_api.py

The same as ``threadmate settle`` and ``threadmate search`` (docs/mechanics.md). A
:class:`Mechanics` builds the meshes once for a thread pair and a compliance; ``settle``
and ``search`` accept it (or a spec, with a cached Mechanics behind it). Writes nothing.
"""

from __future__ import annotations

import math

from threadmate.contact import Compliance, Mechanics, screw, search, settle
from threadmate.geometry import spec_from_designation

# The thesis's flat parts, whose example state (4, 0, 185) this follows; drop the two
# keywords for the standard chamfered point and countersunk nut.
spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
# 10 N down, 1 N m/rad about X and Y through the centre at the bolt's tip, friction 0.15.
compliance = Compliance(force=10.0, stiffness=1.0, friction=0.15)
mech = Mechanics(spec, compliance)

# One rest state: the bolt held at roll 4 deg, turned to phase 185 deg.
rest = settle(mech, 4, 0, 185)
s = rest.state
tilt = math.degrees(math.acos(math.cos(math.radians(s.roll)) * math.cos(math.radians(s.pitch))))
print(
    f"settle (4, 0, 185): {rest.classification}; rests at roll {s.roll:.3f}, pitch "
    f"{s.pitch:.3f} deg (axis {tilt:.3f} deg from vertical, held 4 deg)"
)
for c in s.touching:
    print(
        f"  {c.regions:16s} force {c.force:7.3f} N at "
        f"({c.point[0]:+.4f}, {c.point[1]:+.4f}, {c.point[2]:+.4f}) {spec.units}"
    )
print(
    f"  driver torque {s.driver_torque * 1e3:.3f} N mm, potential {s.potential:.3f} mJ, "
    f"{len(rest.path)} unstable state(s) on the way"
)

# The counter-clockwise search from phase 300. Held 4 degrees off, the bolt reaches the
# thread, but screwed in from there it cross-threads (jams): that landing is no snap.
run = search(mech, 4, 0, 300, turns=1)
if run.snap is None:
    print(f"search: no snap within {run.turns:g} turn")
    for e in run.events:
        if e.note:
            print(f"  at phase {e.phase:.2f} deg, {e.note}")
else:
    print(
        f"search from (4, 0, 300): snap at phase {run.snap.phase:.2f} deg after "
        f"{run.snap_turn:.2f} deg, click {run.snap.click:.5f} {spec.units}"
    )
print(
    f"  work {run.work:.3f} mJ (friction {run.work_friction:.3f}, potential "
    f"{run.work_potential:.3f}); events: {', '.join(e.kind for e in run.events) or 'none'}"
)

# Turned clockwise directly from the same start: engaged, riding or jammed.
turned = screw(mech, 4, 0, 300)
print(f"screw from (4, 0, 300): {turned.outcome} ({turned.reason})")
