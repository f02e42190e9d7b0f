"""The compiled kernels: compiled where numba is installed, and grouping contact points as
a graph's connected components do."""

from __future__ import annotations

import numpy as np
from scipy.sparse.csgraph import connected_components
from scipy.spatial.distance import cdist


def test_kernels_are_compiled_with_an_on_disk_cache():
    from threadmate._compiled import COMPILED

    # An internal with no public form: the grouping of contact points.
    from threadmate.contact.scene._linkage import _linked

    # And the collision query's walk of the trees.
    from threadmate.contact.scene._obb import _crossing

    assert COMPILED
    for kernel in (_linked, _crossing):
        assert kernel._cache.__class__.__name__ == "FunctionCache"  # numba's cache=True


def test_contact_points_group_as_the_connected_components_of_their_links():
    from threadmate.contact.scene import single_linkage

    rng = np.random.default_rng(7)
    separation = 0.2
    cases = [rng.uniform(0.0, 1.0, (n, 3)) * rng.uniform(0.2, 3.0) for n in (1, 2, 5, 40, 300)]
    # Beyond 400 points, the grid's branch: scattered, and patches of a lattice a sixteenth
    # of the separation apart with holes (a flat face on a flat face), a few at once.
    cases += [rng.uniform(0.0, 1.0, (n, 3)) * rng.uniform(0.5, 4.0) for n in (450, 1200)]
    for _ in range(4):
        patches = []
        for _ in range(int(rng.integers(1, 5))):
            x, y = np.meshgrid(*(np.arange(int(rng.integers(5, 60))) for _ in range(2)))
            lattice = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
            corner = rng.uniform(0.0, 8.0, 3) * [1.0, 1.0, 0.05]
            patches.append(corner + lattice[rng.random(len(lattice)) < 0.7] * separation / 16)
        cases.append(np.concatenate(patches))
    assert sum(len(points) > 400 for points in cases) >= 4
    for points in cases:
        labels = single_linkage(points, separation)
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
    from threadmate.contact.scene import _kernels, _linkage, _obb
    from threadmate.geometry import _profile_distance, with_parts

    warm_kernels(reverse=True)
    warm_kernels()
    mech = Mechanics(with_parts("1/4-20 UNC-2A/2B"), Compliance())
    mech.settle(1.0, -1.0, 100.0)
    search(mech, 1.0, -1.0, 100.0, turns=0.05)
    kernels = [
        (module.__name__, name, kernel)
        for module in (_obb, _kernels, _linkage, _profile_distance)
        for name, kernel in vars(module).items()
        if hasattr(kernel, "signatures") and hasattr(kernel, "py_func")
    ]
    assert len(kernels) >= 10
    for module, name, kernel in kernels:
        assert len(kernel.signatures) <= 1, (module, name, kernel.signatures)
    assert all(len(k.signatures) == 1 for _, n, k in kernels if n in ("_build", "_crossing"))


def test_processes_warming_the_kernels_compile_each_step_once(tmp_path, monkeypatch):
    """Two processes warming at once (a pool's workers, in their alternate orders) take
    turns: each step is done first by one of them alone, and the other does it only once
    that one has finished (numba then loads what the first saved). Steps here stand in for
    the kernels: the first to run one "compiles" it (0.3 s, then marks it done), a later
    run "loads" it; each records when it ran."""
    import multiprocessing
    import time

    from threadmate.contact.scene import _warm

    done, log = tmp_path / "done", tmp_path / "log"
    done.mkdir()

    def step(name: str):
        def run() -> None:
            start = time.monotonic()
            compiled = not (done / name).exists()
            if compiled:
                time.sleep(0.3)
                (done / name).touch()
            with open(log, "a") as out:
                out.write(f"{name} {compiled} {start} {time.monotonic()}\n")

        run.__name__ = name
        return run

    monkeypatch.setattr(_warm, "_STEPS", tuple(step(n) for n in "abcd"))
    monkeypatch.setattr(_warm, "_lock_folder", lambda: tmp_path / "locks")
    context = multiprocessing.get_context("fork")
    workers = [context.Process(target=_warm.warm_kernels, args=(r,)) for r in (False, True)]
    for w in workers:
        w.start()
    for w in workers:
        w.join(30)
        assert w.exitcode == 0
    runs: dict[str, list[tuple[bool, float, float]]] = {}
    for line in log.read_text().splitlines():
        name, compiled, start, end = line.split()
        runs.setdefault(name, []).append((compiled == "True", float(start), float(end)))
    assert sorted(runs) == list("abcd")
    for name, (first, second) in ((n, sorted(r, key=lambda x: x[1])) for n, r in runs.items()):
        assert (first[0], second[0]) == (True, False), name  # compiled once, then loaded
        assert second[1] >= first[2], name  # not while the other compiled it
    # Each compiled two of the four (in its own order), none waiting for the other first.
    assert (
        max(end for r in runs.values() for _, _, end in r)
        - min(start for r in runs.values() for _, start, _ in r)
        < 4 * 0.3
    )


def test_kernels_warmed_aside_in_a_process_that_ends():
    from threadmate.contact import warm_kernels_aside

    process = warm_kernels_aside()
    assert process is not None and process.daemon  # this machine has two CPUs and fork
    # Asked again while it warms, the same process; once it has ended, a new one.
    second = warm_kernels_aside()
    assert second is process or process.exitcode is not None
    process.join(300)
    assert process.exitcode == 0
    again = warm_kernels_aside()
    assert again is not None and again is not process
    for p in (second, again):
        assert p is not None
        p.join(300)
        assert p.exitcode == 0


def test_warming_without_a_folder_for_its_lock_files_runs_every_step(monkeypatch, tmp_path):
    from threadmate.contact.scene import _warm

    ran: list[str] = []

    def step(name: str):
        def run() -> None:
            ran.append(name)

        run.__name__ = name
        return run

    blocked = tmp_path / "file"
    blocked.write_text("")  # a file where the folder would go: mkdir fails
    monkeypatch.setattr(_warm, "_STEPS", tuple(step(n) for n in "abcd"))
    monkeypatch.setattr(_warm, "_lock_folder", lambda: blocked / "locks")
    _warm.warm_kernels(reverse=True)
    assert ran == list("dcba")


def test_a_querys_face_pairs_are_numpys_unique_rows():
    """The distinct (bolt face, nut face) pairs of a query's rows, sorted, as numpy's
    lexicographic unique of the rows has them (empty, single, repeated, and face numbers
    up to the largest meshes')."""
    from threadmate.contact.scene._obb import unique_face_pairs

    rng = np.random.default_rng(2)
    for n, high in ((0, 10), (1, 10), (7, 3), (500, 60_000), (4000, 2_500_000)):
        rows = rng.integers(0, high, (n, 3)).astype(np.int64)
        rows = np.concatenate([rows, rows[: n // 2]])
        expected = np.unique(rows[:, :2], axis=0) if len(rows) else np.empty((0, 2), int)
        assert np.array_equal(unique_face_pairs(rows), expected)


def test_the_feature_at_a_point_is_pythons_to_the_last_bit():
    """The compiled feature classification (``contact.scene.feature_at``) gives what the
    same arithmetic in Python gives (``tests/_feature_reference.py``: Python's own
    ``math.hypot`` and ``** 2``, which the C library's differ from in the last bit of about
    one result in two hundred and one in a thousand), bit for bit: kind, normal, tangent
    and side, at points near every feature of five thread pairs (chamfered, flat and
    round points, countersunk and plain nuts, inch and metric) and on the kinks where a
    point or countersink meets the thread, within three tolerances."""
    import math

    from _feature_reference import feature_at as reference
    from threadmate.contact.scene import feature_at
    from threadmate.contact.scene._kernels import kink_height
    from threadmate.geometry import bolt_body, nut_body, spec_from_designation, with_parts

    specs = [
        with_parts("1/4-20 UNC-2A/2B"),
        spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False),
        with_parts("1/4-20 UNC-2A/2B", point="round"),
        with_parts("M6x1-6g/6H"),
        spec_from_designation("M10x1.5-6g/6H", point="flat", countersink=False),
    ]
    rng = np.random.default_rng(11)
    kinds: set[str] = set()
    for spec in specs:
        for body in (bolt_body(spec), nut_body(spec)):
            prof, env = body.profile, body.envelope
            for i in range(1500):
                theta = rng.uniform(-math.pi, math.pi)
                near_face = rng.random() < 0.3
                z = body.cap_z + prof.pitch * (
                    rng.uniform(-0.05, 0.05) if near_face else rng.uniform(-3.0, 3.0)
                )
                t = z - body.hand * body.lead * theta / (2 * math.pi)
                r = float(prof.radius(t)) + rng.normal() * (
                    1e-6 if rng.random() < 0.5 else 0.02 * prof.pitch
                )
                if env is not None and rng.random() < 0.5:
                    if rng.random() < 0.5:  # on the kink, or within a few tolerances of it
                        z = kink_height(body, theta, z) + rng.normal() * 2e-6
                    e = float(env.radius(z))
                    if math.isfinite(e):
                        r = e + rng.normal() * 2e-6
                p = np.array([r * math.cos(theta), r * math.sin(theta), z])
                tol = (1e-7, 2e-6, 5e-6)[i % 3]
                got, want = feature_at(body, p, tol), reference(body, p, tol)
                kinds.add(want.kind)
                assert got.kind == want.kind, (spec.designation, body.kind, p, tol)
                for a, b in ((got.normal, want.normal), (got.tangent, want.tangent)):
                    assert (a is None and b is None) or np.array_equal(a, b), (got, want)
                assert np.array_equal(got.side, want.side), (got, want)
    assert kinds == {"rim", "cap", "kink", "bevel", "corner", "thread"}


def _numpy_rounds_as_the_kernels() -> bool:
    """Whether numpy here rounds as the compiled kernels reproduce: its ``cos``, ``sin``
    and ``arctan2`` the C library's (``math``'s), its product of a few points by a 3 x 3
    matrix, per coordinate, a chain of fused multiply-adds, and of a few rows by a vector
    another (as OpenBLAS computes them on x86-64 processors with FMA; one row by a vector
    left to right); the exact products by ``fractions``."""
    import math
    from fractions import Fraction

    rng = np.random.default_rng(5)
    x, m = rng.normal(size=(40, 3)), rng.normal(size=(3, 3))
    if not (
        np.array_equal(np.cos(x[:, 0]), [math.cos(v) for v in x[:, 0]])
        and np.array_equal(np.sin(x[:, 0]), [math.sin(v) for v in x[:, 0]])
        and np.array_equal(np.arctan2(x[:, 1], x[:, 2]), list(map(math.atan2, x[:, 1], x[:, 2])))
    ):
        return False

    def fused(a: float, b: float, c: float) -> float:
        return float(Fraction(a) * Fraction(b) + Fraction(c))

    product, along = x @ m, x @ m[:, 1]
    return (
        all(
            product[i, j] == fused(x[i, 2], m[2, j], fused(x[i, 1], m[1, j], x[i, 0] * m[0, j]))
            for i in range(len(x))
            for j in range(3)
        )
        # A matrix by a vector: its own order; one row, left to right.
        and all(
            along[i] == fused(x[i, 2], m[2, 1], fused(x[i, 0], m[0, 1], x[i, 1] * m[1, 1]))
            for i in range(len(x))
        )
        and all(
            (x[i : i + 1] @ m[:, 1])[0] == x[i, 0] * m[0, 1] + x[i, 1] * m[1, 1] + x[i, 2] * m[2, 1]
            for i in range(len(x))
        )
    )


def test_the_search_along_an_edge_is_numpys_to_the_last_bit():
    """The compiled refinement of an edge-on-face contact (``contact.scene.refine_on_edge``:
    the point of the exact edge closest to, or deepest into, the other body) gives what
    numpy gave (``tests/_refine_reference.py``), bit for bit where numpy rounds as the
    kernel reproduces (else within a few rounding errors): at points on every kind of
    edge of either body (the circle where a point or countersink meets the end face, a
    flat end's outline, the kink, the profile's sharp corners) of four thread pairs, the
    bolt at tilted poses, and at the contacts of rest states."""
    import math

    from _refine_reference import refine_on_edge as reference
    from threadmate.contact import Compliance, Mechanics
    from threadmate.contact.scene import feature_at, refine_on_edge
    from threadmate.contact.scene._exact import _sharp_corners
    from threadmate.contact.scene._kernels import kink_height
    from threadmate.geometry import (
        Pose,
        bolt_body,
        nut_body,
        spec_from_designation,
        with_parts,
    )

    exact = _numpy_rounds_as_the_kernels()
    specs = [
        with_parts("1/4-20 UNC-2A/2B"),
        spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False),
        with_parts("1/4-20 UNC-2A/2B", point="round"),
        spec_from_designation("M10x1.5-6g/6H", point="flat", countersink=False),
    ]
    rng = np.random.default_rng(3)
    tol = 2e-6
    seen: set[tuple[str, str, str]] = set()
    cases = 0

    def compare(nut, bolt, pose, p, window):
        nonlocal cases
        fn, fb = feature_at(nut, p, tol), feature_at(bolt, pose.to_bolt(p), tol)
        if fn.is_edge == fb.is_edge:
            return
        got = refine_on_edge(nut, bolt, pose, p, tol, window)
        want = reference(nut, bolt, pose, p, window, fn, fb)
        if exact:
            assert np.array_equal(got, want), (fn.kind, fb.kind, got - want)
        else:  # pragma: no cover - numpy rounding otherwise here
            assert np.allclose(got, want, rtol=0.0, atol=1e-12), (fn.kind, fb.kind)
        edge = "nut" if fn.is_edge else "bolt"
        seen.add((edge, fn.kind if fn.is_edge else fb.kind, "envelope" if nut.envelope else ""))
        cases += 1

    for spec in specs:
        nut, bolt = nut_body(spec), bolt_body(spec)
        pitch = bolt.profile.pitch
        for _ in range(150):
            pose = Pose.from_angles(
                rng.uniform(-3.0, 3.0),
                rng.uniform(-3.0, 3.0),
                rng.uniform(0.0, 360.0),
                h=rng.uniform(-2.0, 2.0) * pitch,
                x=rng.normal() * 0.02 * pitch,
                y=rng.normal() * 0.02 * pitch,
            )
            body = nut if rng.random() < 0.5 else bolt
            prof, env = body.profile, body.envelope
            theta = rng.uniform(-math.pi, math.pi)
            kinds = ["rim", "corner"] + (["kink"] if env is not None else [])
            kind = kinds[rng.integers(len(kinds))]
            inward = 1.0 if body.kind == "bolt" else -1.0  # the body's material from its end
            if kind == "rim":
                z = body.cap_z
                r = env.face_radius if env else float(prof.radius(body.t_of(theta, z)))
            elif kind == "kink":
                z = kink_height(body, theta, body.cap_z + inward * 0.3 * env.depth)
                r = float(env.radius(z))
            else:
                corner = _sharp_corners(body)[rng.integers(len(_sharp_corners(body)))]
                t = corner * rng.choice([-1.0, 1.0])
                z = body.cap_z + inward * rng.uniform(1.0, 3.0) * pitch
                z += t - float(body.t_of(theta, z))
                r = float(prof.radius(t))
            q = np.array([r * math.cos(theta), r * math.sin(theta), z]) + rng.normal(size=3) * 1e-7
            compare(nut, bolt, pose, q if body is nut else pose.to_fixed(q), pitch / 80)
    # The contacts of rest states of the default parts, as the contact set refines them.
    mech = Mechanics(specs[0], Compliance())
    found = []
    for roll, pitch_angle, phase in [(1.0, -1.0, 100.0), (0.0, 2.0, 40.0), (-2.0, 1.0, 250.0)]:
        state = mech.settle(roll, pitch_angle, phase).state
        found += [(state.pose, c.point) for c in state.contacts]
    assert found
    for pose, point in found:
        compare(mech.scene.nut, mech.scene.bolt, pose, np.asarray(point), mech.separation / 4)
    assert cases >= 300
    assert {(e, k) for e, k, _ in seen} >= {
        ("nut", "rim"),
        ("nut", "kink"),
        ("nut", "corner"),
        ("bolt", "rim"),
        ("bolt", "kink"),
        ("bolt", "corner"),
    }
    assert {("bolt", "rim", "envelope"), ("bolt", "rim", "")} <= seen


def test_the_paired_triangles_are_numpys_to_the_last_bit():
    """The compiled placement of paired triangles (``CollisionPair.triangles``: the bolt's
    in the fixed frame at a pose, the nut's as they are) gives ``Pose.to_fixed``'s numbers
    bit for bit where numpy rounds as the kernel reproduces (else within rounding): at
    random pairs of the default parts' meshes and random tilted poses."""
    from threadmate.contact import Compliance, Mechanics
    from threadmate.geometry import Pose, with_parts

    exact = _numpy_rounds_as_the_kernels()
    engine = Mechanics(with_parts("1/4-20 UNC-2A/2B"), Compliance()).engine
    rng = np.random.default_rng(8)
    for n in (0, 1, 2, 7, 300):
        for _ in range(20):
            pose = Pose.from_angles(*rng.uniform(-5.0, 5.0, 2), rng.uniform(0.0, 360.0), h=0.1)
            pairs = np.column_stack(
                [
                    rng.integers(len(engine.bolt_faces), size=n),
                    rng.integers(len(engine.nut_faces), size=n),
                ]
            )
            bolt, nut = engine.triangles(pose, pairs)
            want = pose.to_fixed(engine.bolt_vertices[engine.bolt_faces[pairs[:, 0]]])
            assert bolt.shape == nut.shape == (n, 3, 3)
            assert np.array_equal(nut, engine.nut_vertices[engine.nut_faces[pairs[:, 1]]])
            if exact:
                assert np.array_equal(bolt, want)
            else:  # pragma: no cover - numpy rounding otherwise here
                assert np.allclose(bolt, want, rtol=0.0, atol=1e-12)


def test_the_contact_rows_are_numpys_to_the_last_bit():
    """The compiled contact rows of the descent (``Mechanics._rows``: each contact's gap
    rate per unit of the bolt's coordinates, and its normal gap) give what the numpy code
    gave, bit for bit where numpy rounds as the kernel reproduces (else within rounding):
    one to ten random contacts above and below the bolt, held laterally and not."""
    import math

    from threadmate.contact import Compliance, Mechanics
    from threadmate.contact.mechanics._contact_set import _Near  # no public form
    from threadmate.geometry import rot_x, with_parts

    def reference(mech, near, centre, tilt):  # the numpy code the kernel replaced
        m = mech.metres
        pitch_axis = rot_x(math.degrees(tilt[0]))[:, 1]
        normal = np.array([c.normal for c in near], dtype=float)
        r = (np.array([c.point for c in near], dtype=float) - centre) * m
        moment = np.column_stack(
            [
                r[:, 1] * normal[:, 2] - r[:, 2] * normal[:, 1],
                r[:, 2] * normal[:, 0] - r[:, 0] * normal[:, 2],
                r[:, 0] * normal[:, 1] - r[:, 1] * normal[:, 0],
            ]
        )
        cols = [normal[:, 2], moment[:, 0], moment @ pitch_axis]
        if not mech.compliance.held_laterally:
            cols += [normal[:, 0], normal[:, 1]]
        rate = [max(-c.normal[2] if c.upper else c.normal[2], 0.05) for c in near]
        gaps = np.array([c.gap for c in near], dtype=float) * m
        return np.column_stack(cols), gaps * np.array(rate)

    exact = _numpy_rounds_as_the_kernels()
    spec = with_parts("1/4-20 UNC-2A/2B")
    rng = np.random.default_rng(12)
    for compliance in (Compliance(), Compliance(lateral_stiffness=2000.0)):
        mech = Mechanics(spec, compliance)
        assert mech.compliance.held_laterally == (compliance.lateral_stiffness is None)
        for _ in range(300):
            near = []
            for _ in range(int(rng.integers(1, 11))):
                normal = rng.normal(size=3)
                near.append(
                    _Near(
                        rng.normal(size=3) * 0.1,
                        normal / np.linalg.norm(normal),
                        float(rng.uniform(0.0, 1e-4)),
                        "flank",
                        "flank",
                        "thread",
                        "thread",
                        upper=bool(rng.random() < 0.3),
                    )
                )
            centre, tilt = rng.normal(size=3) * 0.1, rng.normal(size=2) * 0.05
            got, want = mech._rows(near, centre, tilt), reference(mech, near, centre, tilt)
            assert got[0].shape == want[0].shape
            for a, b in zip(got, want, strict=True):
                if exact:
                    assert np.array_equal(a, b)
                else:  # pragma: no cover - numpy rounding otherwise here
                    assert np.allclose(a, b, rtol=1e-12, atol=1e-300)
        assert mech._rows([], np.zeros(3), np.zeros(2))[0].shape == (
            0,
            3 if compliance.lateral_stiffness is None else 5,
        )
