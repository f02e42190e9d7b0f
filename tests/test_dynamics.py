"""The independent dynamics check (docs/scripts/dynamics_check.py) on its closed-form case.

An upright, stiffly held bolt (k_r = 100 N m/rad) resting flat on the nut's top face is
turned in MuJoCo over the last few degrees before the in-phase window opens; it must
snap where the window opens (348.78 degrees for the flat 1/4-20) and drop by the axial
clearance ``(nut pd - bolt pd) / sqrt(3)`` (docs/mechanics.md, "Limits with closed
forms" and "Dynamics").
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

import pytest

pytest.importorskip("mujoco")

SCRIPT = Path(__file__).resolve().parents[1] / "docs" / "scripts" / "dynamics_check.py"


def _load() -> ModuleType:
    """Import the script as a module (it lives outside the package)."""
    spec = importlib.util.spec_from_file_location("dynamics_check", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow
def test_stiff_upright_snap_matches_closed_form() -> None:
    """The simulated snap of a stiff upright bolt: at the window's edge, by the clearance."""
    dc = _load()
    spec = dc.thesis_spec()
    phase, clearance = dc.closed_form(spec)
    # resting flat on the top face: the tip centre at the face, upright
    sim = dc.simulate(
        spec,
        (0.0, 0.0),
        100.0,
        (0.0, 0.0, 0.0, phase - 3.0),
        until=phase + 3.0,
        proof=30.0,
        log=False,
    )
    assert sim.snap is not None, f"no snap; jumps {sim.jumps}"
    assert abs(sim.snap.phase - phase) < 0.5
    assert abs(sim.snap.drop - clearance) < 0.05 * clearance
    # frictionless, hard contacts: the hulls barely interpenetrate on the way
    assert sim.penetration_by_stage["ride"] < 1e-6


def test_pieces_follow_the_chamfered_point_and_the_countersink() -> None:
    """The convex pieces of the default parts (45-degree chamfered point, 120-degree
    countersink): every vertex on or inside the exact body, some on each end's cone, the
    point's core a frustum down to the tip circle, and the hulls within a micrometre of
    the exact bodies both ways (docs/scripts/dynamics_check.py, "Geometry")."""
    import numpy as np

    from threadmate.geometry import bolt_body, nut_body, spec_from_designation

    dc = _load()
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    micrometre = 1e-6 / 0.0254  # in
    for body in (bolt_body(spec), nut_body(spec)):
        env = body.envelope
        assert env is not None and env.kind == "cone"
        parts = dc.pieces(body)
        v = np.concatenate([p.vertices for p in parts])
        outside = np.where(body.contains(v), 0.0, body.surface_distance(v))
        assert outside.max() < 1e-9
        # the cone clips the sections: vertices on it, none on its air side
        r = np.hypot(v[:, 0], v[:, 1])
        cone = env.side * (env.r0 + env.slope_rz * v[:, 2] - r)
        assert cone.min() > -1e-12
        assert (np.abs(cone) < 1e-12).sum() > 100
        outward, inward = dc.hull_deviation(body, parts)
        assert outward < micrometre and inward < 0.5 * micrometre
    core = [p for p in dc.pieces(bolt_body(spec)) if p.sector < 0]
    assert len(core) == 1
    tip = core[0].vertices[core[0].vertices[:, 2] == 0.0]
    assert np.allclose(np.hypot(tip[:, 0], tip[:, 1]), bolt_body(spec).envelope.r0)
