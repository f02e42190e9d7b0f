"""Interactive pages: a search and a run, each one self-contained HTML file.

A page holds plotly.js, its data and its script inline, so that it opens in a browser
with no network. :func:`write_search_page` draws a search (``threadmate search --json``'s
document): the bolt on the nut at every state of the turn under a slider, the contacts
and their forces, and the compliance centre's height, the tilt and the driver's torque
against phase with the events marked. :func:`write_run_page` draws a run's report
(``threadmate run``) with interactive figures, each start linked to its search's page;
:func:`write_start_page` computes and writes that page for one start. Lengths in the
spec's units, angles in degrees, forces in N, torques in N m; scenes in the nut's frame F
(conventions.md).
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from ._display import (
        DisplayMesh as DisplayMesh,
        decimate as decimate,
        display_meshes as display_meshes,
    )
    from ._run_page import (
        start_page_name as start_page_name,
        write_run_page as write_run_page,
        write_start_page as write_start_page,
        write_start_views as write_start_views,
    )
    from ._search_page import (
        ARROW_PITCHES as ARROW_PITCHES,
        read_search_document as read_search_document,
        search_page as search_page,
        search_view_data as search_view_data,
        write_search_page as write_search_page,
    )


#: The submodule of each public name, imported when the name is first used (PEP 562):
#: importing the package loads none of them; __all__ is made from it.
#: tests/test_cli_contract.py checks it against the re-exports above.
_SOURCES = {
    "._display": ("DisplayMesh", "decimate", "display_meshes"),
    "._run_page": (
        "start_page_name",
        "write_run_page",
        "write_start_page",
        "write_start_views",
    ),
    "._search_page": (
        "ARROW_PITCHES",
        "read_search_document",
        "search_page",
        "search_view_data",
        "write_search_page",
    ),
}


__getattr__, __dir__, __all__ = lazy_exports(__name__, globals(), _SOURCES)
