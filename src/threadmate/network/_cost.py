"""Resistance of a transition between contact states: the edge weight.

An edge ``u -> v`` of the network costs the energy the insertion system spends to take the
bolt from state ``u`` to state ``v``, in millijoules (mJ = N mm), whatever the spec's
length unit (lengths in inches are converted at 25.4 mm/in)::

    weight = F * max(0, z_v - z_u)                     work against the axial load
           + (k / 2) * dtheta**2                       elastic energy in the compliance
           + mu * F * r_u * dphi                       friction work of turning
           + P * [v is unstable]                       penalty for entering an unstable state

with

- ``F`` the axial load [N] acting along -Z through the compliance centre;
- ``z`` the resting height of the compliance centre in a state (the bolt origin at the
  last contact stage reached, plus ``compliance_z`` along the bolt axis) [mm];
- ``k`` the rotational stiffness of the compliance [N m/rad, x 1000 to N mm/rad];
- ``dtheta`` the change of the bolt's resting tilt between the states [rad]: the length of
  the change of (final roll, final pitch), each taken as the held roll and pitch where the
  contact stages give none;
- ``mu`` the friction coefficient between the threads, ``r_u`` the mean distance of the
  source state's contacts from the nut axis [mm], ``dphi`` the phase turned [rad] (turning
  edges only; settling edges turn nothing);
- ``P`` the penalty [mJ] charged on every edge whose label is ``unstable``; by default the
  work of lifting the axial load through one thread pitch (``F * pitch``), the energy of
  backing the bolt out of a cross-threaded engagement.

Every term is non-negative, so every weight is; :func:`edge_costs` asserts it.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._errors import InputError

__all__ = [
    "COST_UNITS",
    "MM_PER_UNIT",
    "WEIGHT_FORMULA",
    "ResistanceParams",
    "edge_costs",
    "variant_weight",
]

#: Unit of every cost (edge weights, path costs, recommendation figures).
COST_UNITS = "mJ"
#: Millimetres per spec length unit.
MM_PER_UNIT = {"mm": 1.0, "in": 25.4}
#: The weight formula in one line (stored in the graph's metadata).
WEIGHT_FORMULA = (
    "weight [mJ] = F*max(0, z_v - z_u) + (k/2)*dtheta^2 + mu*F*r_u*dphi (turning) "
    "+ P*[label unstable]; F axial force [N], z compliance-centre resting height [mm], "
    "k rotational stiffness [N mm/rad], dtheta resting tilt change [rad], mu friction "
    "coefficient, r_u contact radius [mm], dphi phase turned [rad], P unstable penalty [mJ]"
)


@dataclass(frozen=True)
class ResistanceParams:
    """Physical parameters of the edge weight (see the module docstring for the formula).

    Attributes
    ----------
    axial_force : float
        Axial load on the bolt through the compliance centre, newtons (default 10 N: a
        light insertion load, within the 5-20 N that passive-compliance insertion of small
        fasteners uses; 1 lbf = 4.448 N).
    rotational_stiffness : float
        Rotational (tilt) stiffness of the compliance, N m/rad (default 1 N m/rad, the
        order of a small commercial remote-centre-compliance device).
    friction : float
        Coefficient of friction between the threads (default 0.15, dry steel on steel
        with a light oil, the middle of ISO 16047's usual 0.10-0.20 range).
    unstable_penalty : float or None
        Penalty, in mJ, for every transition into an unstable state; None (default) takes
        the work of lifting the axial load through one pitch, ``axial_force * pitch``.
    """

    axial_force: float = 10.0
    rotational_stiffness: float = 1.0
    friction: float = 0.15
    unstable_penalty: float | None = None

    def __post_init__(self) -> None:
        checks = (("axial_force", self.axial_force, False),
                  ("rotational_stiffness", self.rotational_stiffness, True),
                  ("friction", self.friction, True))
        for name, value, zero_ok in checks:
            if isinstance(value, bool) or not isinstance(value, int | float | np.number) \
                    or not math.isfinite(value) or value < 0 or (value == 0 and not zero_ok):
                sign = "non-negative" if zero_ok else "positive"
                raise InputError(f"resistance parameter {name} = {value!r} must be a "
                                 f"{sign} finite number")
            object.__setattr__(self, name, float(value))
        p = self.unstable_penalty
        if p is not None:
            if isinstance(p, bool) or not isinstance(p, int | float | np.number) \
                    or not math.isfinite(p) or p < 0:
                raise InputError(f"resistance parameter unstable_penalty = {p!r} must be a "
                                 "non-negative finite number of mJ (or None)")
            object.__setattr__(self, "unstable_penalty", float(p))

    def penalty_mj(self, pitch_mm: float) -> float:
        """The unstable penalty in mJ for a thread of ``pitch_mm`` millimetres."""
        if self.unstable_penalty is not None:
            return self.unstable_penalty
        return self.axial_force * float(pitch_mm)

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping with units spelled out in the keys' documentation."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, doc: dict[str, Any]) -> ResistanceParams:
        """Inverse of :meth:`to_dict` (unknown keys refused)."""
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(doc) - names)
        if unknown:
            raise InputError(f"unknown resistance parameter {unknown[0]!r}; expected one of "
                             f"{', '.join(sorted(names))}")
        return cls(**doc)


def edge_costs(rise: np.ndarray, tilt_change: np.ndarray, turn: np.ndarray,
               contact_radius: np.ndarray, unstable: np.ndarray, params: ResistanceParams,
               pitch_mm: float) -> dict[str, np.ndarray]:
    """The weight of many edges at once and its four terms, in mJ.

    Parameters
    ----------
    rise : array of float
        ``z_v - z_u``, change of the compliance centre's resting height [mm]; NaN (a
        height the contact stages did not give) counts as no rise.
    tilt_change : array of float
        Change of the bolt's resting tilt [rad].
    turn : array of float
        Phase turned [rad] (0 for settling edges).
    contact_radius : array of float
        Mean distance of the source state's contacts from the nut axis [mm].
    unstable : array of bool
        The edge's label is ``unstable``.
    params : ResistanceParams
    pitch_mm : float
        Thread pitch [mm] (for the default penalty).

    Returns
    -------
    dict of arrays
        ``work``, ``elastic``, ``friction``, ``penalty`` and their sum ``weight``.
    """
    force = params.axial_force
    k_nmm = params.rotational_stiffness * 1000.0  # N m/rad -> N mm/rad
    work = force * np.maximum(np.nan_to_num(np.asarray(rise, float), nan=0.0), 0.0)
    elastic = 0.5 * k_nmm * np.square(np.asarray(tilt_change, float))
    friction = params.friction * force * np.asarray(contact_radius, float) \
        * np.abs(np.asarray(turn, float))
    penalty = np.where(np.asarray(unstable, bool), params.penalty_mj(pitch_mm), 0.0)
    weight = work + elastic + friction + penalty
    # Each term is non-negative by construction; a negative or NaN weight would be a bug
    # that silently breaks Dijkstra, so refuse it here.
    assert np.all(np.isfinite(weight)) and np.all(weight >= 0.0), "edge weight < 0 or NaN"
    return {"work": work, "elastic": elastic, "friction": friction, "penalty": penalty,
            "weight": weight}


def variant_weight(stiffness: float = 1.0, friction: float = 1.0, penalty: float = 1.0,
                   ) -> Any:
    """An edge-weight function for networkx that scales the elastic, friction and penalty
    terms stored on each edge (for sensitivity studies without rebuilding the graph).

    The terms are linear in their parameters, so scaling a term is the same as scaling
    ``rotational_stiffness``, ``friction`` or ``unstable_penalty``.
    """
    def weight(u: str, v: str, d: dict[str, Any]) -> float:
        return (d["work"] + stiffness * d["elastic"] + friction * d["friction"]
                + penalty * d["penalty"])
    return weight
