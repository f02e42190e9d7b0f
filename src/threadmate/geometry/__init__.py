"""Exact thread geometry: standards, specs, profiles, regions, frames and meshes.

Everything here follows ``conventions.md`` (see the package documentation, "Conventions"):
lengths in the spec's ``units``, angles in degrees at every interface.
"""

from ._body import ThreadBody, bolt_body, nut_body
from ._frames import Pose, axis_angle_rotation, bolt_rotation, rot_x, rot_y, rot_z
from ._profile import BOLT_REGIONS, NUT_REGIONS, Profile, bolt_profile, nut_profile, wrap_t
from ._spec import UNITS, BoltSpec, NutSpec, ThreadSpec, load_spec, save_spec

__all__ = [
    "BOLT_REGIONS",
    "NUT_REGIONS",
    "UNITS",
    "BoltSpec",
    "NutSpec",
    "Pose",
    "Profile",
    "ThreadBody",
    "ThreadSpec",
    "axis_angle_rotation",
    "bolt_body",
    "bolt_profile",
    "bolt_rotation",
    "load_spec",
    "nut_body",
    "nut_profile",
    "rot_x",
    "rot_y",
    "rot_z",
    "save_spec",
    "wrap_t",
]
