"""Progress as the commands show it: a bar on stderr fed by a stage's progress callback,
and the words for how far a library's sweep got."""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

__all__ = ["progress_bar", "progress_words"]


@contextlib.contextmanager
def progress_bar(label: str) -> Iterator[Any]:
    """A rich bar on stderr fed by ``callback(done, total)``: done, rate, time left."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        ProgressColumn,
        Task,
        TextColumn,
        TimeRemainingColumn,
    )
    from rich.text import Text

    class _Rate(ProgressColumn):
        def render(self, task: Task) -> Text:
            return Text(f"{task.speed:.1f}/s" if task.speed else "-/s")

    columns = (
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        _Rate(),
        TimeRemainingColumn(),
    )
    # The bar starts with the first report, i.e. once the request is validated, so that a
    # refused request prints its one error line and nothing else.
    bar: Progress | None = None
    task = None

    def callback(done: int, total: int) -> None:
        nonlocal bar, task
        if bar is None:
            bar = Progress(*columns, console=Console(file=sys.stderr), transient=False)
            bar.start()
            # Configurations resumed from disk fill the bar but do not count in the rate.
            task = bar.add_task(label, total=total, completed=done)
        elif task is not None:  # set with the bar
            # The total may grow (a search that asks for more as it goes: the envelope).
            bar.update(task, completed=done, total=total)

    try:
        yield callback
    finally:
        if bar is not None:
            bar.stop()


def progress_words(library: str | Path, done: int, total: int, model: str = "mechanics") -> str:
    """``"4 of 8 starts done"``, and for an incomplete library whether its sweep still
    runs (the process holding its lock) or was interrupted."""
    from ..library import lock_holder

    noun = "starts" if model == "mechanics" else "configurations"
    words = f"{done} of {total} {noun} done"
    if done >= total:
        return words
    holder = lock_holder(library)
    if holder is not None:
        return (
            f"{words}: INCOMPLETE, a sweep (process {holder['pid']} on {holder['host']}, "
            f"since {holder['started']}) is still writing it"
        )
    return f"{words}: INCOMPLETE, its sweep was interrupted (run the same sweep to finish it)"
