"""Contacts of a bolt on its nut: the mechanics of the held bolt, and the thesis's stages.

Two models live here.

**The mechanics** (docs/mechanics.md; :mod:`.mechanics`). The bolt is
held through a compliance (:class:`Compliance`: axial force, rotational stiffness about
the compliance centre, optional lateral stiffness, friction). A *rest state* is a local
minimum of the potential ``F z_C + k/2 |tilt - held tilt|^2`` over the poses where bolt
and nut do not interpenetrate; :func:`settle` finds the one reached from first contact
by an active-set descent (the thesis's stages completed by its rolling pivot), with the
contact forces, the driver's torque and the unstable states passed on the way.
:func:`search` simulates the counter-clockwise search: a quasi-static continuation in
phase, its contact changes, jumps and the snap into the thread, with the driver's work.
Classes: ``stable`` (the contacts alone hold the load), ``quasi-stable`` (a rest state
that needs the compliance), ``unstable`` (not a rest state), ``in-phase`` (engaged: every
load-carrying contact lies on the helices). A snap is a jump into the in-phase state
proved by screwing in: from it a clockwise continuation descends at the lead
(:class:`Engagement`). :func:`screw` turns a start clockwise directly: ``engaged``,
``riding`` or ``jammed`` (the thesis's clockwise question); :class:`ClockwiseStarts` turns
a held tilt's starts so, their walks shared where they meet. A continuation's settings have
their defaults, ranges and checks in :mod:`.mechanics` (:data:`CONTINUATION_STEP`,
:func:`check_continuation`, :func:`check_screw`); :func:`plot_search` and
:func:`plot_screw` draw a turn's signature (height, tilt and torque against phase).

**The thesis's fixed-pivot procedure** (:mod:`.thesis`: :class:`ContactAnalyzer`,
:func:`analyze`; its chapter 3 and section 4.2). The bolt, at a fixed tilt, comes down
until it first touches (*first*), turns about the nut's tangent there until a second
contact (*second*), then about the pivot axis through the two until a third (*third*);
the compliance is ignored.
Classified by the thesis's own criteria: ``quasi-stable`` when the pivot axis passes
within pitch/10 of the compliance centre, ``unstable`` when the third contact needed an
embedding deeper than the origin's drop (and than the mesh noise), ``stable`` otherwise;
``rolling`` marks a pivot contact whose triangle pairs grew during the third turn.

The record contract (:mod:`._records`) declares once the columns of both kinds of row
that leave this package: a *state record* of the mechanics (a contact state and the one
passive transition that leaves it: settling, turning, jump or snap) and the thesis's
configuration record.

Both stand on one :class:`ContactScene` (:mod:`.scene`): collision queries of the
meshes, contact location from triangle pairs and exact vertical touches, and the exact
bodies for regions, normals and edge contact points. Lengths are in the spec's
units, angles in degrees, forces in N, torques in N m, energies in mJ.

Example
-------
>>> from threadmate.geometry import spec_from_designation
>>> from threadmate.contact import Compliance, search, settle
>>> spec = spec_from_designation("1/4-20 UNC-2A/2B")
>>> rest = settle(spec, 4, 0, 185, compliance=Compliance(force=10))  # doctest: +SKIP
>>> rest.classification, rest.state.roll                           # doctest: +SKIP
>>> run = search(spec, 4, 0, 185)                                   # doctest: +SKIP
>>> run.snap.phase, run.snap.click, run.work                         # doctest: +SKIP
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:  # re-exported for type checkers; at run time __getattr__ imports them
    from .._validate import MAX_TILT as MAX_TILT
    from ._records import (
        ROLES as ROLES,
        STATE_COLUMNS as STATE_COLUMNS,
        TRANSITIONS as TRANSITIONS,
        Column as Column,
        blank_row as blank_row,
        state_id as state_id,
        state_row as state_row,
        state_schema as state_schema,
        thesis_schema as thesis_schema,
    )
    from .mechanics import (
        BALANCE as BALANCE,
        CLICK_SPAN as CLICK_SPAN,
        COMPLIANCE_LIMITS as COMPLIANCE_LIMITS,
        CONTINUATION_STEP as CONTINUATION_STEP,
        JOIN_DISTANCE as JOIN_DISTANCE,
        JOIN_TILT as JOIN_TILT,
        LEAD_TOLERANCE as LEAD_TOLERANCE,
        MAX_SCREW_IN as MAX_SCREW_IN,
        MAX_STEP as MAX_STEP,
        MAX_STEPS as MAX_STEPS,
        MAX_TURNS as MAX_TURNS,
        PHASE_TOLERANCE as PHASE_TOLERANCE,
        PROOF_FOLD_TOLERANCE as PROOF_FOLD_TOLERANCE,
        PROOF_TURN_LIMIT as PROOF_TURN_LIMIT,
        SCREW_IN as SCREW_IN,
        SCREW_OUTCOMES as SCREW_OUTCOMES,
        TIGHTEN_STEP as TIGHTEN_STEP,
        ClockwiseStarts as ClockwiseStarts,
        Compliance as Compliance,
        Continuation as Continuation,
        Engagement as Engagement,
        Leg as Leg,
        LoadedContact as LoadedContact,
        MechanicalState as MechanicalState,
        Mechanics as Mechanics,
        RestState as RestState,
        ScrewResult as ScrewResult,
        SearchEvent as SearchEvent,
        SearchResult as SearchResult,
        check_continuation as check_continuation,
        check_screw as check_screw,
        default_torque_limit as default_torque_limit,
        plot_screw as plot_screw,
        plot_search as plot_search,
        same_pose as same_pose,
        screw as screw,
        search as search,
        sensor_click as sensor_click,
        settle as settle,
    )
    from .scene import (
        CLASSIFICATIONS as CLASSIFICATIONS,
        ERROR_CLASS as ERROR_CLASS,
        IN_PHASE as IN_PHASE,
        NO_CONTACT as NO_CONTACT,
        OFF_SPEC_REGIONS as OFF_SPEC_REGIONS,
        QUASI_STABLE as QUASI_STABLE,
        REST_CLASSES as REST_CLASSES,
        STABLE as STABLE,
        TRANSITION_LABELS as TRANSITION_LABELS,
        TRAVEL_TOLERANCE as TRAVEL_TOLERANCE,
        UNSTABLE as UNSTABLE,
        ContactScene as ContactScene,
        check_mesh_file as check_mesh_file,
        contact_scene as contact_scene,
        engagement_outline as engagement_outline,
        off_spec_region as off_spec_region,
        region_at as region_at,
        warm_kernels as warm_kernels,
        warm_kernels_aside as warm_kernels_aside,
    )
    from .thesis import (
        STAGES as STAGES,
        Contact as Contact,
        ContactAnalyzer as ContactAnalyzer,
        ContactResult as ContactResult,
        StageResult as StageResult,
        analyze as analyze,
        record_schema as record_schema,
    )


#: The submodule of each public name, imported when the name is first used (PEP 562):
#: importing the package loads none of them, so that a command that does not need
#: a stage's heavy dependencies (scipy, trimesh, numba, pandas, matplotlib) never
#: imports them; __all__ is made from it. tests/test_cli_contract.py checks it against
#: the re-exports above.
_SOURCES = {
    # The tilt limit is a validation rule (threadmate._validate), light to import: the
    # commands check --roll and --pitch with it before anything is built.
    ".._validate": ("MAX_TILT",),
    ".scene": (
        "TRAVEL_TOLERANCE",
        "ContactScene",
        "check_mesh_file",
        "contact_scene",
        "CLASSIFICATIONS",
        "ERROR_CLASS",
        "IN_PHASE",
        "NO_CONTACT",
        "QUASI_STABLE",
        "REST_CLASSES",
        "STABLE",
        "TRANSITION_LABELS",
        "UNSTABLE",
        "OFF_SPEC_REGIONS",
        "engagement_outline",
        "off_spec_region",
        "region_at",
        "warm_kernels",
        "warm_kernels_aside",
    ),
    ".thesis": (
        "ContactAnalyzer",
        "analyze",
        "STAGES",
        "Contact",
        "ContactResult",
        "StageResult",
        "record_schema",
    ),
    # The mechanics; its continuation settings and their checks are light to import (the
    # commands quote and check them before anything is built).
    ".mechanics": (
        "COMPLIANCE_LIMITS",
        "Compliance",
        "LEAD_TOLERANCE",
        "Engagement",
        "LoadedContact",
        "MechanicalState",
        "RestState",
        "SearchEvent",
        "SearchResult",
        "SCREW_OUTCOMES",
        "ScrewResult",
        "screw",
        "ClockwiseStarts",
        "plot_screw",
        "plot_search",
        "CLICK_SPAN",
        "Continuation",
        "Leg",
        "default_torque_limit",
        "same_pose",
        "search",
        "sensor_click",
        "CONTINUATION_STEP",
        "JOIN_DISTANCE",
        "JOIN_TILT",
        "MAX_SCREW_IN",
        "MAX_STEP",
        "MAX_TURNS",
        "PHASE_TOLERANCE",
        "PROOF_FOLD_TOLERANCE",
        "PROOF_TURN_LIMIT",
        "SCREW_IN",
        "TIGHTEN_STEP",
        "check_continuation",
        "check_screw",
        "BALANCE",
        "MAX_STEPS",
        "Mechanics",
        "settle",
    ),
    "._records": (
        "ROLES",
        "STATE_COLUMNS",
        "TRANSITIONS",
        "Column",
        "blank_row",
        "state_id",
        "state_row",
        "state_schema",
        "thesis_schema",
    ),
}


__getattr__, __dir__, __all__ = lazy_exports(__name__, globals(), _SOURCES)
