"""The graph stage: the contact-state network of a mechanics library, least-resistance
paths to the snap, the SRCC recommendation, GraphML.

A library (:mod:`threadmate.library`, mechanics model) becomes a networkx directed graph
(:func:`build_network`, :func:`from_library`). Nodes are its contact states: the rest
state each start (held tilt, phase) reaches, the unstable states passed on the way, the
continuation's states at each grid phase and both sides of every jump. Edges are the
passive transitions (settling, turning, jump, snap; labelled ``stable``, ``quasi-stable``
or ``unstable`` by the stability of the transition; weighted by the driver's work in mJ,
:data:`WEIGHT_FORMULA`) and, when asked, the active moves (change the held tilt by a grid
step: lift and re-drop; marked ``active``). A passive edge never changes the held tilt.

Without active moves the path from a start is the passive search itself
(:func:`least_resistance_path`; :func:`start_outcomes` gives every start's at once: does
it snap within a turn, how far it turns, the work, the click, the peak torque, whether it
passes an unstable transition). :func:`recommend` ranks the SRCC settings (held pitch,
and compliance across libraries). Angles in degrees, lengths in the spec's units, work
in mJ, torques in N m.

Example
-------
>>> from threadmate import network
>>> g = network.from_library("lib-1-4-20")                             # doctest: +SKIP
>>> p = network.least_resistance_path(g, roll=2, pitch=-1, phase=40)   # doctest: +SKIP
>>> p.path, p.labels, p.cost, p.snap                                   # doctest: +SKIP
>>> rec = network.recommend(g, roll_spread=2)                          # doctest: +SKIP
>>> print(network.format_recommendation(rec))                          # doctest: +SKIP
>>> network.write_graphml(g, "network.graphml")                        # doctest: +SKIP
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from .._validate import MAX_K as MAX_K
    from ._build import (
        COST_UNITS as COST_UNITS,
        EDGE_KINDS as EDGE_KINDS,
        NODE_ATTRIBUTES as NODE_ATTRIBUTES,
        WEIGHT_FORMULA as WEIGHT_FORMULA,
        build_network as build_network,
        from_library as from_library,
        start_node as start_node,
        starts as starts,
    )
    from ._figures import (
        plot_click_signature as plot_click_signature,
        plot_click_vs_tilt as plot_click_vs_tilt,
    )
    from ._paths import (
        PathResult as PathResult,
        k_best_paths as k_best_paths,
        least_resistance_path as least_resistance_path,
        no_path_document as no_path_document,
        snap_click as snap_click,
        snap_targets as snap_targets,
        start_outcomes as start_outcomes,
    )
    from ._readwrite import (
        GEOMETRY_ATTRIBUTES as GEOMETRY_ATTRIBUTES,
        START_COLUMN_UNITS as START_COLUMN_UNITS,
        read_graphml as read_graphml,
        start_outcomes_csv as start_outcomes_csv,
        write_graphml as write_graphml,
        write_node_link as write_node_link,
    )
    from ._recommend import (
        METRICS as METRICS,
        Recommendation as Recommendation,
        format_recommendation as format_recommendation,
        plot_recommendation as plot_recommendation,
        recommend as recommend,
        write_recommendation as write_recommendation,
    )


#: The submodule of each public name, imported when the name is first used (PEP 562):
#: importing the package loads none of them, so that a command that does not need
#: a stage's heavy dependencies (scipy, trimesh, numba, pandas, matplotlib) never
#: imports them; __all__ is made from it. tests/test_cli_contract.py checks it against
#: the re-exports above.
_SOURCES = {
    # The limit of k, a validation rule (threadmate._validate), light to import: the
    # command quotes it before the stage loads.
    ".._validate": ("MAX_K",),
    "._build": (
        "COST_UNITS",
        "EDGE_KINDS",
        "NODE_ATTRIBUTES",
        "WEIGHT_FORMULA",
        "build_network",
        "from_library",
        "start_node",
        "starts",
    ),
    "._figures": ("plot_click_signature", "plot_click_vs_tilt"),
    "._paths": (
        "PathResult",
        "k_best_paths",
        "least_resistance_path",
        "no_path_document",
        "snap_click",
        "snap_targets",
        "start_outcomes",
    ),
    "._readwrite": (
        "GEOMETRY_ATTRIBUTES",
        "START_COLUMN_UNITS",
        "read_graphml",
        "start_outcomes_csv",
        "write_graphml",
        "write_node_link",
    ),
    "._recommend": (
        "METRICS",
        "Recommendation",
        "format_recommendation",
        "plot_recommendation",
        "recommend",
        "write_recommendation",
    ),
}


__getattr__, __dir__, __all__ = lazy_exports(__name__, globals(), _SOURCES)
