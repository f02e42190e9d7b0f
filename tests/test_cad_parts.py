"""Real CAD parts through ``settle`` and ``search`` (issue 26): bolts with a hex or a round
head (thread, shank and head one manifold) and hex nuts with flats and a chamfer on both
faces, built with trimesh booleans (manifold3d) around threadmate's own threads, for a
1/4-20 and an M6, as OBJ in mm and in inches; and meshes whose ends differ from the
spec's (a chamfered point, a countersink) given with a spec of flat ends.

The parts' threads are threadmate's generated meshes, so where the thread is they follow
the spec within their chord: the rest state on them is the generated meshes' within the
mesh tolerance, and no contact lies on a head or on the flats. A mesh whose ends the spec
does not state is taken as given: its rest state is that of the spec that states them.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from _cad_parts import HEX, MM_PER_IN, hex_bolt, hex_nut, in_units, round_bolt, thread_spec
from _cli import run_captured, run_json
from threadmate import MeshError
from threadmate.geometry import bolt_body, load_mesh, spec_from_designation

QUARTER, M6 = "1/4-20 UNC-2A/2B", "M6x1-6g/6H"
#: Per size: a coarse chord (spec units; a few thousandths of the pitch, for speed), the
#: parts' thread length and plain shank (real parts are longer than the spec's default).
SIZES = {QUARTER: (2e-4, 0.3, 0.1), M6: (5e-3, 8.0, 2.0)}
#: A held tilt and start phase whose rest state every pair here reaches (the generated
#: meshes too) at these chords: the descent converges (a balance within 1e-6 of the load).
CONFIG = ["--roll", "1", "--pitch", "0", "--phase", "185"]


@pytest.fixture(scope="module")
def parts(tmp_path_factory) -> dict[str, Any]:
    """Per size: the parts as OBJ in mm and in inches, their volumes (spec units^3)."""
    folder = tmp_path_factory.mktemp("cad")
    out: dict[str, Any] = {}
    for designation, (chord, length, shank) in SIZES.items():
        spec = thread_spec(designation, length, "standard")
        built = {
            "hex_bolt": hex_bolt(spec, chord, shank),
            "round_bolt": round_bolt(spec, chord),
            "nut": hex_nut(spec, chord),
        }
        files: dict[tuple[str, str], Path] = {}
        for name, mesh in built.items():
            for units in ("in", "mm"):
                path = folder / f"{spec.units}_{name}_{units}.obj"
                in_units(mesh, spec.units, units).export(path)
                files[name, units] = path
        out[designation] = {
            "built": built,
            "files": files,
            "volume": {name: float(m.volume) for name, m in built.items()},
            "units": spec.units,
            "chord": chord,
        }
    return out


def _kind(name: str) -> str:
    return "nut" if name == "nut" else "bolt"


#: Exit statuses of the commands here: 0, or 3 for a search that does not snap.
DONE = (0, 3)


# -- the size where the thread is --------------------------------------------------------
@pytest.mark.parametrize("designation", [QUARTER, M6])
@pytest.mark.parametrize("units", ["in", "mm"])
@pytest.mark.parametrize("name", ["hex_bolt", "round_bolt", "nut"])
def test_headed_bolts_and_hex_nuts_load_in_both_units(parts, designation, units, name):
    spec = spec_from_designation(designation)
    part = parts[designation]
    path = part["files"][name, units]
    mesh = load_mesh(path, _kind(name), spec=spec, units=units)
    # Scaled into the spec's units: the part's own volume (trimesh's, of the built part).
    assert mesh.volume == pytest.approx(part["volume"][name], rel=1e-6)
    if name != "nut":
        # The head reaches out to the hexagon's corners (across flats / sqrt 3) or the
        # round head's rim: well beyond the size band of the spec's major radius, so a
        # size read over the whole mesh refuses it.
        r = np.hypot(mesh.vertices[:, 0], mesh.vertices[:, 1]).max()
        head = HEX[spec.units].across_flats / (math.sqrt(3) if name == "hex_bolt" else 2.08)
        assert r == pytest.approx(head, rel=0.02)
        assert r > 1.6 * spec.bolt.major / 2


def test_size_is_judged_where_the_thread_is(tmp_path):
    # An M8 thread under the M6 head, given as an M6: refused, the radius read over the
    # M6's bolt length with its unit, the M8's major radius.
    m6 = spec_from_designation(M6)
    m8 = thread_spec("M8", 8.0, "standard")
    path = tmp_path / "m8_as_m6.obj"
    hex_bolt(m8, 5e-3, 2.0).export(path)
    with pytest.raises(MeshError) as info:
        load_mesh(path, "bolt", spec=m6, units="mm")
    text = str(info.value)
    numbers = dict(re.findall(r"(its major radius|the spec's) is ([0-9.]+) mm", text))
    assert float(numbers["its major radius"]) == pytest.approx(m8.bolt.major / 2, abs=5e-3)
    assert float(numbers["the spec's"]) == pytest.approx(m6.bolt.major / 2, rel=1e-6)
    assert f"z 0 to {m6.bolt.length:.6g} mm" in text
    # A headed inch bolt exported in mm, given without units: the hint still reads the thread.
    quarter = spec_from_designation(QUARTER)
    bolt = hex_bolt(thread_spec(QUARTER, 0.3, "standard"), 2e-4, 0.1)
    mm = tmp_path / "quarter_mm.obj"
    in_units(bolt, "in", "mm").export(mm)
    with pytest.raises(MeshError, match=r"in but the spec's is 0\.122425 in: it looks like mm"):
        load_mesh(mm, "bolt", spec=quarter)


# -- the pipeline on them ----------------------------------------------------------------
@pytest.mark.parametrize(
    "designation, units, bolt",
    [(QUARTER, "mm", "hex_bolt"), (QUARTER, "in", "round_bolt"), (M6, "in", "hex_bolt")],
)
def test_settle_on_cad_parts_is_the_generated_meshes_rest(parts, capsys, designation, units, bolt):
    part = parts[designation]
    chord = part["chord"]
    files = part["files"]
    _, gen, _ = run_json(capsys, "settle", designation, *CONFIG, "--chord", chord, codes=DONE)
    args = ["--bolt-mesh", files[bolt, units], "--nut-mesh", files["nut", units]]
    _, own, err = run_json(
        capsys, "settle", designation, *CONFIG, *args, "--mesh-units", units, codes=DONE
    )
    assert own["balance"]["converged"] and gen["balance"]["converged"]
    assert own["classification"] == gen["classification"]
    # The threads are the generated meshes (float rounding of the OBJ aside).
    tol = 4 * chord
    np.testing.assert_allclose(own["rest"]["origin"], gen["rest"]["origin"], atol=tol)
    assert own["potential"] == pytest.approx(gen["potential"], rel=1e-3)
    # Nothing touches the head or the flats, and the contact zone follows the spec.
    assert {c["bolt_region"] for c in own["contacts"]} == {
        c["bolt_region"] for c in gen["contacts"]
    }
    assert all(c["nut_region"] != "other" and c["bolt_region"] != "other" for c in own["contacts"])
    for kind in ("bolt", "nut"):
        block = own["mesh"][kind]
        assert block["units"] == units
        assert block["scale"] == pytest.approx(
            1.0 if units == part["units"] else (MM_PER_IN if units == "in" else 1 / MM_PER_IN)
        )
        assert block["zone_off_spec_share"] < 0.02
        assert block["deviation"] <= 2 * chord
    assert "Traceback" not in err


@pytest.mark.parametrize("designation, units", [(QUARTER, "mm"), (M6, "in")])
def test_search_a_short_turn_on_cad_parts(parts, capsys, designation, units):
    part = parts[designation]
    files = part["files"]
    args = ["--bolt-mesh", files["hex_bolt", units], "--nut-mesh", files["nut", units]]
    start = [*CONFIG, "--turns", "0.05", "--step", "5"]
    rc, doc, err = run_json(
        capsys, "search", designation, *start, *args, "--mesh-units", units, codes=DONE
    )
    _, gen, _ = run_json(
        capsys, "search", designation, *start, "--chord", part["chord"], codes=DONE
    )
    assert doc["units"]["length"] == gen["units"]["length"] == part["units"]
    assert (doc["snap"] is None) == (gen["snap"] is None)
    # 18 degrees turned against friction: work done, as on the generated meshes.
    assert doc["work"]["total"] > 0
    assert doc["work"]["total"] == pytest.approx(gen["work"]["total"], rel=0.05)
    assert doc["mesh"]["bolt"]["units"] == units and "Traceback" not in err


# -- ends the spec does not state (issue 26, item 1) ---------------------------------------
@pytest.fixture(scope="module")
def chamfered_meshes(tmp_path_factory) -> dict[str, Path]:
    """``threadmate mesh`` of the designation: a chamfered bolt and a countersunk nut."""
    folder = tmp_path_factory.mktemp("ends")
    code, _, err = run_captured("mesh", QUARTER, "-o", folder, "--chord", "2e-4")
    assert code == 0, err
    return {"bolt": folder / "bolt.stl", "nut": folder / "nut.stl"}


FLAT = ["--point", "flat", "--no-countersink"]


@pytest.mark.parametrize(
    "given, stated",
    [
        (["bolt"], ["--no-countersink"]),  # the chamfered bolt: a spec with its point
        (["nut"], ["--point", "flat"]),  # the countersunk nut: a spec with its countersink
        (["bolt", "nut"], []),  # both: the designation's own ends
    ],
)
def test_meshes_with_ends_the_spec_does_not_state_settle_as_given(
    chamfered_meshes, capsys, given, stated
):
    files = [a for kind in given for a in (f"--{kind}-mesh", chamfered_meshes[kind])]
    # (The body not given is generated at the default chord; the reference's at the files'.)
    _, own, err = run_json(capsys, "settle", QUARTER, *FLAT, *CONFIG, *files, codes=DONE)
    _, ref, _ = run_json(capsys, "settle", QUARTER, *stated, *CONFIG, "--chord", "2e-4", codes=DONE)
    assert own["balance"]["converged"] and ref["balance"]["converged"]
    assert own["classification"] == ref["classification"]
    # The rest state of the spec that states the ends, within the mesh's tolerance.
    np.testing.assert_allclose(own["rest"]["origin"], ref["rest"]["origin"], atol=1e-4)
    assert own["potential"] == pytest.approx(ref["potential"], rel=2e-3)
    assert len(own["contacts"]) == len(ref["contacts"])
    names = {"chamfer": "point", "countersink": "countersink", "base": "base"}
    for mine in own["contacts"]:
        # The stated spec's contact there: at the same place, with the same normal; the
        # off-spec ends labelled by where they lie (the chamfer "point").
        theirs = min(
            ref["contacts"],
            key=lambda c: float(np.linalg.norm(np.subtract(c["point"], mine["point"]))),
        )
        # (Along the bore's round edge a near-upright bolt's support is flat: a few
        # degrees about the axis apart.)
        assert np.linalg.norm(np.subtract(theirs["point"], mine["point"])) < 0.2 * 0.05
        assert mine["bolt_region"] == names[theirs["bolt_region"]]
        assert mine["nut_region"] == theirs["nut_region"]
        # Where a face touches, its normal; edge on edge (where the chamfer meets the
        # thread, on the bore's edge or the countersink's), the cross product of the two
        # edges, one the mesh's polyline, whose segments at this chord run some degrees
        # off the exact curve (a steep one: a cone cut by the flank's helicoid).
        edges = {"mesh-edge", "rim", "kink", "corner"}
        both = mine["bolt_feature"] in edges and mine["nut_feature"] in edges
        cos = float(np.dot(mine["normal"], theirs["normal"]))
        assert math.degrees(math.acos(min(1.0, cos))) < (25.0 if both else 3.0)
    if given == ["bolt"]:
        # The nut's bore edge on the chamfer's face: the normal is the 45-degree cone's
        # (from the chamfered spec's exact body), not the flat spec's flank or tip face.
        cone = bolt_body(spec_from_designation(QUARTER))
        rot = np.array(own["rest"]["rotation"])
        origin = np.array(own["rest"]["origin"])
        on_face = [c for c in own["contacts"] if c["bolt_feature"] == "mesh"]
        assert on_face
        for c in on_face:
            p = rot.T @ (np.array(c["point"]) - origin)
            r = math.hypot(p[0], p[1])
            assert float(cone.surface_distance(p)) <= 5 * 2e-4
            outward = np.array([p[0] / r, p[1] / r, -1.0]) / math.sqrt(2)  # the cone's
            angle = math.degrees(math.acos(min(1.0, float(-(rot @ outward) @ c["normal"]))))
            assert angle < 3.0, angle
    assert "Traceback" not in err
    assert "contact zone lies off the spec" in err


@pytest.mark.parametrize(
    "given, stated", [("bolt", ["--no-countersink"]), ("nut", ["--point", "flat"])]
)
def test_meshes_with_other_ends_than_the_spec_search_a_short_turn(
    chamfered_meshes, capsys, given, stated
):
    files = [f"--{given}-mesh", chamfered_meshes[given]]
    start = [*CONFIG, "--turns", "0.05", "--step", "5"]
    rc, own, err = run_json(capsys, "search", QUARTER, *FLAT, *start, *files, codes=DONE)
    _, ref, _ = run_json(capsys, "search", QUARTER, *stated, *start, "--chord", "2e-4", codes=DONE)
    assert (own["snap"] is None) == (ref["snap"] is None)
    # 18 degrees turned on the end the spec does not state: the friction of the spec that
    # states it (the faceted end rocks the bolt by a chord or so, which the potential sees).
    assert own["work"]["friction"] == pytest.approx(ref["work"]["friction"], rel=0.02)
    assert "Traceback" not in err


def test_the_parts_are_one_manifold_each(parts):
    # One closed shell each: the booleans fused thread, shank and head into one body.
    for part in parts.values():
        for name, mesh in part["built"].items():
            assert mesh.is_watertight and mesh.is_winding_consistent, name
            assert mesh.body_count == 1 and mesh.volume > 0, name
