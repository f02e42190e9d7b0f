"""``threadmate planar``: JSON shape, figures and exit codes, through the real entry point."""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ET

import pytest

from _cli import THESIS_PARTS, run_cli

SQ3 = math.sqrt(3.0)

# 1/4-20 UNC-2A/2B at mean material, from the ASME B1.1 table values (sharp corners).
SPEC = {
    "units": "in",
    "pitch": 0.05,
    "bolt": {"major": 0.24485, "pitch_diameter": 0.21455, "minor": 0.1887},
    "nut": {"major": 0.25, "pitch_diameter": 0.21995, "minor": 0.2015},
}
HALF_WINDOW = 360.0 * (0.21995 - 0.21455) / SQ3 / (2 * 0.05)


def test_json_document(spec_file, capsys):
    rc, out, err = run_cli(capsys, "planar", str(spec_file), "--json")
    assert rc == 0
    doc = json.loads(out)  # exactly one document
    for key in (
        "units",
        "phase",
        "in_phase",
        "in_phase_window",
        "contact_angle",
        "pivot_axis_length",
        "contacts",
        "critical_phases",
        "figures",
    ):
        assert key in doc
    assert doc["units"] == "in" and doc["figures"] == []
    # The default phase is the thesis's example, 30 degrees, with two contacts.
    assert doc["phase"] == 30.0 and doc["in_phase"] is False and len(doc["contacts"]) == 2
    ((a, b),) = doc["in_phase_window"]
    assert b == pytest.approx(HALF_WINDOW, abs=1e-9) and a == pytest.approx(-HALF_WINDOW)
    for i, c in enumerate(doc["contacts"]):
        for key in ("theta", "x", "y", "bolt_region", "nut_region", "normal"):
            assert key in c
        assert c["contact"] == i + 1 and c["normal"] == [0.0, 0.0, 1.0]
        r = math.hypot(c["x"], c["y"])
        assert math.degrees(math.atan2(c["y"], c["x"])) % 360.0 == pytest.approx(c["theta"])
        assert SPEC["nut"]["minor"] / 2 - 1e-12 <= r <= SPEC["bolt"]["major"] / 2 + 1e-12
    x1, y1 = doc["contacts"][0]["x"], doc["contacts"][0]["y"]
    x2, y2 = doc["contacts"][1]["x"], doc["contacts"][1]["y"]
    assert doc["pivot_axis_length"] == pytest.approx(math.hypot(x2 - x1, y2 - y1))
    crit = doc["critical_phases"]
    assert crit and all({"phase", "contact", "before", "after"} <= set(c) for c in crit)
    assert any(c["before"] is None and c["phase"] == pytest.approx(HALF_WINDOW) for c in crit)


def test_phase_modulo_and_in_phase(spec_file, capsys):
    rc, out, _ = run_cli(capsys, "planar", str(spec_file), "--json", "--phase", "-350")
    assert rc == 0 and json.loads(out)["phase"] == pytest.approx(10.0)
    doc = json.loads(out)
    assert doc["in_phase"] is True and doc["contacts"] == [] and doc["contact_angle"] == 0.0
    rc, out, _ = run_cli(capsys, "planar", str(spec_file), "--json", "--phase", "390")
    doc390 = json.loads(out)
    rc, out, _ = run_cli(capsys, "planar", str(spec_file), "--json", "--phase", "30")
    assert doc390["contacts"] == json.loads(out)["contacts"]


def test_plots(spec_file, tmp_path, capsys):
    disk = tmp_path / "figs" / "disk.png"
    rc, out, err = run_cli(capsys, "planar", str(spec_file), "--json", "--plot", str(disk))
    assert rc == 0
    pivot = tmp_path / "figs" / "disk-pivot.png"
    assert json.loads(out)["figures"] == [str(disk), str(pivot)]
    for f in (disk, pivot):
        assert f.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    svg = tmp_path / "pivot.svg"
    rc, out, _ = run_cli(
        capsys,
        "planar",
        str(spec_file),
        "--plot",
        str(tmp_path / "d.svg"),
        "--pivot-plot",
        str(svg),
    )
    assert rc == 0 and "contact 1" in out
    assert ET.parse(svg).getroot().tag.endswith("svg")
    assert ET.parse(tmp_path / "d.svg").getroot().tag.endswith("svg")
    assert not (tmp_path / "d-pivot.svg").exists()


@pytest.mark.parametrize("phase", ["nan", "inf", "-inf"])
def test_non_finite_phase_is_refused(spec_file, capsys, phase):
    rc, out, err = run_cli(capsys, "planar", str(spec_file), "--json", f"--phase={phase}")
    assert rc == 2 and out == ""
    assert err.startswith("threadmate: error:") and "phase" in err and "Traceback" not in err


def test_bad_plot_suffix_is_refused_before_any_work(tmp_path, capsys):
    # The spec does not exist: the figure name is checked first, and nothing is written.
    rc, out, err = run_cli(
        capsys, "planar", str(tmp_path / "missing.json"), "--plot", str(tmp_path / "disk.pdf")
    )
    assert rc == 2 and out == "" and "disk.pdf" in err and ".png" in err
    rc, out, err = run_cli(
        capsys,
        "planar",
        str(tmp_path / "missing.json"),
        "--pivot-plot",
        str(tmp_path / "pivot.jpeg"),
    )
    assert rc == 2 and "pivot.jpeg" in err
    assert list(tmp_path.iterdir()) == []


def test_missing_and_invalid_spec(tmp_path, capsys):
    rc, out, err = run_cli(capsys, "planar", str(tmp_path / "nope.json"), "--json")
    assert rc == 2 and out == "" and "nope.json" in err
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({**SPEC, "nut": {**SPEC["nut"], "pitch_diameter": 0.2}}))
    rc, out, err = run_cli(capsys, "planar", str(bad), "--json", "--plot", str(tmp_path / "d.png"))
    assert rc == 2 and out == "" and "pitch_diameter" in err
    assert not (tmp_path / "d.png").exists()


def test_designation(capsys):
    rc, out, err = run_cli(capsys, "planar", "1/4-20 UNC-2A/2B", *THESIS_PARTS, "--json")
    assert rc == 0, err
    doc = json.loads(out)
    # Mean pitch diameters from ASME B1.1: bolt 0.2127-0.2164, nut 0.2175-0.2224.
    ((a, b),) = doc["in_phase_window"]
    assert b == pytest.approx(HALF_WINDOW, abs=1e-6) and a == pytest.approx(-HALF_WINDOW, abs=1e-6)
    assert doc["units"] == "in" and len(doc["contacts"]) == 2


def test_unwritable_figure_location(spec_file, tmp_path, capsys):
    blocker = tmp_path / "blocker"
    blocker.write_text("a file where a folder is needed")
    rc, out, err = run_cli(
        capsys, "planar", str(spec_file), "--json", "--plot", str(blocker / "disk.png")
    )
    assert rc == 2 and out == "" and "disk.png" in err and "Traceback" not in err


# -- issue 11 ------------------------------------------------------------------------------
def test_absurd_pitch_exits_2_with_range_and_writes_nothing(tmp_path, capsys):
    spec = tmp_path / "spec" / "absurd.json"
    spec.parent.mkdir()
    spec.write_text(json.dumps({**SPEC, "pitch": 1e308}))
    out_dir = tmp_path / "figs"
    rc, out, err = run_cli(capsys, "planar", str(spec), "--json", "--plot", str(out_dir / "d.png"))
    assert rc == 2 and out == "" and "Traceback" not in err and err.count("\n") == 1
    assert "'pitch'" in err and "from 0.0001 to 1000 in" in err
    assert not out_dir.exists()


@pytest.mark.parametrize("option", ["--plot", "--pivot-plot"])
def test_uncreatable_figure_folder_exits_2(spec_file, capsys, option):
    rc, out, err = run_cli(capsys, "planar", str(spec_file), option, "/proc/threadmate-x/d.png")
    assert rc == 2 and out == "" and "Traceback" not in err and err.count("\n") == 1
    assert f"{option} /proc/threadmate-x/d.png" in err


def test_figure_path_that_is_a_folder_exits_2(spec_file, tmp_path, capsys):
    folder = tmp_path / "d.png"
    folder.mkdir()
    rc, out, err = run_cli(capsys, "planar", str(spec_file), "--plot", str(folder))
    assert rc == 2 and out == "" and "is a directory" in err
    assert list(folder.iterdir()) == []


def test_empty_designation_and_directory(tmp_path, capsys):
    rc, out, err = run_cli(capsys, "planar", "")
    assert rc == 2 and out == "" and "empty thread designation" in err
    rc, out, err = run_cli(capsys, "planar", str(tmp_path))
    assert rc == 2 and out == "" and "is a directory, not a spec file" in err


def test_figure_under_a_file_exits_2_and_a_missing_folder_is_made(spec_file, tmp_path, capsys):
    """A figure's folder that is a file is refused by name; a missing one is created."""
    blocker = tmp_path / "blocker"
    blocker.write_text("a file")
    target = blocker / "d.png"
    rc, out, err = run_cli(capsys, "planar", str(spec_file), "--plot", str(target))
    assert rc == 2 and out == ""
    assert f"cannot create {target}: {blocker} is not a directory" in err
    assert blocker.read_text() == "a file"
    made = tmp_path / "new" / "deeper" / "d.png"
    rc, out, err = run_cli(capsys, "planar", str(spec_file), "--plot", str(made))
    assert rc == 0, err
    assert made.is_file() and made.stat().st_size > 0
