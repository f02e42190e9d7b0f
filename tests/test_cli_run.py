"""``threadmate run`` end to end on tiny grids: the layout, the report (every figure it
lists embedded and on disk), recommendation.json and starts.csv against each other and
against a reading of the library's rows, bad input refused before any work."""

from __future__ import annotations

import contextlib
import io
import json
import re
import shutil
from pathlib import Path

import networkx as nx
import pandas as pd
import pytest

from _cli import THESIS_PARTS, run_cli
from _libraries import (
    DESIGNATION,
    REAL_GRID,
    library_rows,
    mechanics_library,
    setting_figures,
    walk_starts,
)
from threadmate.cli import main

SETTING_KEYS = (
    "share_snap",
    "turn_mean",
    "turn_worst",
    "work_mean",
    "work_worst",
    "click_mean",
    "torque_peak",
)
EMBED = re.compile(r"!\[[^\]]*\]\((figures/[^)\s]+)\)")


@pytest.fixture(scope="module")
def job(tmp_path_factory):
    """``threadmate run`` over the session's real library (same thread, grid, compliance
    and chord: the sweep stage finds it complete and reuses it)."""
    lib = mechanics_library(tmp_path_factory)
    out = tmp_path_factory.mktemp("run") / "job"
    shutil.copytree(lib, out / "library")
    before = {p.name: p.stat().st_size for p in (out / "library").iterdir()}
    argv = [
        "run",
        DESIGNATION,
        *THESIS_PARTS,
        "-o",
        str(out),
        "--roll",
        REAL_GRID["roll"],
        "--pitch",
        REAL_GRID["pitch"],
        "--phase",
        REAL_GRID["phase"],
        "--workers",
        "2",
        "--json",
    ]
    # capsys is function-scoped: capture this module-scoped run by hand.
    stdout, stderr = io.StringIO(), io.StringIO()
    with (
        contextlib.redirect_stdout(stdout),
        contextlib.redirect_stderr(stderr),
        pytest.raises(SystemExit) as exc,
    ):
        main(argv)
    assert exc.value.code == 0, stderr.getvalue()
    return out, json.loads(stdout.getvalue()), before


def test_run_writes_the_layout_and_reuses_the_library(job):
    out, doc, before = job
    for name in (
        "network.graphml",
        "network.json",
        "starts.csv",
        "recommendation.json",
        "report.md",
    ):
        assert (out / name).is_file(), name
    assert {p.name: p.stat().st_size for p in (out / "library").iterdir()} == before
    assert doc["units"] == {
        "length": "in",
        "angle": "deg",
        "work": "mJ",
        "torque": "N m",
        "force": "N",
        "stiffness": "N m/rad",
    }
    rows = library_rows(out / "library")
    graph = nx.read_graphml(out / "network.graphml")
    assert graph.number_of_nodes() == len(rows)
    assert graph.number_of_edges() == int((rows["next_id"] != "").sum())
    starts = {k: v for k, v in doc["counts"].items() if k.startswith("starts ")}
    assert sum(starts.values()) == int((rows["role"] == "start").sum()) == 2 * 3 * 12


def test_report_embeds_every_figure_it_lists(job):
    out, doc, _ = job
    report = (out / "report.md").read_text()
    mentioned = set(re.findall(r"figures/[\w.-]+", report))
    embedded = EMBED.findall(report)
    assert embedded and set(embedded) == mentioned
    assert len(embedded) == len(set(embedded))
    for rel in embedded:
        assert (out / rel).is_file() and (out / rel).stat().st_size > 1000, rel
    listed = {Path(p).relative_to(out).as_posix() for p in doc["figures"].values()}
    assert listed == set(embedded)
    on_disk = {f"figures/{p.name}" for p in (out / "figures").iterdir()}
    assert on_disk == set(embedded)
    assert {"click_signature", "click_vs_tilt", "recommendation"} <= set(doc["figures"])


def test_report_says_what_to_set_and_with_what(job):
    out, doc, _ = job
    report = (out / "report.md").read_text()
    best = json.loads((out / "recommendation.json").read_text())["recommended"]
    assert f"**Pre-tilt (held pitch): {best['held_pitch']:+g} deg**" in report
    for text in (
        "axial force 10 N",
        "rotational stiffness 1/1 N m/rad",
        "friction 0.15",
        "roll 0..1 (2) x pitch -1..1 (3) x phase 0..330 (12)",
        "**quasi-stable**",
        "**in-phase**",
        "Work: turning: max(0, work_friction + work_potential)",
    ):
        assert text in report, text
    paragraphs = [p.strip() for p in report.split("\n\n") if p.strip()]
    assert len(paragraphs) == len(set(paragraphs)), "a paragraph twice"
    if json.loads((out / "recommendation.json").read_text())["at_edge"]:
        assert "edge of the range searched" in report


def test_recommendation_and_starts_agree(job):
    out, doc, _ = job
    rec = json.loads((out / "recommendation.json").read_text())
    starts = pd.read_csv(out / "starts.csv", keep_default_na=True)
    walked = walk_starts(library_rows(out / "library"))
    starts = starts.set_index("node").loc[walked.index]
    for col in ("snapped", "reaches", "failed", "passes_unstable"):
        assert list(starts[col]) == list(walked[col]), col
    for col in ("turn", "work", "click", "torque_peak"):
        assert starts[col].to_numpy() == pytest.approx(
            walked[col].to_numpy(float), nan_ok=True, rel=1e-9
        ), col
    assert sorted(s["held_pitch"] for s in rec["settings"]) == sorted(set(starts["held_pitch"]))
    for s in rec["settings"]:
        assert set(SETTING_KEYS) <= set(s)
        want = setting_figures(starts, s["held_pitch"])
        for key in SETTING_KEYS:
            if want[key] is None:
                assert s[key] is None, key
            else:
                assert s[key] == pytest.approx(want[key], rel=1e-9), key
    assert rec["recommended"] == rec["settings"][0]
    assert {k: v for k, v in doc["recommended"].items() if k != "units"} == rec["recommended"]
    pitches = sorted(set(starts["held_pitch"]))
    assert rec["at_edge"] == (rec["recommended"]["held_pitch"] in (pitches[0], pitches[-1]))


@pytest.mark.slow
def test_run_from_scratch_on_one_tilt(tmp_path, capsys):
    """A grid no library holds yet: the sweep stage runs, then everything else; with one
    setting there is no margin and no edge."""
    out = tmp_path / "tiny"
    rc, stdout, err = run_cli(
        capsys,
        "run",
        DESIGNATION,
        *THESIS_PARTS,
        "-o",
        out,
        "--roll",
        "0",
        "--pitch",
        "0",
        "--phase",
        "300,330",
        "--workers",
        "1",
    )
    assert rc == 0, err
    assert "recommended pre-tilt: held pitch +0 deg" in stdout
    rows = library_rows(out / "library")
    assert int((rows["role"] == "start").sum()) == 2
    rec = json.loads((out / "recommendation.json").read_text())
    assert len(rec["settings"]) == 1 and rec["margin"] is None and rec["at_edge"] is False
    want = setting_figures(walk_starts(rows), 0.0)
    assert rec["recommended"]["share_snap"] == pytest.approx(want["share_snap"])
    report = (out / "report.md").read_text()
    for rel in EMBED.findall(report):
        assert (out / rel).is_file()
    assert "Margin over the next setting" not in report


@pytest.mark.parametrize(
    "args",
    [
        ["M7x9"],
        [DESIGNATION, "--roll", "99"],
        [DESIGNATION, "--phase", "0:10:-1"],
        [DESIGNATION, "--roll-spread", "-1"],
        [DESIGNATION, "--workers", "0"],
        [DESIGNATION, "--compare-force", "ten"],
        [DESIGNATION, "--force", "-5"],
    ],
)
def test_run_refuses_bad_input(tmp_path, capsys, args):
    out = tmp_path / "x"
    rc, stdout, err = run_cli(capsys, "run", *args, "-o", out)
    assert rc == 2 and stdout == ""
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("threadmate: error:"), err
    assert not out.exists()
