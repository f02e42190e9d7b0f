"""Binary STL in the thesis's Figure 3.3 layout, round trips, and user meshes from CAD:
accepted when closed, consistently wound, plausibly sized and in frame; refused otherwise."""

from __future__ import annotations

import struct

import numpy as np
import pytest
import trimesh

from threadmate import InputError, MeshError
from threadmate.geometry import (
    ThreadSpec,
    bolt_mesh,
    load_mesh,
    mesh_deviation,
    nut_mesh,
    read_stl,
    write_stl,
)
from threadmate.geometry._meshio import MeshWarning  # an internal with no public form

CHORD = 1e-4  # coarse meshes keep these tests fast


@pytest.fixture(scope="module")
def meshes(quarter_20):
    return bolt_mesh(quarter_20, CHORD), nut_mesh(quarter_20, CHORD)


@pytest.fixture(scope="module")
def bolt_stl(meshes, tmp_path_factory):
    path = tmp_path_factory.mktemp("stl") / "bolt.stl"
    write_stl(meshes[0].mesh, path, "threadmate bolt 1/4-20 units=in")
    return path


def test_stl_layout_parsed_with_struct(meshes, bolt_stl):
    mesh = meshes[0].mesh
    data = bolt_stl.read_bytes()
    n = len(mesh.faces)
    assert len(data) == 80 + 4 + 50 * n
    assert data[:80] == b"threadmate bolt 1/4-20 units=in".ljust(80, b" ")
    assert struct.unpack("<I", data[80:84])[0] == n
    tri = np.asarray(mesh.vertices)[mesh.faces]
    for k in (0, 1, n // 3, n // 2, n - 1):
        rec = struct.unpack("<12fH", data[84 + 50 * k : 84 + 50 * (k + 1)])
        normal = np.array(rec[0:3])
        verts = np.array(rec[3:12]).reshape(3, 3)
        assert rec[12] == 0  # attribute, unused
        assert np.allclose(verts, tri[k], rtol=0, atol=1e-7)  # float32 of the vertices
        # Unit normal, on the side the vertex order (right-hand rule) says.
        cross = np.cross(tri[k][1] - tri[k][0], tri[k][2] - tri[k][0])
        assert np.linalg.norm(normal) == pytest.approx(1.0, abs=1e-6)
        assert np.allclose(normal, cross / np.linalg.norm(cross), atol=1e-6)


def test_round_trip_keeps_the_solid(meshes, bolt_stl, quarter_20):
    tb = meshes[0]
    back = read_stl(bolt_stl)
    assert isinstance(back, trimesh.Trimesh)
    assert len(back.faces) == len(tb.mesh.faces)
    assert len(back.vertices) == len(tb.mesh.vertices)  # welded again
    assert back.is_watertight and back.is_winding_consistent
    assert back.volume == pytest.approx(tb.mesh.volume, rel=1e-6)
    f32 = np.asarray(tb.mesh.vertices, dtype=np.float32).astype(float)[tb.mesh.faces]
    assert np.array_equal(
        np.sort(back.triangles.reshape(-1, 9), axis=0), np.sort(f32.reshape(-1, 9), axis=0)
    )
    # float32 moves vertices by ~1e-8 in: still within the chord of the exact surface.
    assert mesh_deviation(back, tb.body) <= CHORD + 1e-7


def test_header_never_reads_as_ascii(meshes, tmp_path):
    path = write_stl(meshes[0].mesh, tmp_path / "a.stl", "solid model")
    assert not path.read_bytes()[:80].lower().startswith(b"solid")
    assert len(read_stl(path).faces) == len(meshes[0].mesh.faces)


def test_write_is_atomic_and_creates_the_folder(meshes, tmp_path):
    path = write_stl(meshes[1].mesh, tmp_path / "deep" / "nut.stl")
    assert path.is_file()
    assert [p.name for p in path.parent.iterdir()] == ["nut.stl"]  # no temporary left


def test_ascii_stl_reads(meshes, tmp_path):
    path = tmp_path / "ascii.stl"
    path.write_text(trimesh.exchange.stl.export_stl_ascii(meshes[1].mesh))
    back = read_stl(path)
    assert back.is_watertight and len(back.faces) == len(meshes[1].mesh.faces)


# -- user meshes -------------------------------------------------------------------------
@pytest.mark.parametrize("suffix", [".stl", ".obj", ".ply"])
def test_user_meshes_accepted(meshes, quarter_20, tmp_path, suffix):
    for tb, kind in zip(meshes, ("bolt", "nut"), strict=True):
        path = tmp_path / f"{kind}{suffix}"
        if suffix == ".stl":
            write_stl(tb.mesh, path)
        else:
            tb.mesh.export(path)
        m = load_mesh(path, kind, spec=quarter_20)
        assert m.is_watertight and m.volume > 0
        assert m.vertices.dtype == np.float64
        assert m.volume == pytest.approx(tb.mesh.volume, rel=1e-6)
        assert mesh_deviation(m, tb.body) <= CHORD + 1e-7
        assert isinstance(load_mesh(path, kind), trimesh.Trimesh)  # no spec: no size check


def test_inside_out_mesh_is_turned_outward_with_a_warning(meshes, quarter_20, tmp_path):
    inverted = meshes[0].mesh.copy()
    inverted.invert()
    assert inverted.volume < 0
    path = write_stl(inverted, tmp_path / "inverted.stl")
    with pytest.warns(MeshWarning, match=r"wound inward \(negative volume, -0\.00\d+ in\^3\)"):
        m = load_mesh(path, "bolt", spec=quarter_20)
    assert m.volume == pytest.approx(meshes[0].mesh.volume, rel=1e-6)


def test_file_in_other_units_is_scaled(meshes, quarter_20, tmp_path):
    mm = meshes[0].mesh.copy()
    mm.apply_scale(25.4)
    path = write_stl(mm, tmp_path / "bolt_mm.stl")
    m = load_mesh(path, "bolt", spec=quarter_20, units="mm")
    assert m.volume == pytest.approx(meshes[0].mesh.volume, rel=1e-5)


def _refused(path, body, spec, match):
    with pytest.raises(MeshError, match=match) as info:
        load_mesh(path, body, spec=spec)
    assert isinstance(info.value, InputError)  # the CLI's exit 2
    return str(info.value)


def test_open_mesh_refused(meshes, quarter_20, tmp_path):
    m = meshes[0].mesh.copy()
    m.update_faces(np.arange(len(m.faces)) != 7)
    path = write_stl(m, tmp_path / "open.stl")
    _refused(path, "bolt", quarter_20, "not a closed volume")


def test_flipped_winding_refused(meshes, quarter_20, tmp_path):
    m = meshes[1].mesh.copy()
    faces = np.asarray(m.faces).copy()
    faces[::5] = faces[::5, ::-1]  # every fifth triangle turned around
    path = tmp_path / "flipped.ply"
    trimesh.Trimesh(m.vertices, faces, process=False).export(path)
    _refused(path, "nut", quarter_20, "inconsistent winding")


@pytest.mark.parametrize(
    ("scale", "words"),
    [(25.4, "looks like mm"), (2.0, "implausible size")],
    ids=["mm for an inch spec", "wrong size"],
)
def test_scaled_bolt_refused(meshes, quarter_20, tmp_path, scale, words):
    m = meshes[0].mesh.copy()
    m.apply_scale(scale)
    path = write_stl(m, tmp_path / "bolt.stl")
    _refused(path, "bolt", quarter_20, words)


def test_inch_mesh_for_a_mm_spec_refused(meshes, quarter_20, tmp_path):
    d = quarter_20.to_dict()
    d["units"] = "mm"
    for key in ("pitch",):
        d[key] *= 25.4
    for body in ("bolt", "nut"):
        for k, v in d[body].items():
            d[body][k] = v * 25.4
    spec_mm = type(quarter_20).from_dict(d)
    path = write_stl(meshes[1].mesh, tmp_path / "nut_in.stl")
    _refused(path, "nut", spec_mm, "looks like inches")


@pytest.mark.parametrize("move", ["lifted", "sideways", "lying", "nut_as_bolt"])
def test_off_frame_refused(meshes, quarter_20, tmp_path, move):
    bolt = meshes[0].mesh.copy()
    body = "bolt"
    if move == "lifted":
        bolt.apply_translation([0, 0, 0.01])
    elif move == "sideways":
        bolt.apply_translation([0.05, 0, 0])
    elif move == "lying":  # axis along X
        bolt.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0]))
        bolt.apply_translation([0, 0, -bolt.bounds[0][2]])
    else:  # a bolt in z >= 0 handed over as the nut (top face must be at z = 0)
        body = "nut"
        bolt = meshes[1].mesh.copy()
        bolt.apply_translation([0, 0, quarter_20.nut.height])
    path = write_stl(bolt, tmp_path / f"{move}.stl")
    with pytest.raises(MeshError, match="frame|size"):
        load_mesh(path, body)  # no spec: the frame alone decides
    _refused(path, body, quarter_20, "frame|size")


def test_missing_file_refused(tmp_path):
    with pytest.raises(MeshError, match="file not found"):
        load_mesh(tmp_path / "nowhere.stl", "bolt")
    with pytest.raises(MeshError, match="file not found"):
        read_stl(tmp_path / "nowhere.stl")


@pytest.mark.parametrize("name", ["garbage.stl", "garbage.obj", "garbage.ply", "empty.stl"])
def test_garbage_bytes_refused(tmp_path, name):
    path = tmp_path / name
    rng = np.random.default_rng(7)
    path.write_bytes(b"" if name.startswith("empty") else rng.bytes(5000))
    with pytest.raises(MeshError):
        load_mesh(path, "bolt")


def test_unsupported_format_and_body_refused(bolt_stl, tmp_path):
    step = tmp_path / "bolt.step"
    step.write_text("ISO-10303-21;")
    with pytest.raises(MeshError, match="unsupported"):
        load_mesh(step, "bolt")
    with pytest.raises(MeshError, match="bolt"):
        load_mesh(bolt_stl, "screw")  # type: ignore[arg-type]


# -- issue 11: STL files that say their units ---------------------------------------------
def test_header_puts_the_units_first_even_for_long_designations(quarter_20):
    from dataclasses import replace

    from threadmate.geometry import stl_header

    header = stl_header("bolt", quarter_20, 5e-6)
    assert header == "threadmate units=in bolt spec chord=5e-06"
    long = replace(quarter_20, designation="X" * 200)
    header = stl_header("nut", long, 5e-6)
    assert len(header) <= 80 and header.startswith("threadmate units=in nut XXX")
    assert header.endswith("... chord=5e-06")


def test_units_in_the_header_are_read_back_and_used(meshes, quarter_20, tmp_path):
    from threadmate.geometry import stl_header, stl_units

    mm = meshes[0].mesh.copy()
    mm.apply_scale(25.4)
    mm_spec = ThreadSpec.from_dict(
        {**quarter_20.to_dict(), "units": "mm"} | _scaled(quarter_20, 25.4)
    )
    path = write_stl(mm, tmp_path / "bolt_mm.stl", stl_header("bolt", mm_spec))
    assert stl_units(path) == "mm"
    # No units given: the header's mm are scaled into the inch spec, not refused.
    m = load_mesh(path, "bolt", spec=quarter_20)
    assert m.volume == pytest.approx(meshes[0].mesh.volume, rel=1e-5)
    # A file without the word declares no units; an ASCII STL neither.
    plain = write_stl(meshes[0].mesh, tmp_path / "plain.stl", "exported by CAD units: in")
    assert stl_units(plain) is None
    assert stl_units(tmp_path / "missing.stl") is None


def _scaled(spec, k):
    d = spec.to_dict()
    return {
        "pitch": d["pitch"] * k,
        **{b: {key: v * k for key, v in d[b].items()} for b in ("bolt", "nut")},
    }


# -- issue 26: faults in user meshes, each named with its count ---------------------------
def _ply(mesh_or_parts, path):
    """Write vertices and faces as given (no processing: trimesh would repair them)."""
    vertices, faces = mesh_or_parts
    trimesh.Trimesh(vertices, faces, process=False).export(path)
    return path


def test_non_finite_vertices_are_named_with_their_count(meshes, quarter_20, tmp_path):
    m = meshes[0].mesh
    v = np.asarray(m.vertices, dtype=float).copy()
    f = np.asarray(m.faces)
    bad = [3, 40, 41]
    v[bad[0], 0] = np.nan
    v[bad[1], 2] = np.inf
    v[bad[2]] = -np.inf
    path = _ply((v, f), tmp_path / "nan.ply")
    touched = int(np.isin(f, bad).any(axis=1).sum())  # the triangles using them
    text = _refused(path, "bolt", quarter_20, "not finite numbers")
    assert f"3 of its {len(v)} vertices are not finite numbers (NaN or inf)" in text
    assert f"in {touched} of its {len(f)} triangles" in text
    assert "watertight" not in text
    # A binary STL repeats each vertex per facet: the distinct points are counted.
    stl = tmp_path / "nan.stl"
    stl.write_bytes(stl_bytes_of(v, f))
    text = _refused(stl, "bolt", quarter_20, "not finite numbers")
    assert f"3 of its {len(v)} vertices" in text


def stl_bytes_of(vertices, faces):
    from threadmate.geometry._meshio import stl_bytes  # an internal with no public form

    with np.errstate(invalid="ignore"):  # the facet normals of the NaN corners
        return stl_bytes(trimesh.Trimesh(vertices, faces, process=False), "cad export")


def test_zero_area_triangles_are_dropped_with_a_warning(meshes, quarter_20, tmp_path):
    m = meshes[0].mesh
    v = np.asarray(m.vertices, dtype=float)
    f = np.asarray(m.faces)
    # A triangle with a repeated vertex (two corners welded into one).
    path = _ply((v, np.vstack([f, [f[0, 0], f[0, 0], f[0, 1]]])), tmp_path / "repeated.ply")
    with pytest.warns(MeshWarning, match="dropped 1 degenerate \\(zero-area\\) triangles"):
        got = load_mesh(path, "bolt", spec=quarter_20)
    assert len(got.faces) == len(f) and got.volume == pytest.approx(m.volume, rel=1e-6)
    # Three vertices in a line: the face a b c split at the middle m of a b, and the
    # sliver a b m closing the T-junction against the neighbour b a d.
    a, b, c = f[0]
    mid = len(v)
    split = np.vstack([f[1:], [[a, mid, c], [mid, b, c], [a, b, mid]]])
    vm = np.vstack([v, 0.5 * (v[a] + v[b])])
    sliver = trimesh.Trimesh(vm, split, process=False)
    assert sliver.is_watertight and sliver.is_winding_consistent  # closed with it
    path = _ply((vm, split), tmp_path / "sliver.ply")
    with pytest.warns(MeshWarning, match="dropped 1 degenerate"):
        got = load_mesh(path, "bolt", spec=quarter_20)
    assert got.is_watertight and got.volume == pytest.approx(m.volume, rel=1e-6)
    # Without the neighbour across its long edge the sliver cannot be closed: refused.
    neighbour = np.flatnonzero(
        (np.roll(f[1:], -1, axis=1) == a).any(axis=1)
        & ((f[1:] == b) & (np.roll(f[1:], -1, axis=1) == a)).any(axis=1)
    )
    open_ = np.delete(split, neighbour, axis=0)
    path = _ply((vm, open_), tmp_path / "sliver_open.ply")
    text = _refused(path, "bolt", quarter_20, "1 degenerate \\(zero-area\\) triangles")
    assert "not closed" in text and "0 edges" not in text


def test_too_many_triangles_are_refused_and_many_warned(meshes, quarter_20, tmp_path, monkeypatch):
    import threadmate.geometry._meshio as meshio  # its limits: internals with no public form

    n = len(meshes[0].mesh.faces)
    path = write_stl(meshes[0].mesh, tmp_path / "bolt.stl")
    with pytest.raises(MeshError) as info:
        load_mesh(path, "bolt", spec=quarter_20, max_faces=n - 1)
    assert f"has {n:,} triangles, more than the {n - 1:,}" in str(info.value)
    assert "max_faces" in str(info.value)
    # Read from the binary STL's header: refused before its triangles are read.
    monkeypatch.setattr(meshio, "_read", lambda *a: pytest.fail("read"))
    with pytest.raises(MeshError, match="triangles, more than"):
        load_mesh(path, "bolt", spec=quarter_20, max_faces=n - 1)
    monkeypatch.undo()
    assert load_mesh(path, "bolt", spec=quarter_20, max_faces=n) is not None
    assert meshio.WARN_FACES < meshio.MAX_FACES
    monkeypatch.setattr(meshio, "WARN_FACES", n - 1)
    with pytest.warns(MeshWarning, match=f"has {n:,} triangles \\(above {n - 1:,}\\)"):
        load_mesh(path, "bolt", spec=quarter_20)


@pytest.mark.parametrize(
    "header, expected",
    [("units=mm bolt", "mm"), ("UNITS=Inch", "in"), ("part units=millimetres", "mm")],
)
def test_units_words_of_binary_and_ascii_headers(meshes, tmp_path, header, expected):
    from threadmate.geometry import stl_units

    path = write_stl(meshes[0].mesh, tmp_path / "b.stl", header)
    assert stl_units(path) == expected
    ascii_stl = tmp_path / "a.stl"
    text = trimesh.exchange.stl.export_stl_ascii(meshes[0].mesh)
    ascii_stl.write_text(text.replace("solid", f"solid {header}", 1))
    assert stl_units(ascii_stl) == expected


def test_unknown_units_in_the_header_are_refused(meshes, quarter_20, tmp_path):
    path = write_stl(meshes[0].mesh, tmp_path / "bolt.stl", "cad units=furlong")
    text = _refused(path, "bolt", quarter_20, "declares units=furlong")
    assert "in or mm" in text


def test_two_bodies_and_a_void_are_refused_with_their_count(meshes, quarter_20, tmp_path):
    bolt = meshes[0].mesh
    twin = bolt.copy()
    twin.apply_translation([0.0, 0.0, 1.0])
    path = write_stl(trimesh.util.concatenate([bolt, twin]), tmp_path / "two.stl")
    _refused(path, "bolt", quarter_20, "is 2 separate bodies \\(2 closed shells\\)")
    # A hollow: a small ball inside the core, wound inward.
    ball = trimesh.creation.icosphere(subdivisions=1, radius=0.3 * quarter_20.bolt.minor / 2)
    ball.apply_translation([0.0, 0.0, 0.5 * bolt.bounds[1][2]])
    ball.invert()
    path = write_stl(trimesh.util.concatenate([bolt, ball]), tmp_path / "void.stl")
    _refused(path, "bolt", quarter_20, "has 1 void inside it \\(2 closed shells")


def test_open_and_non_manifold_edges_are_counted(meshes, quarter_20, tmp_path):
    m = meshes[0].mesh
    f = np.asarray(m.faces)
    path = _ply((m.vertices, np.vstack([f, f[:1]])), tmp_path / "twice.ply")
    text = _refused(path, "bolt", quarter_20, "not a closed volume")
    assert "3 edges are shared by more than two triangles" in text
