"""Spatial contact analysis (thesis chapter 3 and section 4.2) on python-fcl.

For a thread pair and an orientation (roll, pitch, phase; degrees, conventions.md) the bolt

1. comes down along -Z of the fixed frame until it first touches the nut (*first*);
2. turns about the nut's tangent at that contact, in the sense that lowers the compliance
   centre, until a second distinct contact appears (*second*);
3. turns about the pivot axis through the two contacts, in the sense that lowers the
   compliance centre, until a third distinct contact appears (*third*).

Each event is found by bisection on yes/no collision queries to 1e-7 in (2.54e-6 mm) of
bolt travel (:mod:`._stages`). A contact's location comes from the intersection segments
of its triangle pairs; distinct contacts are single-linkage clusters of segment end points
a quarter pitch apart (:mod:`._triangles`). Regions, normals and the second stage's axis
come from the exact bodies (:mod:`._exact`); the stability rules are in
:mod:`._stability`. Lengths are in the spec's units, angles in degrees.

Classification (:mod:`._stability`), in this order: ``no-contact`` (the first or second
stage finds nothing within its range: the bolt misses the nut, or no second contact within
30 degrees); ``in-phase`` (at the first contact the whole tip face is below the nut's top
face: the bolt dropped into the nut, the snap; later stages are not run); ``quasi-stable`` (the
pivot axis through the two contacts passes within ``quasi_tolerance``, default pitch/10,
of the compliance centre); ``no-contact`` (no third contact within 30 degrees);
``stable`` (three contacts with an interference, measured on the exact bodies, within
``interference_tolerance``, default four mesh-deviation bounds); ``unstable`` (the third
contact needed the bolt to embed beyond that; the thesis's case is an embedding deeper
than the drop of the origin, and the record keeps both numbers).

Second-stage axis: the nut's edge tangent where the nut touches with an edge, else the
bolt edge's tangent projected on the nut's face (the one tangent of the face the bolt can
turn about without cutting into it), else the circumferential (top face) or helix (thread)
direction; an upright tip face resting flat over an area is resolved by the area's convex
hull (three contacts around the compliance centre, or a tip over the hull edge facing it).

Example
-------
>>> from threadmate.contact import ContactAnalyzer
>>> analyzer = ContactAnalyzer(spec)                                   # doctest: +SKIP
>>> result = analyzer.analyze(roll=4, pitch=0, phase=185)              # doctest: +SKIP
>>> result.classification, result.to_record()["third_c1_x"]           # doctest: +SKIP
"""

from ._analyzer import MAX_TILT, TRAVEL_TOLERANCE, ContactAnalyzer, analyze
from ._result import CLASSIFICATIONS, STAGES, Contact, ContactResult, StageResult, record_schema

__all__ = [
    "CLASSIFICATIONS",
    "MAX_TILT",
    "STAGES",
    "TRAVEL_TOLERANCE",
    "Contact",
    "ContactAnalyzer",
    "ContactResult",
    "StageResult",
    "analyze",
    "record_schema",
]
