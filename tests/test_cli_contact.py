"""``threadmate contact``: JSON document, text output and exit codes via the real entry point."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from _cli import run_cli

# 1/4-20 UNC-2A/2B at mean material (ASME B1.1 table values), UNR root radius 0.125 p.
SPEC = {
    "units": "in",
    "pitch": 0.05,
    "bolt": {"major": 0.24485, "pitch_diameter": 0.21455, "minor": 0.1887, "root_fillet": 0.00625},
    "nut": {"major": 0.25, "pitch_diameter": 0.21995, "minor": 0.2015},
}


def test_json_document(spec_file, capsys):
    rc, out, err = run_cli(
        capsys, "contact", str(spec_file), "--roll", "4", "--pitch", "4", "--phase", "235", "--json"
    )
    assert rc == 0
    doc = json.loads(out)  # exactly one JSON document on stdout
    assert doc["units"] == "in"
    assert (doc["roll"], doc["pitch"], doc["phase"]) == (4.0, 4.0, 235.0)
    assert doc["classification"] in ("stable", "quasi-stable", "unstable", "in-phase", "no-contact")
    for key in ("interference", "origin_drop", "stages", "pivot_offset", "rolling"):
        assert key in doc
    assert isinstance(doc["rolling"], bool)
    if doc["stages"]["third"]["found"] and len(doc["stages"]["second"]["contacts"]) == 2:
        before = [c["pairs"] for c in doc["stages"]["second"]["contacts"]]
        after = [c["pairs"] for c in doc["stages"]["third"]["contacts"][:2]]
        assert doc["rolling"] == any(b > a for a, b in zip(before, after, strict=True))
    if doc["classification"] == "unstable":
        assert doc["interference"] > doc["origin_drop"]
    first = doc["stages"]["first"]
    assert first["origin"][:2] == [0.0, 0.0]
    # The tilted bolt's lowest tip point sits on the nut's top plane or below it.
    R = np.array(first["rotation"])
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert first["contacts"], "a first contact"
    for name in ("second", "third"):
        stage = doc["stages"][name]
        assert "angle" in stage
        if stage["found"]:
            assert len(stage["origin"]) == 3 and len(stage["rotation"]) == 3
            for c in stage["contacts"]:
                assert len(c["point"]) == 3 and len(c["normal"]) == 3
                assert math.isclose(np.linalg.norm(c["normal"]), 1.0, abs_tol=1e-9)
                assert c["pairs"] >= 1 and c["bolt_region"] and c["nut_region"]


def test_text_output_has_the_figure_4_1_fields(spec_file, capsys):
    rc, out, err = run_cli(
        capsys, "contact", str(spec_file), "--roll", "-4", "--pitch", "0", "--phase", "131"
    )
    assert rc == 0
    for field in (
        "ROLL = -4",
        "PHASE = 131",
        "Classification:",
        "1st contact",
        "2nd contact",
        "3rd contact",
        "BOLT origin",
        "pairs",
        "bolt/nut",
        "Interference",
        "origin drop",
        "rolling pivot axis: ",
    ):
        assert field in out


def test_help_names_the_fixed_pivot_procedure_and_the_thesis_criteria(capsys):
    rc, out, err = run_cli(capsys, "contact", "--help")
    assert rc == 0
    text = " ".join(out.split())
    for phrase in (
        "fixed-pivot procedure",
        "compliance holding the bolt is ignored",
        "threadmate settle",
        "threadmate search",
        "section 4.2",
        "unstable",
        "quasi-stable",
        "stable",
        "rolling",
    ):
        assert phrase in text, phrase


def test_in_phase_configuration(spec_file, capsys):
    rc, out, err = run_cli(
        capsys, "contact", str(spec_file), "--roll", "0", "--pitch", "0", "--phase", "0", "--json"
    )
    assert rc == 0
    doc = json.loads(out)
    assert doc["classification"] == "in-phase"
    c = (0.21995 - 0.21455) / math.sqrt(3)  # axial clearance: the bolt drops half of it
    assert doc["stages"]["first"]["origin"][2] == pytest.approx(-c / 2, abs=5e-6)
    assert doc["stages"]["second"]["found"] is False


@pytest.mark.parametrize(
    "argv",
    [
        ["--roll", "50", "--pitch", "0", "--phase", "0"],
        ["--roll", "0", "--pitch", "-45.5", "--phase", "0"],
        ["--roll", "nan", "--pitch", "0", "--phase", "0"],
        ["--roll", "0", "--pitch", "0", "--phase", "inf"],
        ["--roll", "0", "--pitch", "0", "--phase", "0", "--chord", "-1e-6"],
        ["--roll", "0", "--pitch", "0", "--phase", "0", "--chord", "0.01"],
    ],
)
def test_bad_input_exits_2(spec_file, capsys, argv):
    rc, out, err = run_cli(capsys, "contact", str(spec_file), *argv, "--json")
    assert rc == 2
    assert out == ""
    assert err.startswith("threadmate: error:") and "Traceback" not in err


def test_bad_spec_exits_2(tmp_path, capsys):
    bad = dict(SPEC, bolt=dict(SPEC["bolt"], pitch_diameter=0.23))  # bolt PD > nut PD
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(bad))
    rc, out, err = run_cli(
        capsys, "contact", str(path), "--roll", "0", "--pitch", "0", "--phase", "0"
    )
    assert rc == 2 and out == "" and "pitch_diameter" in err
    rc, out, err = run_cli(
        capsys,
        "contact",
        str(tmp_path / "missing.json"),
        "--roll",
        "0",
        "--pitch",
        "0",
        "--phase",
        "0",
    )
    assert rc == 2 and "not found" in err


def test_missing_option_is_a_usage_error(spec_file, capsys):
    rc, out, err = run_cli(capsys, "contact", str(spec_file), "--roll", "0", "--pitch", "0")
    assert rc == 2 and "--phase" in err


# -- issue 11 ------------------------------------------------------------------------------
@pytest.mark.parametrize("value", ["1e308", "-1001", "nan", "inf"])
def test_absurd_compliance_z_exits_2_with_range(spec_file, capsys, value):
    rc, out, err = run_cli(
        capsys,
        "contact",
        str(spec_file),
        "--roll",
        "4",
        "--pitch",
        "0",
        "--phase",
        "185",
        "--compliance-z",
        value,
    )
    assert rc == 2 and out == "" and "Traceback" not in err and err.count("\n") == 1
    assert "--compliance-z" in err
    if value not in ("nan", "inf"):
        assert "from -1000 to 1000 in" in err


def test_absurd_spec_and_empty_designation(tmp_path, capsys):
    absurd = tmp_path / "absurd.json"
    absurd.write_text(json.dumps({**SPEC, "pitch": 1e308}))
    for spec, text in (
        (absurd, "from 0.0001 to 1000 in"),
        ("", "empty thread designation"),
        (tmp_path, "is a directory, not a spec file"),
    ):
        rc, out, err = run_cli(
            capsys, "contact", str(spec), "--roll", "4", "--pitch", "0", "--phase", "185"
        )
        assert rc == 2 and out == "" and text in err and "Traceback" not in err
