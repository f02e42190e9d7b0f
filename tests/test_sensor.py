"""The design stage's sensor and controller figures, recomputed from a library's rows.

A small real library (the 1/4-20 pair with its standard parts, a chamfered point in a
countersunk nut; held roll 1 and 2 at pitch -2, three start phases) is swept once: at
roll 2 the searches land in phase and jam (non-snap jumps), at 1 they snap. Every
figure of :func:`threadmate.design.snap_detection` and
:func:`threadmate.design.controller_program` is checked against a walk of the Parquet
rows with pandas alone (next_id to next_id), never against the code's own output; the
threshold logic is checked on hand-made values with known answers and by brute force.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from _cli import one_line, refused, run_cli, run_json
from threadmate.design import controller_program, separation, snap_detection
from threadmate.geometry import spec_from_designation
from threadmate.library import load, sweep
from threadmate.network import from_library

GRID = {"roll": "1,2", "pitch": "-2", "phase": "0:240:120"}
PHASE_STEP = 120.0
FRICTION, HIGH_FRICTION = 0.15, 0.20


@pytest.fixture(scope="module")
def library(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("sensor") / "library"
    sweep(
        spec_from_designation("1/4-20 UNC-2A/2B"),
        GRID["roll"],
        GRID["pitch"],
        GRID["phase"],
        out=out,
        workers=1,
    )
    return out


def lateral(row: pd.Series) -> np.ndarray:
    """The lateral part of a state's contact normal forces, sum lambda_i n_i,xy (N)."""
    f = np.asarray(row["contact_forces"], dtype=float)
    n = np.asarray(row["contact_normals"], dtype=float).reshape(-1, 3)
    return (f[:, None] * n[:, :2]).sum(axis=0)


def walk(rows: pd.DataFrame) -> pd.DataFrame:
    """Each start's passive search from the rows alone: its snap's click, the largest
    click of its other jumps, its turn to the snap and its largest driver torque (the
    states' and the transitions' peaks) and at the high friction (the states'),
    following next_id. A snap transition not labelled unstable passed into phase without a
    jump: the start snaps, but there is no click to tell."""
    by_id = rows.set_index("state_id")
    out = []
    for sid, start in by_id[by_id["role"] == "start"].iterrows():
        if start["classification"] in ("error", "unstable"):
            continue
        seen, n = set(), sid
        turn, snap, jumps = 0.0, math.nan, []
        snap_lateral, jump_lateral = math.nan, [math.nan]
        torques, high, falls = [start["driver_torque"]], [], [math.nan]
        ok = False
        while True:
            r = by_id.loc[n]
            t, f = r["driver_torque"], r["friction_torque"]
            if np.isfinite(t):
                torques.append(t)
                high.append(t - f + f * HIGH_FRICTION / FRICTION)
            if r["classification"] == "in-phase" and r["engaged"]:
                ok = True
                break
            if n in seen or r["next_id"] == "":
                break
            seen.add(n)
            click = r["click"] if np.isfinite(r["click"]) else r["drop"]
            if r["transition"] in ("snap", "jump"):
                change = float(np.hypot(*(lateral(by_id.loc[r["next_id"]]) - lateral(r))))
            if r["transition"] == "snap" and r["transition_label"] == "unstable":
                snap, snap_lateral = click, change
            elif r["transition"] == "jump":
                jumps.append(click)
                jump_lateral.append(change)
            if np.isfinite(r["torque_peak"]):
                torques.append(r["torque_peak"])
            if r["transition"] == "turning" and r["transition_turn"] > 0:
                falls.append(r["drop"] / r["transition_turn"])
            turn += r["transition_turn"]
            n = r["next_id"]
        out.append(
            {
                "held_roll": start["held_roll"],
                "held_pitch": start["held_pitch"],
                "phase": start["phase"],
                "snaps": ok,
                "turn": turn if ok else math.nan,
                "snap_click": snap,
                "jump_click": max(jumps) if jumps else math.nan,
                "snap_lateral": snap_lateral,
                "jump_lateral": np.nanmax(jump_lateral) if len(jump_lateral) > 1 else math.nan,
                "torque": max(torques),
                "torque_high": max(high),
                "branch_fall": np.nanmax(falls) if np.isfinite(falls).any() else math.nan,
            }
        )
    return pd.DataFrame(out).sort_values(["held_roll", "held_pitch", "phase"], ignore_index=True)


@pytest.fixture(scope="module")
def walked(library: Path) -> pd.DataFrame:
    return walk(load(library))


# -- the snap a sensor sees -------------------------------------------------------------------
def test_clicks_are_those_of_the_rows(library, walked):
    """The snap clicks and each search's largest other jump are the rows' own, walked
    with pandas; the library holds both kinds, so the comparison means something."""
    det = snap_detection(from_library(library), load(library))
    got = det.searches_table.sort_values(["held_roll", "held_pitch", "phase"], ignore_index=True)
    assert len(got) == len(walked) == 6
    assert walked["snap_click"].notna().any() and walked["jump_click"].notna().any()
    np.testing.assert_allclose(got["snap_click"], walked["snap_click"], rtol=1e-12)
    np.testing.assert_allclose(got["jump_click"], walked["jump_click"], rtol=1e-12)
    np.testing.assert_allclose(got["snap_lateral_force_change"], walked["snap_lateral"], rtol=1e-9)
    np.testing.assert_allclose(got["jump_lateral_force_change"], walked["jump_lateral"], rtol=1e-9)
    assert det.snaps == int(walked["snap_click"].notna().sum())
    assert det.with_jumps == int(walked["jump_click"].notna().sum())
    assert det.branch_fall == pytest.approx(walked["branch_fall"].max(), rel=1e-12)


@pytest.mark.slow
def test_a_passage_into_phase_without_a_jump_has_no_click(tmp_path, monkeypatch):
    """M8x1.25 with its standard ends held (0, -2) from 140 degrees, the helix probe's
    window for a bolt carried partly by the thread narrowed to the entry's (as in
    tests/test_engagement.py): the bolt's crest rides the countersink and its states pass
    into phase with no fall. The start snaps (its path ends in the thread, proved), yet
    a sensor has nothing to see: the rows hold its snap transition continuous (not
    labelled unstable, no fall beyond the jump threshold, pitch / 40), the sensor counts
    no snap click and says why, the start's outcome has no click and its path a click
    of 0."""
    from threadmate.contact.mechanics import _search
    from threadmate.network import least_resistance_path, start_outcomes

    monkeypatch.setitem(_search.HELIX_SHARES, "thread", _search.HELIX_SHARES["entry"])

    out = tmp_path / "library"
    sweep(spec_from_designation("M8x1.25-6g/6H"), "0", "-2", "140", out=out, workers=1)
    rows = load(out)
    snap = rows[rows["transition"] == "snap"]
    assert len(snap) == 1
    assert snap["transition_label"].iloc[0] in ("stable", "quasi-stable")
    assert abs(snap["drop"].iloc[0]) < 1.25 / 40
    assert walk(rows)["snaps"].tolist() == [True]
    graph = from_library(out)
    det = snap_detection(graph, rows)
    assert det.snaps == 0 and det.click.smallest_snap is None
    assert any("without a jump" in note for note in det.notes)
    outcome = start_outcomes(graph)
    assert outcome["snapped"].tolist() == [True] and outcome["click"].isna().all()
    path = least_resistance_path(graph, 0.0, -2.0, 140.0)
    assert path.snap["click"] == 0.0 and path.kinds[-1] == "snap"


def test_threshold_separates_or_overlap_is_stated(library, walked):
    """Either every snap click is at or above the threshold and every other jump below
    it, or the statement says none separates and the counts at its threshold recount."""
    s = snap_detection(from_library(library)).click
    snaps = walked["snap_click"].dropna()
    jumps = walked["jump_click"].dropna()
    t = s.threshold
    if s.separates:
        assert (snaps >= t).all() and (jumps < t).all()
    else:
        assert jumps.max() >= snaps.min()
        assert "no threshold separates" in s.statement("in")
        assert s.missed_snaps == int((snaps < t).sum())
        assert s.false_alarms == int((jumps >= t).sum())
    # No threshold decides fewer searches wrongly (brute force over a fine sweep).
    for x in np.linspace(0.0, 2 * max(snaps.max(), jumps.max()), 2001):
        wrong = ((walked["snap_click"] < x) | (walked["jump_click"] >= x)).sum()
        assert wrong >= s.wrong


def test_separation_with_a_gap():
    s = separation([3.0, 4.0, 5.0, math.nan], [1.0, math.nan, 2.0, 1.5])
    assert s.separates and s.threshold == pytest.approx(2.5)
    assert s.margin_snap == pytest.approx(0.5) and s.margin_jump == pytest.approx(0.5)
    assert (s.missed_snaps, s.false_alarms, s.wrong) == (0, 0, 0)


def test_separation_without_other_jumps():
    s = separation([2.0, 4.0], [math.nan, math.nan])
    assert s.separates and s.threshold == pytest.approx(1.0) and s.largest_jump is None


def test_separation_without_snaps():
    s = separation([math.nan, math.nan], [1.0, math.nan])
    assert not s.separates and s.threshold is None and s.false_alarms == 1


def test_separation_equal_values_do_not_separate():
    s = separation([2.0, 3.0], [math.nan, 2.0])
    assert not s.separates and s.wrong == 1


def test_separation_overlap_best_threshold():
    """Snaps 1..4; one never-snapping search jumps 0.5, another 5: any threshold in
    (0.5, 1] misses no snap and admits one alarm, the fewest."""
    snap = [1.0, 2.0, 3.0, 4.0, math.nan, math.nan]
    jump = [math.nan, math.nan, math.nan, math.nan, 0.5, 5.0]
    s = separation(snap, jump)
    assert not s.separates
    assert 0.5 < s.threshold <= 1.0
    assert (s.missed_snaps, s.false_alarms, s.false_alarms_before_snap, s.wrong) == (0, 1, 0, 1)


def test_separation_counts_an_alarm_before_the_snap():
    s = separation([3.0, 1.0], [4.0, math.nan])
    # t <= 1 alarms on the 4 before the snap 3 (1 wrong); t in (1, 3] misses the 1 and
    # alarms (2 wrong); t > 4 misses both (2 wrong).
    assert s.wrong == 1 and s.false_alarms_before_snap == 1 and s.missed_snaps == 0


# -- what to program ------------------------------------------------------------------------
def test_turn_limit_covers_its_share(library, walked):
    prog = controller_program(from_library(library, active=True))
    t = prog.turn_limit
    assert t["value"] == pytest.approx(walked["turn"].max() + PHASE_STEP)
    caught = (walked["snaps"] & (walked["turn"] <= t["value"])).sum()
    assert t["caught"] == caught and t["share_caught"] == pytest.approx(caught / len(walked))


def test_torque_limit_from_the_rows(library, walked):
    prog = controller_program(from_library(library, active=True), torque_margin=0.5)
    q = prog.torque_limit
    snapping = walked[walked["snaps"]]
    assert q["largest_torque_to_snap"] == pytest.approx(snapping["torque"].max())
    assert q["largest_torque_to_snap_high_friction"] == pytest.approx(snapping["torque_high"].max())
    top = max(snapping["torque"].max(), snapping["torque_high"].max())
    assert q["value"] == pytest.approx(1.5 * top)


def test_retry_plans_end_in_the_thread(library):
    """Each retry plan ends at a held tilt whose rows hold an engaged in-phase state,
    and its moves end with the turn to the snap."""
    rows = load(library)
    prog = controller_program(from_library(library, active=True))
    engaged = rows[(rows["classification"] == "in-phase") & rows["engaged"]]
    tilts = set(zip(engaged["held_roll"], engaged["held_pitch"], strict=True))
    assert prog.retry["plans"] == len(prog.retry["plans_list"]) > 0
    for plan in prog.retry["plans_list"]:
        end = plan["retry_tilt"]
        assert (end["held_roll"], end["held_pitch"]) in tilts
        assert plan["moves"][-1].endswith("to the snap")


def test_axial_force_is_constant_in_the_model(library):
    s = controller_program(from_library(library, active=True)).snap_signal
    assert s["axial_force_change"] == 0.0 and "constant axial force" in s["axial_force"]


# -- the commands ---------------------------------------------------------------------------
def test_sensor_json_has_units(capsys, library, tmp_path):
    fig = tmp_path / "sensor.png"
    _, doc, _ = run_json(capsys, "sensor", library, "--plot", fig)
    assert doc["units"]["length"] == "in" and doc["units"]["torque"] == "N m"
    assert fig.stat().st_size > 0 and doc["figure"] == str(fig)
    (setting,) = doc["settings"]
    assert setting["signals"]["click"]["unit"] == "length"


def test_program_json_has_units(capsys, library):
    _, doc, _ = run_json(capsys, "program", library)
    assert doc["units"]["torque"] == "N m" and doc["turn_limit"]["value"] > 0


def test_bad_input_is_one_line(capsys, library, tmp_path):
    assert "no library" in refused(capsys, "sensor", tmp_path / "missing")
    assert "--plot" in refused(capsys, "sensor", library, "--plot", tmp_path / "x.txt")
    assert not (tmp_path / "x.txt").exists()
    assert "--torque-margin" in refused(capsys, "program", library, "--torque-margin", "-1")
    assert "given twice" in refused(capsys, "sensor", library, library)
    code, _, err = run_cli(capsys, "program", tmp_path / "missing", "--json")
    assert code == 2 and one_line(err)


def test_a_runs_folder_holds_the_design_documents(tmp_path):
    """A run writes sensor.json and program.json; running again into its folder is a
    resume, not a refusal."""
    from threadmate.library import METADATA_FILE
    from threadmate.pipeline import check_run_folder

    (tmp_path / "library").mkdir()
    (tmp_path / "library" / METADATA_FILE).write_text("{}")
    for name in ("report.md", "recommendation.json", "sensor.json", "program.json"):
        (tmp_path / name).write_text("{}")
    assert check_run_folder(tmp_path) == tmp_path


def test_retry_without_active_moves_is_at_the_best_held_tilt(library, walked):
    """Without active moves the retry tilt is the held tilt that catches the largest
    share of its starts within the turn limit (recounted from the rows)."""
    prog = controller_program(from_library(library))
    retry = prog.retry
    assert retry["plans"] == 0 and retry["retry_tilt"]["source"] == "best held tilt"
    limit = prog.turn_limit["value"]
    share = (
        walked.assign(caught=walked["snaps"] & (walked["turn"] <= limit))
        .groupby(["held_roll", "held_pitch"])["caught"]
        .mean()
    )
    tilt = (retry["retry_tilt"]["held_roll"], retry["retry_tilt"]["held_pitch"])
    assert share[tilt] == share.max()
