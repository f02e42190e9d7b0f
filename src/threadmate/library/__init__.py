"""The contact-state library: every configuration of a roll/pitch/phase grid, on disk.

The thesis's chapter 4 swept roll and pitch from -4 to +4 deg by 1 and phase over a turn by
5 deg (5,832 configurations). :func:`sweep` runs the contact stages
(:mod:`threadmate.contact`) over any grid, in a local process pool (one analyser, meshes
and BVHs included, per worker) or on Dask, and writes the rows in chunks as a Parquet
dataset directory that describes itself (spec, grid, mesh and contact settings, units,
version). An interrupted sweep resumes where it stopped; a library of another request is
refused, never mixed.

Configurations are numbered roll-major, phase fastest:
``config_id = (i_roll * n_pitch + i_pitch) * n_phase + i_phase``. A polar grid of
misalignment (:class:`PolarGrid`: ``sweep(spec, tilt="0:4:0.5", direction="0:360:22.5")``)
holds tilts by size and by the direction toward which the bolt leans, and numbers them
``config_id = i_held * n_phase + i_phase``; its rows carry the held roll and pitch as a
square grid's do. Angles are degrees,
lengths the spec's units, poses per conventions.md.

Example
-------
>>> from threadmate.geometry import spec_from_designation
>>> from threadmate import library
>>> spec = spec_from_designation("1/4-20 UNC-2A/2B")
>>> path = library.sweep(spec, out="lib-1-4-20")                      # doctest: +SKIP
>>> df = library.load(path)                                            # doctest: +SKIP
>>> library.summary(path)["counts"]                                    # doctest: +SKIP

The directory also reads directly: ``pandas.read_parquet("lib-1-4-20")``,
``pyarrow.dataset.dataset("lib-1-4-20")`` or DuckDB's
``SELECT * FROM read_parquet('lib-1-4-20/*.parquet')``.
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from ._grid import (
        DEFAULT_GRID as DEFAULT_GRID,
        DEFAULT_POLAR_RANGES as DEFAULT_POLAR_RANGES,
        DEFAULT_RANGES as DEFAULT_RANGES,
        DIRECTION_DEFINITION as DIRECTION_DEFINITION,
        MAX_TILT as MAX_TILT,
        AnyGrid as AnyGrid,
        Grid as Grid,
        PolarGrid as PolarGrid,
        make_grid as make_grid,
        parse_range as parse_range,
        read_grid as read_grid,
    )
    from ._models import MODELS as MODELS
    from ._probes import HeldTiltProbe as HeldTiltProbe
    from ._store import (
        METADATA_FILE as METADATA_FILE,
        compare_metadata as compare_metadata,
        configurations as configurations,
        info as info,
        library_schema as library_schema,
        load as load,
        lock_holder as lock_holder,
        progress as progress,
        query as query,
    )
    from ._summary import (
        CLASS_ORDER as CLASS_ORDER,
        plot_phase_strips as plot_phase_strips,
        plot_region_combinations as plot_region_combinations,
        plot_stability_map as plot_stability_map,
        summary as summary,
        write_figures as write_figures,
    )
    from ._sweep import (
        ProgressCallback as ProgressCallback,
        SweepInterrupted as SweepInterrupted,
        sweep as sweep,
        write_library as write_library,
    )


#: The submodule of each public name, imported when the name is first used (PEP 562):
#: importing the package loads none of them, so that a command that does not need
#: a stage's heavy dependencies (scipy, trimesh, numba, pandas, matplotlib) never
#: imports them; __all__ is made from it. tests/test_cli_contract.py checks it against
#: the re-exports above.
_SOURCES = {
    "._grid": (
        "DEFAULT_GRID",
        "DEFAULT_POLAR_RANGES",
        "DEFAULT_RANGES",
        "DIRECTION_DEFINITION",
        "MAX_TILT",
        "AnyGrid",
        "Grid",
        "PolarGrid",
        "make_grid",
        "parse_range",
        "read_grid",
    ),
    # The models, light to import: the commands offer them before the stage loads.
    "._models": ("MODELS",),
    "._probes": ("HeldTiltProbe",),
    "._store": (
        "METADATA_FILE",
        "compare_metadata",
        "configurations",
        "info",
        "library_schema",
        "load",
        "lock_holder",
        "progress",
        "query",
    ),
    "._summary": (
        "CLASS_ORDER",
        "plot_phase_strips",
        "plot_region_combinations",
        "plot_stability_map",
        "summary",
        "write_figures",
    ),
    "._sweep": ("ProgressCallback", "SweepInterrupted", "sweep", "write_library"),
}


__getattr__, __dir__, __all__ = lazy_exports(__name__, globals(), _SOURCES)
