"""Exact thread geometry: standards, specs, profiles, regions, frames and meshes.

Everything here follows ``conventions.md`` (see the package documentation, "Conventions"):
lengths in the spec's ``units``, angles in degrees at every interface.
"""

from ._body import ThreadBody, bolt_body, nut_body
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
from ._mesh import (
    DEFAULT_CHORD,
    TessellatedBody,
    bolt_mesh,
    check_chord,
    mesh_deviation,
    nut_mesh,
    thread_meshes,
)
from ._meshio import load_mesh, read_stl, stl_header, stl_units, write_stl
from ._nuts import countersink_limits, standard_countersink_diameter, standard_nut_height
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
    "wrap_t",
    "write_stl",
]
