"""``threadmate mesh``: two STL files, one JSON document, refusals with exit 2."""

from __future__ import annotations

import json
import struct

import numpy as np
import pytest

from _cli import run_cli
from threadmate.geometry import bolt_body, load_mesh, mesh_deviation, nut_body, save_spec

CHORD = "1e-4"


run = run_cli


@pytest.fixture(scope="module")
def spec_file(quarter_20, tmp_path_factory):
    return save_spec(quarter_20, tmp_path_factory.mktemp("spec") / "quarter.json")


def test_json_from_spec_file(capsys, tmp_path, spec_file, quarter_20):
    out_dir = tmp_path / "out"
    rc, out, err = run(capsys, "mesh", str(spec_file), "-o", str(out_dir), "--chord", CHORD,
                       "--json")
    assert rc == 0, err
    doc = json.loads(out)  # exactly one JSON document on stdout
    assert doc["units"] == "in" and doc["chord"] == pytest.approx(1e-4)
    for name, body in (("bolt", bolt_body(quarter_20)), ("nut", nut_body(quarter_20))):
        part = doc[name]
        assert part["path"] == str(out_dir / f"{name}.stl")
        data = (out_dir / f"{name}.stl").read_bytes()
        count = struct.unpack("<I", data[80:84])[0]
        assert part["triangles"] == count and len(data) == 84 + 50 * count
        assert 0 < part["max_deviation"] <= 1e-4
        # The file is a valid solid of this spec, within the chord of the exact body.
        mesh = load_mesh(out_dir / f"{name}.stl", name, spec=quarter_20)
        assert mesh_deviation(mesh, body) <= 1e-4 + 1e-7
    assert sorted(p.name for p in out_dir.iterdir()) == ["bolt.stl", "nut.stl"]


def test_designation_and_summary(capsys, tmp_path):
    rc, out, err = run(capsys, "mesh", "M6x1-6g/6H", "-o", str(tmp_path), "--chord", "0.0025",
                       "--condition", "max")
    assert rc == 0, err
    assert "bolt" in out and "nut" in out and "triangles" in out and "mm" in out
    assert (tmp_path / "bolt.stl").is_file() and (tmp_path / "nut.stl").is_file()
    # Maximum material: the bolt reaches its largest major diameter, 5.974 mm (ISO 965-1).
    data = (tmp_path / "bolt.stl").read_bytes()
    verts = np.frombuffer(data[84:], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)),
                                                      ("a", "<u2")]))["v"].reshape(-1, 3)
    assert np.hypot(verts[:, 0], verts[:, 1]).max() == pytest.approx(5.974 / 2, abs=1e-5)


@pytest.mark.parametrize("chord", ["0", "-1e-5", "nan", "inf", "0.5", "1e-13"])
def test_bad_chord_exits_2_and_writes_nothing(capsys, tmp_path, spec_file, chord):
    out_dir = tmp_path / "out"
    rc, out, err = run(capsys, "mesh", str(spec_file), "-o", str(out_dir), "--chord", chord)
    assert rc == 2
    assert err.startswith("threadmate: error:") and "chord" in err
    assert "Traceback" not in err and out == ""
    assert not out_dir.exists() or not any(out_dir.iterdir())


def test_bad_spec_and_designation_exit_2(capsys, tmp_path):
    rc, _, err = run(capsys, "mesh", str(tmp_path / "missing.json"), "-o", str(tmp_path))
    assert rc == 2 and "not found" in err
    rc, _, err = run(capsys, "mesh", "M6x7.3-9z", "-o", str(tmp_path / "x"))
    assert rc == 2 and err.startswith("threadmate: error:")
    assert not (tmp_path / "x").exists()


def test_output_that_is_a_file_leaves_nothing_half_written(capsys, tmp_path, spec_file):
    blocker = tmp_path / "taken"
    blocker.write_text("not a folder")
    rc, _, err = run(capsys, "mesh", str(spec_file), "-o", str(blocker), "--chord", CHORD)
    assert rc != 0
    assert blocker.read_text() == "not a folder"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["taken"]


def test_existing_files_replaced_whole(capsys, tmp_path, spec_file):
    (tmp_path / "bolt.stl").write_text("old")
    rc, _, _ = run(capsys, "mesh", str(spec_file), "-o", str(tmp_path), "--chord", CHORD)
    assert rc == 0
    data = (tmp_path / "bolt.stl").read_bytes()
    assert len(data) == 84 + 50 * struct.unpack("<I", data[80:84])[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bolt.stl", "nut.stl"]
