"""Run the real ``threadmate`` entry point in-process for the CLI tests.

One calling convention: ``helper(capsys, *args)`` in a test, ``run_captured(*args)`` in a
module-scoped fixture (where no ``capsys`` exists); ``args`` are the command line after
``threadmate`` (paths and numbers are turned into text).
"""

from __future__ import annotations

import contextlib
import io
import json
from typing import Any

import pytest

from threadmate.cli import main

#: The thesis's flat parts on the command line (a designation's default is a chamfered bolt
#: in a countersunk nut): for the tests that reproduce the thesis or its numbers.
THESIS_PARTS = ("--point", "flat", "--no-countersink")


def run_cli(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    """Run ``threadmate ARGS``; return (exit status, stdout, stderr)."""
    with pytest.raises(SystemExit) as exc:
        main([str(a) for a in args])
    out, err = capsys.readouterr()
    return exc.value.code, out, err


def run_captured(*args: Any) -> tuple[int, str, str]:
    """Run ``threadmate ARGS`` outside a test's ``capsys`` (a module-scoped fixture);
    return (exit status, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        with pytest.raises(SystemExit) as exc:
            main([str(a) for a in args])
    return exc.value.code, out.getvalue(), err.getvalue()


def run_json(
    capsys: pytest.CaptureFixture[str], *args: Any, codes: tuple[int, ...] = (0,)
) -> tuple[int, dict[str, Any], str]:
    """Run ``threadmate ARGS --json``, which must exit with one of ``codes``; return (exit
    status, the one JSON document on stdout, stderr)."""
    code, out, err = run_cli(capsys, *args, "--json")
    assert code in codes, (code, err)
    return code, json.loads(out), err


def one_line(err: str) -> str:
    """The one message on stderr (checked: a single non-blank line, no traceback)."""
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


def refused(capsys: pytest.CaptureFixture[str], *args: str) -> str:
    """Run ``threadmate ARGS``, which must refuse: exit 2, nothing on stdout, one line on
    stderr and no traceback; return that line."""
    code, out, err = run_cli(capsys, *args)
    assert code == 2 and out == "", (code, out, err)
    return one_line(err)
