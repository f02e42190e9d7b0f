"""The spatial contact engine against geometry computed independently of the meshes.

References:
- triangle-pair intersection segments and touch points: hand-worked cases;
- first-contact height, roll = pitch = 0: closed form (0 where the flush outlines overlap;
  in the in-phase window the drop until flank meets flank, c/2 - s, c the axial clearance,
  s = lead * phase / 360);
- first-contact height, tilted: a dense parametric search over the EXACT bolt surface (tip
  face and thread) for the highest point of nut material under each bolt point, and over
  the nut's edges for the lowest bolt material above them, written from the profile
  formula in tests/_exact_geometry.py (no mesh involved);
- contact points on both exact surfaces, interference of stable poses, proper rotations,
  the record schema of docs/architecture.md.
"""

from __future__ import annotations

import math

import numpy as np
import pyarrow as pa
import pytest

from _exact_geometry import exact_first_height, rot as _rot
from threadmate import InputError
from threadmate.contact import (
    CLASSIFICATIONS,
    ContactAnalyzer,
    ContactResult,
    record_schema,
)
from threadmate.contact.scene import (
    cluster_location,
    cluster_segments,
    intersection_segments,
    touch_points,
)
from threadmate.geometry import BOLT_REGIONS, NUT_REGIONS, bolt_body, nut_body

ACCURACY = 5e-6  # inch: the first-contact accuracy at the default chord


# -- triangle pairs ---------------------------------------------------------------------


def test_segment_of_crossing_triangles_is_bounded_by_both():
    a = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)  # in z = 0, hypotenuse x + y = 1
    # Vertical triangle in x = 0.25; its section at z = 0 spans y in [-0.25, 1.25].
    b = np.array([[0.25, -1, -1], [0.25, 2, -1], [0.25, 0.5, 1]], float)
    seg = intersection_segments(a[None], b[None])
    assert seg.valid[0]
    ends = sorted([seg.start[0].tolist(), seg.end[0].tolist()], key=lambda p: p[1])
    np.testing.assert_allclose(ends, [[0.25, 0.0, 0.0], [0.25, 0.75, 0.0]], atol=1e-12)
    # A narrower vertical triangle: its own section (y in [0.2, 0.5]) bounds the segment.
    c = np.array([[0.25, 0.05, -1], [0.25, 0.65, -1], [0.25, 0.35, 1]], float)
    seg = intersection_segments(a[None], c[None])  # section at z = 0: y in [0.2, 0.5]
    ys = sorted([seg.start[0, 1], seg.end[0, 1]])
    np.testing.assert_allclose(ys, [0.2, 0.5], atol=1e-12)
    np.testing.assert_allclose(seg.midpoint[0], [0.25, 0.35, 0.0], atol=1e-12)


def test_touching_pair_reports_the_touch_point():
    a = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    b = np.array([[0.2, 0.2, 0], [0.9, 0.3, 0.5], [0.3, 0.8, 0.6]], float)  # vertex on a
    seg = intersection_segments(a[None], b[None])
    np.testing.assert_allclose(touch_points(a[None], b[None])[0], [0.2, 0.2, 0.0], atol=1e-12)
    assert not seg.valid[0] or np.allclose(seg.midpoint[0], [0.2, 0.2, 0.0])
    # Disjoint edges crossing at a distance 0.1: the midpoint of the closest points.
    e = np.array([[0.5, -1, 0.1], [0.5, 1, 0.1], [0.5, 0, 1]], float)
    f = np.array([[-1, 0.2, 0], [1, 0.2, 0], [0, 0.2, -1]], float)
    np.testing.assert_allclose(touch_points(e[None], f[None])[0], [0.5, 0.2, 0.05], atol=1e-12)


def test_distinct_contacts_are_linked_by_segment_ends():
    def seg(p, q):
        return np.array(p, float), np.array(q, float)

    # A long chain of end-to-end segments (one contact) and a far-away pair.
    chain = [seg([0.01 * k, 0, 0], [0.01 * (k + 1), 0, 0]) for k in range(20)]
    far = [seg([1, 1, 0], [1.001, 1, 0])]
    start = np.array([s for s, _ in chain + far])
    end = np.array([e for _, e in chain + far])
    from threadmate.contact.scene import IntersectionSegments

    segs = IntersectionSegments(start, end, np.ones(len(start), bool))
    labels = cluster_segments(segs, separation=0.0125)
    assert labels.tolist() == [0] * 20 + [1]
    # The chain's location lies on the chain, at its length-weighted centre.
    sub = IntersectionSegments(start[:20], end[:20], np.ones(20, bool))
    np.testing.assert_allclose(cluster_location(sub), [0.1, 0, 0], atol=1e-12)


def test_vertical_touch_is_the_least_drop_of_a_linear_program():
    """The drop at which a lowered bolt triangle first meets a nut triangle, against the
    linear program it is: over barycentric weights ``l`` (bolt) and ``m`` (nut), minimise
    ``l . a_z - m . b_z`` with the two points' XY equal (scipy's HiGHS; infeasible: the
    projections do not overlap, ``inf``). Random pairs, tilted and near-vertical ones
    included, in one call (the function's rows are independent)."""
    from scipy.optimize import linprog

    from threadmate.contact.scene import vertical_touch

    rng = np.random.default_rng(7)
    n = 400
    bolt = rng.uniform(-1, 1, (n, 3, 3))
    nut = rng.uniform(-1, 1, (n, 3, 3))
    bolt[:40, :, 2] = 0.5  # flat faces: the least drop along a whole region
    nut[:40, :, 2] = -0.25
    bolt[40:60, :, 0] = 0.1  # seen edge-on from above: no area to land on
    drop, point = vertical_touch(bolt, nut)
    for i in range(n):
        a, b = bolt[i], nut[i]
        res = linprog(
            np.concatenate([a[:, 2], -b[:, 2]]),
            A_eq=np.vstack(
                [
                    np.concatenate([a[:, :2].T, -b[:, :2].T], axis=1),
                    [1, 1, 1, 0, 0, 0],
                    [0, 0, 0, 1, 1, 1],
                ]
            ),
            b_eq=[0, 0, 1, 1],
            bounds=(0, None),
            method="highs",
        )
        if res.status == 2:  # infeasible: the projections do not overlap
            assert drop[i] == np.inf and np.isnan(point[i]).all()
            continue
        assert res.status == 0
        edge_on = 40 <= i < 60
        if edge_on and drop[i] == np.inf:  # the function's own answer for no area
            continue
        assert drop[i] == pytest.approx(res.fun, abs=1e-9)
        # The point lies on the nut triangle and, but for an edge-on bolt triangle (whose
        # projection is a segment), under the bolt triangle at that drop.
        m = np.linalg.lstsq(np.vstack([b.T, np.ones(3)]), [*point[i], 1.0], rcond=None)[0]
        assert m.min() >= -1e-9 and np.allclose(m @ b, point[i], atol=1e-12)
        if not edge_on:
            xy1 = np.vstack([a[:, :2].T, np.ones(3)])
            lo = np.linalg.solve(xy1, [*point[i, :2], 1.0])
            assert lo.min() >= -1e-9
            assert lo @ a[:, 2] - point[i, 2] == pytest.approx(drop[i], abs=1e-9)


@pytest.mark.parametrize("seed", range(6))
def test_dense_contact_patches_cluster_as_brute_force_single_linkage(seed):
    """Many pairs (the two-level path): the same partition as linking every pair of
    segment ends within the separation, computed from all pairwise distances."""
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial.distance import cdist

    from threadmate.contact.scene import IntersectionSegments

    rng = np.random.default_rng(seed)
    n, sep = int(rng.integers(65, 500)), 0.0125
    centres = rng.uniform(0, 0.3, (int(rng.integers(1, 7)), 3)) * [1, 1, seed % 2]
    start = centres[rng.integers(0, len(centres), n)] + rng.normal(0, 0.01, (n, 3))
    end = start + rng.normal(0, 1e-3, (n, 3))
    labels = cluster_segments(IntersectionSegments(start, end, np.ones(n, bool)), sep)
    pts = np.concatenate([start, end])
    adjacent = cdist(pts, pts) <= sep
    adjacent[np.arange(n), np.arange(n) + n] = True
    ref = connected_components(adjacent, directed=False)[1][:n]
    pairs = {(a, b) for a, b in zip(labels.tolist(), ref.tolist(), strict=True)}
    assert len(pairs) == len(set(labels.tolist())) == len(set(ref.tolist()))


def test_sector_queries_agree_with_the_whole_nut(analyzer):
    """The nut's sectors together answer as its single BVH, pose by pose."""
    from threadmate.geometry import Pose

    eng = analyzer.engine
    rng = np.random.default_rng(7)
    seen = set()
    for _ in range(40):
        rotation = _rot(*rng.uniform(-4, 4, 2), rng.uniform(0, 360))
        h = -eng.lowest_bolt_z(rotation) - rng.uniform(0, 0.004)
        pose = Pose(rotation, np.array([0.0, 0.0, h]))
        whole = eng.collides(pose)
        hit = eng.colliding_sectors(pose)
        # Excluding a sector that does not exist asks every sector in turn.
        assert bool(hit) == whole == eng.collides_outside(pose, frozenset({36}))
        if hit:
            nut_sectors = set(eng.nut_sector[eng.pairs(pose)[:, 1]].tolist())
            assert nut_sectors == set(hit)
            np.testing.assert_array_equal(eng.pairs(pose, hit), eng.pairs(pose))
        seen.add(whole)
    assert seen == {True, False}


def _pair_engine(point: str):
    """The 1/4-20 UNC-2A/2B pair with flat ends (``point`` "flat") or its standard ones,
    and the collision engine of its generated meshes."""
    from threadmate.contact.scene import CollisionPair
    from threadmate.geometry import spec_from_designation, thread_meshes

    if point == "flat":
        spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    else:
        spec = spec_from_designation("1/4-20 UNC-2A/2B")
    bolt, nut = thread_meshes(spec)
    return spec, CollisionPair(bolt.mesh, nut.mesh)


def _random_placing(rng):
    """A random rotation (tilt up to 8 degrees in any direction, any phase) and a lateral
    shift of the origin up to 0.004 in each way."""
    size, direction = rng.uniform(0, 8), rng.uniform(0, 2 * np.pi)
    rotation = _rot(size * np.cos(direction), size * np.sin(direction), rng.uniform(0, 360))
    return rotation, rng.uniform(-1, 1, 2) * 0.004


@pytest.mark.parametrize("point", ["flat", "chamfer"])
def test_one_walk_answers_as_the_two_queries_it_stands_for(point):
    """The bracket's two questions asked in one walk of the trees (``pairs_below``):
    whether the bolt at a height is free and the pairs crossing a little lower are, pose by
    pose, those of the yes/no query at the one and the enumeration at the other, at
    heights from above the nut to deep in it and drops from a hair to a pitch. And the
    walk's sweep answers between the two as the queries there do (of all sectors or some),
    and covers no pose outside them."""
    from threadmate.geometry import Pose

    spec, eng = _pair_engine(point)
    rng = np.random.default_rng(17)
    seen, between = set(), set()
    for _ in range(80):
        rotation, shift = _random_placing(rng)
        h = -eng.lowest_bolt_z(rotation) - rng.uniform(-0.002, 0.03)
        drop = 10.0 ** rng.uniform(-7, np.log10(spec.pitch))
        top = Pose(rotation, np.array([shift[0], shift[1], h]))
        low = Pose(rotation, np.array([shift[0], shift[1], h - drop]))
        sweep = eng.pairs_below(low, top)
        if eng.collides(top):
            assert sweep is None
        else:
            assert sweep is not None
            np.testing.assert_array_equal(sweep.pairs, eng.pairs(low))
            sectors = frozenset(rng.choice(36, 12, replace=False).tolist())
            for u in (0.0, 1.0, *rng.uniform(0, 1, 3)):
                pose = Pose(rotation, np.array([shift[0], shift[1], h - u * drop]))
                assert sweep.covers(pose)
                np.testing.assert_array_equal(sweep.pairs_at(pose), eng.pairs(pose))
                np.testing.assert_array_equal(
                    sweep.pairs_at(pose, sectors), eng.pairs(pose, sectors)
                )
                assert sweep.collides_at(pose) == eng.collides(pose)
                between.add(sweep.collides_at(pose))
            for z, xy in ((h + 1e-9, shift), (h - drop - 1e-9, shift), (h, shift + 1e-9)):
                assert not sweep.covers(Pose(rotation, np.array([xy[0], xy[1], z])))
            assert not sweep.covers(Pose(rotation @ _rot(0.0, 0.0, 1.0), top.origin))
        seen.add((sweep is None, sweep is not None and len(sweep.pairs) > 0))
    assert seen == {(True, False), (False, True), (False, False)}
    assert between == {True, False}


def test_a_triangle_meets_another_lowered_within_a_drop_as_their_exact_touches_say():
    """The swept test of two triangles (``_obb._cross_over``: the nut's triangle rising by
    up to a drop, the prism it sweeps against the bolt's by the separating axes) against
    the exact vertical touch and rise of the pair: the bolt's triangle lowered by ``t``
    meets the nut's for ``t`` between the touch's drop and minus the rise, so the two meet
    within a drop ``D`` exactly where that interval meets ``[0, D]``; pairs within a
    rounding margin of either end are left out."""
    from threadmate.contact.scene import vertical_rise, vertical_touch
    from threadmate.contact.scene._obb import _cross_over

    rng = np.random.default_rng(3)
    w = np.empty((14, 3))
    seen, tested = set(), 0
    for _ in range(4000):
        bolt = rng.normal(0, 1, (1, 3, 3)) * rng.uniform(0.1, 1.0, 3)
        nut = bolt.mean(axis=1)[:, None] + rng.normal(0, 1, (1, 3, 3)) * rng.uniform(0.1, 1.0)
        drop_first, _ = vertical_touch(bolt, nut)
        rise, _ = vertical_rise(bolt, nut)
        depth = float(rng.uniform(0.0, 1.5))
        lo, hi = float(drop_first[0]), -float(rise[0])
        if not (np.isfinite(lo) and np.isfinite(hi)):
            meets = False
        elif min(abs(lo), abs(lo - depth), abs(hi), abs(hi - depth)) < 1e-9:
            continue  # at an end: rounding decides
        else:
            meets = lo <= depth and hi >= 0.0
        got = _cross_over(bolt[0], nut[0], np.array([0.0, 0.0, depth]), w)
        assert got == meets, (lo, hi, depth)
        seen.add(meets)
        tested += 1
    assert seen == {True, False} and tested > 3000


@pytest.mark.parametrize("point", ["flat", "chamfer"])
def test_a_walk_finds_every_pair_the_bolt_meets_lowered_within_its_drop(point):
    """A walk's sweep names the pairs the bolt, lowered from its top by up to a drop, meets
    (``Sweep.touching_within``): pose by pose, those among all its candidate pairs whose
    exact vertical touch from the top lies in ``[0, drop]`` (brute force, every candidate
    pair's exact touch), none else, at drops from none to the walk's whole span. The
    sweep narrowed to the leaf pairs of those (``Sweep.narrowed``) answers at heights
    within the drop as the whole meshes' queries do there."""
    from threadmate.contact.scene import pair_keys, vertical_touch
    from threadmate.geometry import Pose

    spec, eng = _pair_engine(point)
    rng = np.random.default_rng(29)
    met, checked, crossing = 0, 0, 0
    for _ in range(40):
        rotation, shift = _random_placing(rng)
        span = 10.0 ** rng.uniform(-5, np.log10(spec.pitch / 8))
        # The top free and, mostly, the bolt touching within the span below it: the
        # first touch from above the nut bisected with the yes/no query.
        free, deep = -eng.lowest_bolt_z(rotation) + 0.002, -eng.lowest_bolt_z(rotation) - 0.03
        for _ in range(40):
            mid = 0.5 * (free + deep)
            if eng.collides(Pose(rotation, np.array([shift[0], shift[1], mid]))):
                deep = mid
            else:
                free = mid
        h = free + rng.uniform(-0.5, 1.5) * span
        top = Pose(rotation, np.array([shift[0], shift[1], h]))
        sweep = eng.pairs_below(Pose(rotation, np.array([shift[0], shift[1], h - span])), top)
        if sweep is None:
            continue
        candidates = sweep.candidates()
        exact, _ = vertical_touch(*eng.triangles(top, candidates))
        for depth in (0.0, *rng.uniform(0, span, 3), span):
            got = sweep.touching_within(top, depth)
            inside = np.isfinite(exact) & (exact >= 0.0) & (exact <= depth)
            margin = 1e-12 + 1e-9 * span
            clear = ~np.isfinite(exact) | (exact < -margin) | (exact > depth + margin)
            keys = pair_keys(got)
            assert np.isin(pair_keys(candidates[inside]), keys).all()
            assert not np.isin(pair_keys(candidates[clear]), keys).any()
            met += int(inside.any())
            checked += 1
            narrow = sweep.narrowed(top, depth)
            for u in (0.0, *rng.uniform(0, 1, 2)):
                pose = top.translated([0.0, 0.0, -u * depth])
                assert narrow.covers(pose)
                np.testing.assert_array_equal(narrow.pairs_at(pose), eng.pairs(pose))
                assert narrow.collides_at(pose) == eng.collides(pose)
                crossing += int(eng.collides(pose))
    assert checked > 100 and met > 25 and crossing > 15


def test_obb_trees_hold_each_triangle_once_inside_every_box_above_it(analyzer):
    """The collision query's trees (contact/scene/_obb.py): each tree's leaves hold its
    group's triangles, once each and at most LEAF_SIZE to a leaf, and every node's box
    (centre, orthonormal axes, half-extents) holds every vertex of the triangles below it,
    checked vertex by vertex."""
    from threadmate.contact.scene._obb import LEAF_SIZE, obb_forest

    eng = analyzer.engine
    groups = [np.flatnonzero(eng.nut_sector == k) for k in (0, 9, 18)]
    forest = obb_forest(eng.nut_vertices, eng.nut_faces, groups)
    np.testing.assert_allclose(
        np.einsum("nai,naj->nij", forest.axes, forest.axes),
        np.broadcast_to(np.eye(3), forest.axes.shape),
        atol=1e-12,
    )
    for root, group in zip(forest.roots.tolist(), groups, strict=True):
        below: dict[int, list[int]] = {}
        order, stack = [], [root]
        while stack:  # every node of the tree, parents first
            node = stack.pop()
            order.append(node)
            if forest.leaf[node] < 0:
                stack += [int(forest.left[node]), int(forest.right[node])]
        for node in reversed(order):  # the triangles below each node, children first
            leaf, size = int(forest.leaf[node]), int(forest.size[node])
            assert (leaf >= 0) == (1 <= size <= LEAF_SIZE) == (forest.left[node] < 0)
            below[node] = (
                list(range(leaf, leaf + size))
                if leaf >= 0
                else below[int(forest.left[node])] + below[int(forest.right[node])]
            )
        assert sorted(forest.faces[below[root]].tolist()) == sorted(group.tolist())
        assert np.array_equal(forest.triangles, eng.nut_vertices[eng.nut_faces[forest.faces]])
        for node in order:
            points = forest.triangles[below[node]].reshape(-1, 3) - forest.centre[node]
            local = np.abs(points @ forest.axes[node])
            assert np.all(local <= forest.extent[node] * (1 + 1e-9) + 1e-12)


def test_obb_trees_split_each_node_where_the_children_have_least_surface():
    """A node's split (contact/scene/_obb.py, the surface-area heuristic): of the planes
    evenly spaced across its triangles' centroids along each of its box's axes, the one
    whose two children (the triangles each side of it, their extents along the node's
    axes) have the least surface weighted by their count, recomputed here plane by plane
    for random triangles of three shapes (the triangles left of the plane returned)."""
    from threadmate.contact.scene import _obb

    rng = np.random.default_rng(7)
    for scale in ([1.0, 1.0, 1.0], [5.0, 0.2, 0.1], [0.3, 2.0, 0.05]):
        centres = rng.normal(size=(150, 1, 3)) * scale
        tri = np.ascontiguousarray(centres + 0.05 * rng.normal(size=(150, 3, 3)))
        order = np.arange(len(tri))
        axes = np.ascontiguousarray(np.linalg.qr(rng.normal(size=(3, 3)))[0])
        along = np.empty(len(tri))
        span = np.empty((len(tri), 3, 3))
        bins = np.empty((_obb.SPLIT_BINS, 8))
        plane = _obb._split(tri, order, 0, len(tri), axes, along, span, bins)
        local = tri @ axes  # each vertex along the node's axes
        centroid = local.mean(axis=1)

        def cost(left: np.ndarray, local: np.ndarray = local) -> float:
            total = 0.0
            for side in (left, ~left):
                ext = local[side].reshape(-1, 3)
                x, y, z = ext.max(axis=0) - ext.min(axis=0)
                total += side.sum() * (x * y + y * z + z * x)
            return total

        costs = {}
        for c in range(3):
            low, high = centroid[:, c].min(), centroid[:, c].max()
            for cut in range(1, _obb.SPLIT_BINS):
                at = low + cut * (high - low) / _obb.SPLIT_BINS
                left = centroid[:, c] < at
                if 0 < left.sum() < len(tri):
                    costs[(c, cut)] = cost(left)
        chosen = along < plane
        assert 0 < chosen.sum() < len(tri)
        axis = int(np.argmin([np.abs(along - centroid[:, c]).max() for c in range(3)]))
        np.testing.assert_allclose(along, centroid[:, axis], rtol=0, atol=1e-12)
        assert cost(chosen) == pytest.approx(min(costs.values()), rel=1e-12)


def test_a_scene_is_built_once_per_spec_and_chord(quarter_20):
    """The scene of the default chord is one whether the chord is given or not (a sweep
    names it, a model built by hand need not): its trees are built once per process."""
    from threadmate.contact import contact_scene
    from threadmate.geometry import DEFAULT_CHORD

    scene = contact_scene(quarter_20)
    assert contact_scene(quarter_20, chord=DEFAULT_CHORD["in"]) is scene
    assert contact_scene(quarter_20, chord=2 * DEFAULT_CHORD["in"]) is not scene


def test_crossing_pairs_at_the_touch_are_python_fcls(quarter_20):
    """At the first touch of the bolt lowered onto the nut (python-fcl's yes/no bisected to
    the last bit, tests/_fcl.py) and a hair either side, the collision query's crossing
    pairs and yes/no are python-fcl's on the two whole meshes, pair for pair: the same
    triangle test where triangles touch, at tilts and phases of all kinds."""
    from _fcl import Collider
    from threadmate.contact.scene import CollisionPair
    from threadmate.geometry import Pose, thread_meshes

    bolt, nut = thread_meshes(quarter_20)
    eng, whole = CollisionPair(bolt.mesh, nut.mesh), Collider(quarter_20)
    rng = np.random.default_rng(3)
    crossing = 0
    for _ in range(12):
        size, direction = rng.uniform(0, 4), rng.uniform(0, 2 * np.pi)
        rotation = _rot(size * np.cos(direction), size * np.sin(direction), rng.uniform(0, 360))
        x, y = rng.uniform(-0.002, 0.002, 2)
        touch = whole.first_touch(rotation, x, y, -eng.lowest_bolt_z(rotation), 0.01)
        for dz in (1e-9, 0.0, -1e-9, -1e-6, -1e-4):
            origin = np.array([x, y, touch + dz])
            expected = whole.pairs(rotation, origin)
            pose = Pose(rotation, origin)
            assert set(map(tuple, eng.pairs(pose).tolist())) == expected
            assert eng.collides(pose) == bool(expected) == whole.collides(rotation, origin)
            crossing += len(expected)
    assert crossing > 0


@pytest.mark.parametrize("point", ["flat", "chamfer"])
def test_queries_without_the_bolts_core_answer_as_the_whole_meshes(point):
    """Where the engine asks the bolt without its core, its answers are those of the whole
    meshes (python-fcl BVHs built by the tests, tests/_fcl.py): every crossing pair and
    the yes/no, at tilts either side of CORE_TILT, shifts beyond the clearance (where the
    core meets the nut) and heights through the thread. The core's vertices then lie
    nearer the axis than the bore, and the bore is the nut mesh's least distance from its
    axis (dense points on every nut triangle, none nearer, the nearest within a hair)."""
    from _fcl import Collider
    from threadmate.contact.scene import CollisionPair
    from threadmate.contact.scene._collision import CORE_TILT
    from threadmate.geometry import Pose, spec_from_designation, thread_meshes

    if point == "flat":
        spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    else:
        spec = spec_from_designation("1/4-20 UNC-2A/2B")
    bolt, nut = thread_meshes(spec)
    eng, whole = CollisionPair(bolt.mesh, nut.mesh), Collider(spec)
    # The bore, by dense barycentric points on every nut triangle.
    tri = eng.nut_vertices[eng.nut_faces]
    w = np.array([(i, j, 24 - i - j) for i in range(25) for j in range(25 - i)]) / 24.0
    radius = np.hypot(*np.einsum("kv,tvc->tkc", w, tri)[..., :2].transpose(2, 0, 1))
    assert radius.min() >= eng.nut_bore * (1 - 1e-12)
    assert radius.min() - eng.nut_bore < 1e-3 * ACCURACY
    core = eng.bolt_faces[eng._core_faces]
    assert 0.3 < eng._core_faces.mean() < 1.0  # the root fillet's faces, most of the mesh
    rng = np.random.default_rng(11)
    asked, met = {True: 0, False: 0}, 0
    for i in range(60):
        size, direction = rng.uniform(0, 2 * CORE_TILT), rng.uniform(0, 2 * np.pi)
        rotation = _rot(size * np.cos(direction), size * np.sin(direction), rng.uniform(0, 360))
        # Within the clearance, and beyond it (where the core can meet the nut).
        shift = rng.uniform(-1, 1, 2) * (0.003 if i % 2 else 0.012)
        h = -eng.lowest_bolt_z(rotation) - rng.uniform(0, 0.06)
        pose = Pose(rotation, np.array([shift[0], shift[1], h]))
        clear = eng._core_clear(pose)
        asked[clear] += 1
        if clear:
            at = pose.to_fixed(eng.bolt_vertices[np.unique(core)])
            assert np.hypot(at[:, 0], at[:, 1]).max() < eng.nut_bore
        expected = whole.pairs(rotation, pose.origin)
        assert set(map(tuple, eng.pairs(pose).tolist())) == expected
        assert eng.collides(pose) == bool(expected) == whole.collides(rotation, pose.origin)
        met += any(eng._core_faces[b] for b, _ in expected)
    assert min(asked.values()) >= 10  # both ways asked
    assert met > 0  # and the core met the nut at some poses, where it was asked


@pytest.mark.parametrize("point", ["flat", "chamfer"])
def test_pairs_under_the_nuts_material_are_every_such_crossing_pair(analyzer, point):
    """The pairs of a nut face turned down and a bolt face turned up, asked of those faces
    alone, are every such pair of all the crossing pairs (brute force, normals from the
    rotated face normals), at tilts either side of the limit where the query asks all."""
    from threadmate.contact import Compliance, Mechanics
    from threadmate.contact.scene._collision import UNDER_TILT
    from threadmate.geometry import Pose, spec_from_designation

    if point == "flat":
        eng = analyzer.engine
    else:  # the default parts: chamfered point, countersunk nut
        eng = Mechanics(spec_from_designation("1/4-20 UNC-2A/2B"), Compliance()).scene.engine
    tri = eng.bolt_vertices[eng.bolt_faces]
    bolt_normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    bolt_normal /= np.linalg.norm(bolt_normal, axis=1)[:, None]
    tri = eng.nut_vertices[eng.nut_faces]
    nut_normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    nut_normal /= np.linalg.norm(nut_normal, axis=1)[:, None]
    rng = np.random.default_rng(5)
    found = 0
    for _ in range(60):
        size, direction = rng.uniform(0, 45), rng.uniform(0, 2 * np.pi)
        rotation = _rot(size * np.cos(direction), size * np.sin(direction), rng.uniform(0, 360))
        h = -eng.lowest_bolt_z(rotation) - rng.uniform(0, 0.1)
        pose = Pose(rotation, np.array([0.0, 0.0, h]))
        every = eng.pairs(pose)
        up = (bolt_normal[every[:, 0]] @ rotation.T)[:, 2] > 1e-12
        down = nut_normal[every[:, 1], 2] < -1e-12
        expected = set(map(tuple, every[up & down].tolist()))
        asked = set(map(tuple, eng.pairs_under_material(pose).tolist()))
        assert expected <= asked <= set(map(tuple, every.tolist()))
        if np.degrees(np.arccos(rotation[2, 2])) > UNDER_TILT:  # beyond it, all are asked
            assert asked == set(map(tuple, every.tolist()))
        found += len(expected)
    assert found > 0


def test_lowest_bolt_point_is_the_least_over_every_vertex(analyzer):
    """The bolt's lowest point, asked of its convex hull's vertices, is the least height of
    all its vertices (brute force), to the last bit, at any attitude."""
    eng = analyzer.engine
    rng = np.random.default_rng(11)
    for _ in range(300):
        tilt = rng.uniform(-30, 30, 2) if rng.random() < 0.5 else rng.uniform(-180, 180, 2)
        rotation = _rot(*tilt, rng.uniform(0, 360))
        heights = eng.bolt_vertices @ rotation[2]
        assert eng.lowest_bolt_z(rotation) == float(heights.min())


# The exact reference (tests/_exact_geometry.py): exact_first_height, and _rot, the frame
# composition written out.

# -- the analyser -------------------------------------------------------------------------


@pytest.fixture(scope="module")
def analyzer(quarter_20):
    return ContactAnalyzer(quarter_20)


CONFIGS = [(4, 0, 185), (4, 4, 235), (-4, 0, 131), (2, -3, 40), (-3, 2, 300), (1, 0.5, 10)]


@pytest.fixture(scope="module")
def results(analyzer):
    return {cfg: analyzer.analyze(*cfg) for cfg in CONFIGS}


def test_reference_matches_closed_form(quarter_20):
    c = quarter_20.axial_clearance
    for phase in (0.0, 6.0, -8.0):
        s = quarter_20.lead * phase / 360
        assert exact_first_height(quarter_20, 0, 0, phase) == pytest.approx(-(c / 2 - s), abs=2e-8)


@pytest.mark.parametrize("phase", [0.0, 6.0, -8.0, 90.0, 200.0])
def test_aligned_first_contact_height_closed_form(analyzer, quarter_20, phase):
    c = quarter_20.axial_clearance
    s = quarter_20.lead * (((phase + 180) % 360) - 180) / 360
    expected = -(c / 2 - s) if abs(s) <= c / 2 else 0.0
    result = analyzer.analyze(0, 0, phase)
    assert result.first.found
    assert result.first.origin[2] == pytest.approx(expected, abs=ACCURACY)
    assert result.first.origin[:2] == (0.0, 0.0)
    if expected < 0:
        assert result.classification == "in-phase"
        # Flank meets flank: the common normal is the 60-degree flank's, sqrt(3)/2 up
        # (to within the helix's lead angle), wherever along the helix the mesh touches.
        for c in result.first.contacts:
            assert c.normal[2] == pytest.approx(math.sqrt(3) / 2, abs=0.01)


def test_tilted_first_contact_height_matches_exact_geometry(results, quarter_20):
    for cfg, result in results.items():
        expected = exact_first_height(quarter_20, *cfg)
        assert result.first.origin[2] == pytest.approx(expected, abs=ACCURACY), cfg


def test_stage_poses_are_proper_rotations_with_the_configuration(results):
    for cfg, result in results.items():
        for stage in result.stages:
            if not stage.found:
                continue
            R = np.array(stage.rotation)
            np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
            assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)
        np.testing.assert_allclose(np.array(result.first.rotation), _rot(*cfg), atol=1e-12)


def test_contact_points_lie_on_both_exact_surfaces(results, analyzer, quarter_20):
    bolt, nut = bolt_body(quarter_20), nut_body(quarter_20)
    tol = 2 * analyzer.chord + 1e-6
    checked = 0
    for cfg, result in results.items():
        for stage in result.stages:
            if not stage.found:
                continue
            pose = stage.pose
            for c in stage.contacts:
                p = np.array(c.point)
                assert nut.surface_distance(p) <= tol, (cfg, stage.name, c)
                assert bolt.surface_distance(pose.to_bolt(p)) <= tol, (cfg, stage.name, c)
                assert np.linalg.norm(c.normal) == pytest.approx(1.0, abs=1e-9)
                assert c.bolt_region in BOLT_REGIONS and c.nut_region in NUT_REGIONS
                assert c.pairs >= 1
                checked += 1
    assert checked >= 10


def test_turns_lower_the_compliance_centre(results):
    for cfg, result in results.items():
        z = [s.origin[2] for s in result.stages if s.found]
        assert all(b <= a + 1e-9 for a, b in zip(z, z[1:], strict=False)), cfg


def _exact_interference(spec, pose, n_theta=1440, n_v=60):
    """Deepest point of the exact bolt surface inside the exact nut at ``pose``."""
    bolt, nut = bolt_body(spec), nut_body(spec)
    th = np.linspace(-np.pi, np.pi, n_theta, endpoint=False)
    v = np.linspace(0, spec.bolt.length, n_v)
    T, V = np.meshgrid(th, v, indexing="ij")
    r = bolt.section_radius(T, V)
    lateral = np.stack([r * np.cos(T), r * np.sin(T), V], -1).reshape(-1, 3)
    S = np.linspace(0, 1, 40)
    T2, S2 = np.meshgrid(th, S, indexing="ij")
    r2 = S2 * bolt.section_radius(T2, 0.0)
    tip = np.stack([r2 * np.cos(T2), r2 * np.sin(T2), 0 * r2], -1).reshape(-1, 3)
    pts = pose.to_fixed(np.concatenate([lateral, tip]))
    inside = nut.contains(pts)
    return float(nut.surface_distance(pts[inside]).max(initial=0.0))


def test_stable_poses_embed_less_than_the_origin_drops(results, analyzer, quarter_20):
    """Thesis 4.2.3: a stable three-point state did not embed deeper than its origin
    dropped from the second stage, checked on a dense sampling of the exact bodies."""
    stable = [(cfg, r) for cfg, r in results.items() if r.classification == "stable"]
    assert stable, "expected a stable configuration among the samples"
    for cfg, result in stable:
        assert result.n_contacts >= 3
        drop = result.second.origin[2] - result.third.origin[2]
        assert drop >= -1e-12, cfg  # the third turn lowers the compliance centre
        depth = _exact_interference(quarter_20, result.third.pose)
        # Within the mesh-noise floor of the interference measurement, as the rule has it.
        assert depth <= max(drop, analyzer.interference_tolerance) + analyzer.chord, cfg


def _expected_class(rec, analyzer):
    """The thesis's 4.2 rules recomputed from a record and the analyser's tolerances
    (the in-phase test is the analyser's own: it shows in the record only as the class)."""
    if not rec["first_found"]:
        return "no-contact"
    if rec["classification"] == "in-phase":
        assert not rec["second_found"]
        return "in-phase"
    if not rec["second_found"]:
        return "no-contact"
    # The pivot axis through the second stage's two contacts, the compliance centre (the
    # bolt origin here, compliance_z = 0) at the second stage (its pose is the bracket's
    # free end, the analyser's the contact end: 1e-7 in of travel apart).
    p1 = np.array([rec[f"second_c1_{a}"] for a in "xyz"])
    p2 = np.array([rec[f"second_c2_{a}"] for a in "xyz"])
    o2 = np.array([rec[f"second_origin_{a}"] for a in "xyz"])
    u = (p2 - p1) / np.linalg.norm(p2 - p1)
    offset = np.linalg.norm((o2 - p1) - ((o2 - p1) @ u) * u)
    assert rec["pivot_offset"] == pytest.approx(offset, abs=1e-6)
    if offset <= analyzer.quasi_tolerance:
        return "quasi-stable"
    if not rec["third_found"]:
        return "no-contact"
    drop = rec["second_origin_z"] - rec["third_origin_z"]
    assert rec["origin_drop"] == pytest.approx(drop, abs=1e-12)
    embedded = rec["interference"] > max(drop, analyzer.interference_tolerance)
    return "unstable" if embedded else "stable"


def test_classifications_follow_the_thesis_rules(results, analyzer):
    for cfg, result in results.items():
        assert result.classification in CLASSIFICATIONS
        rec = result.to_record()
        assert rec["classification"] == _expected_class(rec, analyzer), cfg
        if result.classification in ("stable", "unstable"):
            assert result.third.found and math.isfinite(result.interference)
        if result.classification == "unstable":  # thesis 4.2.1
            assert result.interference > result.origin_drop
        if result.classification == "stable":  # thesis 4.2.3
            assert result.n_contacts >= 3
            assert result.interference <= max(result.origin_drop, analyzer.interference_tolerance)


def test_classification_rules_and_their_order():
    from threadmate.contact.thesis import classify

    base = dict(
        first_found=True,
        in_phase=False,
        second_found=True,
        offset=0.1,
        third_found=True,
        interference=0.004,
        origin_drop=0.001,
        quasi_tolerance=0.005,
        interference_tolerance=1e-5,
    )

    def cls(**kw):
        return classify(**{**base, **kw})

    # Thesis 4.2.1: embedded 0.004 in while the origin moved 0.001 in.
    assert cls() == "unstable"
    # Thesis 4.2.3 (and 4.2.2's numbers): the origin dropped more than the bolt embedded.
    assert cls(interference=0.0013, origin_drop=0.0045) == "stable"
    assert cls(interference=0.001, origin_drop=0.001) == "stable"  # not LARGER
    # An embedding within the noise floor is none, even with no drop at all.
    assert cls(interference=1e-18, origin_drop=0.0) == "stable"
    assert cls(interference=2e-5, origin_drop=0.0) == "unstable"
    # Order: no-contact, in-phase, quasi-stable, no-contact (no third), unstable, stable.
    assert cls(first_found=False, in_phase=True) == "no-contact"
    assert cls(in_phase=True, second_found=False) == "in-phase"
    assert cls(second_found=False, offset=0.0) == "no-contact"
    assert cls(offset=0.005) == "quasi-stable"  # even though it embedded
    assert cls(offset=0.001, third_found=False) == "quasi-stable"
    assert cls(third_found=False, interference=math.nan, origin_drop=math.nan) == "no-contact"


def test_rolling_is_a_pivot_contact_gaining_triangle_pairs(results, analyzer):
    """Thesis 4.2: a rolling axis acquires more triangles at one or both of the original
    points once rotation about the pivot axis commences."""
    seen = set()
    for cfg, result in results.items():
        assert isinstance(result.rolling, bool)
        rec, doc = result.to_record(), result.to_dict()
        assert rec["rolling"] is result.rolling and doc["rolling"] is result.rolling
        c2, c3 = result.second.contacts, result.third.contacts
        if not result.third.found or len(c2) != 2:
            assert result.rolling is False, cfg
            continue
        # The third stage lists the pivot contacts first, in the second stage's order (a
        # rolling contact moves along its own end of the axis, never to the other end).
        d = np.linalg.norm(
            np.subtract([c.point for c in c3[:2]], np.array([c.point for c in c2])[:, None]),
            axis=-1,
        )
        assert d[0, 0] < d[1, 0] and d[1, 1] < d[0, 1], cfg
        grew = c3[0].pairs > c2[0].pairs or c3[1].pairs > c2[1].pairs
        assert result.rolling is grew, cfg
        assert rec["rolling"] == (
            rec["third_c1_pairs"] > rec["second_c1_pairs"]
            or rec["third_c2_pairs"] > rec["second_c2_pairs"]
        )
        seen.add(grew)
    assert seen == {True, False}, "expected rolling and non-rolling pivots among the samples"


# -- record and JSON ---------------------------------------------------------------------


def _architecture_columns():
    """The contact record's columns as docs/architecture.md lists them."""
    cols = [
        "roll",
        "pitch",
        "phase",
        "classification",
        "n_contacts",
        "region_combination",
        "interference",
        "origin_drop",
        "pivot_offset",
        "rolling",
        "final_roll",
        "final_pitch",
        "final_phase",
        "final_origin_z",
        "queries",
    ]
    for s in ("first", "second", "third"):
        cols += [f"{s}_found", f"{s}_angle", f"{s}_origin_x", f"{s}_origin_y", f"{s}_origin_z"]
        cols += [f"{s}_r{i}{j}" for i in range(3) for j in range(3)]
        for i in (1, 2, 3):
            cols += [f"{s}_c{i}_{a}" for a in "xyz"] + [f"{s}_c{i}_n{a}" for a in "xyz"]
            cols += [f"{s}_c{i}_pairs", f"{s}_c{i}_bolt_region", f"{s}_c{i}_nut_region"]
    return cols


def test_record_has_exactly_the_architecture_columns(results):
    schema = record_schema()
    assert schema.names == _architecture_columns()
    rows = [r.to_record() for r in results.values()]
    for row in rows:
        assert list(row) == schema.names
    table = pa.Table.from_pylist(rows, schema=schema)
    assert table.num_rows == len(rows)
    for name in ("n_contacts", "queries", "first_c1_pairs"):
        assert schema.field(name).type == pa.int64()
    assert schema.field("first_found").type == pa.bool_()
    assert schema.field("rolling").type == pa.bool_()
    assert schema.field("region_combination").type == pa.string()


def test_record_values(results):
    for cfg, result in results.items():
        rec = result.to_record()
        assert (rec["roll"], rec["pitch"], rec["phase"]) == cfg
        last = result.last_stage
        assert rec["n_contacts"] == len(last.contacts)
        assert rec["region_combination"].count("+ ") + 1 == len(last.contacts) or rec[
            "region_combination"
        ].count(" + ") + 1 == len(last.contacts)
        assert rec["final_origin_z"] == last.origin[2]
        fr, fp, fph = rec["final_roll"], rec["final_pitch"], rec["final_phase"]
        np.testing.assert_allclose(_rot(fr, fp, fph), np.array(last.rotation), atol=1e-9)
        assert rec["first_angle"] == 0.0
        for s in ("first", "second", "third"):
            stage = getattr(result, s)
            assert rec[f"{s}_found"] == stage.found
            n = len(stage.contacts)
            for i in (1, 2, 3):
                if i > n:
                    assert rec[f"{s}_c{i}_pairs"] == 0 and rec[f"{s}_c{i}_bolt_region"] == ""
                    assert math.isnan(rec[f"{s}_c{i}_x"])
        assert rec["queries"] == result.queries > 0


def test_in_phase_result_record_fills_missing_values(analyzer):
    result = analyzer.analyze(0, 0, 0)
    assert result.classification == "in-phase"
    rec = result.to_record()
    assert rec["first_found"] and not rec["second_found"] and not rec["third_found"]
    assert math.isnan(rec["second_angle"]) and math.isnan(rec["interference"])
    assert rec["rolling"] is False
    assert rec["third_c1_pairs"] == 0 and rec["third_c1_nut_region"] == ""
    pa.Table.from_pylist([rec], schema=record_schema())


def test_json_document_layout(results):
    import json

    # The JSON rule: an internal with no public form.
    from threadmate._json import to_jsonable

    doc = json.loads(json.dumps(to_jsonable(results[(4, 4, 235)].to_dict())))
    assert {
        "units",
        "roll",
        "pitch",
        "phase",
        "classification",
        "stages",
        "interference",
        "origin_drop",
        "pivot_offset",
        "rolling",
    } <= set(doc)
    assert isinstance(doc["rolling"], bool)
    assert doc["units"] == "in"
    first = doc["stages"]["first"]
    assert len(first["origin"]) == 3 and np.array(first["rotation"]).shape == (3, 3)
    for c in first["contacts"]:
        assert {"point", "normal", "pairs", "bolt_region", "nut_region"} <= set(c)
    assert "angle" in doc["stages"]["second"] and "angle" in doc["stages"]["third"]


# -- bad input ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "angles", [(46, 0, 0), (0, -60, 0), (float("nan"), 0, 0), (0, 0, float("inf"))]
)
def test_bad_angles_are_refused(analyzer, angles):
    with pytest.raises(InputError):
        analyzer.analyze(*angles)


def test_bad_settings_are_refused(quarter_20):
    with pytest.raises(InputError):
        ContactAnalyzer(quarter_20, chord=-1.0)
    with pytest.raises(InputError):
        ContactAnalyzer(quarter_20, compliance_z=float("nan"))
    with pytest.raises(InputError):
        ContactAnalyzer("1/4-20")  # type: ignore[arg-type]


def test_user_mesh_off_its_frame_is_refused(quarter_20):
    import trimesh

    from threadmate.geometry import thread_meshes

    bolt, nut = thread_meshes(quarter_20)
    lifted = bolt.mesh.copy()
    lifted.apply_translation([0, 0, 0.01])
    with pytest.raises(InputError, match="frame"):
        ContactAnalyzer(quarter_20, bolt_mesh=lifted, nut_mesh=nut.mesh)
    assert isinstance(nut.mesh, trimesh.Trimesh)


def test_result_is_a_plain_object(results):
    r = results[(4, 0, 185)]
    assert isinstance(r, ContactResult)
    with pytest.raises(AttributeError):
        r.classification = "stable"  # frozen
