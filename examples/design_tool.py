"""What a design tool does with threadmate's graph stage: library -> network -> path ->
SRCC pitch recommendation -> GraphML.

Run: ``python examples/design_tool.py [LIBRARY [OUT]]``. Without LIBRARY a small library
of a 1/4-20 UNC-2A/2B pair (roll 0..1, pitch -1..1, phases every 30 deg) is swept first
(a minute or two) into ``OUT/library``; the thesis's grid is
``threadmate sweep "1/4-20 UNC-2A/2B" -o LIBRARY``.

Everything is written into OUT, by default the folder ``threadmate-design`` in the current
directory, and kept there: ``network.graphml``, ``recommendation.json``,
``recommendation.png`` (and ``library/`` when swept here; a second run resumes it). The
last line printed says where.
"""

from __future__ import annotations

import sys
from pathlib import Path

from threadmate import NoPathError, library, network
from threadmate.geometry import spec_from_designation


def main(lib: Path, out: Path) -> None:
    # 1. The network, with the resistance parameters of the insertion cell.
    params = network.ResistanceParams(axial_force=8.0,          # N
                                      rotational_stiffness=0.8,  # N m/rad of the SRCC
                                      friction=0.12)
    g = network.from_library(lib, params)
    print(f"{g.number_of_nodes()} states, {g.number_of_edges()} transitions, "
          f"{len(network.snap_targets(g))} in-phase (snap) states")

    # 2. The least-resistance path from a first touch (snapped to the grid if need be).
    try:
        p = network.least_resistance_path(g, roll=0.4, pitch=-1, phase=95)
        print(p.message)
        print(f"path to the snap: {len(p.path) - 1} steps, {p.cost:.3g} mJ, "
              f"{'safe' if p.safe else 'passes an unstable state'}: {' -> '.join(p.path)}")
    except NoPathError as exc:
        print(f"no path: {exc}")

    # 3. Which SRCC pitch setting to use for a roll error of at most 1 degree.
    rec = network.recommend_pitch(g, roll_spread=1.0)
    print(network.format_recommendation(rec))

    # 4. Files for other tools: GraphML (yEd, Gephi, Cytoscape), JSON, a figure.
    network.write_graphml(g, out / "network.graphml")
    network.write_recommendation(rec, out / "recommendation.json")
    network.plot_recommendation(rec, out / "recommendation.png")
    print(f"wrote {out / 'network.graphml'}, recommendation.json and recommendation.png")


if __name__ == "__main__":
    out = Path(sys.argv[2]) if len(sys.argv) > 2 else Path("threadmate-design")
    if len(sys.argv) > 1:
        lib = Path(sys.argv[1])
    else:
        spec = spec_from_designation("1/4-20 UNC-2A/2B")
        lib = library.sweep(spec, roll="0:1:1", pitch="-1:1:1", phase="0:330:30",
                            out=out / "library", workers=1)
    main(lib, out)
    print(f"output kept in {out.resolve()}")
