"""``run_pipeline``: library -> network -> recommendation -> GraphML, figures, report.

Layout of the output folder::

    DIR/library/            the contact-state library (Parquet dataset, resumable)
    DIR/network.graphml     the contact-state network
    DIR/network.json        the same graph as node-link JSON
    DIR/recommendation.json the SRCC pitch recommendation
    DIR/figures/            planar disk and pivot chart, stability map, phase strips,
                            region combinations, recommendation chart
    DIR/report.md           a short report
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .._io import atomic_write_text
from .._version import __version__
from ..geometry import ThreadSpec
from ..library import summary, sweep, write_figures
from ..network import (
    ResistanceParams,
    format_recommendation,
    from_library,
    plot_recommendation,
    recommend_pitch,
    write_graphml,
    write_node_link,
    write_recommendation,
)
from ..planar import plot_pivot_axes, plot_region_disk

__all__ = ["DEFAULT_DESIGNATION", "RunResult", "run_pipeline"]

#: The built-in default of ``threadmate run``: the thesis's thread pair.
DEFAULT_DESIGNATION = "1/4-20 UNC-2A/2B"


@dataclass(frozen=True)
class RunResult:
    """What :func:`run_pipeline` wrote, and the headline figures."""

    out: Path
    library: Path
    graphml: Path
    node_link: Path
    recommendation: Path
    report: Path
    figures: dict[str, Path] = field(default_factory=dict)
    counts: dict[str, int] = field(default_factory=dict)
    recommended_pitch: float | None = None
    note: str = ""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready mapping of paths and figures."""
        return {
            "out": str(self.out), "library": str(self.library), "graphml": str(self.graphml),
            "node_link": str(self.node_link), "recommendation": str(self.recommendation),
            "report": str(self.report),
            "figures": {k: str(v) for k, v in self.figures.items()},
            "counts": self.counts, "recommended_pitch": self.recommended_pitch,
            "note": self.note,
        }


def run_pipeline(
    spec: ThreadSpec,
    out: str | os.PathLike[str],
    *,
    roll: Any = None,
    pitch: Any = None,
    phase: Any = None,
    workers: int | None = None,
    scheduler: str | None = None,
    chord: float | None = None,
    roll_spread: float | None = None,
    params: ResistanceParams | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> RunResult:
    """Run the whole pipeline into ``out`` (see the module docstring for the layout).

    The library in ``out/library`` is resumed (or reused when complete); a library for
    another spec or grid is refused by the sweep stage, never mixed. Grid arguments default
    to the thesis's grid (roll and pitch -4..4 by 1 degree, phase 0..355 by 5).
    """
    out = Path(out)
    lib = out / "library"
    sweep(spec, roll, pitch, phase, out=lib, workers=workers, scheduler=scheduler,
          chord=chord, progress=progress)
    counts = summary(lib)
    graph = from_library(lib, params)
    graphml = write_graphml(graph, out / "network.graphml")
    node_link = write_node_link(graph, out / "network.json")
    rec = recommend_pitch(graph, roll_spread)
    rec_path = write_recommendation(rec, out / "recommendation.json")
    figdir = out / "figures"
    figures = {f"library_{k}": Path(v) for k, v in write_figures(lib, figdir).items()}
    figures["recommendation"] = plot_recommendation(rec, figdir / "recommendation.png")
    figures["region_disk"] = plot_region_disk(spec, figdir / "planar-region-disk.png")
    figures["pivot_axes"] = plot_pivot_axes(spec, figdir / "planar-pivot-axes.png")
    report = _report(spec, counts, format_recommendation(rec), rec.note(), figures, out)
    report_path = atomic_write_text(out / "report.md", report)
    return RunResult(out, lib, graphml, node_link, rec_path, report_path, figures,
                     _flat_counts(counts), rec.pitch, rec.note())


def _flat_counts(counts: dict[str, Any]) -> dict[str, int]:
    raw = counts.get("counts", counts)
    return {str(k): int(v) for k, v in raw.items() if isinstance(v, int | float)}


def _report(spec: ThreadSpec, counts: dict[str, Any], table: str, note: str,
            figures: dict[str, Path], out: Path) -> str:
    name = spec.designation or "custom spec"
    lines = [
        f"# threadmate run: {name}",
        "",
        f"threadmate {__version__}; lengths in {spec.units}, angles in degrees; frames and "
        "regions per docs/conventions.md.",
        "",
        "## Contact states",
        "",
        "| classification | states |",
        "|---|---|",
    ]
    lines += [f"| {k} | {v} |" for k, v in _flat_counts(counts).items()]
    lines += ["", "## SRCC pitch recommendation", "", note, "", "```", table.rstrip(), "```",
              "", "## Files", "",
              "- `library/`: the contact-state library (Parquet)",
              "- `network.graphml`, `network.json`: the contact-state network",
              "- `recommendation.json`: the recommendation", ""]
    lines += [f"- `{p.relative_to(out)}`" for p in figures.values()]
    return "\n".join(lines) + "\n"
