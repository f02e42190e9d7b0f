"""The library's metadata document: what a sweep's request writes, and its check.

A new library starts with the request's metadata (format, version, model, units, spec,
grid, mesh, compliance and continuation settings, a ``library_id`` every part carries); a
resumed one must hold the same request, or it is refused, never mixed. The first finished
chunk adds what the workers actually used (mesh deviation, tolerances, how CAD meshes fit
the spec).
"""

from __future__ import annotations

import datetime as _dt
import uuid
from pathlib import Path
from typing import Any

from .._errors import LibraryError
from .._io import remove_stale_temporaries
from .._version import __version__
from ..contact import (
    JOIN_DISTANCE,
    JOIN_TILT,
    PROOF_FOLD_TOLERANCE,
    PROOF_TURN_LIMIT,
    SCREW_IN,
    TIGHTEN_STEP,
)
from ._held_tilt import MAX_FOLLOW_TURNS
from ._store import (
    FORMAT,
    FORMAT_VERSION,
    METADATA_FILE,
    compare_metadata,
    read_metadata,
    write_metadata,
)
from ._workers import Job, MeshFile, describe_analyzer

__all__ = ["open_library", "record_settings", "request_metadata"]


def request_metadata(job: Job) -> dict[str, Any]:
    """The metadata document of ``job``'s request; what the workers use (mesh deviation,
    tolerances) stays None until the first chunk reports it."""
    meta: dict[str, Any] = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "threadmate_version": __version__,
        "model": job.model,
        "units": job.spec.units,
        "angles": "degrees",
        "conventions": "conventions.md: x_F = Rx(roll) Ry(pitch) Rz(phase) x_B + origin",
        "spec": job.spec.to_dict(),
        "grid": job.grid.to_dict(),
        "mesh": {
            "chord": job.chord,
            "max_deviation": None,
            "bolt": _mesh_metadata(job.bolt_mesh),
            "nut": _mesh_metadata(job.nut_mesh),
        },
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        # Every part carries this id in its schema: a part of another library is told.
        "library_id": uuid.uuid4().hex,
    }
    if job.model == "mechanics":
        meta["compliance"] = job.compliance.to_dict()
        meta["continuation"] = {
            "step": job.step,
            "phase_tolerance": job.phase_tolerance,
            "screw_in": SCREW_IN,
            "proof_turn_limit": PROOF_TURN_LIMIT,
            "proof_fold_tolerance": PROOF_FOLD_TOLERANCE,
            "tighten_step": TIGHTEN_STEP,
            "clockwise": job.clockwise,
            "max_turns": MAX_FOLLOW_TURNS,
            "join_tilt": JOIN_TILT,
            "join_distance_pitches": JOIN_DISTANCE,
            "units": "degrees; turns; pitches",
        }
        meta["contact"] = {"tolerances": None}
        meta["columns"] = (
            "one row per contact state: threadmate.contact.STATE_COLUMNS (docs/architecture.md)"
        )
    else:
        meta["compliance"] = {"compliance_z": job.compliance.compliance_z}
        meta["contact"] = {
            "compliance_z": job.compliance.compliance_z,
            "tolerances": None,
            "analyzer": describe_analyzer(job.analyzer),
        }
        meta["columns"] = "config_id, the contact record of docs/architecture.md, error"
    return meta


def _mesh_metadata(mesh: MeshFile | None) -> dict[str, Any] | None:
    """A CAD mesh in the metadata: file name, SHA-256 and units (None: generated); its
    deviation and off-spec shares are added from the first finished chunk."""
    if mesh is None:
        return None
    return {"file": Path(mesh.path).name, "sha256": mesh.sha256, "units": mesh.units}


def open_library(out: Path, job: Job) -> dict[str, Any]:
    """Create the library directory, or check that an existing one holds this request."""
    wanted = request_metadata(job)
    if out.exists() and not out.is_dir():
        raise LibraryError(f"{out} exists and is not a directory: give a library directory")
    if out.is_dir() and (out / METADATA_FILE).exists():
        meta = read_metadata(out)
        diff = compare_metadata(meta, wanted)
        if diff:
            raise LibraryError(
                f"{out} holds a different sweep; refusing to mix it with this "
                f"request. It differs in: {'; '.join(diff)}. Use another "
                "output directory."
            )
        remove_stale_temporaries(out)
        return meta
    if out.is_dir() and any(not p.name.startswith(".") for p in out.iterdir()):
        raise LibraryError(
            f"{out} exists, is not empty and is not a threadmate library: "
            "give a new or empty directory"
        )
    try:
        write_metadata(out, wanted)
    except OSError as exc:
        raise LibraryError(f"cannot create the library at {out}: {exc.strerror or exc}") from None
    return wanted


def record_settings(meta: dict[str, Any], settings: dict[str, Any], chord: float) -> bool:
    """Add to ``meta``, in place, the settings the workers' models actually used (from a
    finished chunk: chord, mesh deviation, tolerances, how CAD meshes follow the spec).

    Returns
    -------
    bool
        Whether ``meta`` was filled (and must be written): False once a chunk's settings
        are recorded.
    """
    if meta["mesh"].get("max_deviation") is not None:
        return False
    meta["mesh"].update(chord=settings["chord"] or chord, max_deviation=settings["max_deviation"])
    meshes = settings.get("meshes") or {}
    for kind in ("bolt", "nut"):
        if isinstance(meta["mesh"].get(kind), dict) and meshes.get(kind):
            # How the CAD mesh follows the spec (deviation, off-spec shares).
            extra = {k: v for k, v in meshes[kind].items() if k != "path"}
            meta["mesh"][kind] = {**extra, **meta["mesh"][kind]}
    if meshes.get("off_spec_tolerance") is not None:
        meta["mesh"]["off_spec_tolerance"] = meshes["off_spec_tolerance"]
    meta["contact"]["tolerances"] = settings["tolerances"]
    return True
