"""The contact scene and its queries: the world both contact models see.

:class:`ContactScene` holds one thread pair's exact bodies, its meshes (generated or from
CAD, with their fit to the spec), the collision queries on them and the tolerances that
follow; :func:`contact_scene` builds it once per process, and :func:`scene_for` gives
a model the scene it was handed or that one. Around it, the queries both models ask:
collisions and triangle pairs (:mod:`._collision`, :mod:`._triangles`), the vertical
touch of a lowering (:mod:`._vertical`), points grouped by single linkage
(:mod:`._linkage`), and the exact contact geometry on the exact
bodies -- features, regions, normals, edge contact points (:mod:`._exact`), where a CAD
mesh leaves the spec (:mod:`._cad`) -- with the record types both share (:mod:`._regions`)
and the names of the contact states' classes (:mod:`._classes`).
"""

from typing import TYPE_CHECKING

from ..._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from ._cad import (
        COARSEST as COARSEST,
        FOLLOW_FACTOR as FOLLOW_FACTOR,
        OFF_SPEC_WARNING as OFF_SPEC_WARNING,
        MeshFit as MeshFit,
        contact_zone as contact_zone,
        describe as describe,
        face_deviation as face_deviation,
        file_units as file_units,
        mesh_fit as mesh_fit,
        off_spec as off_spec,
        sha256_of as sha256_of,
    )
    from ._classes import (
        CLASSIFICATIONS as CLASSIFICATIONS,
        ERROR_CLASS as ERROR_CLASS,
        IN_PHASE as IN_PHASE,
        NO_CONTACT as NO_CONTACT,
        QUASI_STABLE as QUASI_STABLE,
        REST_CLASSES as REST_CLASSES,
        STABLE as STABLE,
        TRANSITION_LABELS as TRANSITION_LABELS,
        UNSTABLE as UNSTABLE,
    )
    from ._collision import (
        CollisionPair as CollisionPair,
        MeshSolid as MeshSolid,
        Sweep as Sweep,
        pair_keys as pair_keys,
        upward as upward,
    )
    from ._exact import (
        CREASE as CREASE,
        EDGE_FEATURE_KINDS as EDGE_FEATURE_KINDS,
        OFF_SPEC_REGIONS as OFF_SPEC_REGIONS,
        Feature as Feature,
        OffSpec as OffSpec,
        contact_normal as contact_normal,
        edge_crossing as edge_crossing,
        engagement_outline as engagement_outline,
        feature_at as feature_at,
        lowest_on_rim as lowest_on_rim,
        off_spec_region as off_spec_region,
        on_thread as on_thread,
        refine_on_edge as refine_on_edge,
        refined_contact as refined_contact,
        region_at as region_at,
        turn_axis_tangent as turn_axis_tangent,
    )
    from ._kernels import contact_rows as contact_rows, deep_candidates as deep_candidates
    from ._linkage import single_linkage as single_linkage
    from ._regions import RegionPair as RegionPair, Vec as Vec, as_vec as as_vec
    from ._scene import (
        OFF_SPEC_FACTOR as OFF_SPEC_FACTOR,
        TRAVEL_TOLERANCE as TRAVEL_TOLERANCE,
        ContactScene as ContactScene,
        check_mesh_file as check_mesh_file,
        contact_scene as contact_scene,
        scene_for as scene_for,
    )
    from ._triangles import (
        IntersectionSegments as IntersectionSegments,
        cluster_location as cluster_location,
        cluster_segments as cluster_segments,
        intersection_segments as intersection_segments,
        touch_points as touch_points,
    )
    from ._vertical import vertical_rise as vertical_rise, vertical_touch as vertical_touch
    from ._warm import warm_kernels as warm_kernels, warm_kernels_aside as warm_kernels_aside


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
        "Sweep",
        "pair_keys",
        "upward",
    ),
    "._exact": (
        "contact_normal",
        "CREASE",
        "EDGE_FEATURE_KINDS",
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
    "._kernels": ("contact_rows", "deep_candidates"),
    "._regions": (
        "as_vec",
        "RegionPair",
        "Vec",
    ),
    "._scene": (
        "check_mesh_file",
        "contact_scene",
        "scene_for",
        "ContactScene",
        "OFF_SPEC_FACTOR",
        "TRAVEL_TOLERANCE",
    ),
    "._warm": ("warm_kernels", "warm_kernels_aside"),
    "._linkage": ("single_linkage",),
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


__getattr__, __dir__, __all__ = lazy_exports(__name__, globals(), _SOURCES)
