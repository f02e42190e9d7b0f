"""The benchmarks' unit of cost: one yes/no python-fcl ``collide`` of the thread pair.

A *query equivalent* (QE) is the CPU time of one yes/no ``fcl.collide`` of the bolt and
nut meshes, each one BVH of the whole mesh (python-fcl's own query, built here from
:func:`threadmate.geometry.thread_meshes`, not threadmate's collision engine, whose
strategy, such as asking the nut by sectors, is part of what is measured). It is timed at
poses the run produced, lifted and lowered by the descent's tolerance: the bodies free
but close all round, and just colliding (the mean of the two).
"""

from __future__ import annotations

import time

import fcl
import numpy as np
import trimesh

from threadmate.geometry import Pose, ThreadSpec, thread_meshes


def bvh(mesh: trimesh.Trimesh) -> fcl.BVHModel:
    """A python-fcl BVH of a trimesh mesh."""
    model = fcl.BVHModel()
    model.beginModel(len(mesh.faces), len(mesh.vertices))  # (triangles, vertices): hints
    model.addSubModel(np.asarray(mesh.vertices, float), np.asarray(mesh.faces, np.int64))
    model.endModel()
    return model


class ReferenceQuery:
    """The yes/no query of the pair's whole meshes (bolt in its frame, nut fixed)."""

    def __init__(self, spec: ThreadSpec, chord: float | None = None) -> None:
        bolt, nut = thread_meshes(spec, chord)
        self.bolt = fcl.CollisionObject(bvh(bolt.mesh), fcl.Transform())
        self.nut = fcl.CollisionObject(bvh(nut.mesh), fcl.Transform())
        self.request = fcl.CollisionRequest(num_max_contacts=1, enable_contact=False)

    def collides(self, pose: Pose) -> bool:
        self.bolt.setTransform(fcl.Transform(pose.rotation, pose.origin))
        return fcl.collide(self.bolt, self.nut, self.request, fcl.CollisionResult()) > 0

    def cpu_time(self, poses: list[Pose], tolerance: float, repeats: int = 50) -> float:
        """Mean CPU time (s) of one query at ``poses`` lifted and lowered by ``tolerance``
        (CPU time, as the work it divides; of the calling thread, so that a thread timing
        it beside other work times the query alone)."""
        times = []
        for pose in poses:
            for dz in (tolerance, -tolerance):
                moved = pose.translated([0.0, 0.0, dz])
                t = time.thread_time()
                for _ in range(repeats):
                    self.collides(moved)
                times.append((time.thread_time() - t) / repeats)
        return float(np.mean(times))
