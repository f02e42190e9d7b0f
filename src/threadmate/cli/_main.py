"""The ``threadmate`` command group and its error handling."""

from __future__ import annotations

import contextlib
import io
import os
import signal
import sys
import warnings
from collections.abc import Iterator
from types import FrameType
from typing import TextIO

import click

from .._errors import InputError, NoPathError
from .._version import __version__

__all__ = ["cli", "main"]

#: Exit status of an interrupted or terminated run (128 + SIGINT, the shell's own).
INTERRUPTED = 130


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="threadmate")
def cli() -> None:
    """threadmate: contact analysis and path planning for threaded fastener insertion.

    Lengths are in the spec's units (in or mm); angles are degrees everywhere.
    """


def _register() -> None:
    # Each command lives in its own module and registers itself on import. The modules
    # import their stages (scipy, trimesh, numba, pandas, matplotlib) inside the commands, so
    # that --help, --version and a refused option answer at once.
    from . import _thread  # noqa: F401, I001  (registers: thread)
    from . import _planar  # noqa: F401  (registers: planar)
    from . import _contact  # noqa: F401  (registers: contact)
    from . import _mechanics  # noqa: F401  (registers: settle, search, screw)
    from . import _library  # noqa: F401  (registers: sweep, library)
    from . import _mesh  # noqa: F401  (registers: mesh)
    from . import _network  # noqa: F401  (registers: network, path, recommend)
    from . import _design  # noqa: F401  (registers: sensor, program)
    from . import _envelope  # noqa: F401  (registers: envelope)
    from . import _design_search  # noqa: F401  (registers: design)
    from . import _run  # noqa: F401  (registers: run)
    from . import _view  # noqa: F401  (registers: view)


class _Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the process is so that it unwinds as an interrupt does: the
    temporaries of atomic writes are removed, a sweep keeps its chunks and stops its
    workers."""


class _StdoutError(Exception):
    """A write to standard output failed (a full device, a closed pipe). Not an OSError:
    a command's handler of a file's write failure must not take it for its file's, nor
    click for the broken pipe it exits on in silence."""

    def __init__(self, exc: OSError) -> None:
        super().__init__(exc.strerror or str(exc))


class _Stdout(io.TextIOWrapper):
    """Standard output that tells its own write failures from a file's."""

    def write(self, s: str) -> int:
        try:
            return super().write(s)
        except OSError as exc:
            raise _StdoutError(exc) from None

    def flush(self) -> None:
        try:
            super().flush()
        except OSError as exc:
            raise _StdoutError(exc) from None


@contextlib.contextmanager
def _watched_stdout() -> Iterator[None]:
    """Standard output as :class:`_Stdout` for the run (only the process's own: a test's
    capture stays as it is), flushed at the end so that a failure shows while it can
    still be reported."""
    original = sys.stdout
    if original is not sys.__stdout__ or not isinstance(original, io.TextIOWrapper):
        yield
        return
    original.flush()
    sys.stdout = _Stdout(
        original.buffer,
        encoding=original.encoding,
        errors=original.errors,
        line_buffering=original.line_buffering,
        write_through=original.write_through,
    )
    try:
        yield
        sys.stdout.flush()
    finally:
        watched, sys.stdout = sys.stdout, original
        try:  # keep the buffer, which is the original's (detach flushes first)
            watched.detach()
        except (_StdoutError, OSError):
            _drop_stdout()  # what is still buffered goes to the null device
            with contextlib.suppress(_StdoutError, OSError, ValueError):
                watched.detach()
        except ValueError:  # already detached or closed
            pass


def _drop_stdout() -> None:
    """After standard output failed: point it at the null device, so that the bytes still
    in its buffer do not fail again (with a traceback) when the interpreter exits."""
    with contextlib.suppress(OSError, ValueError, AttributeError):
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.__stdout__.fileno())  # type: ignore[union-attr]
        os.close(null)


@contextlib.contextmanager
def _sigterm_as_interrupt() -> Iterator[None]:
    """SIGTERM raises :class:`_Terminated` in this process (a worker forked from it dies
    of the signal as before); an interrupt or SIGTERM that Python could only drop, raised
    within a finaliser, is raised again a moment later."""
    main_pid = os.getpid()

    def handler(signum: int, frame: FrameType | None) -> None:
        if os.getpid() != main_pid:  # a forked worker: die of the signal, as it would have
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        raise _Terminated()

    dropped: list[BaseException] = []

    def unraisable(report: sys.UnraisableHookArgs) -> None:
        # A signal that arrives while Python runs a finaliser or a weakref callback
        # (matplotlib's transforms have many) raises there, where Python can only report
        # and drop the exception. Raise it again a moment later, from a timer's signal,
        # where it stops the command; not from here, which is such a place too.
        if isinstance(report.exc_value, KeyboardInterrupt) and os.getpid() == main_pid:
            dropped[:] = [report.exc_value]
            signal.setitimer(signal.ITIMER_REAL, 0.01)
        else:
            hook(report)

    def again(signum: int, frame: FrameType | None) -> None:
        if dropped:
            raise dropped.pop()

    try:
        previous = signal.signal(signal.SIGTERM, handler)
    except ValueError:  # not the main thread (an embedding program's): leave it alone
        yield
        return
    alarm = signal.signal(signal.SIGALRM, again)
    hook, sys.unraisablehook = sys.unraisablehook, unraisable
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGTERM, previous)
        signal.signal(signal.SIGALRM, alarm)
        sys.unraisablehook = hook


def _error(message: str) -> None:
    click.echo(f"threadmate: error: {message}", err=True)


@contextlib.contextmanager
def _warnings_said() -> Iterator[None]:
    """threadmate's own warnings (a mesh off the spec, one turned outward) said as one line
    each on stderr, ``threadmate: warning: ...``, not as Python's source-line report."""
    shown = warnings.showwarning

    def show(
        message: Warning | str,
        category: type[Warning],
        filename: str,
        lineno: int,
        file: TextIO | None = None,
        line: str | None = None,
    ) -> None:
        if category.__module__.startswith("threadmate"):
            click.echo(f"threadmate: warning: {message}", err=True)
        else:
            shown(message, category, filename, lineno, file, line)

    warnings.showwarning = show
    try:
        yield
    finally:
        warnings.showwarning = shown


def _run(argv: list[str] | None) -> int:
    """Run the command line; the exit status, every failure said in one line."""
    try:
        with _sigterm_as_interrupt(), _watched_stdout(), _warnings_said():
            rc = cli.main(args=argv, prog_name="threadmate", standalone_mode=False)
        return rc if isinstance(rc, int) else 0
    except click.exceptions.Abort as exc:  # click's form of an interrupt
        why = " (SIGTERM)" if isinstance(exc.__cause__, _Terminated) else ""
        click.echo(f"threadmate: aborted{why}", err=True)
        return INTERRUPTED
    except click.UsageError as exc:
        # One line naming the problem (click's usage block would bury it), and where to look.
        where = exc.ctx.command_path if exc.ctx is not None else "threadmate"
        _error(f"{exc.format_message()} (see '{where} --help')")
        return 2
    except click.ClickException as exc:
        exc.show()
        return exc.exit_code
    except NoPathError as exc:
        click.echo(f"threadmate: no path: {exc}", err=True)
        return 3
    except InputError as exc:
        # The API names its parameters; the user gave options (one map, _options.FLAGS).
        from ._options import flag_words

        _error(flag_words(str(exc)))
        return 2
    except _Terminated:
        click.echo("threadmate: aborted (SIGTERM)", err=True)
        return INTERRUPTED
    except KeyboardInterrupt:
        click.echo("threadmate: interrupted", err=True)
        return INTERRUPTED
    except _StdoutError as exc:
        _drop_stdout()
        _error(f"cannot write to standard output: {exc}")
        return 2
    except OSError as exc:
        # The system refused a read or write the checks could not foresee (a disk that
        # filled, a folder removed meanwhile): the fault, in one line, not a traceback.
        where = f"{exc.filename}: " if exc.filename else ""
        _error(f"{where}{exc.strerror or exc}")
        return 2


def main(argv: list[str] | None = None) -> None:
    """Entry point: bad input and faults exit 2 with one message, no path exits 3, an
    interrupt or SIGTERM exits 130 (the temporaries removed)."""
    _register()
    if sys.stdout is None:  # started with standard output closed (>&-)
        _error("standard output is closed; redirect it to a file or to /dev/null")
        sys.exit(2)
    from ._common import new_folders

    with new_folders() as created:
        rc = _run(argv)
        if rc != 0:
            created.remove_empty()
    sys.exit(rc)
