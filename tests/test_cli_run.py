"""``threadmate run`` end to end on tiny grids: the layout, the report (every figure it
lists embedded and on disk), recommendation.json and starts.csv against each other and
against a reading of the library's rows, bad input refused before any work."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import networkx as nx
import numpy as np
import pandas as pd
import pytest

from _cli import THESIS_PARTS, run_captured, run_cli
from _libraries import (
    DESIGNATION,
    REAL_GRID,
    library_rows,
    mechanics_library,
    setting_figures,
    walk_starts,
)
from threadmate import InputError

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
    code, stdout, stderr = run_captured(*argv)  # capsys is function-scoped
    assert code == 0, stderr
    return out, json.loads(stdout), before


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
    assert {"click_signature", "click_vs_tilt", "recommendation", "envelope"} <= set(doc["figures"])


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
        # The click is the fall a sensor sees within a degree of turn (mechanics.md).
        "The click to listen for: a fall of",
        "*click*, the fall of the compliance centre a sensor sees at the snap, from the "
        "highest the bolt stands within the last degree of turn to the landing",
    ):
        assert text in report, text
    paragraphs = [p.strip() for p in report.split("\n\n") if p.strip()]
    assert len(paragraphs) == len(set(paragraphs)), "a paragraph twice"
    if json.loads((out / "recommendation.json").read_text())["at_edge"]:
        assert "edge of the range searched" in report


def _lean_direction(roll: float, pitch: float) -> float:
    """The azimuth (deg, from +X toward +Y) toward which ``Rx(roll) Ry(pitch) e_z`` leans."""
    r, p = np.radians(roll), np.radians(pitch)
    axis = np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]]) @ (
        np.array([np.sin(p), 0.0, np.cos(p)])
    )
    return float(np.degrees(np.arctan2(axis[1], axis[0])) % 360.0)


def test_report_leads_with_what_to_buy_and_what_it_tolerates(job):
    """The first section names the force and stiffness, held upright, and the misalignment
    every start phase tolerates, read off the grid: recomputed from starts.csv with the
    tilt's direction from explicit rotation matrices."""
    out, doc, _ = job
    report = (out / "report.md").read_text()
    sections = re.findall(r"^## (.+)$", report, flags=re.M)
    assert sections[0] == "What to buy and set", sections
    assert sections.index("The pre-tilt, where the nut's azimuth is known") > sections.index(
        "The snap a sensor sees"
    )
    assert "- **F = 10 N, k = 1 N m/rad, held upright**: every start phase snaps" in report
    assert "![envelope](figures/envelope.png)" in report
    starts = pd.read_csv(out / "starts.csv")
    by_direction: dict[float, list[tuple[float, float]]] = {}
    for (roll, pitch), group in starts.groupby(["held_roll_deg", "held_pitch_deg"]):
        share = float((group["snapped"] & ~group["failed"]).mean())
        if roll == 0 and pitch == 0:
            upright = share
            continue
        size = float(np.hypot(roll, pitch))  # within 1e-3 deg at these tilts: order only
        d = round(_lean_direction(roll, pitch), 1)
        by_direction.setdefault(d, []).append((size, share))
    assert upright == 1.0
    # Each direction holds every phase up to the last size before its first failure; the
    # grid here has one size per direction.
    holds = {d: 0.0 if sizes[0][1] < 1 else None for d, sizes in by_direction.items()}
    tolerated = doc["tolerated"]
    assert tolerated["located"] is False and tolerated["force"] == 10
    if any(v == 0.0 for v in holds.values()):
        assert tolerated["tilt"] == 0.0
        assert "**but not at the smallest misalignment the grid holds**" in report
        worst = sorted(d for d, v in holds.items() if v == 0.0)
        assert sorted(round(d, 1) for d in tolerated["worst_directions"]) == worst
    else:
        assert tolerated["tilt"] > 0
        assert f"up to **{tolerated['tilt']:.2f} deg** of misalignment" in report
    env = json.loads((out / "envelope.json").read_text())
    assert env["units"]["angle"] == "deg" and len(env["settings"]) == 1
    assert len(env["settings"][0]["directions"]) == len(by_direction)


#: starts.csv's columns with their units, by the outcome's name (spec lengths in inches).
STARTS_UNITS = {
    "held_roll": "held_roll_deg",
    "held_pitch": "held_pitch_deg",
    "held_tilt": "held_tilt_deg",
    "held_direction": "held_direction_deg",
    "phase": "phase_deg",
    "turn": "turn_deg",
    "work": "work_mJ",
    "click": "click_in",
    "snap_phase": "snap_phase_deg",
    "torque_peak": "torque_peak_N_m",
}


def test_recommendation_and_starts_agree(job):
    out, doc, _ = job
    rec = json.loads((out / "recommendation.json").read_text())
    starts = pd.read_csv(out / "starts.csv", keep_default_na=True)
    assert set(STARTS_UNITS.values()) <= set(starts.columns)
    assert not set(STARTS_UNITS) & set(starts.columns)  # no column without its unit
    starts = starts.rename(columns={v: k for k, v in STARTS_UNITS.items()})
    walked = walk_starts(library_rows(out / "library"))
    starts = starts.set_index("node").loc[walked.index]
    for col in ("snapped", "reaches", "failed", "passes_unstable"):
        assert list(starts[col]) == list(walked[col]), col
    for col in ("turn", "work", "click", "torque_peak"):
        assert starts[col].to_numpy() == pytest.approx(
            walked[col].to_numpy(float), nan_ok=True, rel=1e-9
        ), col
    assert sorted(s["held_pitch"] for s in rec["settings"]) == sorted(set(starts["held_pitch"]))
    # The ranking leaves out the starts whose descent did not reach a rest state.
    at_rest = starts[starts["classification"] != "unstable"]
    for s in rec["settings"]:
        assert set(SETTING_KEYS) <= set(s)
        want = setting_figures(at_rest, s["held_pitch"])
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
    assert "recommended pre-tilt (nut azimuth known): held pitch +0 deg" in stdout
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


def test_report_counts_the_starts_not_at_rest(job):
    """The line "N starts did not reach a rest state", N read off the library's rows (the
    starts of class unstable: their descent did not converge), each of them named."""
    out, _, _ = job
    report = (out / "report.md").read_text()
    rows = library_rows(out / "library")
    stopped = rows[(rows["role"] == "start") & (rows["classification"] == "unstable")]
    n = len(stopped)
    assert re.search(rf"(^|\*\*){n} starts? did not reach a rest state", report, re.M), n
    for r, p, ph in stopped[["held_roll", "held_pitch", "phase"]].itertuples(index=False):
        assert f"({r:g}, {p:g}, {ph:g})" in report
    assert f"{n} not at rest" in report


def test_class_map_shows_the_phase_where_the_classes_differ_most(job):
    """The class map's phase: where the held tilts' classes are most mixed (the largest
    Shannon entropy of their shares, the first such grid phase), computed from the rows."""
    out, _, _ = job
    rows = library_rows(out / "library")
    starts = rows[rows["role"] == "start"]
    best, best_h = None, -1.0
    for phase in sorted(starts["phase"].unique()):
        counts = starts.loc[starts["phase"] == phase, "classification"].value_counts()
        q = counts.to_numpy() / counts.sum()
        h = float(-(q * np.log(q)).sum())
        if h > best_h + 1e-12:
            best, best_h = phase, h
    caption = re.search(r"!\[library stability map\][^\n]*\n\n\*([^*]+)\*", report_of(out))
    assert caption and f"at start phase {best:g} deg" in caption.group(1)


def report_of(out: Path) -> str:
    return (out / "report.md").read_text()


def test_report_torque_is_in_newton_metres(job, monkeypatch, tmp_path):
    """The click signature's torque axis is in N m, as the report and the library: the
    values drawn are the states' driver torques as stored."""
    # The figure is caught where its module saves it (an internal with no public form).
    # The module whose figure saving is patched: an internal, the place the figure is saved.
    import threadmate.network._figures as figures
    from threadmate.network import from_library, least_resistance_path, plot_click_signature

    out, _, _ = job
    report = report_of(out)
    assert "torques in N m" in report
    m = re.search(r"from held roll (\S+), pitch (\S+), phase (\S+) deg", report)
    assert m
    graph = from_library(out / "library")
    path = least_resistance_path(graph, *(float(v) for v in m.groups()))
    drawn = []
    monkeypatch.setattr(figures, "save_figure", lambda fig, path, fmt=None: drawn.append(fig))
    plot_click_signature(graph, path, tmp_path / "c.png")
    torque_axes = drawn[0].axes[2]
    assert torque_axes.get_ylabel() == "driver torque (N m)"
    y = torque_axes.lines[0].get_ydata()
    want = [graph.nodes[n]["driver_torque"] for n in path.path]
    assert np.asarray(y) == pytest.approx(want, nan_ok=True)


def test_planar_captions_say_they_take_flat_ends():
    """The planar charts take flat ends: a run on chamfered, countersunk parts says so in
    their captions; on the thesis's flat parts there is nothing to say."""
    from threadmate.geometry import spec_from_designation
    from threadmate.pipeline._run import _planar_note  # an internal with no public form

    chamfered = spec_from_designation(DESIGNATION)
    note = _planar_note(chamfered)
    assert "flat ends" in note
    assert chamfered.bolt.point.describe("in") in note
    assert chamfered.nut.countersink.describe("in") in note
    assert _planar_note(spec_from_designation(DESIGNATION, point="flat", countersink=False)) == ""


def test_run_refuses_a_folder_of_the_users(tmp_path, capsys):
    """A non-empty folder that is not a run's is refused before any work: one message,
    exit 2, the folder as it was. An empty folder is not refused (checked without
    running: the folder rule itself)."""
    from threadmate.pipeline import check_run_folder

    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "thesis.docx").write_text("my words")
    (mine / "library").mkdir()  # a folder of that name is not yet a library
    rc, out, err = run_cli(capsys, "run", "-o", mine, "--roll", "0", "--pitch", "0")
    assert rc == 2 and out == ""
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in err
    assert lines[0].startswith(f"threadmate: error: -o {mine} exists, is not empty")
    assert "'thesis.docx'" in lines[0]
    assert sorted(p.name for p in mine.iterdir()) == ["library", "thesis.docx"]
    assert [p.name for p in (mine / "library").iterdir()] == []
    (mine / "thesis.docx").unlink()
    with pytest.raises(InputError, match="not a threadmate run's folder"):
        check_run_folder(mine)  # an empty library folder alone
    (mine / "library").rmdir()
    (mine / ".DS_Store").write_text("")  # hidden entries are ignored, as the sweep does
    assert check_run_folder(mine) == mine


def test_run_resumes_a_previous_runs_folder(job, tmp_path):
    """A previous run's folder is taken (to resume); the same with a file of the user's
    beside the run's is refused."""
    from threadmate.pipeline import check_run_folder

    out, _, _ = job
    assert check_run_folder(out) == out
    again = tmp_path / "again"
    shutil.copytree(out, again)
    (again / "notes.txt").write_text("mine")
    with pytest.raises(InputError, match="'notes.txt'"):
        check_run_folder(again)


def test_report_has_the_sensor_and_the_program(job):
    """The design stage's sections and documents, from the run's library: the snap click
    the sensor section starts from is one of the library's snap transitions."""
    out, doc, _ = job
    report = (out / "report.md").read_text()
    for text in ("## The snap a sensor sees", "## What to program", "**Turn limit:"):
        assert text in report, text
    sensor = json.loads((out / "sensor.json").read_text())
    program = json.loads((out / "program.json").read_text())
    assert sensor["units"]["length"] == program["units"]["length"] == "in"
    rows = library_rows(out / "library")
    snaps = rows.loc[rows["transition"] == "snap", "click"].to_numpy()
    smallest = sensor["settings"][0]["signals"]["click"]["smallest_snap"]
    assert np.isclose(snaps, smallest, rtol=0, atol=1e-15).any()
    assert set(doc["design"]) == {"envelope", "sensor", "program"}
