"""``threadmate settle`` and ``threadmate search``: JSON documents, text, figures and exit codes
via the real entry point."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from _cli import THESIS_PARTS, run_cli

DESIGNATION = "1/4-20 UNC-2A/2B"
PITCH = 0.05  # in

# A custom 1/4-20 pair with every corner sharp (the published mean-material limits, no
# root fillet), written by hand as a spec file.
SPEC = {
    "units": "in",
    "pitch": 0.05,
    "bolt": {"major": 0.24485, "pitch_diameter": 0.21455, "minor": 0.1887},
    "nut": {"major": 0.25, "pitch_diameter": 0.21995, "minor": 0.2015},
}

# The upright, stiffly held bolt: it rests flat outside the in-phase window and snaps at its
# edge (about -11 deg for this pair) within a turn.
UPRIGHT = ["--roll", "0", "--pitch", "0", "--phase", "330", "--stiffness", "1000"]


def _one_line_error(err: str, after_progress: bool = False) -> None:
    """One error line on stderr; a search's progress bar may stand before it."""
    assert "Traceback" not in err
    lines = err.splitlines()
    errors = [line for line in lines if line.startswith("threadmate: ")]
    assert len(errors) == 1 and lines[-1] == errors[0], err
    assert after_progress or len(lines) == 1, err


def test_settle_json_document(capsys):
    rc, out, err = run_cli(
        capsys,
        "settle",
        DESIGNATION,
        *THESIS_PARTS,
        "--roll",
        "4",
        "--pitch",
        "0",
        "--phase",
        "170",
        "--json",
    )
    assert rc == 0, err
    doc = json.loads(out)  # exactly one JSON document on stdout
    for key in (
        "units",
        "held",
        "phase",
        "parameters",
        "classification",
        "rest",
        "contacts",
        "potential",
        "driver_torque",
        "path",
    ):
        assert key in doc, key
    assert doc["units"]["length"] == "in" and doc["units"]["angle"] == "deg"
    assert doc["units"]["force"] == "N" and doc["units"]["torque"] == "N m"
    assert doc["units"]["potential"] == "mJ"
    assert doc["held"] == {"roll": 4.0, "pitch": 0.0} and doc["phase"] == 170.0
    params = doc["parameters"]
    assert params["force"] == 10.0 and params["friction"] == 0.15
    assert params["stiffness"] == {"roll": 1.0, "pitch": 1.0}
    assert doc["classification"] in ("stable", "quasi-stable", "in-phase")
    rest = doc["rest"]
    for key in ("origin", "rotation", "roll", "pitch"):
        assert key in rest, key
    R = np.array(rest["rotation"])
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-9)
    assert len(rest["origin"]) == 3
    assert doc["contacts"], "a rest state touches"
    for c in doc["contacts"]:
        for key in ("point", "normal", "force", "bolt_region", "nut_region"):
            assert key in c, key
        assert math.isclose(np.linalg.norm(c["normal"]), 1.0, abs_tol=1e-9)
        assert c["force"] >= 0.0
        assert c["point"][2] >= -PITCH  # on the nut's top or in its first thread
    # An independent check from the document alone: the contact forces carry the load.
    carried = sum(c["force"] * c["normal"][2] for c in doc["contacts"])
    assert carried == pytest.approx(params["force"], rel=1e-5)
    assert math.isfinite(doc["potential"]) and math.isfinite(doc["driver_torque"])
    assert isinstance(doc["path"], list)
    for state in doc["path"]:
        assert state["classification"] == "unstable" and "kind" in state


def test_settle_text_on_a_spec_file(spec_file, capsys):
    rc, out, err = run_cli(
        capsys,
        "settle",
        str(spec_file),
        "--roll",
        "4",
        "--pitch",
        "0",
        "--phase",
        "170",
        "--stiffness",
        "1,2",
        "--friction",
        "0.1",
    )
    assert rc == 0, err
    for field in (
        "held at roll 4, pitch 0 deg",
        "phase 170 deg",
        "force 10 N",
        "rotational stiffness 1/2 N m/rad (roll/pitch)",
        "friction 0.1",
        "Class: ",
        "Rest pose:",
        "compliance centre height",
        "force N",
        "bolt/nut",
        "Potential:",
        " mJ",
        "driver torque:",
        " N m",
        "Path from first contact",
    ):
        assert field in out, field
    cls = out.split("Class: ", 1)[1].split()[0]
    assert cls in ("stable", "quasi-stable", "in-phase")


@pytest.mark.parametrize(
    "argv, words",
    [
        # The Compliance's refusals, each named as the option the user gave.
        (["--force", "-1"], "--force -1 N is out of range"),
        (["--force", "nan"], "--force must be a finite number"),
        (["--stiffness", "inf"], "--stiffness must be a finite number"),
        (["--stiffness", "1,-2"], "--stiffness (pitch) -2 N m/rad is out of range"),
        (["--stiffness", "1,2,3"], "--stiffness"),
        (["--stiffness", "stiff"], "--stiffness"),
        (["--friction", "-0.1"], "--friction -0.1 is out of range"),
        (["--lateral-stiffness", "0"], "--lateral-stiffness 0 N/m is out of range"),
        (["--roll", "100"], "--roll 100 deg is out of range"),
    ],
)
def test_settle_bad_parameters_exit_2(capsys, argv, words):
    base = {"--roll": "4", "--pitch": "0", "--phase": "170"}
    args = [a for k, v in base.items() if k not in argv for a in (k, v)]
    rc, out, err = run_cli(capsys, "settle", DESIGNATION, *args, *argv, "--json")
    assert rc == 2 and out == ""
    _one_line_error(err)
    assert err.startswith("threadmate: error:") and words in err


@pytest.mark.parametrize(
    "argv",
    [
        ["--turns", "0"],
        ["--turns", "11"],
        ["--step", "0"],
        ["--force", "-1"],
        ["--stiffness", "1,2,3"],
        ["--roll", "100"],
    ],
)
def test_search_bad_input_writes_nothing(tmp_path, capsys, argv):
    fig = tmp_path / "out.png"
    base = {"--roll": "4", "--pitch": "0", "--phase": "170"}
    args = [a for k, v in base.items() if k not in argv for a in (k, v)]
    rc, out, err = run_cli(capsys, "search", DESIGNATION, *args, *argv, "--plot", str(fig))
    assert rc == 2 and out == ""
    _one_line_error(err)
    assert not fig.exists() and list(tmp_path.iterdir()) == []


def test_search_bad_figure_suffix_is_refused_first(tmp_path, capsys):
    # The spec file does not exist: the figure's name is checked first.
    rc, out, err = run_cli(
        capsys,
        "search",
        str(tmp_path / "missing.json"),
        "--roll",
        "0",
        "--pitch",
        "0",
        "--phase",
        "0",
        "--plot",
        str(tmp_path / "out.jpg"),
    )
    assert rc == 2 and out == "" and ".jpg" in err
    assert list(tmp_path.iterdir()) == []


def test_search_without_snap_exits_3_after_printing(capsys):
    rc, out, err = run_cli(
        capsys,
        "search",
        DESIGNATION,
        *THESIS_PARTS,
        "--roll",
        "4",
        "--pitch",
        "0",
        "--phase",
        "170",
        "--turns",
        "0.05",
        "--json",
    )
    assert rc == 3
    doc = json.loads(out)  # the document is printed all the same, and only it
    assert doc["snap"] is None and doc["turns"] == 0.05
    assert doc["start"] == {"roll": 4.0, "pitch": 0.0, "phase": 170.0}
    assert set(doc["work"]) >= {"total", "friction", "potential"}
    assert doc["work"]["total"] == pytest.approx(doc["work"]["friction"] + doc["work"]["potential"])
    assert all(e["kind"] != "snap" for e in doc["events"])
    assert doc["states"] and all(s["classification"] != "in-phase" for s in doc["states"])
    _one_line_error(err, after_progress=True)
    assert "no snap within 0.05 turn(s)" in err
    # The same in text (the Mechanics is cached in-process: a short second run).
    rc, out, err = run_cli(
        capsys,
        "search",
        DESIGNATION,
        *THESIS_PARTS,
        "--roll",
        "4",
        "--pitch",
        "0",
        "--phase",
        "170",
        "--turns",
        "0.02",
    )
    assert rc == 3
    for field in (
        "counter-clockwise search from roll 4, pitch 0 deg, phase 170 deg",
        "Snap: no snap within 0.02 turn(s)",
        "Work over the turns searched: total",
        "mJ",
        "Events (0)",
    ):
        assert field in out, field
    _one_line_error(err, after_progress=True)


def test_search_that_snaps_with_plot(tmp_path, capsys):
    fig = tmp_path / "signature.png"
    rc, out, err = run_cli(
        capsys, "search", DESIGNATION, *THESIS_PARTS, *UPRIGHT, "--json", "--plot", str(fig)
    )
    assert rc == 0, err
    doc = json.loads(out)
    for key in ("units", "parameters", "start", "snap", "work", "events", "states"):
        assert key in doc, key
    snap = doc["snap"]
    assert snap is not None and snap["drop"] > 0
    assert 330 < snap["phase"] <= 330 + 360
    assert snap["turn"] == pytest.approx(snap["phase"] - 330)
    assert doc["parameters"]["stiffness"] == {"roll": 1000.0, "pitch": 1000.0}
    assert doc["events"][-1]["kind"] == "snap"
    assert doc["states"][-1]["classification"] == "in-phase"
    for state in doc["states"]:
        for key in ("phase", "classification", "origin", "rotation", "contacts", "driver_torque"):
            assert key in state, key
    assert fig.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == [fig.name]  # no temporary file left


def test_help_says_units_and_defaults(capsys):
    for command in ("settle", "search"):
        rc, out, err = run_cli(capsys, command, "--help")
        assert rc == 0
        text = " ".join(out.split())
        for phrase in (
            "in N",
            "N m/rad",
            "N/m",
            "spec's length units",
            "degrees",
            "Compliance",
            "Whitney",
            "VDI 2230",
        ):
            assert phrase in text, (command, phrase)
    assert "work in mJ" in text and "--turns" in text and ".pdf" in text
