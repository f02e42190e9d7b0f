"""The ``threadmate`` command group and its error handling."""

from __future__ import annotations

import sys

import click

from .._errors import InputError, NoPathError
from .._version import __version__

__all__ = ["cli", "main"]


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="threadmate")
def cli() -> None:
    """threadmate: contact analysis and path planning for threaded fastener insertion.

    Lengths are in the spec's units (in or mm); angles are degrees everywhere.
    """


def _register() -> None:
    # Each command lives in its own module and registers itself on import.
    from . import _thread  # noqa: F401, I001  (registers: thread)
    from . import _planar  # noqa: F401  (registers: planar)
    from . import _contact  # noqa: F401  (registers: contact)
    from . import _mechanics  # noqa: F401  (registers: settle, search, screw)
    from . import _library  # noqa: F401  (registers: sweep, library)
    from . import _mesh  # noqa: F401  (registers: mesh)
    from . import _network  # noqa: F401  (registers: network, path, recommend)
    from . import _run  # noqa: F401  (registers: run)


def main(argv: list[str] | None = None) -> None:
    """Entry point: bad input exits 2 with one message, no path exits 3."""
    _register()
    try:
        rc = cli.main(args=argv, prog_name="threadmate", standalone_mode=False)
    except click.exceptions.Abort:
        click.echo("threadmate: aborted", err=True)
        sys.exit(130)
    except click.UsageError as exc:
        # One line naming the problem (click's usage block would bury it), and where to look.
        where = exc.ctx.command_path if exc.ctx is not None else "threadmate"
        click.echo(f"threadmate: error: {exc.format_message()} (see '{where} --help')", err=True)
        sys.exit(2)
    except click.ClickException as exc:
        exc.show()
        sys.exit(exc.exit_code)
    except NoPathError as exc:
        click.echo(f"threadmate: no path: {exc}", err=True)
        sys.exit(3)
    except InputError as exc:
        click.echo(f"threadmate: error: {exc}", err=True)
        sys.exit(2)
    except KeyboardInterrupt:
        click.echo("threadmate: interrupted", err=True)
        sys.exit(130)
    sys.exit(rc if isinstance(rc, int) else 0)
