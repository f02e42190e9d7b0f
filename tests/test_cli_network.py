"""``threadmate network``, ``path`` and ``recommend``: documents, files, exit statuses 2 and 3,
nothing half-written."""

from __future__ import annotations

import itertools
import json
import math

import networkx as nx
import pyarrow as pa
import pytest

from threadmate.cli import main
from threadmate.library import Grid
from threadmate.library._store import FORMAT, library_schema, write_metadata, write_part
from threadmate.network import node_id


def run(capsys, *args: str) -> tuple[int, str, str]:
    """Run the real entry point in-process; return (exit status, stdout, stderr)."""
    with pytest.raises(SystemExit) as exc:
        main(list(args))
    out, err = capsys.readouterr()
    return exc.value.code, out, err


def write_library(path, classes: dict[tuple[float, float, float], str]):
    """A library directory with the real schema and metadata, rows built by hand."""
    rolls = sorted({k[0] for k in classes})
    pitches = sorted({k[1] for k in classes})
    phases = sorted({k[2] for k in classes})
    grid = Grid(rolls, pitches, phases)
    schema = library_schema()
    blank = {f.name: (math.nan if pa.types.is_floating(f.type) else 0 if pa.types.is_integer(
        f.type) else False if pa.types.is_boolean(f.type) else "") for f in schema}
    rows = []
    for (r, p, ph), c in classes.items():
        i, j, k = grid.roll.index(r), grid.pitch.index(p), grid.phase.index(ph)
        rows.append({**blank, "config_id": grid.config_id(i, j, k), "roll": r, "pitch": p,
                     "phase": ph, "classification": c, "final_origin_z": 0.0,
                     "third_found": True, "third_c1_x": 0.1, "third_c1_y": 0.0})
    spec = {"units": "in", "pitch": 0.05, "bolt": {"pitch_diameter": 0.2146}}
    meta = {"format": FORMAT, "format_version": 1, "spec": spec, "grid": grid.to_dict(),
            "mesh": {"chord": 1e-4}, "contact": {"compliance_z": 0.0}, "units": "in",
            "threadmate_version": "test"}
    write_metadata(path, meta)
    write_part(path, 0, pa.Table.from_pylist(rows, schema=schema))
    return path


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    """Two rolls x three pitches x four phases; one in-phase state per ring except at
    pitch +1 roll 0, which has none and cannot settle anywhere (its finals are NaN)."""
    classes = {}
    for r, p in itertools.product((0.0, 1.0), (-1.0, 0.0, 1.0)):
        for k, ph in enumerate((0.0, 90.0, 180.0, 270.0)):
            snap = k == (int(p) + 1) % 4 and not (r == 0.0 and p == 1.0)
            classes[(r, p, ph)] = "in-phase" if snap else ("unstable" if k == 3 else "stable")
    return write_library(tmp_path_factory.mktemp("cli-net") / "lib", classes)


def test_network_writes_graphml_and_node_link(library, tmp_path, capsys):
    out, link = tmp_path / "n.graphml", tmp_path / "n.json"
    rc, stdout, stderr = run(capsys, "network", str(library), "-o", str(out),
                             "--json-graph", str(link), "--friction", "0.1", "--json")
    assert rc == 0, stderr
    doc = json.loads(stdout)
    g = nx.read_graphml(out)
    assert doc["nodes"] == g.number_of_nodes() == 24
    # 4 turning edges per ring minus the one leaving each of the 5 in-phase states
    assert doc["edge_kinds"] == {"turning": 24 - 5} == {
        "turning": sum(d["kind"] == "turning" for *_, d in g.edges(data=True))}
    assert json.loads(g.graph["parameters"])["friction"] == 0.1
    assert nx.node_link_graph(json.loads(link.read_text()), edges="edges").number_of_edges() \
        == g.number_of_edges()


def test_path_json_document(library, capsys):
    rc, stdout, stderr = run(capsys, "path", str(library), "--roll", "0.2", "--pitch", "-1",
                             "--phase", "95", "--json")
    assert rc == 0, stderr
    doc = json.loads(stdout)
    # the in-phase state of pitch -1 is at phase 0: 90 -> 180 -> 270 -> 0
    assert doc["start"] == node_id(0, -1, 90) and doc["snapped"] is True
    assert "nearest" in doc["message"]
    assert doc["path"] == [node_id(0, -1, ph) for ph in (90, 180, 270, 0)]
    assert doc["labels"] == ["stable", "unstable", "stable"]
    assert doc["cost"] == pytest.approx(sum(doc["weights"]))
    c = 0.15 * 10.0 * 0.1 * 25.4 * math.pi / 2
    assert doc["cost"] == pytest.approx(3 * c + 10.0 * 0.05 * 25.4)


def test_path_text_and_alternatives(library, capsys):
    rc, stdout, stderr = run(capsys, "path", str(library), "--roll", "1", "--pitch", "0",
                             "--phase", "180", "--k", "3")
    assert rc == 0, stderr
    assert "least-resistance path" in stdout and node_id(1, 0, 90) in stdout
    assert "only 1 distinct paths exist" in stdout


def test_recommend_json_and_files(library, tmp_path, capsys):
    fig, out = tmp_path / "rec.svg", tmp_path / "rec.json"
    rc, stdout, stderr = run(capsys, "recommend", str(library), "--roll-spread", "0.5",
                             "--plot", str(fig), "-o", str(out), "--json")
    assert rc == 0, stderr
    doc = json.loads(stdout)
    assert doc == {**json.loads(out.read_text()), "library": str(library), "figure": str(fig)}
    assert fig.read_text().lstrip().startswith("<?xml")
    by_pitch = {s["pitch"]: s for s in doc["settings"]}
    assert by_pitch[1.0]["reachable"] == 0 and by_pitch[1.0]["expected_cost"] is None
    # at roll 0: pitch -1 costs (3c + P) / ... by hand: starts 0, 90, 180, 270 need
    # 0, 3, 2, 1 steps; the steps into 270 pay the penalty P (from 90 and 180)
    c = 0.15 * 10.0 * 0.1 * 25.4 * math.pi / 2
    pen = 10.0 * 0.05 * 25.4
    assert by_pitch[-1.0]["expected_cost"] == pytest.approx((6 * c + 2 * pen) / 4)
    assert by_pitch[-1.0]["share_safe"] == 0.5          # only 0 and 270 avoid the unstable
    # pitch 0 (snap at 90): from 0: c, 90: 0, 180: 3c + P (through 270), 270: 2c
    assert by_pitch[0.0]["expected_cost"] == pytest.approx((6 * c + pen) / 4)
    assert doc["recommended_pitch"] == 0.0 and doc["next_best_pitch"] == -1.0


def test_recommend_table(library, capsys):
    rc, stdout, _ = run(capsys, "recommend", str(library))
    assert rc == 0 and "<- recommended" in stdout and "Recommended SRCC pitch" in stdout


def test_no_path_exits_3(library, capsys):
    rc, stdout, stderr = run(capsys, "path", str(library), "--roll", "0", "--pitch", "1",
                             "--phase", "0", "--json")
    assert rc == 3 and stdout == "" and "no path" in stderr


@pytest.mark.parametrize("args", [
    ("path", "{missing}", "--roll", "0", "--pitch", "0", "--phase", "0"),
    ("path", "{lib}", "--roll", "60", "--pitch", "0", "--phase", "0"),
    ("path", "{lib}", "--roll", "9", "--pitch", "0", "--phase", "0"),
    ("path", "{lib}", "--roll", "nan", "--pitch", "0", "--phase", "0"),
    ("path", "{lib}", "--roll", "0", "--pitch", "0", "--phase", "0", "--k", "0"),
    ("recommend", "{lib}", "--roll-spread", "-2"),
    ("recommend", "{lib}", "--plot", "{tmp}/fig.gif"),
    ("network", "{notlib}", "-o", "{tmp}/n.graphml"),
    ("network", "{lib}", "-o", "{tmp}/n.txt"),
    ("network", "{lib}", "-o", "{tmp}/n.graphml", "--friction", "-1"),
])
def test_bad_input_exits_2_and_writes_nothing(library, tmp_path, capsys, args):
    notlib = tmp_path / "notlib"
    notlib.mkdir()
    (notlib / "x.parquet").write_bytes(b"junk")
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    fill = {"missing": str(tmp_path / "missing"), "lib": str(library), "notlib": str(notlib),
            "tmp": str(out_dir)}
    rc, stdout, stderr = run(capsys, *(a.format(**fill) for a in args))
    assert rc == 2, stderr
    assert stderr.startswith("threadmate: error:") and "Traceback" not in stderr
    assert stdout == "" and list(out_dir.iterdir()) == []
