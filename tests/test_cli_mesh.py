"""``threadmate mesh``: two STL files, one JSON document, refusals with exit 2."""

from __future__ import annotations

import json
import struct

import numpy as np
import pytest

from _cli import run_cli
from threadmate.geometry import bolt_body, load_mesh, mesh_deviation, nut_body

CHORD = "1e-4"


def test_json_from_spec_file(capsys, tmp_path, quarter_20_file, quarter_20):
    out_dir = tmp_path / "out"
    rc, out, err = run_cli(
        capsys, "mesh", str(quarter_20_file), "-o", str(out_dir), "--chord", CHORD, "--json"
    )
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
    rc, out, err = run_cli(
        capsys, "mesh", "M6x1-6g/6H", "-o", str(tmp_path), "--chord", "0.0025", "--condition", "max"
    )
    assert rc == 0, err
    assert "bolt" in out and "nut" in out and "triangles" in out and "mm" in out
    assert (tmp_path / "bolt.stl").is_file() and (tmp_path / "nut.stl").is_file()
    # Maximum material: the bolt reaches its largest major diameter, 5.974 mm (ISO 965-1).
    data = (tmp_path / "bolt.stl").read_bytes()
    verts = np.frombuffer(
        data[84:], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    )["v"].reshape(-1, 3)
    assert np.hypot(verts[:, 0], verts[:, 1]).max() == pytest.approx(5.974 / 2, abs=1e-5)


@pytest.mark.parametrize("chord", ["0", "-1e-5", "nan", "inf", "0.5", "1e-13"])
def test_bad_chord_exits_2_and_writes_nothing(capsys, tmp_path, quarter_20_file, chord):
    out_dir = tmp_path / "out"
    rc, out, err = run_cli(
        capsys, "mesh", str(quarter_20_file), "-o", str(out_dir), "--chord", chord
    )
    assert rc == 2
    assert err.startswith("threadmate: error:") and "chord" in err
    assert "Traceback" not in err and out == ""
    assert not out_dir.exists() or not any(out_dir.iterdir())


def test_bad_spec_and_designation_exit_2(capsys, tmp_path):
    rc, _, err = run_cli(capsys, "mesh", str(tmp_path / "missing.json"), "-o", str(tmp_path))
    assert rc == 2 and "not found" in err
    rc, _, err = run_cli(capsys, "mesh", "M6x7.3-9z", "-o", str(tmp_path / "x"))
    assert rc == 2 and err.startswith("threadmate: error:")
    assert not (tmp_path / "x").exists()


def test_output_that_is_a_file_leaves_nothing_half_written(capsys, tmp_path, quarter_20_file):
    blocker = tmp_path / "taken"
    blocker.write_text("not a folder")
    rc, _, err = run_cli(capsys, "mesh", str(quarter_20_file), "-o", str(blocker), "--chord", CHORD)
    assert rc != 0
    assert blocker.read_text() == "not a folder"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["taken"]


def test_existing_files_replaced_whole_with_force(capsys, tmp_path, quarter_20_file):
    (tmp_path / "bolt.stl").write_text("old")
    args = ("mesh", str(quarter_20_file), "-o", str(tmp_path), "--chord", CHORD, "--force")
    rc, _, _ = run_cli(capsys, *args)
    assert rc == 0
    data = (tmp_path / "bolt.stl").read_bytes()
    assert len(data) == 84 + 50 * struct.unpack("<I", data[80:84])[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bolt.stl", "nut.stl"]


# -- issue 11 ------------------------------------------------------------------------------
def test_absurd_outer_radius_exits_2_with_range_and_writes_nothing(capsys, tmp_path, quarter_20):
    data = quarter_20.to_dict()
    data["nut"]["outer_radius"] = 1e300
    spec = tmp_path / "absurd.json"
    spec.write_text(json.dumps(data))
    out_dir = tmp_path / "out"
    rc, out, err = run_cli(capsys, "mesh", str(spec), "-o", str(out_dir))
    assert rc == 2 and out == "" and "Traceback" not in err and err.count("\n") == 1
    assert "'nut.outer_radius'" in err and "from 0.0001 to 1000 in" in err
    assert not out_dir.exists()


@pytest.mark.parametrize("target", ["/proc/threadmate-x/y", "/proc/threadmate-x"])
def test_uncreatable_output_exits_2(capsys, quarter_20_file, target):
    rc, out, err = run_cli(capsys, "mesh", str(quarter_20_file), "-o", target, "--chord", CHORD)
    assert rc == 2 and out == "" and "Traceback" not in err and err.count("\n") == 1
    assert f"-o {target}:" in err and "/proc" in err


def test_output_under_a_file_exits_2(capsys, tmp_path, quarter_20_file):
    blocker = tmp_path / "taken"
    blocker.write_text("not a folder")
    rc, out, err = run_cli(
        capsys, "mesh", str(quarter_20_file), "-o", str(blocker / "sub"), "--chord", CHORD
    )
    assert rc == 2 and out == "" and "Traceback" not in err
    assert "is not a directory" in err and blocker.read_text() == "not a folder"


def test_empty_designation_and_directory(capsys, tmp_path):
    out_dir = tmp_path / "out"
    rc, _, err = run_cli(capsys, "mesh", "", "-o", str(out_dir))
    assert rc == 2 and "empty thread designation" in err
    rc, _, err = run_cli(capsys, "mesh", str(tmp_path), "-o", str(out_dir))
    assert rc == 2 and "is a directory, not a spec file" in err
    assert not out_dir.exists()


def test_stl_header_says_the_units(capsys, tmp_path):
    from threadmate.geometry import stl_units

    rc, _, err = run_cli(capsys, "mesh", "M6x1-6g/6H", "-o", str(tmp_path), "--chord", "0.0025")
    assert rc == 0, err
    for name in ("bolt", "nut"):
        header = (tmp_path / f"{name}.stl").read_bytes()[:80].decode("ascii")
        assert header.startswith(f"threadmate units=mm {name} M6x1-6g/6H")
        assert stl_units(tmp_path / f"{name}.stl") == "mm"
