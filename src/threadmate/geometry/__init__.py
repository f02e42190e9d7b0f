"""Exact thread geometry: standards, specs, profiles, regions, frames and meshes.

Everything here follows ``conventions.md`` (see the package documentation, "Conventions"):
lengths in the spec's ``units``, angles in degrees at every interface. A designation or a
spec takes its bolt's point, its nut's countersink and their lengths from
:func:`with_parts` (its keyword arguments held as one value: :class:`SpecParts`); the
meshes' chord from :data:`DEFAULT_CHORD` and :func:`check_chord`.
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from ._body import ThreadBody as ThreadBody, bolt_body as bolt_body, nut_body as nut_body
    from ._chord import DEFAULT_CHORD as DEFAULT_CHORD, check_chord as check_chord
    from ._designation import (
        MATERIAL_CONDITIONS as MATERIAL_CONDITIONS,
        Designation as Designation,
        ThreadLimits as ThreadLimits,
        material_condition as material_condition,
        parse_designation as parse_designation,
        spec_from_designation as spec_from_designation,
        thread_limits as thread_limits,
    )
    from ._ends import (
        POINT_FORMS as POINT_FORMS,
        BoltPoint as BoltPoint,
        Countersink as Countersink,
        Envelope as Envelope,
    )
    from ._frames import (
        Pose as Pose,
        axis_angle_rotation as axis_angle_rotation,
        bolt_rotation as bolt_rotation,
        held_tilt_from_polar as held_tilt_from_polar,
        polar_from_held_tilt as polar_from_held_tilt,
        rot_x as rot_x,
        rot_y as rot_y,
        rot_z as rot_z,
    )
    from ._mesh import (
        TessellatedBody as TessellatedBody,
        bolt_mesh as bolt_mesh,
        mesh_deviation as mesh_deviation,
        nut_mesh as nut_mesh,
        thread_meshes as thread_meshes,
    )
    from ._meshio import (
        load_mesh as load_mesh,
        read_stl as read_stl,
        stl_header as stl_header,
        stl_units as stl_units,
        write_stl as write_stl,
    )
    from ._nuts import (
        countersink_limits as countersink_limits,
        standard_countersink_diameter as standard_countersink_diameter,
        standard_nut_height as standard_nut_height,
    )
    from ._parts import SpecParts as SpecParts, with_parts as with_parts
    from ._profile import (
        BOLT_REGIONS as BOLT_REGIONS,
        NUT_REGIONS as NUT_REGIONS,
        Profile as Profile,
        bolt_profile as bolt_profile,
        nut_profile as nut_profile,
        wrap_t as wrap_t,
    )
    from ._spec import (
        UNITS as UNITS,
        BoltSpec as BoltSpec,
        NutSpec as NutSpec,
        ThreadSpec as ThreadSpec,
        load_spec as load_spec,
        parse_length as parse_length,
        save_spec as save_spec,
    )


#: The submodule of each public name, imported when the name is first used (PEP 562):
#: importing the package loads none of them, so that a command that does not need
#: a stage's heavy dependencies (scipy, trimesh, numba, pandas, matplotlib) never
#: imports them; __all__ is made from it. tests/test_cli_contract.py checks it against
#: the re-exports above.
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
    "._frames": (
        "Pose",
        "axis_angle_rotation",
        "bolt_rotation",
        "held_tilt_from_polar",
        "polar_from_held_tilt",
        "rot_x",
        "rot_y",
        "rot_z",
    ),
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


__getattr__, __dir__, __all__ = lazy_exports(__name__, globals(), _SOURCES)
