"""``threadmate run`` end to end on a tiny grid: the layout, the GraphML, the report."""

from __future__ import annotations

import json

import networkx as nx
import pandas as pd
import pytest

from threadmate.cli import main


def test_run_writes_the_whole_layout(tmp_path, capsys):
    out = tmp_path / "job"
    with pytest.raises(SystemExit) as exc:
        main(["run", "1/4-20 UNC-2A/2B", "-o", str(out), "--roll", "0", "--pitch", "-1,0",
              "--phase", "0:360:60", "--workers", "1", "--json"])
    assert exc.value.code == 0
    doc = json.loads(capsys.readouterr().out)
    for name in ("network.graphml", "network.json", "recommendation.json", "report.md"):
        assert (out / name).is_file()
    lib = pd.read_parquet(out / "library")
    assert len(lib) == 2 * 6
    graph = nx.read_graphml(out / "network.graphml")
    assert set(graph.nodes) and all(isinstance(n, str) for n in graph.nodes)
    assert graph.number_of_nodes() == len(lib)
    rec = json.loads((out / "recommendation.json").read_text())
    assert doc["recommended_pitch"] in (-1.0, 0.0)
    assert rec
    assert all((out / "figures").joinpath(p.split("/")[-1]).is_file()
               for p in doc["figures"].values())
    assert sum(doc["counts"].values()) == len(lib)


def test_run_refuses_bad_input(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", "M7x9", "-o", str(tmp_path / "x")])
    assert exc.value.code == 2
    assert "Traceback" not in capsys.readouterr().err
    assert not (tmp_path / "x").exists()
