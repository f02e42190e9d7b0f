"""Exact thread geometry: standards, specs, profiles, regions, frames and meshes.

Everything here follows ``conventions.md`` (see the package documentation, "Conventions"):
lengths in the spec's ``units``, angles in degrees at every interface. A designation or a
spec takes its bolt's point, its nut's countersink and their lengths from
:func:`with_parts` (its keyword arguments held as one value: :class:`SpecParts`); the
meshes' chord from :data:`DEFAULT_CHORD` and :func:`check_chord`.
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # the names for type checkers; at run time __getattr__ imports them
    from ._body import ThreadBody, bolt_body, nut_body
    from ._chord import DEFAULT_CHORD, check_chord
    from ._designation import (
        MATERIAL_CONDITIONS,
        Designation,
        ThreadLimits,
        material_condition,
        parse_designation,
        spec_from_designation,
        thread_limits,
    )
    from ._ends import POINT_FORMS, BoltPoint, Countersink, Envelope
    from ._frames import Pose, axis_angle_rotation, bolt_rotation, rot_x, rot_y, rot_z
    from ._mesh import TessellatedBody, bolt_mesh, mesh_deviation, nut_mesh, thread_meshes
    from ._meshio import load_mesh, read_stl, stl_header, stl_units, write_stl
    from ._nuts import countersink_limits, standard_countersink_diameter, standard_nut_height
    from ._parts import SpecParts, with_parts
    from ._profile import BOLT_REGIONS, NUT_REGIONS, Profile, bolt_profile, nut_profile, wrap_t
    from ._spec import UNITS, BoltSpec, NutSpec, ThreadSpec, load_spec, parse_length, save_spec

__all__ = [
    "BOLT_REGIONS",
    "DEFAULT_CHORD",
    "Envelope",
    "MATERIAL_CONDITIONS",
    "NUT_REGIONS",
    "POINT_FORMS",
    "UNITS",
    "BoltPoint",
    "BoltSpec",
    "Countersink",
    "Designation",
    "NutSpec",
    "Pose",
    "SpecParts",
    "Profile",
    "TessellatedBody",
    "ThreadBody",
    "ThreadLimits",
    "ThreadSpec",
    "axis_angle_rotation",
    "bolt_body",
    "bolt_mesh",
    "check_chord",
    "countersink_limits",
    "bolt_profile",
    "bolt_rotation",
    "load_mesh",
    "load_spec",
    "mesh_deviation",
    "nut_body",
    "nut_mesh",
    "nut_profile",
    "parse_length",
    "material_condition",
    "parse_designation",
    "rot_x",
    "rot_y",
    "rot_z",
    "read_stl",
    "save_spec",
    "spec_from_designation",
    "standard_countersink_diameter",
    "standard_nut_height",
    "stl_header",
    "stl_units",
    "thread_limits",
    "thread_meshes",
    "with_parts",
    "wrap_t",
    "write_stl",
]

#: The submodule of each public name, imported when the name is first used (PEP 562):
#: importing the package loads none of them, so that a command that does not need
#: a stage's heavy dependencies (scipy, trimesh, fcl, pandas, matplotlib) never
#: imports them. tests/test_cli_contract.py checks it against the imports above.
_SOURCES = {
    "._body": ("ThreadBody", "bolt_body", "nut_body"),
    # The chord's default and check, light to import: the commands quote and check them
    # before any mesh is built.
    "._chord": ("DEFAULT_CHORD", "check_chord"),
    "._designation": (
        "MATERIAL_CONDITIONS",
        "Designation",
        "ThreadLimits",
        "material_condition",
        "parse_designation",
        "spec_from_designation",
        "thread_limits",
    ),
    "._ends": ("POINT_FORMS", "BoltPoint", "Countersink", "Envelope"),
    "._frames": ("Pose", "axis_angle_rotation", "bolt_rotation", "rot_x", "rot_y", "rot_z"),
    "._mesh": ("TessellatedBody", "bolt_mesh", "mesh_deviation", "nut_mesh", "thread_meshes"),
    "._meshio": ("load_mesh", "read_stl", "stl_header", "stl_units", "write_stl"),
    "._nuts": ("countersink_limits", "standard_countersink_diameter", "standard_nut_height"),
    "._parts": ("SpecParts", "with_parts"),
    "._profile": (
        "BOLT_REGIONS",
        "NUT_REGIONS",
        "Profile",
        "bolt_profile",
        "nut_profile",
        "wrap_t",
    ),
    "._spec": (
        "UNITS",
        "BoltSpec",
        "NutSpec",
        "ThreadSpec",
        "load_spec",
        "parse_length",
        "save_spec",
    ),
}
#: Public names that differ from their submodule's.
_ALIASES: dict[str, str] = {}
_WHERE = {name: module for module, names in _SOURCES.items() for name in names}


__getattr__, __dir__ = lazy_exports(__name__, globals(), _WHERE, _ALIASES)
