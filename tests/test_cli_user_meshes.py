"""``--bolt-mesh``, ``--nut-mesh`` and ``--mesh-units`` end to end on ``contact``, ``settle``,
``search``, ``sweep`` and ``run``: real meshes written by threadmate itself (STL, and OBJ
and PLY through trimesh, in inches and in mm), real python-fcl.

The generated meshes written to files must give the generated meshes' results (within the
mesh tolerance); a chamfered CAD bolt on a flat spec must put ``point`` on the contacts on
its chamfer; bad files exit 2 with one line and write nothing.
"""

from __future__ import annotations

import hashlib
import json
import pickle
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import trimesh

from _cad_parts import MM_PER_IN
from _cli import run_captured, run_cli, run_json
from _libraries import library_rows
from threadmate.contact import OFF_SPEC_REGIONS, Compliance
from threadmate.geometry import (
    BoltPoint,
    ThreadSpec,
    bolt_body,
    read_stl,
    save_spec,
    write_stl,
)
from threadmate.library import METADATA_FILE, Grid

CHORD = "1e-4"  # coarse meshes, for speed (in)
STEP = "10"  # continuation step (deg), for speed
CONFIG = ["--roll", "4", "--pitch", "0", "--phase", "185"]
# The sweep's and the run's grid: one held tilt, two start phases (the run's smallest).
GRID = ["--roll", "0", "--pitch", "0", "--phase", "300,330"]


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def specs(quarter_20, tmp_path_factory) -> dict[str, Path]:
    """The flat 1/4-20 (the thesis's parts) and the same pair with a chamfered bolt."""
    folder = tmp_path_factory.mktemp("specs")
    chamfered = ThreadSpec(
        units=quarter_20.units,
        pitch=quarter_20.pitch,
        bolt=type(quarter_20.bolt)(
            major=quarter_20.bolt.major,
            pitch_diameter=quarter_20.bolt.pitch_diameter,
            minor=quarter_20.bolt.minor,
            root_fillet=quarter_20.bolt.root_fillet,
            point=BoltPoint("chamfer"),
        ),
        nut=quarter_20.nut,
    )
    return {
        "flat": save_spec(quarter_20, folder / "flat.json"),
        "chamfered": save_spec(chamfered, folder / "chamfered.json"),
    }


@pytest.fixture(scope="module")
def meshes(specs, tmp_path_factory, capsys_module) -> dict[str, Path]:
    """Mesh files: threadmate's own STL (``threadmate mesh``, header units=in), the same
    bodies as OBJ in mm (no units in the file), as PLY in inches and as a binary STL in mm
    whose header says so; the chamfered spec's bolt; and broken files."""
    folder = tmp_path_factory.mktemp("meshes")
    for name in ("flat", "chamfered"):
        capsys_module("mesh", specs[name], "-o", folder / name, "--chord", CHORD)
    bolt, nut = folder / "flat" / "bolt.stl", folder / "flat" / "nut.stl"
    b, n = read_stl(bolt), read_stl(nut)
    files = {"bolt": bolt, "nut": nut, "chamfered_bolt": folder / "chamfered" / "bolt.stl"}
    for name, mesh, scale, path in (
        ("bolt_obj_mm", b, MM_PER_IN, folder / "bolt_mm.obj"),
        ("nut_obj_mm", n, MM_PER_IN, folder / "nut_mm.obj"),
        ("bolt_ply", b, 1.0, folder / "bolt.ply"),
        ("nut_ply", n, 1.0, folder / "nut.ply"),
    ):
        m = mesh.copy()
        m.apply_scale(scale)
        m.export(path)
        files[name] = path
    mm = b.copy()
    mm.apply_scale(MM_PER_IN)
    files["bolt_stl_mm"] = write_stl(mm, folder / "bolt_mm.stl", "threadmate units=mm bolt")
    broken = trimesh.Trimesh(b.vertices, b.faces[1:], process=False)  # one triangle missing
    broken.export(folder / "open.stl")
    files["open"] = folder / "open.stl"
    lifted = b.copy()
    lifted.apply_translation([0.0, 0.0, 0.01])  # tip face at z = 0.01, not 0
    lifted.export(folder / "lifted.ply")
    files["lifted"] = folder / "lifted.ply"
    files["furlong"] = write_stl(b, folder / "furlong.stl", "cad export units=furlong")
    v = np.asarray(b.vertices, dtype=float).copy()
    v[[5, 6]] = np.nan
    trimesh.Trimesh(v, b.faces, process=False).export(folder / "nan.ply")
    files["nan"] = folder / "nan.ply"
    return files


@pytest.fixture(scope="module")
def generated_contact(specs, capsys_module) -> dict[str, Any]:
    """``contact --json`` on the generated meshes."""
    return capsys_module("contact", specs["flat"], *CONFIG, "--chord", CHORD)


@pytest.fixture(scope="module")
def capsys_module():
    """Run a command in-process with --json outside a test's capsys (module fixtures)."""

    def call(*args: Any) -> dict[str, Any]:
        code, out, err = run_captured(*args, "--json")
        assert code == 0, err
        return json.loads(out)

    return call


def _contacts(doc: dict[str, Any]) -> list[dict[str, Any]]:
    return [c for stage in doc["stages"].values() for c in stage["contacts"]]


def _same_stages(a: dict[str, Any], b: dict[str, Any], tol: float) -> None:
    """Two contact documents agree within ``tol`` (spec units): class, stages, contacts."""
    assert a["classification"] == b["classification"]
    for name in ("first", "second", "third"):
        sa, sb = a["stages"][name], b["stages"][name]
        assert sa["found"] == sb["found"], name
        if not sa["found"]:
            continue
        np.testing.assert_allclose(sa["origin"], sb["origin"], atol=tol)
        assert len(sa["contacts"]) == len(sb["contacts"]), name
        for ca, cb in zip(sa["contacts"], sb["contacts"], strict=True):
            np.testing.assert_allclose(ca["point"], cb["point"], atol=tol)


# -- contact -----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "bolt, nut, units, scale",
    [
        ("bolt", "nut", None, 1.0),  # threadmate's STL: units=in from the header
        ("bolt_obj_mm", "nut_obj_mm", "mm", 1 / MM_PER_IN),  # OBJ in mm, said on the line
        ("bolt_ply", "nut_ply", None, 1.0),  # PLY: no units, the spec's
        ("bolt_stl_mm", "nut", None, 1 / MM_PER_IN),  # STL whose header says mm
    ],
)
def test_contact_on_the_generated_meshes_as_files(
    specs, meshes, generated_contact, capsys, bolt, nut, units, scale
):
    args = ["--bolt-mesh", meshes[bolt], "--nut-mesh", meshes[nut]]
    if units:
        args += ["--mesh-units", units]
    _, doc, err = run_json(capsys, "contact", specs["flat"], *CONFIG, "--chord", CHORD, *args)
    gen = generated_contact
    tol = gen["tolerances"]["feature"]
    _same_stages(doc, gen, tol)
    # The files follow the spec everywhere: no contact is labelled off the spec.
    for c in _contacts(doc):
        assert c["bolt_region"] not in OFF_SPEC_REGIONS
        assert c["nut_region"] not in OFF_SPEC_REGIONS
    block = doc["mesh"]
    for kind, name in (("bolt", bolt), ("nut", nut)):
        part = block[kind]
        assert part["file"] == meshes[name].name
        assert part["sha256"] == _digest(meshes[name])
        assert part["units"] == ("mm" if name.endswith("mm") else "in")
        # Measured where the mesh follows the spec: the chord (float32 rounding aside).
        assert 0 < part["deviation"] <= float(CHORD) * 1.01
        assert part["off_spec_share"] == 0.0 and part["zone_off_spec_share"] == 0.0
        assert part["warning"] is None
    assert block["bolt"]["scale"] == pytest.approx(scale)
    assert block["off_spec_tolerance"] > doc["tolerances"]["feature"]
    assert gen["mesh"]["bolt"]["generated"] is True
    assert gen["mesh"]["bolt"]["chord"] == float(CHORD)
    assert gen["mesh"]["off_spec_tolerance"] is None
    if scale != 1.0:
        assert f"scaled by {scale:.6g} into the spec's in" in err
    else:
        assert "scaled" not in err


def test_flat_spec_on_a_chamfered_cad_bolt_labels_the_chamfer_point(
    specs, meshes, generated_contact, quarter_20, capsys
):
    _, doc, err = run_json(
        capsys,
        "contact",
        specs["flat"],
        *CONFIG,
        "--chord",
        CHORD,
        "--bolt-mesh",
        meshes["chamfered_bolt"],
    )
    block = doc["mesh"]["bolt"]
    # The chamfer is off the flat spec, and does not blow the tolerances up: the deviation
    # stays a few chords (the chamfer is some 0.01 in deep).
    assert block["deviation"] <= 3 * float(CHORD)
    assert 0.1 < block["zone_off_spec_share"] < 0.5
    assert block["warning"] and "contact zone lies off the spec" in block["warning"]
    assert "threadmate: warning: bolt mesh bolt.stl" in err and len(err.splitlines()) == 1
    off = doc["mesh"]["off_spec_tolerance"]
    assert off == pytest.approx(
        doc["tolerances"]["feature"] + 3 * doc["tolerances"]["mesh_deviation"]
    )

    # Independently: every contact labelled point lies on the chamfer (near the chamfered
    # spec's exact bolt, far from the flat one's, within the point's height); every
    # contact not so labelled lies on the flat spec's surface.
    chamfered = ThreadSpec.from_dict(json.loads(specs["chamfered"].read_text()))
    on_chamfer, on_flat = bolt_body(chamfered), bolt_body(quarter_20)
    labelled = 0
    for stage in doc["stages"].values():
        if not stage["found"]:
            continue
        R, origin = np.array(stage["rotation"]), np.array(stage["origin"])
        for c in stage["contacts"]:
            p = R.T @ (np.array(c["point"]) - origin)  # bolt frame
            d_flat = float(on_flat.surface_distance(p))
            if c["bolt_region"] == "point":
                labelled += 1
                assert d_flat > off
                assert float(on_chamfer.surface_distance(p)) <= 2 * float(CHORD)
                assert p[2] <= chamfered.point_height + 2 * float(CHORD)
            else:
                assert d_flat <= off
    assert labelled >= 1
    # The generated flat bolt has no point: nothing is labelled so there.
    assert all(c["bolt_region"] != "point" for c in _contacts(generated_contact))


# -- settle and search ---------------------------------------------------------------------
def test_settle_and_search_on_the_generated_meshes_as_files(specs, meshes, capsys):
    files = ["--bolt-mesh", meshes["bolt_ply"], "--nut-mesh", meshes["nut"]]
    base = ["--chord", CHORD]
    _, gen, _ = run_json(capsys, "settle", specs["flat"], *CONFIG, *base)
    _, own, _ = run_json(capsys, "settle", specs["flat"], *CONFIG, *base, *files)
    assert own["classification"] == gen["classification"]
    tol = 4 * float(CHORD)
    np.testing.assert_allclose(own["rest"]["origin"], gen["rest"]["origin"], atol=tol)
    np.testing.assert_allclose(own["rest"]["rotation"], gen["rest"]["rotation"], atol=1e-3)
    assert [c["force"] for c in own["contacts"]] == pytest.approx(
        [c["force"] for c in gen["contacts"]], rel=1e-2, abs=1e-3
    )
    assert own["mesh"]["bolt"]["file"] == "bolt.ply" and own["mesh"]["nut"]["file"] == "nut.stl"
    assert gen["mesh"]["bolt"]["generated"] is True

    start = ["--roll", "0", "--pitch", "0", "--phase", "300", "--step", STEP]
    _, gen, _ = run_json(capsys, "search", specs["flat"], *start, *base)
    _, own, _ = run_json(capsys, "search", specs["flat"], *start, *base, *files)
    assert (gen["snap"] is None) == (own["snap"] is None)
    assert gen["snap"] is not None, "the start snaps within a turn"
    assert own["snap"]["phase"] == pytest.approx(gen["snap"]["phase"], abs=0.05)
    assert own["snap"]["drop"] == pytest.approx(gen["snap"]["drop"], abs=tol)
    assert [e["kind"] for e in own["events"]] == [e["kind"] for e in gen["events"]]
    assert own["mesh"]["nut"]["sha256"] == _digest(meshes["nut"])


# -- sweep and run -----------------------------------------------------------------------
@pytest.fixture(scope="module")
def libraries(specs, meshes, tmp_path_factory, capsys_module) -> dict[str, Path]:
    """The same tiny mechanics sweep on the generated meshes and on them as files."""
    folder = tmp_path_factory.mktemp("sweeps")
    common = [*GRID, "--step", STEP, "--chord", CHORD, "--workers", "1"]
    out = {"generated": folder / "generated", "files": folder / "files"}
    capsys_module("sweep", specs["flat"], *common, "-o", out["generated"])
    capsys_module(
        "sweep",
        specs["flat"],
        *common,
        "-o",
        out["files"],
        "--bolt-mesh",
        meshes["bolt_stl_mm"],
        "--nut-mesh",
        meshes["nut_obj_mm"],
        "--mesh-units",
        "mm",
    )
    return out


def test_sweep_on_mesh_files_equals_the_generated_and_records_them(
    libraries, meshes, specs, capsys
):
    gen, own = library_rows(libraries["generated"]), library_rows(libraries["files"])
    a = gen[gen["role"] == "start"].sort_values("config_id")
    b = own[own["role"] == "start"].sort_values("config_id")
    assert list(a["classification"]) == list(b["classification"])
    np.testing.assert_allclose(b["centre_z"], a["centre_z"], atol=4 * float(CHORD))
    assert list(a["error"]) == list(b["error"]) == ["", ""]

    meta = json.loads((libraries["files"] / METADATA_FILE).read_text())["mesh"]
    assert meta["bolt"]["file"] == "bolt_mm.stl" and meta["bolt"]["units"] == "mm"
    assert meta["bolt"]["sha256"] == _digest(meshes["bolt_stl_mm"])
    assert meta["nut"]["file"] == "nut_mm.obj" and meta["nut"]["units"] == "mm"
    assert meta["nut"]["sha256"] == _digest(meshes["nut_obj_mm"])
    assert meta["nut"]["zone_off_spec_share"] == 0.0
    generated = json.loads((libraries["generated"] / METADATA_FILE).read_text())["mesh"]
    assert generated["bolt"] is None and generated["nut"] is None

    # Resuming with other meshes, or none, is refused naming the difference; with the same
    # meshes it resumes (nothing left to do).
    common = [*GRID, "--step", STEP, "--chord", CHORD, "--workers", "1"]
    files = ["--bolt-mesh", meshes["bolt_stl_mm"], "--nut-mesh", meshes["nut_obj_mm"]]
    for extra, words in (
        ([], "bolt mesh (bolt_mm.stl, sha256"),
        ([*files[:2]], "nut mesh (nut_mm.obj"),
        (
            ["--bolt-mesh", meshes["chamfered_bolt"], "--nut-mesh", meshes["nut"]],
            "bolt mesh (bolt_mm.stl, sha256",
        ),
    ):
        rc, out, err = run_cli(
            capsys, "sweep", specs["flat"], *common, "-o", libraries["files"], *extra
        )
        assert rc == 2 and words in err and len(err.strip().splitlines()) == 1, err
    rc, out, err = run_cli(
        capsys,
        "sweep",
        specs["flat"],
        *common,
        "-o",
        libraries["files"],
        *files,
        "--mesh-units",
        "mm",
    )
    assert rc == 0 and "resuming" in err, err

    # What a worker receives pickles (paths, not meshes): the sweep's job, an internal with
    # no public form.
    from threadmate.library._workers import Job, MeshFile

    job = Job(
        ThreadSpec.from_dict(json.loads(specs["flat"].read_text())),
        Grid.parse("0", "0", "300,330"),
        float(CHORD),
        "mechanics",
        Compliance(),
        bolt_mesh=MeshFile(str(meshes["bolt"]), "in", _digest(meshes["bolt"])),
    )
    assert pickle.loads(pickle.dumps(job)) == job


def test_run_passes_the_meshes_and_the_report_names_them(
    libraries, meshes, specs, tmp_path, capsys
):
    out = tmp_path / "run"
    out.mkdir()
    shutil.copytree(libraries["files"], out / "library")  # the run reuses it when it agrees
    base = [*GRID, "--step", STEP, "--chord", CHORD, "--workers", "1", "-o", out]
    files = [
        "--bolt-mesh",
        meshes["bolt_stl_mm"],
        "--nut-mesh",
        meshes["nut_obj_mm"],
        "--mesh-units",
        "mm",
    ]
    # Without the meshes the library would not agree: the run hands them to the sweep.
    rc, _, err = run_cli(capsys, "run", specs["flat"], *base)
    assert rc == 2 and "bolt mesh" in err and "nut mesh" in err, err
    _, doc, err = run_json(capsys, "run", specs["flat"], *base, *files)
    assert doc["mesh"]["bolt"]["sha256"] == _digest(meshes["bolt_stl_mm"])
    assert doc["mesh"]["nut"]["file"] == "nut_mm.obj"
    report = (out / "report.md").read_text()
    line = next(ln for ln in report.splitlines() if ln.startswith("- Meshes:"))
    assert "bolt from CAD `bolt_mm.stl`" in line
    assert _digest(meshes["bolt_stl_mm"])[:16] in line
    assert "nut from CAD `nut_mm.obj`" in line and "units mm" in line and "scaled into in" in line


# -- bad files -----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "args, words",
    [
        (["--bolt-mesh", "{open}"], "is not a closed volume (not watertight)"),
        (["--bolt-mesh", "{lifted}"], "is not in its frame (tip face at z = 0"),
        (["--bolt-mesh", "{bolt}", "--mesh-units", "mm"], "header declares units=in"),
        (["--nut-mesh", "{missing}"], "mesh file not found"),
        (["--bolt-mesh", "{bolt_obj_mm}"], "looks like mm (give its units, --mesh-units mm, or"),
        (["--mesh-units", "mm"], "--mesh-units needs --bolt-mesh or --nut-mesh"),
        (["--bolt-mesh", "{furlong}"], "declares units=furlong, which threadmate does not"),
        (["--bolt-mesh", "{nan}"], "2 of its"),
        (["--bolt-mesh", "{nan}"], "vertices are not finite numbers (NaN or inf)"),
    ],
)
@pytest.mark.parametrize("command", ["contact", "settle", "sweep"])
def test_bad_mesh_files_exit_2_with_one_line(specs, meshes, tmp_path, capsys, command, args, words):
    files = {**{k: str(v) for k, v in meshes.items()}, "missing": str(tmp_path / "none.stl")}
    args = [a.format(**files) for a in args]
    out = tmp_path / "lib"
    extra = [*GRID, "-o", out] if command == "sweep" else CONFIG
    rc, stdout, err = run_cli(capsys, command, specs["flat"], *extra, "--chord", CHORD, *args)
    assert rc == 2, err
    assert words in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert stdout == "" and not out.exists()


def test_a_mesh_warning_is_one_line_on_stderr(specs, meshes, tmp_path, capsys):
    """A bolt mesh wound inside out is turned outward (its volume then positive) with a
    warning: one ``threadmate: warning:`` line on stderr, not Python's source-line report,
    and the command goes on."""
    inverted = read_stl(meshes["bolt"])
    inverted.invert()
    assert inverted.volume < 0
    path = write_stl(inverted, tmp_path / "inverted.stl", "threadmate units=in bolt")
    rc, out, err = run_cli(
        capsys, "settle", specs["flat"], "--roll", "1", "--pitch", "0", "--phase", "185",
        "--bolt-mesh", path, "--chord", CHORD, "--json",
    )  # fmt: skip
    assert rc == 0, err
    said = [line for line in err.splitlines() if "warning" in line.lower()]
    assert said and all(line.startswith("threadmate: warning: ") for line in said), err
    assert "MeshWarning" not in err and ".py:" not in err
    assert json.loads(out)["classification"] in ("stable", "quasi-stable", "in-phase", "unstable")
