"""``threadmate sweep`` and ``threadmate library ...``: JSON output on both models, the
compliance options, resume (after Ctrl-C, said on stderr), refusals (exit 2, nothing
half-written)."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest

from _cli import run_captured, run_cli
from threadmate.contact import Compliance, ContactAnalyzer, Mechanics
from threadmate.library import METADATA_FILE, load, sweep

CHORD = "1e-4"  # the thesis's model only; the mechanics run at the default chord
STEP = "10"  # the mechanics' continuation step (degrees; coarse, for speed)
GRID = ["--roll", "1,2", "--pitch", "-1", "--phase", "0:270:90"]  # 2 held tilts x 4 phases


@pytest.fixture(scope="module")
def mech(quarter_20):
    return Mechanics(quarter_20, Compliance())


@pytest.fixture(scope="module")
def swept(quarter_20_file, tmp_path_factory):
    """A mechanics library made by the command (the default model)."""
    out = tmp_path_factory.mktemp("cli") / "lib"
    code, _, err = run_captured(
        "sweep",
        str(quarter_20_file),
        *GRID,
        "-o",
        str(out),
        "--step",
        STEP,
        "--workers",
        "2",
        "--json",
    )
    assert code == 0, err
    return out


@pytest.fixture(scope="module")
def thesis_swept(quarter_20_file, tmp_path_factory):
    """A thesis-model library made by the command: roll -1..1 by 1 at pitch 1, phases 0,
    120, 240."""
    out = tmp_path_factory.mktemp("cli") / "thesis"
    code, _, err = run_captured(
        "sweep",
        str(quarter_20_file),
        "--model",
        "thesis",
        "--roll",
        "-1:1:1",
        "--pitch",
        "1",
        "--phase",
        "0:360:120",
        "-o",
        str(out),
        "--chord",
        CHORD,
        "--workers",
        "2",
        "--json",
    )
    assert code == 0, err
    return out


def test_thesis_sweep_json_is_one_clean_document(quarter_20_file, tmp_path, capsys, quarter_20):
    out = tmp_path / "lib"
    rc, stdout, stderr = run_cli(
        capsys,
        "sweep",
        str(quarter_20_file),
        "--model",
        "thesis",
        "--roll",
        "0,4",
        "--pitch",
        "0",
        "--phase",
        "185",
        "-o",
        str(out),
        "--chord",
        CHORD,
        "--workers",
        "1",
        "--json",
    )
    assert rc == 0
    doc = json.loads(stdout)
    assert doc["model"] == "thesis" and doc["units"]["length"] == "in"
    assert doc["configurations"] == doc["done"] == 2 and doc["complete"]
    assert not doc["resumed"] and doc["done_before"] == 0
    assert "2/2" in stderr  # the progress bar went to stderr
    assert "resuming" not in stderr
    analyzer = ContactAnalyzer(quarter_20, chord=float(CHORD))
    expected = [analyzer.analyze(r, 0, 185).classification for r in (0, 4)]
    assert sum(doc["classifications"].values()) == 2
    assert pd.Series(expected).value_counts().to_dict() == doc["classifications"]


def test_mechanics_sweep_json_and_metadata(swept, capsys, mech):
    meta = json.loads((swept / METADATA_FILE).read_text())
    assert meta["model"] == "mechanics"
    assert meta["compliance"] == json.loads(json.dumps(Compliance().to_dict()))
    assert meta["continuation"]["step"] == float(STEP)
    rows = pd.read_parquet(swept)
    starts = rows[rows["role"] == "start"]
    for _, row in starts.iterrows():
        assert (
            row["classification"]
            == mech.settle(row["held_roll"], row["held_pitch"], row["phase"]).classification
        )


def test_mechanics_sweep_with_compliance_options(quarter_20_file, tmp_path, capsys, quarter_20):
    out = tmp_path / "stiff"
    args = [
        "sweep",
        str(quarter_20_file),
        "--roll",
        "1",
        "--pitch",
        "-1",
        "--phase",
        "90",
        "-o",
        str(out),
        "--step",
        STEP,
        "--phase-tolerance",
        "0.02",
        "--force",
        "20",
        "--stiffness",
        "0.5,2",
        "--friction",
        "0.1",
        "--compliance-z",
        "0.01",
        "--workers",
        "1",
        "--json",
    ]
    rc, stdout, stderr = run_cli(capsys, *args)
    assert rc == 0, stderr
    doc = json.loads(stdout)
    compliance = Compliance(force=20, stiffness=(0.5, 2), friction=0.1, compliance_z=0.01)
    assert doc["model"] == "mechanics" and doc["done"] == 1
    assert doc["compliance"] == json.loads(json.dumps(compliance.to_dict()))
    assert doc["continuation"]["phase_tolerance"] == 0.02
    assert doc["units"] == {
        "length": "in",
        "angle": "deg",
        "force": "N",
        "torque": "N m",
        "potential": "mJ",
        "work": "mJ",
    }
    mech = Mechanics(quarter_20, compliance)
    starts = pd.read_parquet(out).query("role == 'start'").sort_values("config_id")
    for phase, cls, z in zip(
        starts["phase"], starts["classification"], starts["centre_z"], strict=True
    ):
        rest = mech.settle(1, -1, phase)
        assert cls == rest.classification
        assert z == pytest.approx(rest.state.centre[2], abs=1e-12)
    # A resume with the same options: nothing to do, and said so on stderr.
    rc, stdout, stderr = run_cli(capsys, *args)
    assert rc == 0
    assert "resuming" in stderr and "1 of 1 configurations were already done" in stderr
    assert json.loads(stdout)["resumed"] and json.loads(stdout)["done_before"] == 1
    # Another compliance is refused, not mixed.
    rc, stdout, stderr = run_cli(capsys, *[a if a != "20" else "30" for a in args])
    assert rc == 2 and "refusing to mix" in stderr and "compliance" in stderr


def test_interrupted_mechanics_sweep_resumes_and_says_so(swept, quarter_20_file, tmp_path, capsys):
    # A library that holds one of its two held tilts (as a sweep stopped after one chunk
    # leaves it): the command computes the other and says how many were already done.
    out = tmp_path / "partial"
    shutil.copytree(swept, out)
    parts = sorted(out.glob("part-*.parquet"))
    assert len(parts) == 2
    parts[-1].unlink()
    rc, stdout, stderr = run_cli(
        capsys,
        "sweep",
        str(quarter_20_file),
        *GRID,
        "-o",
        str(out),
        "--step",
        STEP,
        "--workers",
        "1",
        "--json",
    )
    assert rc == 0
    assert f"resuming {out}: 4 of 8 configurations were already done" in stderr
    doc = json.loads(stdout)
    assert doc["resumed"] and doc["done_before"] == 4 and doc["done"] == 8
    pd.testing.assert_frame_equal(load(out), load(swept))


def test_info_query_summary(swept, capsys, quarter_20, tmp_path, mech):
    rc, out, _ = run_cli(capsys, "library", "info", str(swept), "--json")
    assert rc == 0
    doc = json.loads(out)
    assert doc["model"] == "mechanics" and doc["units"]["length"] == "in"
    assert doc["configurations"] == doc["done"] == 8
    assert doc["metadata"]["spec"] == json.loads(json.dumps(quarter_20.to_dict()))
    assert doc["metadata"]["grid"]["phase"] == [0.0, 90.0, 180.0, 270.0]
    rows = pd.read_parquet(swept)
    assert doc["states"]["by_role"] == rows["role"].value_counts().to_dict()

    rc, out, _ = run_cli(capsys, "library", "info", str(swept))
    assert rc == 0 and "mechanics model" in out and "compliance: axial force 10 N" in out

    rc, _, err = run_cli(
        capsys,
        "library",
        "query",
        str(swept),
        "--roll",
        "1.9",
        "--pitch",
        "-1",
        "--phase",
        "-90",
        "--json",
    )
    assert rc == 2 and "nearest configuration is roll 2, pitch -1, phase 270" in err
    rc, out, _ = run_cli(
        capsys,
        "library",
        "query",
        str(swept),
        "--roll",
        "1.9",
        "--pitch",
        "-1",
        "--phase",
        "-90",
        "--nearest",
        "--json",
    )
    assert rc == 0
    q = json.loads(out)
    assert q["model"] == "mechanics" and q["units"]["length"] == "in"
    assert q["moved_to_grid"] and q["grid"] == {"roll": 2.0, "pitch": -1.0, "phase": 270.0}
    direct = mech.settle(2, -1, 270)
    assert q["record"]["role"] == "start"
    assert q["record"]["classification"] == direct.classification
    assert q["record"]["contact_regions"] == [c.regions for c in direct.state.touching]

    rc, out, _ = run_cli(
        capsys, "library", "query", str(swept), "--roll", "2", "--pitch", "-1", "--phase", "270"
    )
    assert rc == 0 and "moved to the nearest" not in out
    assert f"Rest state: {direct.classification}" in out
    rc, out, _ = run_cli(
        capsys,
        "library",
        "query",
        str(swept),
        "--roll",
        "1.9",
        "--pitch",
        "-1",
        "--phase",
        "-90",
        "--nearest",
    )
    assert rc == 0 and "config_id" in out and "(moved to the nearest grid state)" in out

    figs = tmp_path / "figs"
    rc, out, _ = run_cli(
        capsys, "library", "summary", str(swept), "--phase", "90", "-o", str(figs), "--json"
    )
    assert rc == 0
    s = json.loads(out)
    assert s["model"] == "mechanics" and s["units"]["length"] == "in"
    counts = rows.loc[rows["role"] == "start", "classification"].value_counts().to_dict()
    assert {k: v for k, v in s["counts"].items() if v} == counts
    assert s["states"]["by_class"] == rows["classification"].value_counts().to_dict()
    assert s["at_phase"]["phase"] == 90.0
    assert sorted(p.name for p in figs.iterdir()) == [
        "phase_strips.png",
        "region_combinations.png",
        "stability_map.png",
    ]

    rc, out, _ = run_cli(capsys, "library", "summary", str(swept))
    assert rc == 0 and "Rest state reached" in out and "Contact-region combinations" in out
    assert "first-contact" in out


def test_thesis_info_query_summary(thesis_swept, capsys, quarter_20):
    rc, out, _ = run_cli(capsys, "library", "info", str(thesis_swept), "--json")
    assert rc == 0
    doc = json.loads(out)
    assert doc["model"] == "thesis" and doc["units"] == {"length": "in", "angle": "deg"}
    assert doc["configurations"] == doc["done"] == 9

    rc, out, _ = run_cli(
        capsys,
        "library",
        "query",
        str(thesis_swept),
        "--roll",
        "0.9",
        "--pitch",
        "1",
        "--phase",
        "-120",
        "--nearest",
        "--json",
    )
    assert rc == 0
    q = json.loads(out)
    assert q["model"] == "thesis" and q["units"]["length"] == "in"
    assert q["moved_to_grid"] and q["grid"] == {"roll": 1.0, "pitch": 1.0, "phase": 240.0}
    direct = ContactAnalyzer(quarter_20, chord=float(CHORD)).analyze(1, 1, 240).to_record()
    assert q["record"]["classification"] == direct["classification"]
    assert q["record"]["n_contacts"] == direct["n_contacts"]

    rc, out, _ = run_cli(
        capsys,
        "library",
        "query",
        str(thesis_swept),
        "--roll",
        "1",
        "--pitch",
        "1",
        "--phase",
        "240",
    )
    assert rc == 0 and "moved to the nearest" not in out and direct["classification"] in out

    rc, out, _ = run_cli(capsys, "library", "summary", str(thesis_swept), "--json")
    assert rc == 0
    s = json.loads(out)
    counts = pd.read_parquet(thesis_swept)["classification"].value_counts().to_dict()
    assert {k: v for k, v in s["counts"].items() if v} == counts
    assert s["model"] == "thesis" and "states" not in s

    rc, out, _ = run_cli(capsys, "library", "info", str(thesis_swept))
    assert rc == 0 and "thesis model" in out and "compliance_z 0" in out


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--roll", "0:4:0"], "--roll: step 0"),
        (["--pitch", "50"], "--pitch: 50 deg is out of range"),
        (["--phase", "abc"], "--phase: 'abc' is not a number"),
        (["--workers", "0"], "--workers 0"),
        (["--chord", "-1"], "--chord"),
        (["--model", "thesis", "--chunk-size", "0"], "--chunk-size must be a whole number"),
        (["--chunk-size", "4"], "--chunk-size applies to --model thesis only"),
        # The API's checks, named as the options.
        (["--step", "0"], "--step must be within (0, 10], got 0.0"),
        (["--step", "11"], "--step must be within (0, 10], got 11.0"),
        (["--step", "2", "--phase-tolerance", "3"], "--phase-tolerance must be within (0, 2]"),
        (["--force", "-1"], "--force -1 N is out of range"),
        (["--stiffness", "1,2,3"], "--stiffness '1,2,3'"),
        (["--friction", "nan"], "--friction must be a finite number"),
        (["--compliance-z", "100"], "--compliance-z 100 is out of range"),
        (["--model", "thesis", "--force", "20"], "--force applies to --model mechanics only"),
        (["--model", "thesis", "--step", "1"], "--step applies to --model mechanics only"),
    ],
)
def test_sweep_bad_input_exits_2_and_writes_nothing(args, words, quarter_20_file, tmp_path, capsys):
    out = tmp_path / "never"
    rc, stdout, stderr = run_cli(capsys, "sweep", str(quarter_20_file), "-o", str(out), *args)
    assert rc == 2
    assert stderr.startswith("threadmate: error:") and words in stderr
    assert "Traceback" not in stderr and stdout == ""
    assert not out.exists()


def test_mismatched_library_exits_2(swept, quarter_20_file, capsys):
    before = sorted(p.name for p in swept.iterdir())
    phase = ["--phase", "0:270:90"]
    for argv, words in (
        (["--roll", "1,2", "--pitch", "-2", *phase, "--step", STEP], "grid pitch values"),
        ([*GRID, "--step", "2"], "continuation settings"),
        ([*GRID, "--step", STEP, "--stiffness", "2"], "compliance"),
        ([*GRID, "--model", "thesis"], "model"),
    ):
        rc, stdout, stderr = run_cli(capsys, "sweep", str(quarter_20_file), *argv, "-o", str(swept))
        assert rc == 2 and "refusing to mix" in stderr and words in stderr, (argv, stderr)
        assert stdout == ""
    assert sorted(p.name for p in swept.iterdir()) == before


@pytest.mark.parametrize(
    "command", [["info"], ["query", "--roll", "0", "--pitch", "0", "--phase", "0"], ["summary"]]
)
def test_reading_a_non_library_exits_2(command, tmp_path, capsys):
    (tmp_path / "empty").mkdir()
    for path in (tmp_path / "missing", tmp_path / "empty"):
        rc, stdout, stderr = run_cli(capsys, "library", command[0], str(path), *command[1:])
        assert rc == 2 and stderr.startswith("threadmate: error:") and stdout == ""


def test_ctrl_c_then_resume_equals_an_uninterrupted_sweep(
    quarter_20_file, quarter_20, tmp_path, capsys
):
    grid = {"roll": "-2:2:1", "pitch": "0,3", "phase": "0:355:45"}  # 80 configurations
    out = tmp_path / "interrupted"
    cmd = [
        sys.executable,
        "-c",
        "from threadmate.cli import main; main()",
        "sweep",
        str(quarter_20_file),
        "--model",
        "thesis",
        "--roll",
        grid["roll"],
        "--pitch",
        grid["pitch"],
        "--phase",
        grid["phase"],
        "-o",
        str(out),
        "--chord",
        CHORD,
        "--workers",
        "1",
        "--chunk-size",
        "2",
    ]
    # A shell starts background jobs with SIGINT ignored, and children inherit that (a
    # Python started so never raises KeyboardInterrupt): give the sweep Ctrl-C's default.
    proc = subprocess.Popen(
        cmd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        deadline = time.monotonic() + 60
        while len(list(out.glob("part-*.parquet"))) < 3 and time.monotonic() < deadline:
            time.sleep(0.005)
        proc.send_signal(signal.SIGINT)  # what Ctrl-C sends
        _, stderr = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, stderr
    assert "run the same command to resume" in stderr
    partial = load(out)
    assert 6 <= len(partial) < 80 and partial["config_id"].is_unique

    rc, stdout, stderr = run_cli(capsys, *cmd[3:], "--json")
    assert rc == 0 and json.loads(stdout)["done"] == 80
    assert f"{len(partial)} of 80 configurations were already done" in stderr
    resumed = load(out)
    reference = load(
        sweep(
            quarter_20,
            grid["roll"],
            grid["pitch"],
            grid["phase"],
            out=tmp_path / "reference",
            workers=2,
            chord=float(CHORD),
            model="thesis",
        )
    )
    pd.testing.assert_frame_equal(resumed, reference)
    assert not [p for p in os.listdir(out) if p.endswith(".tmp")]
