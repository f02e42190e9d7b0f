"""Run the real ``threadmate`` entry point in-process for the CLI tests."""

from __future__ import annotations

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


def refused(capsys: pytest.CaptureFixture[str], *args: str) -> str:
    """Run ``threadmate ARGS``, which must refuse: exit 2, nothing on stdout, one line on
    stderr and no traceback; return that line."""
    code, out, err = run_cli(capsys, *args)
    assert code == 2 and out == "", (code, out, err)
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]
