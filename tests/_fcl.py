"""python-fcl objects the tests build themselves, as the independent reference: one BVH
of a whole mesh (no sectors, none of the engine's strategy)."""

from __future__ import annotations

from typing import Any

import fcl
import numpy as np


def bvh(mesh: Any) -> fcl.BVHModel:
    """A python-fcl BVH of a trimesh mesh, whole."""
    model = fcl.BVHModel()
    model.beginModel(len(mesh.faces), len(mesh.vertices))  # (triangles, vertices)
    model.addSubModel(np.asarray(mesh.vertices, float), np.asarray(mesh.faces, np.int64))
    model.endModel()
    return model
