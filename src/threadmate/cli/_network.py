"""``threadmate network``, ``threadmate path`` and ``threadmate recommend``: the graph stage
over a mechanics library."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import click

from .._errors import InputError, NoPathError
from .._validate import FIGURE_FORMATS, MAX_K, check_configuration, check_roll_spread
from ..contact import UNSTABLE
from ._common import (
    echo_err,
    emit_json,
    shown_phase,
    turn_words,
    writable_output,
    write_failed,
)
from ._main import cli
from ._options import DIRECTION_HELP, held_tilt_from_options, roll_spread_option
from ._progress import progress_words

# The graph stage (networkx, pandas, matplotlib) is imported where it is used, so that
# --help and a refused option answer at once.

__all__ = ["network_command", "path_command", "recommend_command"]


def _out_file(path: str, option: str, suffixes: tuple[str, ...] | None = None) -> Path:
    """Refuse an output path that has a wrong suffix or cannot be written, before any
    work."""
    out = Path(path)
    if suffixes is not None and out.suffix.lower() not in suffixes:
        raise InputError(f"{option} {path}: expected a file ending in {' or '.join(suffixes)}")
    return writable_output(out, option)


def _check_once(libraries: tuple[str, ...]) -> None:
    """Refuse a library given twice: every row of the ranking would be there twice."""
    seen: dict[Path, str] = {}
    for lib in libraries:
        key = Path(lib).resolve()
        if key in seen:
            given = lib if lib == seen[key] else f"{seen[key]} and {lib}"
            raise InputError(
                f"library {given} given twice: give each library once (recommend compares "
                "the compliances of different libraries)"
            )
        seen[key] = lib


def _graph_options(func: Any) -> Any:
    for option in reversed(
        [
            click.option(
                "--active",
                is_flag=True,
                help="Add active moves: change the held tilt by one grid step (lift "
                "and re-drop), each at its stated cost.",
            ),
            click.option(
                "--jump-penalty",
                type=float,
                default=0.0,
                show_default=True,
                help="Weight of a jump [mJ] (a jump releases energy; 0 by default).",
            ),
            click.option(
                "--move-penalty",
                type=float,
                default=None,
                help="Price of one active move [mJ] (default: force x thread pitch).",
            ),
        ]
    ):
        func = option(func)
    return func


def _summary(graph: Any) -> tuple[dict[str, Any], Any]:
    """Counts and the outcome of every start."""
    from ..network import start_outcomes

    kinds: dict[str, int] = {}
    labels: dict[str, int] = {}
    for _, _, d in graph.edges(data=True):
        kinds[d["kind"]] = kinds.get(d["kind"], 0) + 1
        labels[d["label"]] = labels.get(d["label"], 0) + 1
    classes: dict[str, int] = {}
    for _, d in graph.nodes(data=True):
        classes[d["classification"]] = classes.get(d["classification"], 0) + 1
    out = start_outcomes(graph)
    ok = out[~out["failed"]]
    snapped = ok[ok["snapped"]]
    # A start whose descent did not converge is not a rest state (its class: unstable).
    not_at_rest = ok.loc[ok["classification"] == UNSTABLE, "node"].tolist()
    return {
        "nodes": graph.number_of_nodes(),
        "edges": graph.number_of_edges(),
        "node_classes": classes,
        "edge_kinds": kinds,
        "edge_labels": labels,
        "starts": len(out),
        "failed_starts": out.loc[out["failed"], "node"].tolist(),
        "not_at_rest": not_at_rest,
        "snap_within_one_turn": len(snapped),
        "never_snap": ok.loc[~ok["snapped"], "node"].tolist(),
        "passes_unstable": ok.loc[ok["passes_unstable"], "node"].tolist(),
        "cost_to_snap": {
            n: float(w) for n, w in zip(snapped["node"], snapped["work"], strict=True)
        },
    }, out


@cli.command("network")
@click.argument("library", type=click.Path())
@click.option(
    "-o", "--output", required=True, type=click.Path(), help="GraphML file to write (.graphml)."
)
@click.option(
    "--json-graph",
    type=click.Path(),
    default=None,
    help="Also write the network as node-link JSON to this file.",
)
@click.option(
    "--starts-csv",
    type=click.Path(),
    default=None,
    help="Also write every start's outcome (snaps within a turn, turn, work, "
    "click, peak torque, unstable passage) to this CSV file.",
)
@_graph_options
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def network_command(
    library: str,
    output: str,
    json_graph: str | None,
    starts_csv: str | None,
    active: bool,
    jump_penalty: float,
    move_penalty: float | None,
    as_json: bool,
) -> None:
    """Build the contact-state network of LIBRARY (a mechanics library) and write it as
    GraphML.

    Nodes are the library's contact states; edges are the passive transitions (settling,
    turning, jump, snap; labelled stable, quasi-stable or unstable; weighted by the
    driver's work in mJ) and, with --active, the active tilt steps. Reports the cost to
    the snap of every start, the starts that never snap within one turn and those whose
    path passes an unstable transition.
    """
    out = _out_file(output, "-o", (".graphml", ".xml"))
    link = _out_file(json_graph, "--json-graph", (".json",)) if json_graph else None
    csv = _out_file(starts_csv, "--starts-csv", (".csv",)) if starts_csv else None
    from ..network import (
        WEIGHT_FORMULA,
        from_library,
        start_outcomes_csv,
        write_graphml,
        write_node_link,
    )

    t0 = time.perf_counter()
    graph = from_library(
        library, active=active, jump_penalty=jump_penalty, move_penalty=move_penalty
    )
    doc, outcomes = _summary(graph)
    # The files carry each state's rotation and contact points and normals from the
    # library (the graph in memory leaves them there).
    target = out  # the file being written, for a write the system refuses (a full disk)
    try:
        written = [write_graphml(graph, out, library=library)]
        if link is not None:
            target = link
            written.append(write_node_link(graph, link, library=library))
        if csv is not None:
            target = csv
            written.append(start_outcomes_csv(outcomes, csv, graph.graph["units"]))
    except OSError as exc:
        raise write_failed(target, exc) from None
    doc.update(
        library=library,
        graphml=str(out),
        node_link=str(link) if link is not None else None,
        starts_csv=str(csv) if csv is not None else None,
        units={"length": graph.graph["units"], "angle": "deg", "cost": "mJ"},
        weight_formula=WEIGHT_FORMULA,
        active=active,
        seconds=round(time.perf_counter() - t0, 3),
        **{k: graph.graph[k] for k in ("complete", "done", "configurations")},
    )
    if doc["not_at_rest"]:
        echo_err(
            f"threadmate: warning: {len(doc['not_at_rest'])} start(s) did not reach a rest "
            f"state (the descent did not converge): {', '.join(doc['not_at_rest'][:5])}"
            + (" ..." if len(doc["not_at_rest"]) > 5 else "")
        )
    if as_json:
        emit_json(doc)
        return
    if not doc["complete"]:
        words = progress_words(library, doc["done"], doc["configurations"])
        click.echo(f"library {library}: {words}; the network holds the states of those done")
    click.echo(
        f"network of {library}: {doc['nodes']} states, {doc['edges']} edges "
        f"({', '.join(f'{v} {k}' for k, v in sorted(doc['edge_kinds'].items()))})"
    )
    click.echo(
        f"starts: {doc['starts']}; snap within one turn: "
        f"{doc['snap_within_one_turn']}; never within one turn: "
        f"{len(doc['never_snap'])}; path passes an unstable transition: "
        f"{len(doc['passes_unstable'])}; failed: {len(doc['failed_starts'])}"
    )
    for path in written:
        click.echo(f"wrote {path}")


@cli.command("path")
@click.argument("library", type=click.Path())
@click.option("--roll", type=float, default=None, help="Held roll of the start [deg].")
@click.option("--pitch", type=float, default=None, help="Held pitch of the start [deg].")
@click.option(
    "--tilt",
    type=float,
    default=None,
    help="Held tilt size of the start [deg], with --direction (instead of --roll/--pitch).",
)
@click.option(
    "--direction",
    type=float,
    default=None,
    help=f"Direction of the held tilt [deg]: {DIRECTION_HELP}.",
)
@click.option("--phase", type=float, required=True, help="Start phase [deg] (modulo 360).")
@click.option(
    "--k",
    "k",
    type=int,
    default=1,
    show_default=True,
    help=f"Paths to report, the least-resistance one first (at most {MAX_K}; "
    "passively there is only one).",
)
@click.option(
    "--nearest",
    is_flag=True,
    help="Take the nearest start of the grid when the one asked for is not on it.",
)
@_graph_options
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def path_command(
    library: str,
    roll: float | None,
    pitch: float | None,
    tilt: float | None,
    direction: float | None,
    phase: float,
    k: int,
    nearest: bool,
    active: bool,
    jump_penalty: float,
    move_penalty: float | None,
    as_json: bool,
) -> None:
    """The least-resistance path from a start of LIBRARY to the snap.

    Without --active it is the passive search from that start (as `threadmate search`
    computes it). Exit status 3 when no path reaches the snap (with --json, the document
    still, its path and snap null). The held tilt is --roll and --pitch, or --tilt and
    --direction (either names a start of either kind of grid).
    """
    roll, pitch = held_tilt_from_options(roll, pitch, tilt, direction)
    check_configuration(roll, pitch, phase)  # the API's check, before the stage loads
    from ..network import from_library, k_best_paths, no_path_document

    graph = from_library(
        library, active=active, jump_penalty=jump_penalty, move_penalty=move_penalty
    )
    try:
        best = k_best_paths(graph, k, roll, pitch, phase, active=active, nearest=nearest)
    except NoPathError as exc:
        if as_json:  # a design tool still gets its document (snap null), as from search
            emit_json(
                no_path_document(graph, roll, pitch, phase, exc, active=active, nearest=nearest)
            )
        raise
    if as_json:
        emit_json(best.to_dict())
        return
    if best.moved_to_grid:
        echo_err(
            f"threadmate: note: roll {roll:g}, pitch {pitch:g}, phase {phase:g} is off "
            f"the grid; starting from the nearest start, {best.start}"
        )
    for rank, result in enumerate([best, *best.alternatives], 1):
        title = "least-resistance path" if rank == 1 else f"alternative {rank}"
        click.echo(
            f"{title}: {len(result.path) - 1} transitions, cost {result.cost:.4g} mJ, "
            f"turn {turn_words(result.turn, '.2f')}, snap at phase "
            f"{shown_phase(result.snap['phase']):.2f} deg, click "
            f"{result.snap['click']:.4g} {graph.graph['units']}"
            + ("; passes an unstable transition" if result.passes_unstable else "")
        )
        click.echo(f"  {result.path[0]}  ({graph.nodes[result.path[0]]['classification']})")
        for node, kind, label, w in zip(
            result.path[1:], result.kinds, result.labels, result.weights, strict=True
        ):
            click.echo(f"  -> {node}  {kind:<9} {label:<12} {w:10.4g} mJ")
    if len(best.alternatives) < k - 1:
        click.echo(f"only {len(best.alternatives) + 1} distinct path(s) exist")


@cli.command("recommend")
@click.argument("libraries", nargs=-1, required=True, type=click.Path())
@roll_spread_option
@click.option(
    "--plot",
    "plot",
    type=click.Path(),
    default=None,
    help="Write the figure (snap share and mean turn vs held pitch) to this .png/.pdf/.svg.",
)
@click.option(
    "--output",
    "-o",
    "output",
    type=click.Path(),
    default=None,
    help="Also write the recommendation's JSON document to this file.",
)
@click.option(
    "--partial",
    is_flag=True,
    help="Rank an incomplete library's starts too (its sweep unfinished or still running), "
    "with a note of how many are done; without it such a library is refused.",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def recommend_command(
    libraries: tuple[str, ...],
    roll_spread: float | None,
    plot: str | None,
    output: str | None,
    partial: bool,
    as_json: bool,
) -> None:
    """Recommend the SRCC setting from one or more LIBRARIES (same thread and grid; give
    several to compare compliances).

    For each held pitch (the pre-tilt) and compliance, over the starts within the roll
    spread at every start phase: the share that snap within one turn, the turn and work to
    the snap, the click, the peak torque; ranked by snap share, then turn, then work; and
    the pick that holds whatever the nut's thread-start azimuth.
    """
    _check_once(libraries)
    check_roll_spread(roll_spread)  # the API's check, before the stage loads
    fig = _out_file(plot, "--plot", tuple(FIGURE_FORMATS)) if plot else None
    out = _out_file(output, "-o", (".json",)) if output else None
    from ..network import (
        format_recommendation,
        from_library,
        plot_recommendation,
        recommend,
        write_recommendation,
    )

    graphs = [from_library(lib) for lib in libraries]
    for lib, g in zip(libraries, graphs, strict=True):
        if not g.graph["complete"] and not partial:
            words = progress_words(lib, g.graph["done"], g.graph["configurations"])
            raise InputError(
                f"library {lib}: {words}. A ranking of the held tilts swept so far may pick "
                "one the rest would beat: finish the sweep, or pass --partial"
            )
    rec = recommend(graphs, roll_spread, partial=partial)
    for path, write in ((out, write_recommendation), (fig, plot_recommendation)):
        if path is not None:
            try:
                write(rec, path)
            except OSError as exc:  # a full disk
                raise write_failed(path, exc) from None
    if as_json:
        doc = rec.to_dict()
        doc["libraries"] = list(libraries)
        doc["figure"] = str(fig) if fig is not None else None
        emit_json(doc)
        return
    click.echo(format_recommendation(rec))
    for note in rec.notes:
        click.echo(f"note: {note}")
    for path in (out, fig):
        if path is not None:
            click.echo(f"wrote {path}")
