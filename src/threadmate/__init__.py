"""threadmate: contact analysis and path planning for threaded fastener insertion.

Stages, each a subpackage, data flowing one way::

    geometry -> planar / contact -> library -> network

and ``threadmate.cli``, a thin command-line layer over them.
"""

from ._errors import (
    DesignationError,
    InputError,
    LibraryError,
    MeshError,
    NoPathError,
    SpecError,
    ThreadmateError,
)
from ._version import __version__

__all__ = [
    "DesignationError",
    "InputError",
    "LibraryError",
    "MeshError",
    "NoPathError",
    "SpecError",
    "ThreadmateError",
    "__version__",
]
