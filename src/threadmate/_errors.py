"""Exception hierarchy shared by every stage.

The command line maps :class:`InputError` to exit status 2 and :class:`NoPathError` to
exit status 3; anything else is a bug and keeps its traceback.
"""

from __future__ import annotations

__all__ = [
    "ThreadmateError",
    "InputError",
    "DesignationError",
    "SpecError",
    "MeshError",
    "LibraryError",
    "NoPathError",
]


class ThreadmateError(Exception):
    """Base class of every error threadmate raises on purpose."""


class InputError(ThreadmateError, ValueError):
    """Bad input from the user: a designation, spec, mesh, angle, file or library."""


class DesignationError(InputError):
    """A thread designation that is malformed or names no standard size."""


class SpecError(InputError):
    """An invalid thread spec; the message names the offending key."""


class MeshError(InputError):
    """A mesh that is not a closed, consistently wound volume of plausible size."""


class LibraryError(InputError):
    """A path that is not a contact-state library, or one that disagrees with a request."""


class NoPathError(ThreadmateError):
    """No path from a start state reaches the in-phase snap."""
