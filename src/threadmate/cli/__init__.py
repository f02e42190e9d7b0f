"""The ``threadmate`` command line: a thin layer over the Python API."""

from ._main import cli, main

__all__ = ["cli", "main"]
