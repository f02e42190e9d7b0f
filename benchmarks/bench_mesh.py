"""Benchmark of the tessellated solids: build time, triangle counts, verified deviation.

Run ``python benchmarks/bench_mesh.py``. For each pair at the default chord (5e-6 in,
1.27e-4 mm) it prints the time to build and verify each mesh, its triangle count and its
largest deviation from the exact surface, then the cost of python-fcl queries on the pair
(a yes/no query and an all-pairs query with the bolt slightly into the nut), which the
contact stage runs about a hundred times per configuration. Each pair is meshed with its
ends as designated (chamfered point, countersink), with flat ends (the thesis's), and with
a round point; a point or countersink lengthens its body (one pitch beyond it), so the
triangles per pitch of length compare the lateral meshes.
"""

from __future__ import annotations

import time
from dataclasses import replace

import fcl
from _reference import bvh

from threadmate.geometry import (
    BoltPoint,
    Pose,
    ThreadSpec,
    bolt_mesh,
    nut_mesh,
    spec_from_designation,
)

PAIRS = ("1/4-20 UNC-2A/2B", "M6x1-6g/6H")


def _time(fn, repeat: int) -> float:
    start = time.perf_counter()
    for _ in range(repeat):
        fn()
    return (time.perf_counter() - start) / repeat


def _variants(spec: ThreadSpec) -> dict[str, ThreadSpec]:
    """The designated ends, flat ends and a round point (default lengths each)."""

    def ends(point: BoltPoint, sink: bool) -> ThreadSpec:
        bolt = replace(spec.bolt, point=point, length=None)
        nut = replace(spec.nut, countersink=spec.nut.countersink if sink else None, height=None)
        return replace(spec, bolt=bolt, nut=nut)

    return {
        "designated": spec,
        "flat": ends(BoltPoint(), False),
        "round": ends(BoltPoint("round"), True),
    }


def main() -> None:
    print(
        f"{'pair':18} {'ends':10} {'body':5} {'build+verify s':>14} {'triangles':>10} "
        f"{'per pitch':>10} {'max deviation':>14} {'chord':>10}"
    )
    for designation in PAIRS:
        built = {}
        for variant, spec in _variants(spec_from_designation(designation)).items():
            for name, make in (("bolt", bolt_mesh), ("nut", nut_mesh)):
                if variant == "round" and name == "nut":
                    continue  # the designated nut
                start = time.perf_counter()
                tb = make(spec)
                seconds = time.perf_counter() - start
                if variant == "flat":
                    built[name] = tb
                length = spec.bolt.length if name == "bolt" else spec.nut.height
                assert length is not None
                print(
                    f"{designation:18} {variant:10} {name:5} {seconds:14.3f} {tb.triangles:10d} "
                    f"{tb.triangles * spec.pitch / length:10.0f} {tb.max_deviation:14.3e} "
                    f"{tb.chord:10.3e}  {spec.units}"
                )
        bolt_o = fcl.CollisionObject(bvh(built["bolt"].mesh))
        nut_o = fcl.CollisionObject(bvh(built["nut"].mesh))
        thread_pitch = spec_from_designation(designation).pitch
        pose = Pose.from_angles(2.0, 0.0, 180.0, 0.04 * thread_pitch)
        bolt_o.setTransform(fcl.Transform(pose.rotation, pose.origin))

        def yes_no(bolt_o=bolt_o, nut_o=nut_o) -> bool:
            result = fcl.CollisionResult()
            return fcl.collide(bolt_o, nut_o, fcl.CollisionRequest(), result) > 0

        def all_pairs(bolt_o=bolt_o, nut_o=nut_o) -> int:
            result = fcl.CollisionResult()
            request = fcl.CollisionRequest(num_max_contacts=10**6, enable_contact=True)
            return fcl.collide(bolt_o, nut_o, request, result)

        pairs = all_pairs()
        print(
            f"{'':18} fcl yes/no {_time(yes_no, 200) * 1e3:.3f} ms, all {pairs} pairs "
            f"{_time(all_pairs, 50) * 1e3:.3f} ms (flat ends; roll 2, phase 180, tip 0.04 p "
            f"into nut)"
        )


if __name__ == "__main__":
    main()
