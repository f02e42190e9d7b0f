"""The spatial contact engine from Python: what a design tool would call.

Run:  python examples/contact_api.py

One analyser per thread pair builds the meshes and collision trees once; each call to
``analyze`` then runs the three contact stages for one orientation in milliseconds.
"""

from __future__ import annotations

from threadmate.contact import ContactAnalyzer, record_schema
from threadmate.geometry import spec_from_designation

# 1/4-20 UNC-2A/2B at mean material: the midpoint of every ASME B1.1 limit, with the
# thesis's flat tip and flat, sharp-edged bore (a designation's default is the standard
# chamfered point and countersunk nut; docs/conventions.md, "Ends"). A pair that is
# no standard size (or measured parts) is typed in instead as
# ThreadSpec(units=..., pitch=..., bolt=BoltSpec(...), nut=NutSpec(...)); see
# docs/conventions.md, "Thread spec file".
spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
print(
    f"{spec.designation} at mean material ({spec.units}): bolt major/PD/minor "
    f"{spec.bolt.major:.5f}/{spec.bolt.pitch_diameter:.5f}/{spec.bolt.minor:.5f}, "
    f"nut {spec.nut.major:.5f}/{spec.nut.pitch_diameter:.5f}/{spec.nut.minor:.5f}"
)

analyzer = ContactAnalyzer(spec)  # compliance centre at the bolt's tip centre

for roll, pitch, phase in [(4, 0, 185), (4, 4, 235), (-4, 0, 131), (0, 0, 0)]:
    result = analyzer.analyze(roll, pitch, phase)
    print(
        f"roll {roll:+g} pitch {pitch:+g} phase {phase:g}: {result.classification}, "
        f"{result.n_contacts} contact(s): {result.region_combination}"
    )
    for stage in result.stages:
        if not stage.found:
            continue
        print(
            f"  {stage.name:6s} turn {stage.angle:7.3f} deg, bolt origin z "
            f"{stage.origin[2]:+.6f} {result.units}"
        )
        for c in stage.contacts:
            x, y, z = c.point
            nx, ny, nz = c.normal
            print(
                f"      ({x:+.5f}, {y:+.5f}, {z:+.5f})  {c.regions:14s} "
                f"normal ({nx:+.3f}, {ny:+.3f}, {nz:+.3f})  {c.pairs} pairs"
            )
    if result.third.found:
        print(
            f"  interference {result.interference:.2e}, origin drop "
            f"{result.origin_drop:.2e}, pivot offset {result.pivot_offset:.4f}"
        )

# One flat row per configuration, the columns a contact-state library stores.
row = result.to_record()
print(f"record: {len(row)} columns, schema of {len(record_schema())} fields")
