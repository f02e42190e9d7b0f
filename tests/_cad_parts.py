"""Real CAD-like parts built with trimesh booleans (manifold3d): bolts with a hex or round
head (thread, shank and head one manifold) and hex nuts with flats and a chamfer on both
faces, around threadmate's own threads. For the tests of meshes from CAD."""

from __future__ import annotations

import math
from dataclasses import dataclass

import manifold3d  # noqa: F401  (trimesh's boolean engine; the test extras install it)
import numpy as np
import trimesh

from threadmate.geometry import ThreadSpec, bolt_mesh, nut_mesh, spec_from_designation

MM_PER_IN = 25.4


@dataclass(frozen=True)
class Hex:
    """A standard hex size (ASME B18.2.1 / B18.2.2, ISO 4017 / 4032), in the spec's units."""

    across_flats: float
    head_height: float
    nut_height: float


#: 1/4 in: 7/16 across flats, head 5/32, nut 7/32; M6: 10 mm, head 4 mm, nut 5.2 mm.
HEX = {"in": Hex(7 / 16, 5 / 32, 7 / 32), "mm": Hex(10.0, 4.0, 5.2)}


def _boolean(kind: str, meshes: list[trimesh.Trimesh]) -> trimesh.Trimesh:
    op = {"union": trimesh.boolean.union, "intersection": trimesh.boolean.intersection}
    out = op[kind](meshes, engine="manifold")
    assert out.is_watertight and out.is_winding_consistent and out.volume > 0
    return out


def _revolved(profile: list[tuple[float, float]], sections: int) -> trimesh.Trimesh:
    """The solid of revolution about Z of a closed (r, z) profile (counter-clockwise)."""
    return trimesh.creation.revolve(np.array(profile, dtype=float), sections=sections)


def thread_spec(designation: str, thread_length: float, nut_height: float) -> ThreadSpec:
    """The designation's pair with the CAD parts' thread length and nut height (longer
    than the spec's defaults, as real parts are)."""
    return spec_from_designation(designation, bolt_length=thread_length, nut_height=nut_height)


def hex_bolt(spec: ThreadSpec, chord: float, shank: float) -> trimesh.Trimesh:
    """The spec's threaded bolt, a plain shank of ``shank`` above it and a hex head with a
    30-degree chamfer on its top: one manifold."""
    hx = HEX[spec.units]
    thread = bolt_mesh(spec, chord).mesh
    top = spec.bolt.length
    overlap = spec.pitch / 4
    # The shank a little under the major diameter (a rolled thread's blank).
    rs = 0.49 * spec.bolt.major
    shank_body = trimesh.creation.cylinder(radius=rs, height=shank + 2 * overlap, sections=64)
    shank_body.apply_translation([0, 0, top + shank / 2])
    corner = hx.across_flats / math.sqrt(3)  # the hexagon's circumradius
    head = trimesh.creation.cylinder(radius=corner, height=hx.head_height + overlap, sections=6)
    base = top + shank
    head.apply_translation([0, 0, base + (hx.head_height - overlap) / 2])
    # The chamfer on the head's top: a cone 30 degrees off the face from the across-flats
    # circle.
    z1 = base + hx.head_height
    r0 = 0.95 * hx.across_flats / 2
    drop = (corner * 1.1 - r0) * math.tan(math.radians(30))
    envelope = _revolved(
        [
            (0, base - overlap),
            (corner * 1.1, base - overlap),
            (corner * 1.1, z1 - drop),
            (r0, z1),
            (0, z1),
        ],
        64,
    )
    head = _boolean("intersection", [head, envelope])
    return _boolean("union", [thread, shank_body, head])


def round_bolt(spec: ThreadSpec, chord: float) -> trimesh.Trimesh:
    """The spec's threaded bolt with a round (button) head straight above the thread:
    one manifold."""
    hx = HEX[spec.units]
    thread = bolt_mesh(spec, chord).mesh
    top = spec.bolt.length
    overlap = spec.pitch / 4
    radius = 0.95 * hx.across_flats / 2
    height = 0.6 * hx.head_height
    # A spherical cap of that radius and height on a short cylinder.
    sphere_r = (radius**2 + height**2) / (2 * height)
    profile = [(0.0, top - overlap), (radius, top - overlap), (radius, top)]
    for a in np.linspace(math.asin(radius / sphere_r), 0.0, 17)[1:]:
        profile.append((sphere_r * math.sin(a), top + height - sphere_r * (1 - math.cos(a))))
    head = _revolved(profile, 64)
    return _boolean("union", [thread, head])


def hex_nut(spec: ThreadSpec, chord: float) -> trimesh.Trimesh:
    """The spec's threaded nut (its bore, countersunk as the spec says) inside hex flats,
    with a 30-degree chamfer on the corners of both faces: one manifold."""
    hx = HEX[spec.units]
    nut = nut_mesh(spec, chord).mesh
    height = spec.nut.height
    corner = hx.across_flats / math.sqrt(3)
    ring_in = 0.97 * float(spec.nut.major / 2 + spec.pitch)  # inside the nut's cylinder
    ring = trimesh.creation.annulus(r_min=ring_in, r_max=corner, height=height, sections=6)
    ring.apply_translation([0, 0, -height / 2])
    body = _boolean("union", [nut, ring])
    r0 = 0.95 * hx.across_flats / 2
    far = corner * 1.1
    drop = (far - r0) * math.tan(math.radians(30))
    envelope = _revolved(
        [(0, -height), (r0, -height), (far, -height + drop), (far, -drop), (r0, 0.0), (0, 0.0)],
        96,
    )
    return _boolean("intersection", [body, envelope])


def in_units(mesh: trimesh.Trimesh, spec_units: str, units: str) -> trimesh.Trimesh:
    """``mesh`` (in ``spec_units``) with its numbers in ``units``."""
    out = mesh.copy()
    if units != spec_units:
        out.apply_scale(MM_PER_IN if units == "mm" else 1 / MM_PER_IN)
    return out
