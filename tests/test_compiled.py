"""The compiled kernels: compiled where numba is installed, and grouping contact points as
a graph's connected components do."""

from __future__ import annotations

import numpy as np
from scipy.sparse.csgraph import connected_components
from scipy.spatial.distance import cdist


def test_kernels_are_compiled_with_an_on_disk_cache():
    from threadmate._compiled import COMPILED

    # An internal with no public form: the grouping of contact points.
    from threadmate.contact.mechanics._contact_set import _linked

    # And the collision query's walk of the trees.
    from threadmate.contact.scene._obb import _crossing

    assert COMPILED
    for kernel in (_linked, _crossing):
        assert kernel._cache.__class__.__name__ == "FunctionCache"  # numba's cache=True


def test_contact_points_group_as_the_connected_components_of_their_links():
    from threadmate.contact.mechanics._contact_set import _single_linkage

    rng = np.random.default_rng(7)
    for n in (1, 2, 5, 40, 300, 450):  # 450: the k-d tree's branch
        points = rng.uniform(0.0, 1.0, (n, 3)) * rng.uniform(0.2, 3.0)
        separation = 0.2
        labels = _single_linkage(points, separation)
        # Independently: the components of the graph of links, numbered by first point.
        _, comp = connected_components(cdist(points, points) <= separation, directed=False)
        order = {c: k for k, c in enumerate(dict.fromkeys(comp.tolist()))}
        assert labels.tolist() == [order[c] for c in comp.tolist()]
