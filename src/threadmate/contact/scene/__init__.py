"""The contact scene and its queries: the world both contact models see.

:class:`ContactScene` holds one thread pair's exact bodies, its meshes (generated or from
CAD, with their fit to the spec), the python-fcl collision pair on them and the tolerances
that follow; :func:`contact_scene` builds it once per process. Around it, the queries both
models ask: collisions and triangle pairs (:mod:`._collision`, :mod:`._triangles`), the
vertical touch of a lowering (:mod:`._vertical`), and the exact contact geometry on the
exact bodies -- features, regions, normals, edge contact points (:mod:`._exact`), where a
CAD mesh leaves the spec (:mod:`._cad`) -- with the record types both share
(:mod:`._regions`) and the names of the contact states' classes (:mod:`._classes`).
"""

from typing import TYPE_CHECKING

from ..._lazy import lazy_exports

if TYPE_CHECKING:  # the names for type checkers; at run time __getattr__ imports them
    from ._cad import (
        COARSEST,
        FOLLOW_FACTOR,
        OFF_SPEC_WARNING,
        MeshFit,
        contact_zone,
        describe,
        face_deviation,
        file_units,
        mesh_fit,
        off_spec,
        sha256_of,
    )
    from ._classes import (
        CLASSIFICATIONS,
        ERROR_CLASS,
        IN_PHASE,
        NO_CONTACT,
        QUASI_STABLE,
        REST_CLASSES,
        STABLE,
        TRANSITION_LABELS,
        UNSTABLE,
    )
    from ._collision import (
        CollisionPair,
        MeshSolid,
        pair_keys,
    )
    from ._exact import (
        CREASE,
        OFF_SPEC_REGIONS,
        Feature,
        OffSpec,
        contact_normal,
        edge_crossing,
        engagement_outline,
        feature_at,
        lowest_on_rim,
        off_spec_region,
        on_thread,
        refine_on_edge,
        refined_contact,
        region_at,
        turn_axis_tangent,
    )
    from ._regions import (
        RegionPair,
        Vec,
        as_vec,
    )
    from ._scene import (
        OFF_SPEC_FACTOR,
        TRAVEL_TOLERANCE,
        ContactScene,
        check_mesh_file,
        contact_scene,
    )
    from ._triangles import (
        IntersectionSegments,
        cluster_location,
        cluster_segments,
        intersection_segments,
        touch_points,
    )
    from ._vertical import (
        vertical_rise,
        vertical_touch,
    )

__all__ = [
    "COARSEST",
    "contact_zone",
    "describe",
    "face_deviation",
    "file_units",
    "FOLLOW_FACTOR",
    "mesh_fit",
    "MeshFit",
    "off_spec",
    "OFF_SPEC_WARNING",
    "sha256_of",
    "CLASSIFICATIONS",
    "ERROR_CLASS",
    "IN_PHASE",
    "NO_CONTACT",
    "QUASI_STABLE",
    "REST_CLASSES",
    "STABLE",
    "TRANSITION_LABELS",
    "UNSTABLE",
    "CollisionPair",
    "MeshSolid",
    "pair_keys",
    "contact_normal",
    "CREASE",
    "edge_crossing",
    "engagement_outline",
    "Feature",
    "feature_at",
    "lowest_on_rim",
    "off_spec_region",
    "OFF_SPEC_REGIONS",
    "OffSpec",
    "on_thread",
    "refine_on_edge",
    "refined_contact",
    "region_at",
    "turn_axis_tangent",
    "as_vec",
    "RegionPair",
    "Vec",
    "check_mesh_file",
    "contact_scene",
    "ContactScene",
    "OFF_SPEC_FACTOR",
    "TRAVEL_TOLERANCE",
    "cluster_location",
    "cluster_segments",
    "intersection_segments",
    "IntersectionSegments",
    "touch_points",
    "vertical_rise",
    "vertical_touch",
]

#: The submodule of each public name, imported when the name is first used (PEP 562).
_SOURCES = {
    "._cad": (
        "COARSEST",
        "contact_zone",
        "describe",
        "face_deviation",
        "file_units",
        "FOLLOW_FACTOR",
        "mesh_fit",
        "MeshFit",
        "off_spec",
        "OFF_SPEC_WARNING",
        "sha256_of",
    ),
    "._classes": (
        "CLASSIFICATIONS",
        "ERROR_CLASS",
        "IN_PHASE",
        "NO_CONTACT",
        "QUASI_STABLE",
        "REST_CLASSES",
        "STABLE",
        "TRANSITION_LABELS",
        "UNSTABLE",
    ),
    "._collision": (
        "CollisionPair",
        "MeshSolid",
        "pair_keys",
    ),
    "._exact": (
        "contact_normal",
        "CREASE",
        "edge_crossing",
        "engagement_outline",
        "Feature",
        "feature_at",
        "lowest_on_rim",
        "off_spec_region",
        "OFF_SPEC_REGIONS",
        "OffSpec",
        "on_thread",
        "refine_on_edge",
        "refined_contact",
        "region_at",
        "turn_axis_tangent",
    ),
    "._regions": (
        "as_vec",
        "RegionPair",
        "Vec",
    ),
    "._scene": (
        "check_mesh_file",
        "contact_scene",
        "ContactScene",
        "OFF_SPEC_FACTOR",
        "TRAVEL_TOLERANCE",
    ),
    "._triangles": (
        "cluster_location",
        "cluster_segments",
        "intersection_segments",
        "IntersectionSegments",
        "touch_points",
    ),
    "._vertical": (
        "vertical_rise",
        "vertical_touch",
    ),
}
_ALIASES: dict[str, str] = {}
_WHERE = {name: module for module, names in _SOURCES.items() for name in names}


__getattr__, __dir__ = lazy_exports(__name__, globals(), _WHERE, _ALIASES)
