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


def test_warming_compiles_the_signatures_the_work_asks_for():
    """The kernels warmed in either order (``contact.warm_kernels``, which a pool's workers
    call first) take the argument types the work passes: after a rest state and a search
    step of the default parts, no kernel holds a second compiled signature (one would
    mean the warm-up compiled a signature the work never asks for)."""
    from threadmate.contact import Compliance, Mechanics, search, warm_kernels
    from threadmate.contact.mechanics import _contact_set
    from threadmate.contact.scene import _kernels, _obb
    from threadmate.geometry import with_parts

    warm_kernels(reverse=True)
    warm_kernels()
    mech = Mechanics(with_parts("1/4-20 UNC-2A/2B"), Compliance())
    mech.settle(1.0, -1.0, 100.0)
    search(mech, 1.0, -1.0, 100.0, turns=0.05)
    kernels = [
        (module.__name__, name, kernel)
        for module in (_obb, _kernels, _contact_set)
        for name, kernel in vars(module).items()
        if hasattr(kernel, "signatures") and hasattr(kernel, "py_func")
    ]
    assert len(kernels) >= 10
    for module, name, kernel in kernels:
        assert len(kernel.signatures) <= 1, (module, name, kernel.signatures)
    assert all(len(k.signatures) == 1 for _, n, k in kernels if n in ("_build", "_crossing"))
