"""The contact-state network over mechanics libraries.

On ONE small real library (tests/_libraries.py: the mechanics through python-fcl) and on
hand-made libraries of known structure written with the public ``write_library``, every
figure is checked against a reading of the Parquet rows written here with pandas alone:
the edges and weights (the documented formula), every passive path (held tilt kept, snap
reached, cost = sum of the weights), every start's outcome, the recommendation's figures,
the active moves (formula, and a Bellman-Ford over an edge list built here), GraphML and
node-link JSON read back, and a few paths against ``threadmate.contact.search``.
"""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ET

import networkx as nx
import numpy as np
import pandas as pd
import pytest

from _libraries import (
    DESIGNATION,
    SYNTH_COMPLIANCE,
    SYNTH_GRID,
    compliance_of,
    expected_weight,
    library_rows,
    mechanics_library,
    metres,
    setting_figures,
    synthetic_library,
    synthetic_rows,
    walk_starts,
)
from _poses import axis_angle
from threadmate import InputError, LibraryError, NoPathError
from threadmate.contact import TRANSITION_LABELS, search, thesis_schema
from threadmate.geometry import spec_from_designation
from threadmate.library import load, write_library
from threadmate.network import (
    MAX_K,
    METRICS,
    WEIGHT_FORMULA,
    build_network,
    from_library,
    k_best_paths,
    least_resistance_path,
    read_graphml,
    recommend,
    start_node,
    start_outcomes,
    write_graphml,
    write_node_link,
)

GRAPHML_NS = "{http://graphml.graphdrawing.org/xmlns}"


# -- fixtures -----------------------------------------------------------------------------
@pytest.fixture(scope="module")
def real_lib(tmp_path_factory):
    return mechanics_library(tmp_path_factory)


@pytest.fixture(scope="module")
def real_rows(real_lib):
    return library_rows(real_lib)


@pytest.fixture(scope="module")
def real_graph(real_lib):
    return from_library(real_lib)


@pytest.fixture(scope="module")
def synth_lib(tmp_path_factory, quarter_20):
    return synthetic_library(tmp_path_factory.mktemp("synthetic") / "lib", quarter_20)


@pytest.fixture(scope="module")
def synth_rows(synth_lib):
    return library_rows(synth_lib)


@pytest.fixture(scope="module")
def synth_graph(synth_lib):
    return from_library(synth_lib)


@pytest.fixture(scope="module")
def synth_active(synth_lib):
    return from_library(synth_lib, active=True)


@pytest.fixture(params=["real", "synthetic"])
def case(request):
    """(library path, its rows, its network) of either library."""
    if request.param == "real":
        names = ("real_lib", "real_rows", "real_graph")
    else:
        names = ("synth_lib", "synth_rows", "synth_graph")
    return tuple(request.getfixturevalue(n) for n in names)


def _starts(rows: pd.DataFrame) -> pd.DataFrame:
    return rows[rows["role"] == "start"]


# -- the graph against the rows -----------------------------------------------------------
def test_nodes_and_passive_edges_are_the_rows(case):
    _, rows, graph = case
    assert graph.graph["model"] == "mechanics" and graph.graph["cost_units"] == "mJ"
    assert graph.graph["units"] == "in" and graph.graph["weight_formula"] == WEIGHT_FORMULA
    assert sorted(graph.nodes) == sorted(rows["state_id"])
    linked = rows[rows["next_id"] != ""]
    assert sorted(graph.edges) == sorted(zip(linked["state_id"], linked["next_id"], strict=True))
    for _, row in rows.iterrows():
        d = graph.nodes[row["state_id"]]
        for key in ("held_roll", "held_pitch", "phase", "classification", "role"):
            assert d[key] == row[key], (row["state_id"], key)
        # The pose (actual tilt and origin) and the contacts' regions and forces.
        assert {"roll", "pitch", "origin_x", "origin_y", "origin_z", "contact_forces"} <= set(d)
        assert d["roll"] == row["roll"] or (math.isnan(d["roll"]) and math.isnan(row["roll"]))
        assert list(d["contact_regions"]) == list(row["contact_regions"])
        if not row["next_id"]:
            assert graph.out_degree(row["state_id"]) == 0
            continue
        e = graph.edges[row["state_id"], row["next_id"]]
        assert e["kind"] == row["transition"] and e["label"] == row["transition_label"]
        assert e["label"] in TRANSITION_LABELS and e["active"] is False
        assert e["turn"] == pytest.approx(row["transition_turn"])
        assert e["weight"] == pytest.approx(expected_weight(row), abs=1e-12)
        assert e["weight"] >= 0
        # A passive edge never changes the held tilt.
        nxt = graph.nodes[row["next_id"]]
        assert (nxt["held_roll"], nxt["held_pitch"]) == (row["held_roll"], row["held_pitch"])


def test_one_state_is_one_node(real_lib, real_rows, real_graph):
    """Continuations that reach a state already known at a grid phase join its node: no
    two rest states of a held tilt at a grid phase are the same state (same load-carrying
    contacts, compliance centre within pitch/1000, axis within 0.05 deg), and some starts'
    searches do merge."""
    force = compliance_of(real_lib).force
    rest = real_rows[real_rows["role"].isin(["start", "continued"])]
    for _, group in rest.groupby(["held_roll", "held_pitch", "phase"]):
        states = list(group.itertuples())
        for i, a in enumerate(states):
            for b in states[i + 1 :]:
                carry_a = sorted(
                    r
                    for r, f in zip(a.contact_regions, a.contact_forces, strict=True)
                    if f > 1e-4 * force
                )
                carry_b = sorted(
                    r
                    for r, f in zip(b.contact_regions, b.contact_forces, strict=True)
                    if f > 1e-4 * force
                )
                angle = axis_angle(a.rotation, b.rotation)
                gap = math.dist(
                    (a.centre_x, a.centre_y, a.centre_z), (b.centre_x, b.centre_y, b.centre_z)
                )
                assert not (
                    a.classification == b.classification
                    and carry_a == carry_b
                    and gap <= 0.05 / 1000
                    and angle <= 0.05
                ), (a.state_id, b.state_id)
    turning_in = [
        n
        for n in real_graph
        if sum(1 for _, _, d in real_graph.in_edges(n, data=True) if d["kind"] != "settling") > 0
        and real_graph.nodes[n]["role"] == "start"
    ]
    assert turning_in  # a start's search continues into another start's rest state


def test_synthetic_weights_by_hand(synth_graph):
    """Turning work clipped at 0 when the potential falls faster than friction takes;
    settling, snap and (by default) jump cost nothing."""
    e = synth_graph.edges["r+0_p-1_ph090.000_s3", "r+0_p-1_ph180.000_s5"]
    assert (e["kind"], e["work_friction"], e["work_potential"]) == ("turning", 0.5, -0.8)
    assert e["weight"] == 0.0
    assert synth_graph.edges["r+0_p-1_ph000.000_s1", "r+0_p-1_ph090.000_s3"][
        "weight"
    ] == pytest.approx(1.0)
    kinds = {
        d["kind"]: d["weight"] for _, _, d in synth_graph.edges(data=True) if d["kind"] != "turning"
    }
    assert kinds == {"settling": 0.0, "snap": 0.0, "jump": 0.0}


def test_jump_penalty_is_added_to_each_jump(synth_lib):
    plain = least_resistance_path(from_library(synth_lib), 1, 0, 0)
    costly = least_resistance_path(from_library(synth_lib, jump_penalty=2.5), 1, 0, 0)
    assert plain.path == costly.path and plain.kinds.count("jump") == 1
    assert costly.cost == pytest.approx(plain.cost + 2.5)
    assert plain.cost == pytest.approx(0.7 + 0.5 + 1.1 + 1.1 + 0.45)
    for bad in (-1.0, math.nan, math.inf):
        with pytest.raises(InputError, match="jump_penalty"):
            from_library(synth_lib, jump_penalty=bad)


# -- every passive path -------------------------------------------------------------------
def test_every_passive_path_keeps_its_tilt_snaps_and_costs_its_weights(case):
    _, rows, graph = case
    by_id = rows.set_index("state_id")
    walked = walk_starts(rows)
    assert len(walked) == len(_starts(rows))
    for sid, w in walked.iterrows():
        r, p, ph = w["held_roll"], w["held_pitch"], w["phase"]
        if not w["reaches"]:
            with pytest.raises(NoPathError, match="failed" if w["failed"] else "never snaps"):
                least_resistance_path(graph, r, p, ph)
            continue
        res = least_resistance_path(graph, r, p, ph)
        assert res.start == sid and res.path == w["path"] and not res.moved_to_grid
        held = {(graph.nodes[n]["held_roll"], graph.nodes[n]["held_pitch"]) for n in res.path}
        assert held == {(r, p)}
        assert by_id.loc[res.path[-1], "classification"] == "in-phase"
        assert all(by_id.loc[n, "classification"] != "in-phase" for n in res.path[:-1])
        weights = [expected_weight(by_id.loc[n]) for n in res.path[:-1]]
        assert res.weights == pytest.approx(weights, abs=1e-12)
        assert res.cost == pytest.approx(sum(weights), abs=1e-12)
        assert res.labels == list(by_id.loc[res.path[:-1], "transition_label"])
        assert res.turn == pytest.approx(by_id.loc[res.path[:-1], "transition_turn"].sum())
        assert res.snap["phase"] == pytest.approx(by_id.loc[res.path[-1], "phase"])
        assert res.snap["turn"] == pytest.approx(w["turn"])
        assert res.snap["click"] == pytest.approx(w["click"])
        if len(res.path) > 1:
            assert res.kinds[-1] == "snap"


def test_synthetic_paths_by_hand(synth_graph):
    res = least_resistance_path(synth_graph, 1, 1, 90)
    assert res.turn == pytest.approx(380.01) and res.to_dict()["within_one_turn"] is False
    assert res.snap["phase"] == pytest.approx(110.01)
    inphase = least_resistance_path(synth_graph, 0, 0, 90)
    assert inphase.path == ["r+0_p+0_ph090.000_s3"] and inphase.cost == 0.0
    assert inphase.turn == 0.0
    with pytest.raises(NoPathError, match="never snaps"):
        least_resistance_path(synth_graph, 0, 1, 180)
    with pytest.raises(NoPathError, match="failed.*no contact"):
        least_resistance_path(synth_graph, 1, -1, 180)
    jumpy = least_resistance_path(synth_graph, 1, 0, 0)
    assert jumpy.kinds == ["turning", "jump", "turning", "turning", "turning", "turning", "snap"]
    assert jumpy.passes_unstable is True


# -- every start at once ------------------------------------------------------------------
def test_start_outcomes_equal_a_walk_over_the_rows(case):
    _, rows, graph = case
    out = start_outcomes(graph).set_index("node")
    walked = walk_starts(rows)
    assert sorted(out.index) == sorted(walked.index)
    out = out.loc[walked.index]
    for col in (
        "held_roll",
        "held_pitch",
        "phase",
        "classification",
        "failed",
        "reaches",
        "snapped",
        "passes_unstable",
    ):
        assert list(out[col]) == list(walked[col]), col
    for col in ("turn", "work", "click", "snap_phase", "torque_peak"):
        np.testing.assert_allclose(
            out[col].to_numpy(float),
            walked[col].to_numpy(float),
            rtol=1e-9,
            atol=1e-12,
            err_msg=col,
        )


def test_synthetic_outcomes_by_hand(synth_graph):
    out = start_outcomes(synth_graph).set_index(["held_roll", "held_pitch", "phase"])
    assert list(out.loc[(0.0, 1.0), "reaches"]) == [False] * 4  # the cycle
    assert out.loc[(1.0, 1.0, 90.0), ["reaches", "snapped"]].tolist() == [True, False]
    assert out.loc[(1.0, -1.0, 180.0), "failed"]
    assert out.loc[(0.0, 0.0, 0.0), ["snapped", "turn", "work"]].tolist() == [True, 0.0, 0.0]
    assert out.loc[(1.0, 0.0, 0.0), "passes_unstable"]
    assert not out.loc[(1.0, 0.0, 90.0), "passes_unstable"]
    # The largest torque round the cycle, whichever start of it the walk met first.
    assert list(out.loc[(0.0, 1.0), "torque_peak"]) == pytest.approx([0.0058] * 4)


# -- the passive path is the search -------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("start", [(1.0, 0.0, 0.0), (0.0, -1.0, 300.0), (1.0, 1.0, 270.0)])
def test_passive_path_agrees_with_search(real_lib, real_graph, start):
    meta = load(real_lib, columns=["config_id"]).attrs["threadmate"]
    step = float(meta["continuation"]["step"])
    phases = meta["grid"]["phase"]
    phase_step = max(b - a for a, b in zip(phases, phases[1:], strict=False))
    run = search(
        spec_from_designation(DESIGNATION, point="flat", countersink=False),
        *start,
        compliance=compliance_of(real_lib),
        step=step,
        phase_tolerance=float(meta["continuation"]["phase_tolerance"]),
        chord=float(meta["mesh"]["chord"]),
    )
    try:
        path = least_resistance_path(real_graph, *start)
    except NoPathError:
        assert run.snap is None, start
        return
    assert run.snap is not None, start
    gap = abs((path.snap["phase"] - run.snap.phase + 180.0) % 360.0 - 180.0)
    assert gap <= phase_step, (start, path.snap, run.snap)
    turned = (run.snap.phase - start[2]) % 360.0 if path.turn else 0.0
    assert abs(path.turn - turned) <= phase_step, (start, path.turn, turned)
    # The driver's work too: the library continues grid phase by grid phase, the search
    # in one go, on the same branch.
    assert path.cost == pytest.approx(max(run.work, 0.0), rel=0.1, abs=1e-6), start


# -- the recommendation -------------------------------------------------------------------
def _check_recommendation(rec, rows, spread=math.inf):
    walked = walk_starts(rows)
    pitches = sorted(set(walked.loc[walked["held_roll"].abs() <= spread, "held_pitch"]))
    assert sorted(s["held_pitch"] for s in rec.settings) == pitches
    for s in rec.settings:
        want = setting_figures(walked, s["held_pitch"], spread)
        assert set(METRICS) <= set(s)
        assert s["starts"] == want["starts"]
        for key in METRICS:
            if want[key] is None:
                assert s[key] is None, (s["held_pitch"], key)
            else:
                assert s[key] == pytest.approx(want[key], rel=1e-9, abs=1e-12), key
    keys = [
        (
            -s["share_snap"],
            s["turn_mean"] if s["turn_mean"] is not None else math.inf,
            s["work_mean"] if s["work_mean"] is not None else math.inf,
        )
        for s in rec.settings
    ]
    assert keys == sorted(keys)
    assert rec.at_edge == (len(pitches) > 1 and rec.best["held_pitch"] in (pitches[0], pitches[-1]))
    assert rec.pitch_range == (pitches[0], pitches[-1])
    if len(rec.settings) > 1:
        a, b = rec.settings[:2]
        assert rec.margin["share_snap"] == pytest.approx(a["share_snap"] - b["share_snap"])
        if a["turn_mean"] is not None and b["turn_mean"] is not None:
            assert rec.margin["turn_mean"] == pytest.approx(b["turn_mean"] - a["turn_mean"])


def test_recommend_figures_recomputed_from_the_rows(case):
    _, rows, graph = case
    rec = recommend(graph)
    _check_recommendation(rec, rows)
    doc = json.loads(json.dumps(rec.to_dict(), allow_nan=False))
    assert doc["recommended"] == doc["settings"][0]
    assert all(set(METRICS) <= set(s) for s in doc["settings"])
    narrow = recommend(graph, roll_spread=0)
    _check_recommendation(narrow, rows, spread=0.0)
    # Pre-tilt size 0 (upright) has one direction: its figures are the pitch-0 setting's.
    upright = [p for p in rec.azimuth_proof if p["tilt_size"] == 0.0]
    if upright:
        zero = next(s for s in rec.settings if s["held_pitch"] == 0.0)
        assert {k: upright[0][k] for k in METRICS} == {k: zero[k] for k in METRICS}


def test_recommend_synthetic_by_hand(synth_graph, synth_lib, synth_rows, tmp_path, quarter_20):
    rec = recommend(synth_graph)
    assert [s["held_pitch"] for s in rec.settings] == [0.0, -1.0, 1.0]
    by_pitch = {s["held_pitch"]: s for s in rec.settings}
    assert by_pitch[1.0]["share_snap"] == pytest.approx(3 / 8)
    assert by_pitch[-1.0]["starts"] == 7 and by_pitch[-1.0]["failed"] == 1
    assert by_pitch[0.0]["turn_mean"] == pytest.approx(750.06 / 8)
    assert by_pitch[0.0]["click_mean"] == pytest.approx(0.005)
    assert by_pitch[0.0]["share_unstable"] == pytest.approx(1 / 8)
    assert rec.at_edge is False
    assert rec.margin["turn_mean"] == pytest.approx(1130.07 / 7 - 750.06 / 8)
    # Without pitch +1 the best pitch, 0, is the edge of the range searched.
    lower = synth_rows[synth_rows["held_pitch"] < 1]
    path = synthetic_library(tmp_path / "lower", quarter_20, rows=lower, pitch=[-1.0, 0.0])
    edge = recommend(from_library(path))
    assert edge.best["held_pitch"] == 0.0 and edge.at_edge is True
    assert any("edge" in note for note in edge.notes)
    assert rec.roll_spread == 1.0  # no spread given: every held roll, 0 and 1
    # One held roll: the starts span no roll error at all, whatever the pitches span.
    upright = synth_rows[synth_rows["held_roll"] == 0]
    path = synthetic_library(tmp_path / "upright", quarter_20, rows=upright, roll=[0.0])
    assert recommend(from_library(path)).roll_spread == 0.0
    with pytest.raises(InputError, match="^roll_spread"):
        recommend(synth_graph, roll_spread=-1)


def test_recommend_compares_compliances(synth_lib, synth_rows, tmp_path, quarter_20):
    stiff = write_library(
        synth_rows,
        tmp_path / "stiff",
        quarter_20,
        SYNTH_GRID["roll"],
        SYNTH_GRID["pitch"],
        SYNTH_GRID["phase"],
        compliance=type(SYNTH_COMPLIANCE)(force=10.0, stiffness=2.0),
    )
    rec = recommend([from_library(synth_lib), from_library(stiff)])
    assert sorted((s["stiffness"][0], s["held_pitch"]) for s in rec.settings) == [
        (k, p) for k in (1.0, 2.0) for p in (-1.0, 0.0, 1.0)
    ]
    for s in rec.settings:
        assert s["force"] == 10.0
        want = setting_figures(walk_starts(synth_rows), s["held_pitch"])
        assert s["share_snap"] == pytest.approx(want["share_snap"])


def test_a_thesis_library_is_refused(tmp_path, quarter_20):
    names = thesis_schema().names
    lib = write_library(
        pd.DataFrame(columns=names),
        tmp_path / "thesis",
        quarter_20,
        0,
        0,
        "0:180:180",
        model="thesis",
    )
    with pytest.raises(LibraryError, match="mechanics"):
        from_library(lib)


# -- active moves -------------------------------------------------------------------------
def _expected_tilt_steps(
    rows: pd.DataFrame, move_penalty: float, force: float, units: str
) -> dict[tuple[str, str], float]:
    """Every rest state at a grid phase (not in phase, not failed) to the first contact
    of each neighbouring held tilt (one grid step in roll or in pitch) at that phase."""
    rolls = sorted(set(rows["held_roll"]))
    pitches = sorted(set(rows["held_pitch"]))
    first = {
        (r["held_roll"], r["held_pitch"], round(r["phase"], 6)): r
        for _, r in rows[rows["role"] == "first-contact"].iterrows()
    }
    out = {}
    rest = rows[
        rows["role"].isin(["start", "continued"])
        & ~rows["classification"].isin(["in-phase", "error"])
    ]
    for _, r in rest.iterrows():
        i, j = rolls.index(r["held_roll"]), pitches.index(r["held_pitch"])
        for ii, jj in ((i - 1, j), (i + 1, j), (i, j - 1), (i, j + 1)):
            if not (0 <= ii < len(rolls) and 0 <= jj < len(pitches)):
                continue
            target = first.get((rolls[ii], pitches[jj], round(r["phase"], 6)))
            if target is None:
                continue
            lift = max(0.0, metres(target["centre_z"] - r["centre_z"], units))
            out[(r["state_id"], target["state_id"])] = 1e3 * force * lift + move_penalty
    return out


def _bellman_ford(edges: dict[tuple[str, str], float], nodes, targets) -> dict[str, float]:
    dist = {n: (0.0 if n in targets else math.inf) for n in nodes}
    for _ in range(len(dist)):
        changed = False
        for (u, v), w in edges.items():
            if dist[v] + w < dist[u] - 1e-15:
                dist[u] = dist[v] + w
                changed = True
        if not changed:
            break
    return dist


@pytest.mark.parametrize("move_penalty", [None, 0.0, 3.0])
def test_active_moves(synth_lib, synth_rows, move_penalty):
    graph = from_library(synth_lib, active=True, move_penalty=move_penalty)
    force = SYNTH_COMPLIANCE.force
    default = 1e3 * force * 0.05 * 0.0254  # F x one pitch of 1/4-20, mJ
    penalty = default if move_penalty is None else move_penalty
    assert graph.graph["move_penalty"] == pytest.approx(penalty)
    want = _expected_tilt_steps(synth_rows, penalty, force, "in")
    got = {(u, v): d for u, v, d in graph.edges(data=True) if d["active"]}
    assert set(got) == set(want) and len(want) > 0
    for key, d in got.items():
        assert d["kind"] == "tilt-step" and d["weight"] == pytest.approx(want[key], abs=1e-12)
    assert any(w > penalty + 1e-9 for w in want.values())  # some lift
    assert any(w == pytest.approx(penalty) for w in want.values())  # some drop: no lift
    assert all(d["kind"] != "tilt-step" for _, _, d in graph.edges(data=True) if not d["active"])

    # Passively nothing changes: the same outcomes, the same paths, no active edge used.
    passive = from_library(synth_lib)
    pd.testing.assert_frame_equal(start_outcomes(graph), start_outcomes(passive))
    res = least_resistance_path(graph, 1, 0, 0)
    assert res.path == least_resistance_path(passive, 1, 0, 0).path and res.moves == 0
    with pytest.raises(NoPathError):
        least_resistance_path(graph, 0, 1, 0)  # the cycle, passively
    with pytest.raises(InputError, match="active"):
        least_resistance_path(passive, 0, 1, 0, active=True)

    # With them, the least-resistance cost to the snap from every start is a Bellman-Ford
    # over an edge list built here.
    edges = {
        (r["state_id"], r["next_id"]): expected_weight(r)
        for _, r in synth_rows[synth_rows["next_id"] != ""].iterrows()
    }
    edges.update(want)
    targets = set(synth_rows.loc[synth_rows["classification"] == "in-phase", "state_id"])
    dist = _bellman_ford(edges, synth_rows["state_id"], targets)
    for _, s in synth_rows[synth_rows["role"] == "start"].iterrows():
        args = (s["held_roll"], s["held_pitch"], s["phase"])
        if math.isinf(dist[s["state_id"]]):
            with pytest.raises(NoPathError):
                least_resistance_path(graph, *args, active=True)
            continue
        best = least_resistance_path(graph, *args, active=True)
        assert best.cost == pytest.approx(dist[s["state_id"]], abs=1e-9)
        assert best.cost == pytest.approx(
            sum(edges[e] for e in zip(best.path, best.path[1:], strict=False))
        )
        assert graph.nodes[best.path[-1]]["classification"] == "in-phase"
    plan = least_resistance_path(graph, 0, 1, 0, active=True)
    assert plan.moves >= 1 and "tilt-step" in plan.kinds
    alt = k_best_paths(graph, 4, 0, 1, 0, active=True)
    costs = [alt.cost] + [a.cost for a in alt.alternatives]
    assert len(alt.alternatives) == 3 and costs == sorted(costs)
    assert len({tuple(a.path) for a in [alt, *alt.alternatives]}) == 4


def test_active_moves_from_a_state_a_hair_below_360(synth_lib, synth_rows, tmp_path, quarter_20):
    """A continuation that summed its turns to 359.99999999999994 is at grid phase 0."""
    rows = synth_rows.copy()
    sheet0 = "r+1_p+1_ph000.000_s10"
    assert rows.loc[rows["state_id"] == sheet0, "role"].item() == "continued"
    rows.loc[rows["state_id"] == sheet0, "phase"] = 359.99999999999994
    graph = from_library(synthetic_library(tmp_path / "lib", quarter_20, rows=rows), active=True)
    steps = {v for _, v, d in graph.out_edges(sheet0, data=True) if d["active"]}
    assert steps == {"r+0_p+1_ph000.000_s0", "r+1_p+0_ph000.000_s0"}


def test_active_moves_on_the_real_library(real_lib, real_rows):
    graph = from_library(real_lib, active=True)
    meta = load(real_lib, columns=["config_id"]).attrs["threadmate"]
    force = meta["compliance"]["force"]
    want = _expected_tilt_steps(real_rows, graph.graph["move_penalty"], force, "in")
    got = {(u, v): d["weight"] for u, v, d in graph.edges(data=True) if d["active"]}
    assert set(got) == set(want)
    for key, w in got.items():
        assert w == pytest.approx(want[key], abs=1e-12)


def test_k_best_paths(synth_graph):
    one = k_best_paths(synth_graph, 3, 0, -1, 90)
    assert one.alternatives == []  # passively the dynamics are deterministic
    for bad in (0, MAX_K + 1, True, 2.0):
        with pytest.raises(InputError, match="^k must be a whole number"):
            k_best_paths(synth_graph, bad, 0, -1, 90)


# -- starts -------------------------------------------------------------------------------
def test_start_node_on_and_off_the_grid(synth_graph):
    assert start_node(synth_graph, 0, -1, 90) == ("r+0_p-1_ph090.000_s3", False)
    assert start_node(synth_graph, 0, -1, 450) == ("r+0_p-1_ph090.000_s3", False)
    with pytest.raises(InputError, match=r"nearest.* roll 0, pitch -1, phase 90\b"):
        start_node(synth_graph, 0.2, -1, 80)
    assert start_node(synth_graph, 0.2, -1, 80, nearest=True) == ("r+0_p-1_ph090.000_s3", True)
    res = least_resistance_path(synth_graph, 0.2, -1, 80, nearest=True)
    assert res.moved_to_grid and res.requested == {"roll": 0.2, "pitch": -1.0, "phase": 80.0}
    for bad in (math.nan, math.inf, True):
        with pytest.raises(InputError):
            start_node(synth_graph, bad, 0, 0)


# -- files --------------------------------------------------------------------------------
def test_graphml_booleans_and_lists_round_trip(real_lib, real_rows, tmp_path):
    graph = from_library(real_lib, active=True)
    start_outcomes(graph)  # the caches it keeps on the graph are not written
    path = write_graphml(graph, tmp_path / "net.graphml")
    root = ET.parse(path).getroot()
    booleans = {
        k.get("id") for k in root.iter(f"{GRAPHML_NS}key") if k.get("attr.type") == "boolean"
    }
    assert booleans  # "active" on edges and graph
    values = [d.text for d in root.iter(f"{GRAPHML_NS}data") if d.get("key") in booleans]
    assert values and set(values) <= {"true", "false"} and set(values) >= {"true", "false"}
    assert not [
        d.text
        for d in root.iter(f"{GRAPHML_NS}data")
        if (d.text or "").strip().lower() in ("nan", "inf", "-inf")
    ]

    back = read_graphml(path)
    plain = nx.read_graphml(path)  # any GraphML reader gets booleans
    assert sorted(back.nodes) == sorted(real_rows["state_id"])
    assert {d["active"] for _, _, d in plain.edges(data=True)} == {True, False}
    assert back.number_of_edges() == graph.number_of_edges()
    by_id = real_rows.set_index("state_id")
    for n, d in back.nodes(data=True):
        row = by_id.loc[n]
        # The list attributes come back as lists (the pose and the contact points stay in
        # the library, one row per node).
        assert d["contact_regions"] == list(row["contact_regions"])
        assert isinstance(d["contact_forces"], list)
        np.testing.assert_array_equal(d["contact_forces"], row["contact_forces"])  # NaN too
        assert d["held_pitch"] == row["held_pitch"] and d["phase"] == row["phase"]
        for key in ("driver_torque", "potential", "centre_z"):
            if np.isfinite(row[key]):
                assert d[key] == row[key]
            else:
                assert math.isnan(d[key])
    for u, v, d in back.edges(data=True):
        assert d["weight"] == graph.edges[u, v]["weight"]
        assert d["active"] == graph.edges[u, v]["active"]
    assert json.loads(back.graph["compliance"])["force"] == 10.0


def test_node_link_json_has_no_nan(synth_active, tmp_path):
    least_resistance_path(synth_active, 0, 1, 0, active=True)
    start_outcomes(synth_active)  # the caches it keeps on the graph are not written
    path = write_node_link(synth_active, tmp_path / "net.json")

    def refuse(name):
        raise AssertionError(f"{name} in the JSON")

    doc = json.loads(path.read_text(), parse_constant=refuse)
    back = nx.node_link_graph(doc, edges="edges")
    assert sorted(back.nodes) == sorted(synth_active.nodes)
    assert back.number_of_edges() == synth_active.number_of_edges()
    err = back.nodes["r+1_p-1_ph180.000_s4"]
    assert err["classification"] == "error" and err["centre_z"] is None
    assert doc["graph"]["active"] is True
    assert not [k for k in doc["graph"] if k.startswith("_")]
    assert json.loads(doc["graph"]["grid"])["phase"] == SYNTH_GRID["phase"]


def test_build_network_needs_library_rows(synth_rows):
    with pytest.raises(InputError, match="metadata"):
        build_network(synth_rows)
    broken = synthetic_rows()
    broken.loc[0, "next_id"] = "r+9_p+9_ph000.000_s0"
    with pytest.raises(LibraryError, match="does\\s+not hold|incomplete"):
        frame = broken.copy()
        frame.attrs["threadmate"] = {
            "model": "mechanics",
            "units": "in",
            "compliance": {"force": 10.0},
            "spec": {"pitch": 0.05},
            "grid": {},
        }
        build_network(frame)


# -- the geometry in the files ------------------------------------------------------------------
def _rotation(roll: float, pitch: float, phase: float) -> np.ndarray:
    """Rx(roll) Ry(pitch) Rz(phase), degrees (conventions.md)."""
    r, p, s = np.radians([roll, pitch, phase])
    rx = np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]])
    ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
    rz = np.array([[np.cos(s), -np.sin(s), 0], [np.sin(s), np.cos(s), 0], [0, 0, 1]])
    return rx @ ry @ rz


def test_graphml_and_node_link_carry_the_pose_and_the_contacts(real_lib, real_rows, tmp_path):
    """Given the library, both files put on every node the rotation (the conventions'
    Rx(roll) Ry(pitch) Rz(phase) of the node's own angles) and the contacts' points and
    normals (3 values per touching contact, normals of unit length); GraphML holds them as
    string keys of JSON text, read back as lists."""
    graph = from_library(real_lib)
    path = write_graphml(graph, tmp_path / "net.graphml", library=real_lib)
    root = ET.parse(path).getroot()
    types = {
        k.get("attr.name"): k.get("attr.type")
        for k in root.iter(f"{GRAPHML_NS}key")
        if k.get("for") == "node"
    }
    for key in ("rotation", "contact_points", "contact_normals"):
        assert types[key] == "string", key  # one type per key, as Gephi wants
    back = read_graphml(path)
    plain = nx.read_graphml(path)
    link = json.loads(write_node_link(graph, tmp_path / "net.json", library=real_lib).read_text())
    linked = {n["id"]: n for n in link["nodes"]}
    by_id = real_rows.set_index("state_id")
    checked = 0
    for n, d in back.nodes(data=True):
        row = by_id.loc[n]
        for key in ("rotation", "contact_points", "contact_normals"):
            np.testing.assert_array_equal(d[key], np.asarray(row[key], float))
            assert json.loads(plain.nodes[n][key]) == linked[n][key]
        rot = np.asarray(d["rotation"]).reshape(3, 3)
        if d["classification"] != "error":
            want = _rotation(d["roll"], d["pitch"], d["phase"])
            np.testing.assert_allclose(rot, want, atol=1e-9)
            checked += 1
        points, normals = np.asarray(d["contact_points"]), np.asarray(d["contact_normals"])
        assert len(points) == len(normals) == 3 * int(row["n_contacts"])
        if len(normals):
            np.testing.assert_allclose(np.linalg.norm(normals.reshape(-1, 3), axis=1), 1, 1e-9)
    assert checked > 100


def test_without_the_library_the_files_leave_the_geometry_out(synth_graph, tmp_path):
    back = read_graphml(write_graphml(synth_graph, tmp_path / "n.graphml"))
    doc = json.loads(write_node_link(synth_graph, tmp_path / "n.json").read_text())
    for d in [*(d for _, d in back.nodes(data=True)), *doc["nodes"]]:
        assert not {"rotation", "contact_points", "contact_normals"} & set(d)


# -- starts that did not reach a rest state, and the recommendation's words --------------------
def _with_unsettled_start(rows: pd.DataFrame) -> tuple[pd.DataFrame, str]:
    """The synthetic rows with the start (0, -1, 90) as a descent that did not converge
    (the class the mechanics gives it: unstable)."""
    rows = rows.copy()
    pick = (rows["role"] == "start") & (rows["held_roll"] == 0) & (rows["held_pitch"] == -1)
    node = rows.loc[pick & (rows["phase"] == 90.0), "state_id"].iloc[0]
    rows.loc[rows["state_id"] == node, "classification"] = "unstable"
    return rows, node


def test_starts_not_at_rest_are_left_out_of_the_recommendation(synth_rows, tmp_path, quarter_20):
    rows, node = _with_unsettled_start(synth_rows)
    lib = synthetic_library(tmp_path / "lib", quarter_20, rows=rows)
    rec = recommend(from_library(lib))
    walked = walk_starts(rows)
    kept = walked.drop(index=node)
    for s in rec.settings:
        want = setting_figures(kept, s["held_pitch"])
        assert s["not_at_rest"] == (1 if s["held_pitch"] == -1 else 0)
        assert s["starts"] == want["starts"]
        for key in ("share_snap", "turn_mean", "work_mean", "share_unstable"):
            if want[key] is None:
                assert s[key] is None
            else:
                assert s[key] == pytest.approx(want[key]), key
    # The start still snaps as the rows say: it is left out, not rewritten.
    assert bool(walked.loc[node, "snapped"])


def test_one_compliance_twice_is_refused(synth_lib):
    graph = from_library(synth_lib)
    with pytest.raises(InputError, match="libraries 1 and 2 hold the same compliance"):
        recommend([graph, from_library(synth_lib)])


def test_notes_name_the_compliance_of_each_setting(synth_lib, synth_rows, tmp_path, quarter_20):
    """Two libraries of the same rows, stiffness 1 and 2 N m/rad: each held pitch of one
    is equivalent to the same of the other, so the note must say which compliance."""
    stiff = write_library(
        synth_rows,
        tmp_path / "stiff",
        quarter_20,
        SYNTH_GRID["roll"],
        SYNTH_GRID["pitch"],
        SYNTH_GRID["phase"],
        compliance=type(SYNTH_COMPLIANCE)(force=10.0, stiffness=2.0),
    )
    rec = recommend([from_library(synth_lib), from_library(stiff)])
    best = rec.best
    (note,) = [n for n in rec.notes if "no better than" in n]
    k = best["stiffness"][0]
    other = 2.0 if k == 1.0 else 1.0
    p = best["held_pitch"]
    assert f"the pick (held pitch {p:+g} deg at 10 N, {k:g}/{k:g} N m/rad)" in note
    assert f"held pitch {p:+g} deg at 10 N, {other:g}/{other:g} N m/rad" in note
