"""Exact axial-section profile of a thread body, its fillets and its nine regions.

conventions.md defines the sharp profile ``R(t) = pd/2 + sqrt(3) (p/4 - |t|)`` clamped to
``[minor/2, major/2]`` on ``t`` in ``[-p/2, p/2)``. Each of the two clamp corners may be
rounded by a circular arc tangent to the flank and to the flat. In ``u = |t|`` the curve is
five pieces::

    [0, a1]   flat  R = r_hi            (bolt crest / nut root)
    [a1, a2]  arc   centre (u_hi - rho_hi/sqrt3, r_hi - rho_hi)   (bolt CF / nut RF)
    [a2, a3]  flank R = pd/2 + sqrt3 (p/4 - u)                  (F)
    [a3, a4]  arc   centre (u_lo + rho_lo/sqrt3, r_lo + rho_lo)   (bolt RF / nut CF)
    [a4, p/2] flat  R = r_lo            (bolt root / nut crest)

where ``u_hi``/``u_lo`` are the sharp corners. A fillet always lowers R at the high corner
and raises it at the low one, whichever body it belongs to; only the region names differ.
``t < 0`` is the positive side (radius grows with +z), ``t > 0`` the negative side.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal, SupportsFloat, cast, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._angles import SQRT3
from .._errors import SpecError

if TYPE_CHECKING:
    from ._spec import ThreadSpec

__all__ = ["Profile", "bolt_profile", "nut_profile", "check_fillets", "BOLT_REGIONS", "NUT_REGIONS"]

#: The nine regions of the bolt, in conventions.md order.
BOLT_REGIONS = ("crest", "+CF", "+F", "+RF", "root", "-RF", "-F", "-CF", "base")
#: The nine regions of the nut, in conventions.md order.
NUT_REGIONS = ("crest", "+CF", "+F", "+RF", "root", "-RF", "-F", "-CF", "surface")

Body = Literal["bolt", "nut"]


def wrap_t(t: ArrayLike, pitch: float) -> NDArray[np.float64]:
    """Wrap an axial coordinate into one pitch, ``[-p/2, p/2)``."""
    t = np.asarray(t, dtype=float)
    return t - pitch * np.floor(t / pitch + 0.5)


def _wrap1(t: float, pitch: float) -> float:
    """:func:`wrap_t` of one number."""
    return t - pitch * math.floor(t / pitch + 0.5)


@dataclass(frozen=True)
class Profile:
    """The axial-section profile ``R(t)`` of one body over one pitch.

    Parameters
    ----------
    body : {"bolt", "nut"}
        Which body; decides region names only (``t = 0`` is the bolt's crest centre
        and the nut's root centre).
    pitch, pitch_diameter, major, minor : float
        Lengths in the spec's units.
    crest_fillet, root_fillet : float
        Fillet radii of the body's crest and root corners (0 keeps them sharp).
    """

    body: Body
    pitch: float
    pitch_diameter: float
    major: float
    minor: float
    crest_fillet: float = 0.0
    root_fillet: float = 0.0

    # -- corner geometry ---------------------------------------------------------------
    @property
    def fillet_hi(self) -> float:
        """Fillet radius at the major-diameter corner (bolt crest, nut root)."""
        return self.crest_fillet if self.body == "bolt" else self.root_fillet

    @property
    def fillet_lo(self) -> float:
        """Fillet radius at the minor-diameter corner (bolt root, nut crest)."""
        return self.root_fillet if self.body == "bolt" else self.crest_fillet

    @functools.cached_property
    def r_hi(self) -> float:
        """Radius of the major flat (capped by the sharp-V apex)."""
        apex = self.pitch_diameter / 2 + SQRT3 * self.pitch / 4
        return min(self.major / 2, apex)

    @functools.cached_property
    def r_lo(self) -> float:
        """Radius of the minor flat (raised to the sharp-V bottom)."""
        bottom = self.pitch_diameter / 2 - SQRT3 * self.pitch / 4
        return max(self.minor / 2, bottom)

    def _flank_u(self, r: float) -> float:
        return self.pitch / 4 + (self.pitch_diameter / 2 - r) / SQRT3

    @functools.cached_property
    def breakpoints(self) -> tuple[float, float, float, float]:
        """``(a1, a2, a3, a4)``: region boundaries in ``u = |t|`` (see module docstring)."""
        u_hi = self._flank_u(self.r_hi)
        u_lo = self._flank_u(self.r_lo)
        rh, rl = self.fillet_hi, self.fillet_lo
        return (
            u_hi - rh / SQRT3,
            u_hi + rh / (2 * SQRT3),
            u_lo - rl / (2 * SQRT3),
            u_lo + rl / SQRT3,
        )

    @functools.cached_property
    def centre_hi(self) -> tuple[float, float]:
        """``(u, r)`` centre of the major-corner fillet arc."""
        u_hi = self._flank_u(self.r_hi)
        return (u_hi - self.fillet_hi / SQRT3, self.r_hi - self.fillet_hi)

    @functools.cached_property
    def centre_lo(self) -> tuple[float, float]:
        """``(u, r)`` centre of the minor-corner fillet arc."""
        u_lo = self._flank_u(self.r_lo)
        return (u_lo + self.fillet_lo / SQRT3, self.r_lo + self.fillet_lo)

    def validate(self) -> None:
        """Raise :class:`SpecError` if a fillet does not fit its corner."""
        a1, a2, a3, a4 = self.breakpoints
        half = self.pitch / 2
        names = {
            "hi": f"{self.body}.{'crest' if self.body == 'bolt' else 'root'}_fillet",
            "lo": f"{self.body}.{'root' if self.body == 'bolt' else 'crest'}_fillet",
        }
        if self.fillet_hi > 0 and a1 < -1e-12:
            raise SpecError(
                f"spec key '{names['hi']}' ({self.fillet_hi:g}) is too large: the flat at the "
                f"major diameter is only {2 * (a1 + self.fillet_hi / SQRT3):g} wide"
            )
        if self.fillet_lo > 0 and a4 > half + 1e-12:
            raise SpecError(
                f"spec key '{names['lo']}' ({self.fillet_lo:g}) is too large: the flat at the "
                f"minor diameter is only {2 * (half - a4 + self.fillet_lo / SQRT3):g} wide"
            )
        if a2 > a3 + 1e-12:
            raise SpecError(
                f"spec keys '{names['hi']}' and '{names['lo']}' are too large together: their "
                f"arcs overlap on the flank"
            )

    # -- evaluation --------------------------------------------------------------------
    @overload
    def radius(self, t: float) -> np.float64: ...
    @overload
    def radius(self, t: ArrayLike) -> NDArray[np.float64]: ...

    def radius(self, t: ArrayLike) -> NDArray[np.float64] | np.float64:
        """Exact profile radius ``R(t)`` (any ``t``; wrapped into one pitch)."""
        # The contact code asks one point at a time (a float: ``np.ndim`` costs more than
        # the evaluation).
        if isinstance(t, float) or np.ndim(t) == 0:
            t0 = float(cast("SupportsFloat", t))  # a number or a 0-d array
            return np.float64(self._radius_at(abs(_wrap1(t0, self.pitch))))
        u = np.abs(wrap_t(t, self.pitch))
        a1, a2, a3, a4 = self.breakpoints
        ch, cl = self.centre_hi, self.centre_lo
        rh, rl = self.fillet_hi, self.fillet_lo
        flank = self.pitch_diameter / 2 + SQRT3 * (self.pitch / 4 - u)
        arc_hi = ch[1] + np.sqrt(np.clip(rh * rh - (u - ch[0]) ** 2, 0.0, None))
        arc_lo = cl[1] - np.sqrt(np.clip(rl * rl - (u - cl[0]) ** 2, 0.0, None))
        return np.select(
            [u <= a1, u <= a2, u <= a3, u <= a4],
            [np.full_like(u, self.r_hi), arc_hi, flank, arc_lo],
            np.full_like(u, self.r_lo),
        )

    @overload
    def slope(self, t: float) -> np.float64: ...
    @overload
    def slope(self, t: ArrayLike) -> NDArray[np.float64]: ...

    def slope(self, t: ArrayLike) -> NDArray[np.float64] | np.float64:
        """``dR/dt`` of the exact profile."""
        if isinstance(t, float) or np.ndim(t) == 0:  # (as :meth:`radius`)
            w = _wrap1(float(cast("SupportsFloat", t)), self.pitch)
            return np.float64(self._slope_at(abs(w)) * (-1.0 if w < 0 else 1.0))
        t = wrap_t(t, self.pitch)
        u = np.abs(t)
        sign = np.where(t < 0, -1.0, 1.0)
        a1, a2, a3, a4 = self.breakpoints
        ch, cl = self.centre_hi, self.centre_lo
        rh, rl = self.fillet_hi, self.fillet_lo
        with np.errstate(divide="ignore", invalid="ignore"):
            d_hi = -(u - ch[0]) / np.sqrt(np.clip(rh * rh - (u - ch[0]) ** 2, 1e-300, None))
            d_lo = (u - cl[0]) / np.sqrt(np.clip(rl * rl - (u - cl[0]) ** 2, 1e-300, None))
        du = np.select(
            [u <= a1, u <= a2, u <= a3, u <= a4],
            [np.zeros_like(u), d_hi, np.full_like(u, -SQRT3), d_lo],
            np.zeros_like(u),
        )
        return sign * du

    def _radius_at(self, u: float) -> float:
        """:meth:`radius` at one ``u = |t|`` (the same pieces, without array overhead)."""
        a1, a2, a3, a4 = self.breakpoints
        if u <= a1:
            return self.r_hi
        if u <= a2:
            (cu, cr), rho = self.centre_hi, self.fillet_hi
            return cr + math.sqrt(max(rho * rho - (u - cu) ** 2, 0.0))
        if u <= a3:
            return self.pitch_diameter / 2 + SQRT3 * (self.pitch / 4 - u)
        if u <= a4:
            (cu, cr), rho = self.centre_lo, self.fillet_lo
            return cr - math.sqrt(max(rho * rho - (u - cu) ** 2, 0.0))
        return self.r_lo

    def _slope_at(self, u: float) -> float:
        """``dR/du`` at one ``u = |t|`` (see :meth:`slope`)."""
        a1, a2, a3, a4 = self.breakpoints
        if u <= a1 or u > a4:
            return 0.0
        if u <= a2:
            cu, rho = self.centre_hi[0], self.fillet_hi
            return -(u - cu) / math.sqrt(max(rho * rho - (u - cu) ** 2, 1e-300))
        if u <= a3:
            return -SQRT3
        cu, rho = self.centre_lo[0], self.fillet_lo
        return (u - cu) / math.sqrt(max(rho * rho - (u - cu) ** 2, 1e-300))

    def _region_names(self) -> tuple[str, str, str, str]:
        """The profile's pieces by increasing ``u = |t|``: the flat at the major diameter,
        its arc, the arc at the minor diameter and its flat (the flank is ``F``)."""
        if self.body == "bolt":
            return "crest", "CF", "RF", "root"
        return "root", "RF", "CF", "crest"

    def region(self, t: ArrayLike) -> NDArray[np.str_]:
        """Region name (``crest``, ``+CF``, ... ``-CF``) of the profile at ``t``."""
        if isinstance(t, float):  # (as :meth:`radius`: the same choice, one number)
            return np.asarray(self._region_at(_wrap1(t, self.pitch)))
        t = wrap_t(t, self.pitch)
        u = np.abs(t)
        a1, a2, a3, a4 = self.breakpoints
        flat_hi, arc_hi, arc_lo, flat_lo = self._region_names()
        side = np.where(t < 0, "+", "-")
        kind = np.select(
            [u <= a1, u <= a2, u <= a3, u <= a4],
            [flat_hi, arc_hi, "F", arc_lo],
            flat_lo,
        ).astype(object)
        signed = np.char.add(side.astype(str), kind.astype(str))
        return np.where(np.isin(kind, ("crest", "root")), kind.astype(str), signed)

    def _region_at(self, t: float) -> str:
        """:meth:`region` at one wrapped ``t``."""
        u = abs(t)
        a1, a2, a3, a4 = self.breakpoints
        flat_hi, arc_hi, arc_lo, flat_lo = self._region_names()
        if u <= a1:
            return flat_hi
        kind = arc_hi if u <= a2 else "F" if u <= a3 else arc_lo if u <= a4 else flat_lo
        if kind in ("crest", "root"):
            return kind
        return ("+" if t < 0 else "-") + kind

    def region_bounds(self) -> list[tuple[str, float, float]]:
        """``(region, t_start, t_end)`` for each non-empty region, ordered in ``t``."""
        a1, a2, a3, a4 = self.breakpoints
        h = self.pitch / 2
        edges = [-h, -a4, -a3, -a2, -a1, a1, a2, a3, a4, h]
        if self.body == "bolt":
            names = ["root", "+RF", "+F", "+CF", "crest", "-CF", "-F", "-RF", "root"]
        else:
            names = ["crest", "+CF", "+F", "+RF", "root", "-RF", "-F", "-CF", "crest"]
        return [(n, a, b) for n, a, b in zip(names, edges[:-1], edges[1:], strict=True) if b > a]

    def sample(self, chord: float) -> NDArray[np.float64]:
        """Profile stations ``t`` in ``[-p/2, p/2]`` whose polyline is within ``chord`` of R.

        Flats and flanks are straight in the axial section and need only their ends; each
        fillet arc is split into equal angles whose sagitta does not exceed ``chord``.
        """
        a1, a2, a3, a4 = self.breakpoints
        h = self.pitch / 2
        u = np.concatenate([[0.0, a1, a2, a3, a4, h], self._arc_stations(chord)])
        u = np.unique(u[(u >= 0) & (u <= h)])
        return np.unique(np.concatenate([-u[::-1], u]))

    def _arc_stations(self, chord: float) -> NDArray[np.float64]:
        out: list[NDArray[np.float64]] = []
        a1, a2, a3, a4 = self.breakpoints
        for rho, centre, lo, hi in (
            (self.fillet_hi, self.centre_hi, a1, a2),
            (self.fillet_lo, self.centre_lo, a3, a4),
        ):
            if rho <= 0 or hi <= lo:
                continue
            phi0 = math.asin(np.clip((lo - centre[0]) / rho, -1, 1))
            phi1 = math.asin(np.clip((hi - centre[0]) / rho, -1, 1))
            dphi = 2 * math.acos(max(-1.0, 1 - chord / rho)) if chord < 2 * rho else math.pi
            n = max(1, math.ceil(abs(phi1 - phi0) / dphi))
            out.append(centre[0] + rho * np.sin(np.linspace(phi0, phi1, n + 1)))
        return np.concatenate(out) if out else np.empty(0)

    def distance(self, t: ArrayLike, r: ArrayLike) -> NDArray[np.float64]:
        """Euclidean distance in the axial section from ``(t, r)`` to the profile curve.

        The profile curve lies on the helical surface, so this bounds the true 3-D
        distance to the surface from above.
        """
        t, r = np.broadcast_arrays(wrap_t(t, self.pitch), np.asarray(r, dtype=float))
        tf = np.ascontiguousarray(t, dtype=float).ravel()
        rf = np.ascontiguousarray(r, dtype=float).ravel()
        from ._profile_distance import profile_distance  # numba: not at import

        out = profile_distance(tf, rf, float(self.pitch), *self._pieces)
        return out.reshape(t.shape)

    @functools.cached_property
    def _pieces(self) -> tuple[NDArray[np.float64], ...]:
        """The profile over one pitch as straight pieces (flats, flanks, and the arcs' end
        points as zero-length pieces: they cover the outside of an arc's angular span) and
        fillet arcs, both sides of ``u = 0``: ``(start, direction, 1/|direction|^2 or 0,
        arc centre, radius, u from, u to, side, bulge)``, ``bulge`` +1 where the arc lies
        above its centre (the major corner), -1 below (the minor)."""
        a1, a2, a3, a4 = self.breakpoints
        h = self.pitch / 2
        pts = [
            (0.0, self.r_hi),
            (a1, self.r_hi),
            (a2, self._radius_at(a2)),
            (a3, self._radius_at(a3)),
            (a4, self.r_lo),
            (h, self.r_lo),
        ]
        lines, arcs = [], []
        for sd in (1.0, -1.0):
            q = [(sd * u, r) for u, r in pts]
            lines += [(q[0], q[1]), (q[2], q[3]), (q[4], q[5])]
            lines += [(q[k], q[k]) for k in (1, 2, 3, 4)]
            if self.fillet_hi > 0:
                arcs.append((*self.centre_hi, self.fillet_hi, a1, a2, sd, 1.0))
            if self.fillet_lo > 0:
                arcs.append((*self.centre_lo, self.fillet_lo, a3, a4, sd, -1.0))
        start = np.array([a for a, _ in lines])
        d = np.array([b for _, b in lines]) - start
        dd = np.einsum("ij,ij->i", d, d)
        inv_dd = np.divide(1.0, dd, out=np.zeros_like(dd), where=dd > 0)
        arc = np.array(arcs).reshape(-1, 7)
        columns = (arc[:, :2], *(arc[:, k] for k in range(2, 7)))
        return (start, d, inv_dd, *(np.ascontiguousarray(c) for c in columns))


def bolt_profile(spec: ThreadSpec) -> Profile:
    """The bolt's profile from a spec."""
    b = spec.bolt
    return Profile(
        "bolt", spec.pitch, b.pitch_diameter, b.major, b.minor, b.crest_fillet, b.root_fillet
    )


def nut_profile(spec: ThreadSpec) -> Profile:
    """The nut's profile from a spec."""
    n = spec.nut
    return Profile(
        "nut", spec.pitch, n.pitch_diameter, n.major, n.minor, n.crest_fillet, n.root_fillet
    )


def check_fillets(spec: ThreadSpec) -> None:
    """Raise :class:`SpecError` if any fillet of ``spec`` does not fit its corner."""
    bolt_profile(spec).validate()
    nut_profile(spec).validate()
