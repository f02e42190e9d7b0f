"""``threadmate network``, ``threadmate path`` and ``threadmate recommend``: the graph stage
over a contact-state library."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import click

from .._errors import InputError
from ..network import (
    ResistanceParams,
    format_recommendation,
    from_library,
    k_best_paths,
    least_resistance_path,
    plot_recommendation,
    recommend_pitch,
    snap_targets,
    unsafe_starts,
    write_graphml,
    write_node_link,
    write_recommendation,
)
from ._common import check_angle, echo_err, emit_json
from ._main import cli

__all__ = ["network_command", "path_command", "recommend_command"]

_FIGURE_SUFFIXES = (".png", ".pdf", ".svg")


def _cost_options(func: Callable[..., Any]) -> Callable[..., Any]:
    """The resistance parameters as options (defaults those of ResistanceParams)."""
    d = ResistanceParams()
    options = [
        click.option("--force", type=float, default=d.axial_force, show_default=True,
                     help="Axial load on the bolt through the compliance centre [N] "
                          "(1 lbf = 4.448 N)."),
        click.option("--stiffness", type=float, default=d.rotational_stiffness,
                     show_default=True,
                     help="Rotational stiffness of the compliance [N m/rad]."),
        click.option("--friction", type=float, default=d.friction, show_default=True,
                     help="Friction coefficient between the threads."),
        click.option("--penalty", type=float, default=None,
                     help="Penalty for entering an unstable state [mJ] (default: force x "
                          "thread pitch)."),
    ]
    for option in reversed(options):
        func = option(func)
    return func


def _params(force: float, stiffness: float, friction: float, penalty: float | None
            ) -> ResistanceParams:
    return ResistanceParams(axial_force=force, rotational_stiffness=stiffness,
                            friction=friction, unstable_penalty=penalty)


def _out_file(path: str, option: str, suffixes: tuple[str, ...] | None = None) -> Path:
    """Refuse an output path that is a folder or has a wrong suffix, before any work."""
    out = Path(path)
    if out.is_dir():
        raise InputError(f"{option} {path}: is a folder; give a file name")
    if suffixes is not None and out.suffix.lower() not in suffixes:
        raise InputError(f"{option} {path}: expected a file ending in {' or '.join(suffixes)}")
    return out


@cli.command("network")
@click.argument("library", type=click.Path())
@click.option("-o", "--output", required=True, type=click.Path(),
              help="GraphML file to write (.graphml).")
@click.option("--json-graph", type=click.Path(), default=None,
              help="Also write the network as node-link JSON to this file.")
@_cost_options
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def network_command(library: str, output: str, json_graph: str | None, force: float,
                    stiffness: float, friction: float, penalty: float | None,
                    as_json: bool) -> None:
    """Build the contact-state network of LIBRARY and write it as GraphML.

    Nodes are the library's states (ids such as r+1.0_p-2.0_ph135.0); edges turn one
    phase step counter-clockwise or settle one roll/pitch step toward the bolt's resting
    orientation, labelled by the destination's stability and weighted by the resistance
    (mJ): work against the axial load, elastic energy in the compliance, friction of
    turning, penalty for entering an unstable state.
    """
    out = _out_file(output, "-o", (".graphml", ".xml"))
    link = _out_file(json_graph, "--json-graph", (".json",)) if json_graph else None
    params = _params(force, stiffness, friction, penalty)
    t0 = time.perf_counter()
    graph = from_library(library, params)
    written = [write_graphml(graph, out)]
    if link is not None:
        written.append(write_node_link(graph, link))
    kinds: dict[str, int] = {}
    labels: dict[str, int] = {}
    for _, _, d in graph.edges(data=True):
        kinds[d["kind"]] = kinds.get(d["kind"], 0) + 1
        labels[d["label"]] = labels.get(d["label"], 0) + 1
    doc = {"library": library, "graphml": str(out),
           "node_link": str(link) if link is not None else None,
           "nodes": graph.number_of_nodes(), "edges": graph.number_of_edges(),
           "edge_kinds": kinds, "edge_labels": labels,
           "snap_targets": len(snap_targets(graph)),
           "unsafe_starts": len(unsafe_starts(graph)),
           "units": graph.graph["units"], "cost_units": graph.graph["cost_units"],
           "parameters": params.to_dict(), "seconds": round(time.perf_counter() - t0, 3)}
    if as_json:
        emit_json(doc)
        return
    click.echo(f"network of {library}: {doc['nodes']} states, {doc['edges']} edges "
               f"({', '.join(f'{v} {k}' for k, v in sorted(kinds.items()))})")
    click.echo(f"snap targets (in-phase states): {doc['snap_targets']}; states with no safe "
               f"path to the snap: {doc['unsafe_starts']}")
    for path in written:
        click.echo(f"wrote {path}")


@cli.command("path")
@click.argument("library", type=click.Path())
@click.option("--roll", type=float, required=True, help="Start roll [deg].")
@click.option("--pitch", type=float, required=True, help="Start pitch [deg].")
@click.option("--phase", type=float, required=True, help="Start phase [deg] (modulo 360).")
@click.option("--k", "k", type=int, default=1, show_default=True,
              help="Number of best paths to report (the least-resistance one first).")
@_cost_options
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def path_command(library: str, roll: float, pitch: float, phase: float, k: int, force: float,
                 stiffness: float, friction: float, penalty: float | None,
                 as_json: bool) -> None:
    """The least-resistance path from a start state of LIBRARY to the in-phase snap.

    A start off the grid is moved to the nearest state (the output says so). Exit status
    3 when no path reaches the snap.
    """
    check_angle("roll", roll, 45.0)
    check_angle("pitch", pitch, 45.0)
    if not math.isfinite(phase):
        raise InputError(f"--phase {phase:g} is not a finite angle")
    if k < 1:
        raise InputError(f"--k {k}: give at least 1 path")
    graph = from_library(library, _params(force, stiffness, friction, penalty))
    if k == 1:
        results = [least_resistance_path(graph, roll=roll, pitch=pitch, phase=phase)]
    else:
        results = k_best_paths(graph, k, roll=roll, pitch=pitch, phase=phase)
    best = results[0]
    if as_json:
        doc = best.to_dict()
        doc["cost_units"] = graph.graph["cost_units"]
        doc["alternatives"] = [r.to_dict() for r in results[1:]]
        emit_json(doc)
        return
    if best.snapped:
        echo_err(f"threadmate: note: {best.message}")
    units = graph.graph["cost_units"]
    for rank, result in enumerate(results, 1):
        title = "least-resistance path" if rank == 1 else f"alternative {rank}"
        click.echo(f"{title}: {len(result.path) - 1} steps, cost {result.cost:.4g} {units}, "
                   f"{'safe' if result.safe else 'passes an unstable state'}")
        click.echo(f"  {result.path[0]}  ({graph.nodes[result.path[0]]['classification']})")
        for node, kind, label, w in zip(result.path[1:], result.kinds, result.labels,
                                        result.weights, strict=True):
            click.echo(f"  -> {node}  {kind:<8} {label:<12} {w:10.4g} {units}")
    if len(results) < k:
        click.echo(f"only {len(results)} distinct paths exist")


@cli.command("recommend")
@click.argument("library", type=click.Path())
@click.option("--roll-spread", type=float, default=None,
              help="Largest roll error expected [deg]: starts have |roll| <= spread "
                   "(default: every roll of the grid).")
@click.option("--plot", "plot", type=click.Path(), default=None,
              help="Write the figure (cost and safe share vs pitch) to this .png/.pdf/.svg.")
@click.option("--output", "-o", "output", type=click.Path(), default=None,
              help="Also write the recommendation's JSON document to this file.")
@_cost_options
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def recommend_command(library: str, roll_spread: float | None, plot: str | None,
                      output: str | None, force: float, stiffness: float, friction: float,
                      penalty: float | None, as_json: bool) -> None:
    """Recommend the SRCC pitch setting for LIBRARY.

    For each pitch of the grid, over rolls within the spread and every starting phase:
    expected and worst least-resistance cost to the snap and the share of starts that
    reach it without an unstable transition; the pick, its margin, and whether it changes
    with friction, penalty or stiffness halved or doubled.
    """
    if roll_spread is not None and (not math.isfinite(roll_spread) or roll_spread < 0):
        raise InputError(f"--roll-spread {roll_spread:g}: give a non-negative number of "
                         "degrees")
    fig = _out_file(plot, "--plot", _FIGURE_SUFFIXES) if plot else None
    out = _out_file(output, "-o", (".json",)) if output else None
    graph = from_library(library, _params(force, stiffness, friction, penalty))
    rec = recommend_pitch(graph, roll_spread)
    if out is not None:
        write_recommendation(rec, out)
    if fig is not None:
        plot_recommendation(rec, fig)
    if as_json:
        doc = rec.to_dict()
        doc["library"] = library
        doc["figure"] = str(fig) if fig is not None else None
        emit_json(doc)
        return
    click.echo(format_recommendation(rec))
    for path in (out, fig):
        if path is not None:
            click.echo(f"wrote {path}")
