"""The graph stage: the contact-state network, least-resistance paths to the snap, the SRCC
pitch recommendation, GraphML.

A library (:mod:`threadmate.library`) becomes a networkx directed graph
(:func:`build_network`): one node per state (string ids such as ``r+1.0_p-2.0_ph135.0``),
*turning* edges one phase step counter-clockwise, *settling* edges one roll/pitch step
toward the bolt's resting orientation, labels from the destination's classification and
weights in mJ from :class:`ResistanceParams` (work against the axial load where the
compliance centre rises, elastic energy in the compliance, friction of turning, penalty for
entering an unstable state; formula in :mod:`threadmate.network._cost`). In-phase states
are the snap targets. Angles in degrees, lengths in the spec's units, costs in mJ.

Example
-------
>>> from threadmate import network
>>> g = network.from_library("lib-1-4-20")                             # doctest: +SKIP
>>> p = network.least_resistance_path(g, roll=2, pitch=-1, phase=40)   # doctest: +SKIP
>>> p.path, p.labels, p.cost                                           # doctest: +SKIP
>>> rec = network.recommend_pitch(g, roll_spread=2)                    # doctest: +SKIP
>>> print(network.format_recommendation(rec))                          # doctest: +SKIP
>>> network.write_graphml(g, "network.graphml")                        # doctest: +SKIP
"""

from ._build import (
    CLASSIFICATIONS,
    EDGE_LABELS,
    NETWORK_COLUMNS,
    NODE_ID_FORMAT,
    build_network,
    from_library,
    node_id,
)
from ._cost import COST_UNITS, WEIGHT_FORMULA, ResistanceParams, edge_costs, variant_weight
from ._paths import (
    PathResult,
    cost_to_snap,
    k_best_paths,
    least_resistance_path,
    resolve_start,
    snap_targets,
    unsafe_starts,
)
from ._readwrite import read_graphml, write_graphml, write_node_link
from ._recommend import (
    PitchSetting,
    Recommendation,
    format_recommendation,
    plot_recommendation,
    recommend_pitch,
    write_recommendation,
)

__all__ = [
    "CLASSIFICATIONS",
    "COST_UNITS",
    "EDGE_LABELS",
    "NETWORK_COLUMNS",
    "NODE_ID_FORMAT",
    "WEIGHT_FORMULA",
    "PathResult",
    "PitchSetting",
    "Recommendation",
    "ResistanceParams",
    "build_network",
    "cost_to_snap",
    "edge_costs",
    "format_recommendation",
    "from_library",
    "k_best_paths",
    "least_resistance_path",
    "node_id",
    "plot_recommendation",
    "read_graphml",
    "recommend_pitch",
    "resolve_start",
    "snap_targets",
    "unsafe_starts",
    "variant_weight",
    "write_graphml",
    "write_node_link",
    "write_recommendation",
]
