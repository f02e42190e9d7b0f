"""The graph stage on hand-built library tables of known structure (and one real sweep):
edge rules, the weight formula by hand, Dijkstra against a Bellman-Ford and a path
enumeration written here, the recommendation by hand, GraphML read back by networkx."""

from __future__ import annotations

import itertools
import json
import math

import networkx as nx
import numpy as np
import pandas as pd
import pytest

from threadmate import LibraryError, NoPathError
from threadmate._errors import InputError
from threadmate.network import (
    ResistanceParams,
    build_network,
    cost_to_snap,
    k_best_paths,
    least_resistance_path,
    node_id,
    read_graphml,
    recommend_pitch,
    resolve_start,
    unsafe_starts,
    write_graphml,
    write_node_link,
)

PITCH_IN = 0.05                  # 1/4-20: 20 threads per inch
PD_IN = 0.2146                   # bolt pitch diameter (in): friction radius without contacts
MM = 25.4


def table(rows: list[dict], units: str = "in", grid: dict | None = None) -> pd.DataFrame:
    """A library table with the library's column names and metadata in ``attrs``."""
    df = pd.DataFrame(rows)
    spec = {"units": units, "pitch": PITCH_IN if units == "in" else 1.0,
            "bolt": {"pitch_diameter": PD_IN if units == "in" else 5.35}}
    df.attrs["threadmate"] = {"units": units, "spec": spec,
                              "contact": {"compliance_z": 0.0}}
    if grid is not None:
        df.attrs["threadmate"]["grid"] = grid
    return df


def ring(classes: list[str], roll: float = 0.0, pitch: float = 0.0, z: float = 0.0,
         step: float | None = None) -> list[dict]:
    """One orientation, phases evenly over a turn, given classifications, flat heights."""
    step = 360.0 / len(classes) if step is None else step
    return [{"roll": roll, "pitch": pitch, "phase": i * step, "classification": c,
             "final_origin_z": z} for i, c in enumerate(classes)]


def random_table(seed: int, n_roll: int = 3, n_pitch: int = 3, n_phase: int = 8,
                 ) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    rows = []
    classes = ["stable", "quasi-stable", "unstable", "no-contact", "in-phase", "error"]
    probs = [0.45, 0.1, 0.25, 0.05, 0.1, 0.05]
    for i, j, k in itertools.product(range(n_roll), range(n_pitch), range(n_phase)):
        roll, pitch = i - (n_roll - 1) / 2, j - (n_pitch - 1) / 2
        rows.append({
            "roll": roll, "pitch": pitch, "phase": k * 360.0 / n_phase,
            "classification": rng.choice(classes, p=probs),
            "final_roll": roll + rng.normal(0, 1.2), "final_pitch": pitch + rng.normal(0, 1.2),
            "final_origin_z": rng.normal(0, 0.003), "n_contacts": int(rng.integers(0, 4)),
            "region_combination": "base/surface + -F/+F + base/surface",
            "interference": abs(rng.normal(0, 1e-4)),
        })
    return table(rows)


def bellman_ford(edges: list[tuple[str, str, float]], nodes: list[str], targets: set[str]
                 ) -> dict[str, float]:
    """Cost to the nearest target by plain relaxation (independent of networkx)."""
    dist = {n: (0.0 if n in targets else math.inf) for n in nodes}
    for _ in range(len(nodes)):
        changed = False
        for u, v, w in edges:
            if dist[v] + w < dist[u] - 1e-15:
                dist[u], changed = dist[v] + w, True
        if not changed:
            break
    return dist


def edge_list(g: nx.DiGraph) -> list[tuple[str, str, float]]:
    return [(u, v, d["weight"]) for u, v, d in g.edges(data=True)]


def check_path(g: nx.DiGraph, result) -> None:
    """Each step a real edge, cost the sum of the weights, the end in phase."""
    assert g.nodes[result.path[-1]]["classification"] == "in-phase"
    assert not any(g.nodes[n]["in_phase"] for n in result.path[:-1])
    total = 0.0
    for (u, v), label, w in zip(itertools.pairwise(result.path), result.labels,
                                result.weights, strict=True):
        assert g.has_edge(u, v)
        assert g.edges[u, v]["label"] == label and g.edges[u, v]["weight"] == w
        total += w
    assert result.cost == pytest.approx(total, rel=1e-12, abs=1e-15)


# --- nodes and edges ----------------------------------------------------------------------

def test_node_ids():
    assert node_id(1, -2, 135) == "r+1.0_p-2.0_ph135.0"
    assert node_id(-0.0, 0.5, 360.0) == "r+0.0_p+0.5_ph0.0"
    assert node_id(0.1 * 3, -1.5, -5) == "r+0.3_p-1.5_ph355.0"


def test_turning_edges_step_counter_clockwise_and_wrap():
    rows = ring(["stable"] * 4 + ["unstable", "stable"], step=60.0)
    g = build_network(table(rows))
    turning = {(u, v) for u, v, d in g.edges(data=True) if d["kind"] == "turning"}
    expected = {(node_id(0, 0, 60 * k), node_id(0, 0, 60 * ((k + 1) % 6))) for k in range(6)}
    assert turning == expected
    for u, v in turning:
        assert g.edges[u, v]["turn"] == pytest.approx(60.0)
        assert g.edges[u, v]["label"] == g.nodes[v]["classification"]


def test_in_phase_absorbs_and_error_isolated():
    g = build_network(table(ring(["stable", "in-phase", "error", "stable"])))
    assert g.out_degree(node_id(0, 0, 90)) == 0                 # the snap ends the search
    assert g.degree(node_id(0, 0, 180)) == 0                    # no analysis, no transition
    assert g.edges[node_id(0, 0, 0), node_id(0, 0, 90)]["label"] == "stable"


def test_non_uniform_phase_grid_wraps_with_its_own_step():
    rows = [{"roll": 0.0, "pitch": 0.0, "phase": ph, "classification": "stable"}
            for ph in (0.0, 10.0, 200.0)]
    g = build_network(table(rows))
    assert g.edges[node_id(0, 0, 200), node_id(0, 0, 0)]["turn"] == pytest.approx(160.0)
    assert g.edges[node_id(0, 0, 10), node_id(0, 0, 200)]["turn"] == pytest.approx(190.0)


@pytest.mark.parametrize(("final", "expected"), [
    ((0.6, -0.2), (1.0, 0.0)),       # more than half a step up in roll only
    ((0.4, 0.3), None),              # within half a step on both axes: no settling
    ((-2.5, 3.0), (-1.0, 1.0)),      # far away: one diagonal step, not a jump
    ((0.0, -0.5), (0.0, -1.0)),      # exactly half a step counts
])
def test_settling_steps_toward_the_resting_orientation(final, expected):
    rows = []
    for r, p in itertools.product((-1.0, 0.0, 1.0), repeat=2):
        row = {"roll": r, "pitch": p, "phase": 0.0, "classification": "stable",
               "final_roll": r, "final_pitch": p}
        if r == 0 and p == 0:
            row["final_roll"], row["final_pitch"] = final
        rows.append(row)
    g = build_network(table(rows))
    out = [(g.nodes[v]["roll"], g.nodes[v]["pitch"]) for _, v, d
           in g.out_edges(node_id(0, 0, 0), data=True) if d["kind"] == "settling"]
    assert out == ([] if expected is None else [expected])
    # states already at their rest never settle
    assert all(d["kind"] != "settling" for u, _, d in g.edges(data=True)
               if u != node_id(0, 0, 0))


def test_settling_stops_at_the_grid_edge():
    rows = [{"roll": r, "pitch": 0.0, "phase": 0.0, "classification": "stable",
             "final_roll": 5.0, "final_pitch": 0.0} for r in (0.0, 1.0)]
    g = build_network(table(rows))
    assert list(g.edges) == [(node_id(0, 0, 0), node_id(1, 0, 0))]


# --- weights ------------------------------------------------------------------------------

def test_weight_formula_by_hand_in_inches():
    """F*rise + k/2*dtheta^2 + mu*F*r*dphi + P, with lengths converted at 25.4 mm/in."""
    rows = [
        {"roll": 0.0, "pitch": 0.0, "phase": 0.0, "classification": "stable",
         "final_roll": 0.5, "final_pitch": -0.25, "final_origin_z": -0.002,
         "third_found": True, "third_c1_x": 0.1, "third_c1_y": 0.0,
         "third_c2_x": 0.0, "third_c2_y": -0.12, "third_c3_x": np.nan, "third_c3_y": np.nan},
        {"roll": 0.0, "pitch": 0.0, "phase": 90.0, "classification": "unstable",
         "final_roll": -0.3, "final_pitch": 0.15, "final_origin_z": 0.001,
         "third_found": True, "third_c1_x": 0.11, "third_c1_y": 0.0,
         "third_c2_x": np.nan, "third_c2_y": np.nan, "third_c3_x": np.nan,
         "third_c3_y": np.nan},
    ]
    params = ResistanceParams(axial_force=12.0, rotational_stiffness=2.0, friction=0.2,
                              unstable_penalty=7.5)
    g = build_network(table(rows), params)
    d = g.edges[node_id(0, 0, 0), node_id(0, 0, 90)]
    work = 12.0 * (0.001 - -0.002) * MM                               # N x mm = mJ
    dtheta = math.radians(math.hypot(-0.3 - 0.5, 0.15 - -0.25))
    elastic = 0.5 * 2000.0 * dtheta ** 2                             # N mm/rad
    friction = 0.2 * 12.0 * (0.11 * MM) * math.pi / 2                 # mean of 0.1, 0.12 in
    assert d["work"] == pytest.approx(work, rel=1e-12)
    assert d["elastic"] == pytest.approx(elastic, rel=1e-12)
    assert d["friction"] == pytest.approx(friction, rel=1e-12)
    assert d["penalty"] == 7.5 and d["label"] == "unstable"
    assert d["weight"] == pytest.approx(work + elastic + friction + 7.5, rel=1e-12)
    # back: the height drops (no work), the destination is stable (no penalty), the
    # friction radius is now the unstable state's single contact at 0.11 in
    back = g.edges[node_id(0, 0, 90), node_id(0, 0, 0)]
    assert back["work"] == 0.0 and back["penalty"] == 0.0
    assert back["friction"] == pytest.approx(0.2 * 12.0 * 0.11 * MM * 3 * math.pi / 2)


def test_default_penalty_is_force_times_pitch_and_mm_needs_no_conversion():
    g = build_network(table(ring(["stable", "unstable"])))
    d = g.edges[node_id(0, 0, 0), node_id(0, 0, 180)]
    assert d["penalty"] == pytest.approx(10.0 * PITCH_IN * MM)
    rows = ring(["stable", "stable"])
    rows[1]["final_origin_z"] = 0.02                                   # mm
    g = build_network(table(rows, units="mm"), ResistanceParams(friction=0.0))
    assert g.edges[node_id(0, 0, 0), node_id(0, 0, 180)]["weight"] == pytest.approx(0.2)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_weights_are_never_negative(seed):
    g = build_network(random_table(seed))
    weights = np.array([d["weight"] for *_, d in g.edges(data=True)])
    assert len(weights) > 0 and np.all(np.isfinite(weights)) and np.all(weights >= 0)


def test_parameters_are_validated():
    for bad in ({"axial_force": 0.0}, {"friction": -0.1}, {"rotational_stiffness": math.nan},
                {"unstable_penalty": -1.0}):
        with pytest.raises(InputError):
            ResistanceParams(**bad)


# --- paths --------------------------------------------------------------------------------

@pytest.mark.parametrize("seed", [4, 5, 6, 7])
def test_cost_to_snap_matches_bellman_ford(seed):
    g = build_network(random_table(seed))
    targets = {n for n, d in g.nodes(data=True) if d["classification"] == "in-phase"}
    expected = bellman_ford(edge_list(g), list(g.nodes), targets)
    got = cost_to_snap(g)
    for n in g.nodes:
        if math.isinf(expected[n]):
            assert math.isinf(got[n])
        else:
            assert got[n] == pytest.approx(expected[n], rel=1e-12, abs=1e-12)
    reachable = [n for n in g.nodes if math.isfinite(expected[n]) and n not in targets]
    assert reachable
    for n in reachable[:12]:
        result = least_resistance_path(g, n)
        check_path(g, result)
        assert result.cost == pytest.approx(expected[n], rel=1e-12, abs=1e-12)


def _all_paths_to_snap(g: nx.DiGraph, start: str) -> list[float]:
    """Costs of every simple path from start to its first in-phase state, by DFS."""
    out = []

    def dfs(node: str, seen: set[str], cost: float) -> None:
        if g.nodes[node]["in_phase"]:
            out.append(cost)
            return
        for nxt, d in g.succ[node].items():
            if nxt not in seen:
                dfs(nxt, seen | {nxt}, cost + d["weight"])
    dfs(start, {start}, 0.0)
    return sorted(out)


def test_k_best_paths_match_enumeration_on_a_tiny_grid():
    df = random_table(11, n_roll=2, n_pitch=2, n_phase=4)
    df.loc[:, "classification"] = df["classification"].replace({"error": "stable"})
    df.loc[3, "classification"] = "in-phase"
    g = build_network(df)
    starts = [n for n in g.nodes if not g.nodes[n]["in_phase"] and _all_paths_to_snap(g, n)]
    assert max(len(_all_paths_to_snap(g, n)) for n in starts) >= 5
    for start in starts:
        costs = _all_paths_to_snap(g, start)
        got = k_best_paths(g, 5, start)
        assert [p.cost for p in got] == pytest.approx(costs[:5], rel=1e-12)
        assert len({tuple(p.path) for p in got}) == len(got)
        for p in got:
            check_path(g, p)
        assert got[0].cost == pytest.approx(least_resistance_path(g, start).cost, rel=1e-12)


def test_unsafe_starts_on_a_known_ring():
    # turning 0 -> 90 (unstable) -> 180 (in phase); 270 -> 0. From 90 the step into the
    # snap is stable; from 0 and 270 every path enters the unstable state at 90.
    g = build_network(table(ring(["stable", "unstable", "in-phase", "stable"])))
    assert sorted(unsafe_starts(g)) == sorted([node_id(0, 0, 0), node_id(0, 0, 270)])
    # a second orientation whose ring has no unstable state offers a safe detour by settling
    rows = ring(["stable", "unstable", "in-phase", "stable"])
    rows[0].update(final_roll=1.0, final_pitch=0.0)
    rows += ring(["stable", "stable", "in-phase", "stable"], roll=1.0)
    g = build_network(table(rows))
    # 270 -> 0 (stable) -> settle to roll 1 -> 90 -> 180: every start now has a safe path
    assert unsafe_starts(g) == []


def test_penalty_steers_the_path_around_unstable_states():
    rows = ring(["stable", "unstable", "in-phase", "stable"])
    rows[0].update(final_roll=1.0, final_pitch=0.0)
    rows += ring(["stable", "stable", "in-phase", "stable"], roll=1.0)
    rows[5]["final_origin_z"] = 0.02     # the detour lifts the load 0.02 in: 5.08 mJ of work
    start = node_id(0, 0, 0)
    high = build_network(table(rows), ResistanceParams(unstable_penalty=100.0))
    path = least_resistance_path(high, start)
    assert path.safe and path.kinds == ["settling", "turning", "turning"]
    c = 0.15 * 10.0 * (PD_IN / 2 * MM) * math.pi / 2
    assert path.cost == pytest.approx(2 * c + 10.0 * 0.02 * MM)
    low = build_network(table(rows), ResistanceParams(unstable_penalty=0.0))
    path = least_resistance_path(low, start)
    assert not path.safe and path.path == [start, node_id(0, 0, 90), node_id(0, 0, 180)]
    # leaving the state that rests at roll 1 for one resting at roll 0 flexes the
    # compliance by 1 degree: k/2 * (pi/180)^2 with k = 1000 N mm/rad
    assert path.cost == pytest.approx(2 * c + 500.0 * math.radians(1.0) ** 2)


def test_start_off_grid_snaps_and_says_so():
    g = build_network(random_table(8))
    node, snapped, message = resolve_start(g, 0.4, -0.6, 358.0)
    assert node == node_id(0, -1, 0) and snapped and node in message
    assert resolve_start(g, 1, 1, 45)[1:] == (False, f"start {node_id(1, 1, 45)} is a state "
                                                     "of the grid")
    with pytest.raises(InputError, match="outside the library's grid"):
        resolve_start(g, 7.0, 0.0, 0.0)
    with pytest.raises(InputError):
        resolve_start(g, math.nan, 0.0, 0.0)


def test_no_path_raises():
    g = build_network(table(ring(["stable", "unstable", "stable"])))
    with pytest.raises(NoPathError, match="no state of the library is in phase"):
        least_resistance_path(g, roll=0, pitch=0, phase=0)
    rows = ring(["in-phase", "stable"]) + ring(["stable", "stable"], roll=1.0)
    g = build_network(table(rows))
    with pytest.raises(NoPathError, match="no sequence"):
        least_resistance_path(g, roll=1, pitch=0, phase=0)
    assert least_resistance_path(g, roll=0, pitch=0, phase=180).path[-1] == node_id(0, 0, 0)


def test_bad_tables_are_refused():
    with pytest.raises(LibraryError, match="classification"):
        build_network(pd.DataFrame({"roll": [0.0], "pitch": [0.0], "phase": [0.0]}))
    df = table(ring(["stable", "in-phase"]))
    df.attrs = {}
    with pytest.raises(LibraryError, match="units"):
        build_network(df)
    with pytest.raises(LibraryError, match="twice"):
        build_network(table(ring(["stable"]) * 2))
    grid = {"roll": [0.0], "pitch": [0.0], "phase": [0.0, 180.0]}
    with pytest.raises(LibraryError, match="not on the library's grid"):
        build_network(table(ring(["stable", "stable", "stable"]), grid=grid))
    with pytest.raises(LibraryError, match="no states"):
        build_network(table(ring(["stable"])).iloc[:0])


# --- recommendation -----------------------------------------------------------------------

def test_recommendation_by_hand():
    """Friction-only weights on two pitch settings of one roll (plus a roll outside the
    spread): c = mu F r dphi per 90-degree step, P the unstable penalty."""
    a = ring(["in-phase", "stable", "stable", "stable"], pitch=-1.0)
    b = ring(["stable", "unstable", "in-phase", "stable"], pitch=1.0)
    far = ring(["stable", "stable", "stable", "in-phase"], roll=3.0, pitch=1.0)
    params = ResistanceParams(rotational_stiffness=0.0, unstable_penalty=4.0)
    g = build_network(table(a + b + far), params)
    c = 0.15 * 10.0 * (PD_IN / 2 * MM) * math.pi / 2
    rec = recommend_pitch(g, roll_spread=1.0)
    sa, sb = rec.settings
    # pitch -1: from 0, 90, 180, 270 the snap is 0, 3, 2, 1 steps away
    assert sa.expected_cost == pytest.approx(1.5 * c) and sa.worst_cost == pytest.approx(3 * c)
    assert sa.share_safe == 1.0 and sa.starts == 4
    # pitch +1: 2c+P, c, 0, 3c+P; the starts at 0 and 270 must pass the unstable state
    assert sb.expected_cost == pytest.approx((6 * c + 8.0) / 4)
    assert sb.worst_cost == pytest.approx(3 * c + 4.0) and sb.share_safe == 0.5
    assert rec.pitch == -1.0 and rec.next_pitch == 1.0 and rec.roll == 0.0
    assert rec.margin == pytest.approx(2.0)                     # P / 2
    assert not rec.roll_matters and len(rec.sensitivity) == 6
    # halving or doubling the penalty cannot make +1 cheaper: the pick is robust
    assert rec.robust
    doc = json.loads(json.dumps(rec.to_dict()))
    assert doc["recommended_pitch"] == -1.0 and len(doc["settings"]) == 2
    # the roll outside the spread joins the starts when the spread grows
    assert recommend_pitch(g, sensitivity=False).settings[1].starts == 8
    with pytest.raises(InputError):
        recommend_pitch(g, roll_spread=-1.0)


def test_recommendation_figure(tmp_path):
    from threadmate.network import plot_recommendation, write_recommendation

    g = build_network(random_table(9, n_phase=6))
    rec = recommend_pitch(g, sensitivity=False)
    png = plot_recommendation(rec, tmp_path / "rec.png")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    doc = json.loads(write_recommendation(rec, tmp_path / "rec.json").read_text())
    assert doc["recommended_pitch"] in (-1.0, 0.0, 1.0)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rec.json", "rec.png"]


# --- export -------------------------------------------------------------------------------

def test_graphml_reads_back_with_scalar_types(tmp_path):
    g = build_network(random_table(10))
    path = write_graphml(g, tmp_path / "net.graphml")
    h = nx.read_graphml(path)
    assert isinstance(h, nx.DiGraph)
    assert set(h.nodes) == set(g.nodes) and set(h.edges) == set(g.edges)
    types = {"roll": float, "phase": float, "classification": str, "n_contacts": int,
             "in_phase": bool, "region_combination": str}
    for n, d in h.nodes(data=True):
        assert isinstance(n, str)
        for key, t in types.items():
            assert type(d[key]) is t, (key, d[key])
        for v in d.values():
            assert type(v) in (str, int, float, bool)
            assert not (isinstance(v, float) and math.isnan(v))
    for u, v, d in h.edges(data=True):
        assert d["weight"] == pytest.approx(g.edges[u, v]["weight"], rel=1e-12)
        assert d["kind"] in ("turning", "settling")
        assert d["label"] in ("stable", "quasi-stable", "unstable")
    meta = h.graph
    assert meta["units"] == "in" and meta["cost_units"] == "mJ"
    assert json.loads(meta["spec"])["pitch"] == PITCH_IN
    assert json.loads(meta["parameters"])["friction"] == 0.15
    assert "threadmate_version" in meta
    back = read_graphml(path)
    assert math.isnan(back.nodes[node_id(-1, -1, 0)]["pivot_offset"])
    assert cost_to_snap(back) == pytest.approx(cost_to_snap(g))


def test_node_link_json(tmp_path):
    g = build_network(random_table(12))
    path = write_node_link(g, tmp_path / "net.json")
    doc = json.loads(path.read_text())
    h = nx.node_link_graph(doc, edges="edges")
    assert set(h.edges) == set(g.edges) and h.is_directed()
    assert h.nodes[node_id(0, 0, 0)]["pivot_offset"] is None        # NaN -> null


# --- a real sweep -------------------------------------------------------------------------

@pytest.fixture(scope="module")
def real_library(quarter_20, tmp_path_factory):
    from threadmate.library import sweep

    out = tmp_path_factory.mktemp("net") / "lib"
    return sweep(quarter_20, roll="0", pitch="-1:1:1", phase="0:330:30", out=out, workers=1,
                 chord=1e-4)


def test_real_library_network(real_library):
    from threadmate.library import load
    from threadmate.network import from_library

    df = load(real_library)
    g = from_library(real_library)
    assert g.number_of_nodes() == len(df) == 36
    assert g.graph["units"] == "in"
    counts = df["classification"].value_counts().to_dict()
    assert sum(d["in_phase"] for _, d in g.nodes(data=True)) == counts.get("in-phase", 0)
    targets = {n for n, d in g.nodes(data=True) if d["in_phase"]}
    assert targets, counts
    expected = bellman_ford(edge_list(g), list(g.nodes), targets)
    got = cost_to_snap(g)
    for n in g.nodes:
        assert got[n] == pytest.approx(expected[n], rel=1e-12, abs=1e-12) \
            if math.isfinite(expected[n]) else math.isinf(got[n])
        if math.isfinite(expected[n]) and n not in targets:
            check_path(g, least_resistance_path(g, n))
    # each node keeps its library row's values
    row = df.iloc[5]
    d = g.nodes[node_id(row["roll"], row["pitch"], row["phase"])]
    assert d["classification"] == row["classification"]
    assert d["third_origin_z"] == row["third_origin_z"] or math.isnan(row["third_origin_z"])
