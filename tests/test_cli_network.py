"""``threadmate network``, ``path`` and ``recommend`` on mechanics libraries: the JSON
documents against a reading of the Parquet rows (tests/_libraries.py), the files written,
bad input (exit 2, one message, no traceback) and no path (exit 3)."""

from __future__ import annotations

import json
import shutil

import networkx as nx
import pandas as pd
import pytest

from _cli import one_line, run_cli
from _libraries import (
    expected_weight,
    library_rows,
    mechanics_library,
    setting_figures,
    synthetic_library,
    walk_starts,
)
from threadmate.contact import thesis_schema
from threadmate.library import write_library
from threadmate.network import METRICS

#: The starts' CSV: every column with its unit (spec lengths in inches here).
STARTS_CSV_COLUMNS = [
    "node",
    "held_roll_deg",
    "held_pitch_deg",
    "held_tilt_deg",
    "held_direction_deg",
    "phase_deg",
    "classification",
    "snapped",
    "reaches",
    "turn_deg",
    "work_mJ",
    "click_in",
    "snap_phase_deg",
    "snap_window_deg",
    "torque_peak_N_m",
    "passes_unstable",
    "failed",
]
SETTING_KEYS = (
    "share_snap",
    "turn_mean",
    "turn_worst",
    "work_mean",
    "work_worst",
    "click_mean",
    "torque_peak",
)


@pytest.fixture(scope="module")
def real_lib(tmp_path_factory):
    return mechanics_library(tmp_path_factory)


@pytest.fixture(scope="module")
def synth_lib(tmp_path_factory, quarter_20):
    return synthetic_library(tmp_path_factory.mktemp("cli-synthetic") / "lib", quarter_20)


@pytest.fixture(scope="module")
def thesis_lib(tmp_path_factory, quarter_20):
    out = tmp_path_factory.mktemp("cli-thesis") / "lib"
    return write_library(
        pd.DataFrame(columns=thesis_schema().names),
        out,
        quarter_20,
        0,
        0,
        "0:180:180",
        model="thesis",
    )


# -- network ------------------------------------------------------------------------------
@pytest.mark.parametrize("which", ["real_lib", "synth_lib"])
def test_network_json_and_files(request, which, tmp_path, capsys):
    lib = request.getfixturevalue(which)
    rows = library_rows(lib)
    walked = walk_starts(rows)
    rc, out, err = run_cli(
        capsys,
        "network",
        lib,
        "-o",
        tmp_path / "net.graphml",
        "--json-graph",
        tmp_path / "net.json",
        "--starts-csv",
        tmp_path / "starts.csv",
        "--json",
    )
    assert rc == 0, err
    doc = json.loads(out)
    assert doc["units"] == {"length": "in", "angle": "deg", "cost": "mJ"}
    assert doc["nodes"] == len(rows) and doc["edges"] == int((rows["next_id"] != "").sum())
    assert (
        doc["edge_kinds"] == rows.loc[rows["next_id"] != "", "transition"].value_counts().to_dict()
    )
    assert doc["starts"] == len(walked)
    ok = walked[~walked["failed"]]
    assert sorted(doc["never_snap"]) == sorted(ok.index[~ok["snapped"]])
    assert sorted(doc["failed_starts"]) == sorted(walked.index[walked["failed"]])
    assert sorted(doc["passes_unstable"]) == sorted(ok.index[ok["passes_unstable"]])
    assert doc["snap_within_one_turn"] == int(ok["snapped"].sum())
    snapped = ok[ok["snapped"]]
    assert doc["cost_to_snap"].keys() == set(snapped.index)
    for node, cost in doc["cost_to_snap"].items():
        assert cost == pytest.approx(snapped.loc[node, "work"], abs=1e-12)
    graph = nx.read_graphml(tmp_path / "net.graphml")
    assert graph.number_of_nodes() == len(rows)
    link = json.loads((tmp_path / "net.json").read_text())
    assert len(link["nodes"]) == len(rows)
    # Both files carry each state's rotation and contacts from the library.
    by_id = rows.set_index("state_id")
    linked = {n["id"]: n for n in link["nodes"]}
    for n, d in graph.nodes(data=True):
        for key in ("rotation", "contact_points", "contact_normals"):
            want = [float(v) for v in by_id.loc[n, key]]
            assert json.loads(d[key]) == linked[n][key] == want, key
    # Every column of the CSV names its unit.
    csv = pd.read_csv(tmp_path / "starts.csv")
    assert list(csv.columns) == STARTS_CSV_COLUMNS
    csv = csv.set_index("node").loc[walked.index]
    assert list(csv["snapped"]) == list(walked["snapped"])
    assert csv["turn_deg"].to_numpy() == pytest.approx(walked["turn"].to_numpy(), nan_ok=True)
    assert csv["work_mJ"].to_numpy() == pytest.approx(walked["work"].to_numpy(), nan_ok=True)
    assert csv["click_in"].to_numpy() == pytest.approx(walked["click"].to_numpy(), nan_ok=True)


def test_network_active_counts_the_moves(synth_lib, tmp_path, capsys):
    rc, out, err = run_cli(
        capsys,
        "network",
        synth_lib,
        "-o",
        tmp_path / "a.graphml",
        "--active",
        "--move-penalty",
        "2",
        "--json",
    )
    assert rc == 0, err
    doc = json.loads(out)
    assert doc["active"] is True and doc["edge_kinds"]["tilt-step"] > 0
    graph = nx.read_graphml(tmp_path / "a.graphml")
    steps = [d for _, _, d in graph.edges(data=True) if d["kind"] == "tilt-step"]
    assert len(steps) == doc["edge_kinds"]["tilt-step"]
    assert all(d["active"] is True and d["weight"] >= 2.0 for d in steps)
    # Passive outcomes do not change with the active moves in the graph.
    assert "r+0_p+1_ph000.000_s1" in doc["never_snap"]


# -- path ---------------------------------------------------------------------------------
@pytest.mark.parametrize("start", [(0, -1, 60), (1, 1, 210), (1, 0, 0)])
def test_path_json_is_the_walk_over_the_rows(real_lib, capsys, start):
    rows = library_rows(real_lib)
    by_id = rows.set_index("state_id")
    walked = walk_starts(rows)
    node = walked.index[
        (walked["held_roll"] == start[0])
        & (walked["held_pitch"] == start[1])
        & (walked["phase"] == start[2])
    ][0]
    w = walked.loc[node]
    args = [
        "path",
        real_lib,
        "--roll",
        start[0],
        "--pitch",
        start[1],
        "--phase",
        start[2],
        "--json",
    ]
    rc, out, err = run_cli(capsys, *args)
    if not w["reaches"]:
        assert rc == 3 and "no path" in one_line(err)
        doc = json.loads(out)
        assert doc["snap"] is None and doc["start"]["node"] == node
        return
    assert rc == 0, err
    doc = json.loads(out)
    assert {"units", "start", "path", "labels", "cost", "snap"} <= set(doc)
    assert set(doc["snap"]) >= {"phase", "turn", "drop", "click"}
    assert doc["units"]["cost"] == "mJ" and doc["units"]["length"] == "in"
    assert doc["start"]["node"] == node and doc["start"]["moved_to_grid"] is False
    assert doc["path"] == w["path"]
    assert doc["labels"] == list(by_id.loc[w["path"][:-1], "transition_label"])
    assert doc["cost"] == pytest.approx(
        sum(expected_weight(by_id.loc[n]) for n in w["path"][:-1]), abs=1e-12
    )
    assert doc["snap"]["phase"] == pytest.approx(w["snap_phase"])
    assert doc["snap"]["turn"] == pytest.approx(w["turn"])
    assert doc["snap"]["click"] == pytest.approx(w["click"])
    assert doc["within_one_turn"] == bool(w["snapped"]) and doc["active"] is False


def test_path_text_lists_each_transition(synth_lib, capsys):
    rc, out, err = run_cli(capsys, "path", synth_lib, "--roll", "1", "--pitch", "0", "--phase", "0")
    assert rc == 0, err
    assert "least-resistance path: 7 transitions" in out
    assert "passes an unstable transition" in out
    assert out.count("->") == 7 and "jump" in out and "snap" in out
    # The turn in degrees and in turns; the snap's phase as stored, in [0, 360).
    turn = walk_starts(library_rows(synth_lib)).set_index(["held_roll", "held_pitch", "phase"])
    t = float(turn.loc[(1.0, 0.0, 0.0), "turn"])
    assert f"turn {t:.2f} deg ({t / 360:.2f} turns), snap at phase " in out


def test_path_off_the_grid_needs_nearest(synth_lib, capsys):
    rc, out, err = run_cli(
        capsys, "path", synth_lib, "--roll", "0.3", "--pitch", "-1", "--phase", "85", "--json"
    )
    assert rc == 2 and out == ""
    msg = one_line(err)
    assert msg.startswith("threadmate: error:") and "--nearest" in msg
    assert "roll 0, pitch -1, phase 90" in msg
    rc, out, err = run_cli(
        capsys,
        "path",
        synth_lib,
        "--roll",
        "0.3",
        "--pitch",
        "-1",
        "--phase",
        "85",
        "--nearest",
        "--json",
    )
    assert rc == 0, err
    doc = json.loads(out)
    assert doc["start"] == {
        "node": "r+0_p-1_ph090.000_s3",
        "roll": 0.3,
        "pitch": -1.0,
        "phase": 85.0,
        "moved_to_grid": True,
    }
    assert doc["snap"]["turn"] == pytest.approx(200.01)


def test_no_path_exits_3(synth_lib, capsys):
    rc, out, err = run_cli(
        capsys, "path", synth_lib, "--roll", "0", "--pitch", "1", "--phase", "180", "--json"
    )
    assert rc == 3
    message = one_line(err)
    assert message.startswith("threadmate: no path:")
    # A design tool still gets one document on stdout, as from `threadmate search`: the
    # keys of a path's, nothing reached, and why.
    doc = json.loads(out)
    assert doc["snap"] is None and doc["path"] is None and doc["cost"] is None
    assert doc["units"]["cost"] == "mJ" and doc["units"]["length"] == "in"
    assert doc["start"]["roll"] == 0 and doc["start"]["moved_to_grid"] is False
    assert doc["start"]["node"] in message and doc["reason"] in message
    assert doc["within_one_turn"] is False and doc["active"] is False
    rc, out, err = run_cli(
        capsys, "path", synth_lib, "--roll", "1", "--pitch", "-1", "--phase", "180"
    )
    assert rc == 3 and "failed" in one_line(err)
    # With active moves the robot can leave the cycle by changing the held tilt.
    rc, out, err = run_cli(
        capsys,
        "path",
        synth_lib,
        "--roll",
        "0",
        "--pitch",
        "1",
        "--phase",
        "180",
        "--active",
        "--k",
        "3",
        "--json",
    )
    assert rc == 0, err
    doc = json.loads(out)
    assert doc["active"] is True and doc["active_moves"] >= 1
    assert "tilt-step" in doc["kinds"] and len(doc["alternatives"]) == 2
    costs = [doc["cost"]] + [a["cost"] for a in doc["alternatives"]]
    assert costs == sorted(costs)
    assert len({tuple(p["path"]) for p in [doc, *doc["alternatives"]]}) == 3


@pytest.mark.parametrize("k", ["0", "1000", "-3"])
def test_path_bad_k(synth_lib, capsys, k):
    rc, out, err = run_cli(
        capsys, "path", synth_lib, "--roll", "0", "--pitch", "0", "--phase", "180", "--k", k
    )
    assert rc == 2 and out == "" and "--k" in one_line(err)


@pytest.mark.parametrize(
    "extra",
    [["--roll", "nan"], ["--pitch", "50"], ["--jump-penalty", "-1"], ["--move-penalty", "inf"]],
)
def test_path_bad_numbers(synth_lib, capsys, extra):
    args = {"--roll": "0", "--pitch": "0", "--phase": "180"}
    args.update(dict(zip(extra[::2], extra[1::2], strict=True)))
    flat = [x for kv in args.items() for x in kv]
    rc, out, err = run_cli(capsys, "path", synth_lib, *flat)
    assert rc == 2 and out == ""
    assert one_line(err).startswith("threadmate: error:")


# -- recommend ----------------------------------------------------------------------------
@pytest.mark.parametrize("which", ["real_lib", "synth_lib"])
def test_recommend_json(request, which, tmp_path, capsys):
    lib = request.getfixturevalue(which)
    walked = walk_starts(library_rows(lib))
    rc, out, err = run_cli(
        capsys, "recommend", lib, "--json", "--plot", tmp_path / "r.png", "-o", tmp_path / "r.json"
    )
    assert rc == 0, err
    doc = json.loads(out)
    assert doc["units"]["work"] == "mJ" and doc["units"]["length"] == "in"
    assert doc["metrics"] == METRICS
    for s in doc["settings"]:
        assert set(SETTING_KEYS) <= set(s), s
        want = setting_figures(walked, s["held_pitch"])
        for key in SETTING_KEYS:
            if want[key] is None:
                assert s[key] is None
            else:
                assert s[key] == pytest.approx(want[key], rel=1e-9, abs=1e-12), key
    assert doc["recommended"] == doc["settings"][0]
    pitches = sorted(s["held_pitch"] for s in doc["settings"])
    assert doc["at_edge"] == (doc["recommended"]["held_pitch"] in (pitches[0], pitches[-1]))
    assert (tmp_path / "r.png").stat().st_size > 1000
    written = json.loads((tmp_path / "r.json").read_text())
    assert written["settings"] == doc["settings"]


def test_recommend_text_and_roll_spread(synth_lib, capsys):
    rc, out, err = run_cli(capsys, "recommend", synth_lib, "--roll-spread", "0")
    assert rc == 0, err
    table = [line for line in out.splitlines() if line.startswith("| ")]
    assert table[1].startswith("| +0 |")  # pitch 0 first: every start there snaps, soonest
    rc, out, err = run_cli(capsys, "recommend", synth_lib, "--roll-spread", "0", "--json")
    walked = walk_starts(library_rows(synth_lib))
    for s in json.loads(out)["settings"]:
        want = setting_figures(walked, s["held_pitch"], roll_spread=0.0)
        assert s["share_snap"] == pytest.approx(want["share_snap"])
        assert s["starts"] == want["starts"]


def test_recommend_text_states_the_pick(request, capsys):
    lib = request.getfixturevalue("synth_lib")
    rc, out, err = run_cli(capsys, "recommend", lib)
    assert rc == 0, err
    rc, doc, err = run_cli(capsys, "recommend", lib, "--json")
    best = json.loads(doc)["recommended"]
    picked = [line for line in out.splitlines() if line.startswith("Recommended: ")]
    assert picked == [
        f"Recommended: held pitch {best['held_pitch']:+g} deg: {best['share_snap']:.0%} of "
        f"{best['starts']} starts snap within one turn, after {best['turn_mean']:.0f} deg and "
        f"{best['work_mean']:.3g} mJ on average."
    ]


def test_recommend_refuses_a_library_twice(synth_lib, tmp_path, capsys):
    copy = tmp_path / "copy"
    shutil.copytree(synth_lib, copy)
    for args, words in (
        ([synth_lib, synth_lib], "given twice"),
        ([synth_lib, f"{synth_lib}/"], "given twice"),  # the same folder, spelt otherwise
        ([synth_lib, copy], "hold the same compliance"),  # a copy: every row twice
    ):
        rc, out, err = run_cli(capsys, "recommend", *args, "-o", tmp_path / "r.json")
        assert rc == 2 and out == ""
        assert words in one_line(err)
        assert not (tmp_path / "r.json").exists()


def test_network_warns_of_starts_not_at_rest(synth_lib, tmp_path, quarter_20, capsys):
    rows = library_rows(synth_lib)
    pick = (rows["role"] == "start") & (rows["held_roll"] == 0) & (rows["held_pitch"] == -1)
    node = rows.loc[pick & (rows["phase"] == 90.0), "state_id"].iloc[0]
    rows.loc[rows["state_id"] == node, "classification"] = "unstable"  # did not converge
    lib = synthetic_library(tmp_path / "lib", quarter_20, rows=rows)
    rc, out, err = run_cli(capsys, "network", lib, "-o", tmp_path / "n.graphml", "--json")
    assert rc == 0
    assert json.loads(out)["not_at_rest"] == [node]
    warning = one_line(err)
    assert warning.startswith("threadmate: warning: 1 start(s) did not reach a rest state")
    assert node in warning


# -- refused libraries --------------------------------------------------------------------
def _commands(lib, tmp_path):
    return [
        ["network", lib, "-o", tmp_path / "x.graphml"],
        ["path", lib, "--roll", "0", "--pitch", "0", "--phase", "0"],
        ["recommend", lib],
    ]


def test_missing_library_exits_2(tmp_path, capsys):
    for args in _commands(tmp_path / "nowhere", tmp_path):
        rc, out, err = run_cli(capsys, *args)
        assert rc == 2 and out == "", args
        assert one_line(err).startswith("threadmate: error:")
    assert not (tmp_path / "x.graphml").exists()


def test_thesis_library_exits_2(thesis_lib, tmp_path, capsys):
    for args in _commands(thesis_lib, tmp_path):
        rc, out, err = run_cli(capsys, *args)
        assert rc == 2 and out == "", args
        assert "mechanics" in one_line(err)
    assert not (tmp_path / "x.graphml").exists()


@pytest.mark.parametrize(
    "args",
    [
        ["network", "{lib}", "-o", "{tmp}/net.txt"],
        ["network", "{lib}", "-o", "{tmp}"],
        ["recommend", "{lib}", "--plot", "{tmp}/fig.bmp"],
        ["recommend", "{lib}", "--roll-spread", "-1"],
    ],
)
def test_bad_outputs_exit_2(synth_lib, tmp_path, capsys, args):
    args = [a.format(lib=synth_lib, tmp=tmp_path) for a in args]
    rc, out, err = run_cli(capsys, *args)
    assert rc == 2 and out == ""
    assert one_line(err).startswith("threadmate: error:")
    assert [p.name for p in tmp_path.iterdir()] == []


def test_nan_free_documents(synth_lib, tmp_path, capsys):
    """Missing numbers are null in every document, never NaN."""

    def refuse(name):
        raise AssertionError(name)

    for args in (
        ["network", synth_lib, "-o", tmp_path / "n.graphml", "--json"],
        ["path", synth_lib, "--roll", "0", "--pitch", "0", "--phase", "0", "--json"],
        ["recommend", synth_lib, "--json"],
    ):
        rc, out, err = run_cli(capsys, *args)
        assert rc == 0, err
        json.loads(out, parse_constant=refuse)


def test_recommend_compares_libraries_of_one_grid_only(synth_lib, tmp_path, quarter_20, capsys):
    rows = library_rows(synth_lib)
    other = synthetic_library(
        tmp_path / "lower", quarter_20, rows=rows[rows["held_pitch"] < 1], pitch=[-1.0, 0.0]
    )
    rc, out, err = run_cli(capsys, "recommend", synth_lib, other)
    assert rc == 2 and out == "" and "one grid" in one_line(err)
