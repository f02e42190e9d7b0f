"""What a design tool does with threadmate's graph stage: library -> network -> path ->
every start's outcome -> SRCC recommendation -> GraphML.

Run: ``python examples/design_tool.py [LIBRARY [OUT]]``. Without LIBRARY a small library
of a 1/4-20 UNC-2A/2B pair (roll 0..1, pitch -1..1, phases every 30 deg) is swept first
(a minute or two) into ``OUT/library``; the thesis's grid is
``threadmate sweep "1/4-20 UNC-2A/2B" -o LIBRARY``.

Everything is written into OUT, by default the folder ``threadmate-design`` in the current
directory, and kept there: ``network.graphml``, ``recommendation.json``,
``recommendation.png``, ``starts.csv`` (and ``library/`` when swept here; a second run
resumes it). The
last line printed says where.
"""

from __future__ import annotations

import sys
from pathlib import Path

from threadmate import NoPathError, library, network
from threadmate.contact import Compliance
from threadmate.geometry import spec_from_designation


def main(lib: Path, out: Path) -> None:
    # 1. The network of the library's states (its compliance is in the library).
    g = network.from_library(lib)
    print(
        f"{g.number_of_nodes()} states, {g.number_of_edges()} transitions, "
        f"{len(network.snap_targets(g))} in-phase (snap) states"
    )

    # 2. The passive search from one start, read off the network (the nearest start of
    #    the grid: the request is off it).
    try:
        p = network.least_resistance_path(g, roll=0.4, pitch=-1, phase=95, nearest=True)
        print(
            f"from {p.start}: snap after {p.turn:.1f} deg at phase {p.snap['phase']:.2f} "
            f"deg, click {p.snap['click']:.4g} in, driver's work {p.cost:.3g} mJ"
            + ("; passes an unstable transition" if p.passes_unstable else "")
        )
    except NoPathError as exc:
        print(f"no path: {exc}")

    # 3. Every start at once: which snap within a turn, how far, at what cost.
    starts = network.start_outcomes(g)
    print(f"{int(starts['snapped'].sum())} of {len(starts)} starts snap within one turn")

    # 4. Which SRCC pre-tilt to use for a roll error of at most 1 degree.
    rec = network.recommend(g, roll_spread=1.0)
    print(network.format_recommendation(rec))
    for note in rec.notes:
        print("note:", note)

    # 5. Files for other tools: GraphML (yEd, Gephi, Cytoscape), JSON, CSV, a figure.
    network.write_graphml(g, out / "network.graphml")
    network.write_recommendation(rec, out / "recommendation.json")
    network.plot_recommendation(rec, out / "recommendation.png")
    starts.to_csv(out / "starts.csv", index=False)
    print(
        f"wrote {out / 'network.graphml'}, recommendation.json, recommendation.png and starts.csv"
    )


if __name__ == "__main__":
    out = Path(sys.argv[2]) if len(sys.argv) > 2 else Path("threadmate-design")
    if len(sys.argv) > 1:
        lib = Path(sys.argv[1])
    else:
        spec = spec_from_designation("1/4-20 UNC-2A/2B")
        lib = library.sweep(
            spec,
            roll="0:1:1",
            pitch="-1:1:1",
            phase="0:330:30",
            out=out / "library",
            compliance=Compliance(force=8.0, stiffness=0.8, friction=0.12),
        )
    main(lib, out)
    print(f"output kept in {out.resolve()}")
