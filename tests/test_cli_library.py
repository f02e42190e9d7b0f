"""``threadmate sweep`` and ``threadmate library ...``: JSON output, resume after Ctrl-C,
refusals (exit 2, nothing half-written)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest

from _cli import run_cli
from threadmate.cli import main
from threadmate.contact import ContactAnalyzer
from threadmate.geometry import save_spec
from threadmate.library import load, sweep

CHORD = "1e-4"


run = run_cli


@pytest.fixture(scope="module")
def spec_file(quarter_20, tmp_path_factory):
    return save_spec(quarter_20, tmp_path_factory.mktemp("spec") / "quarter-20.json")


@pytest.fixture(scope="module")
def swept(spec_file, tmp_path_factory):
    """A library made by the command: roll -1..1 by 1 at pitch 1, phases 0, 120, 240."""
    out = tmp_path_factory.mktemp("cli") / "lib"
    with pytest.raises(SystemExit) as exc:
        main(["sweep", str(spec_file), "--roll", "-1:1:1", "--pitch", "1", "--phase",
              "0:360:120", "-o", str(out), "--chord", CHORD, "--workers", "2", "--json"])
    assert exc.value.code == 0
    return out


def test_sweep_json_is_one_clean_document(spec_file, tmp_path, capsys, quarter_20):
    out = tmp_path / "lib"
    rc, stdout, stderr = run(capsys, "sweep", str(spec_file), "--roll", "0,4", "--pitch",
                             "0", "--phase", "185", "-o", str(out), "--chord", CHORD,
                             "--workers", "1", "--json")
    assert rc == 0
    doc = json.loads(stdout)
    assert doc["configurations"] == doc["done"] == 2 and doc["complete"]
    assert "2/2" in stderr                       # the progress bar went to stderr
    analyzer = ContactAnalyzer(quarter_20, chord=float(CHORD))
    expected = [analyzer.analyze(r, 0, 185).classification for r in (0, 4)]
    assert sum(doc["classifications"].values()) == 2
    assert pd.Series(expected).value_counts().to_dict() == doc["classifications"]


def test_info_query_summary(swept, capsys, quarter_20, tmp_path):
    rc, out, _ = run(capsys, "library", "info", str(swept), "--json")
    assert rc == 0
    doc = json.loads(out)
    assert doc["configurations"] == doc["done"] == 9
    assert doc["metadata"]["spec"] == json.loads(json.dumps(quarter_20.to_dict()))
    assert doc["metadata"]["grid"]["phase"] == [0.0, 120.0, 240.0]

    rc, out, _ = run(capsys, "library", "query", str(swept), "--roll", "0.9", "--pitch", "1",
                     "--phase", "-120", "--json")
    assert rc == 0
    q = json.loads(out)
    assert q["snapped"] and q["grid"] == {"roll": 1.0, "pitch": 1.0, "phase": 240.0}
    direct = ContactAnalyzer(quarter_20, chord=float(CHORD)).analyze(1, 1, 240).to_record()
    assert q["record"]["classification"] == direct["classification"]
    assert q["record"]["n_contacts"] == direct["n_contacts"]

    rc, out, _ = run(capsys, "library", "query", str(swept), "--roll", "1", "--pitch", "1",
                     "--phase", "240")
    assert rc == 0 and "snapped" not in out and direct["classification"] in out

    figs = tmp_path / "figs"
    rc, out, _ = run(capsys, "library", "summary", str(swept), "--phase", "120", "-o",
                     str(figs), "--json")
    assert rc == 0
    s = json.loads(out)
    counts = pd.read_parquet(swept)["classification"].value_counts().to_dict()
    assert {k: v for k, v in s["counts"].items() if v} == counts
    assert s["at_phase"]["phase"] == 120.0
    assert sorted(p.name for p in figs.iterdir()) == [
        "phase_strips.png", "region_combinations.png", "stability_map.png"]

    rc, out, _ = run(capsys, "library", "summary", str(swept))
    assert rc == 0 and "unstable" in out and "Contact-region combinations" in out


@pytest.mark.parametrize(("args", "words"), [
    (["--roll", "0:4:0"], "--roll: step 0"),
    (["--pitch", "50"], "--pitch: 50 deg is out of range"),
    (["--phase", "abc"], "--phase: 'abc' is not a number"),
    (["--workers", "0"], "--workers 0"),
    (["--chord", "-1"], "--chord"),
    (["--chunk-size", "0"], "--chunk-size 0"),
])
def test_sweep_bad_input_exits_2_and_writes_nothing(args, words, spec_file, tmp_path,
                                                    capsys):
    out = tmp_path / "never"
    rc, stdout, stderr = run(capsys, "sweep", str(spec_file), "-o", str(out), *args)
    assert rc == 2
    assert stderr.startswith("threadmate: error:") and words in stderr
    assert "Traceback" not in stderr and stdout == ""
    assert not out.exists()


def test_mismatched_library_exits_2(swept, spec_file, capsys):
    before = sorted(p.name for p in swept.iterdir())
    rc, stdout, stderr = run(capsys, "sweep", str(spec_file), "--roll", "-1:1:1", "--pitch",
                             "2", "--phase", "0:360:120", "-o", str(swept), "--chord", CHORD)
    assert rc == 2 and "refusing to mix" in stderr and "grid pitch values" in stderr
    assert sorted(p.name for p in swept.iterdir()) == before


@pytest.mark.parametrize("command", [["info"], ["query", "--roll", "0", "--pitch", "0",
                                                "--phase", "0"], ["summary"]])
def test_reading_a_non_library_exits_2(command, tmp_path, capsys):
    (tmp_path / "empty").mkdir()
    for path in (tmp_path / "missing", tmp_path / "empty"):
        rc, stdout, stderr = run(capsys, "library", command[0], str(path), *command[1:])
        assert rc == 2 and stderr.startswith("threadmate: error:") and stdout == ""


def test_ctrl_c_then_resume_equals_an_uninterrupted_sweep(spec_file, quarter_20, tmp_path,
                                                         capsys):
    grid = {"roll": "-2:2:1", "pitch": "0,3", "phase": "0:355:45"}    # 80 configurations
    out = tmp_path / "interrupted"
    cmd = [sys.executable, "-c", "from threadmate.cli import main; main()", "sweep",
           str(spec_file), "--roll", grid["roll"], "--pitch", grid["pitch"], "--phase",
           grid["phase"], "-o", str(out), "--chord", CHORD, "--workers", "1",
           "--chunk-size", "2"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 60
        while len(list(out.glob("part-*.parquet"))) < 3 and time.monotonic() < deadline:
            time.sleep(0.005)
        proc.send_signal(signal.SIGINT)                 # what Ctrl-C sends
        _, stderr = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, stderr
    assert "run the same command to resume" in stderr
    partial = load(out)
    assert 6 <= len(partial) < 80 and partial["config_id"].is_unique

    rc, stdout, _ = run(capsys, *cmd[3:], "--json")
    assert rc == 0 and json.loads(stdout)["done"] == 80
    resumed = load(out)
    reference = load(sweep(quarter_20, grid["roll"], grid["pitch"], grid["phase"],
                           out=tmp_path / "reference", workers=2, chord=float(CHORD)))
    pd.testing.assert_frame_equal(resumed, reference)
    assert not [p for p in os.listdir(out) if p.endswith(".tmp")]
