"""Slope stability by limit equilibrium: methods of slices on circular slip surfaces.

Fellenius (1936) and Bishop (1955), Geotechnique 5(1), 7-17: the ordinary and the simplified
methods of slices, for one circle (:func:`circle_factor`) and for the critical circle of a
ground profile (:func:`critical_circle`, an entry-and-exit search); Whitman & Bailey (1967),
J. Soil Mech. Found. Div. 93(SM4): the m_alpha >= 0.2 rule that rejects circles with an
unrealistic normal force near a steep exit. Dry soil, factors of safety dimensionless.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from hybrid.references._common import non_negative, phi_rad

#: A soil description for the methods of slices: ``soil(x, y) -> (unit weight [kN/m3],
#: cohesion [kPa], friction angle [deg])``, arrays of the shape of ``x``; unit weight 0 where
#: there is no soil, cohesion inf where the ground cannot be cut (no slip passes there).
Soil = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]

# smallest m_alpha = cos(alpha) (1 + tan(alpha) tan(phi) / F) of a valid circle (Whitman &
# Bailey 1967: below it Bishop's normal force becomes unrealistic near a steep exit)
_M_ALPHA_MIN = 0.2


def uniform_soil(unit_weight: float, cohesion: float, phi_deg: float) -> Soil:
    """A homogeneous soil (kN/m3, kPa, degrees) for :func:`circle_factor`."""
    gamma = non_negative(unit_weight, "unit_weight", "kN/m3")
    c = non_negative(cohesion, "cohesion", "kPa")
    phi = math.degrees(phi_rad(phi_deg))

    def soil(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        shape = np.shape(x)
        return np.full(shape, gamma), np.full(shape, c), np.full(shape, phi)

    return soil


class SlipCircle(NamedTuple):
    """A circular slip surface and its factor of safety.

    ``centre`` (x, y) [m], ``radius`` [m]; ``entry`` and ``exit`` the x [m] where the arc meets
    the ground surface (entry < exit); ``factor`` by ``method``.
    """

    factor: float
    centre: tuple[float, float]
    radius: float
    entry: float
    exit: float
    method: str = "bishop"

    def as_dict(self) -> dict[str, Any]:
        """The figures for a summary: F, centre, radius, entry and exit x [m]."""
        return {"F": self.factor, "centre_m": list(self.centre), "radius_m": self.radius,
                "entry_x_m": self.entry, "exit_x_m": self.exit}

    def arc(self, n: int = 100) -> np.ndarray:
        """(n, 2) points of the slip surface from entry to exit [m]."""
        x = np.linspace(self.entry, self.exit, n)
        xc, yc = self.centre
        return np.stack([x, yc - np.sqrt(np.maximum(self.radius**2 - (x - xc) ** 2, 0.0))],
                        axis=1)


def _surface(surface: np.ndarray) -> np.ndarray:
    pts = np.asarray(surface, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2:
        raise ValueError(f"surface has shape {pts.shape}: give the ground surface as (n >= 2, 2) "
                         "points (x, y) [m]")
    if not np.all(np.isfinite(pts)) or np.any(np.diff(pts[:, 0]) <= 0):
        raise ValueError("surface: x must be finite and strictly increasing (a ground profile "
                         "y(x) from left to right)")
    return pts


def _arc_interval(pts: np.ndarray, xc: float, yc: float, R: float) -> tuple[float, float] | None:
    """The widest x-interval where the lower arc lies below the ground surface."""
    lo, hi = max(xc - R, pts[0, 0]), min(xc + R, pts[-1, 0])
    if hi <= lo:
        return None
    x = np.linspace(lo, hi, 801)
    below = yc - np.sqrt(np.maximum(R * R - (x - xc) ** 2, 0.0)) < np.interp(x, *pts.T)
    if not below.any():
        return None
    edges = np.flatnonzero(np.diff(np.concatenate([[0], below.astype(np.int8), [0]])))
    starts, stops = edges[0::2], edges[1::2] - 1
    k = int(np.argmax(x[stops] - x[starts]))

    def crossing(a: float, b: float) -> float:  # bisection on arc - surface
        fa = yc - math.sqrt(max(R * R - (a - xc) ** 2, 0.0)) - float(np.interp(a, *pts.T))
        for _ in range(60):
            m = 0.5 * (a + b)
            fm = yc - math.sqrt(max(R * R - (m - xc) ** 2, 0.0)) - float(np.interp(m, *pts.T))
            if (fm > 0) == (fa > 0):
                a, fa = m, fm
            else:
                b = m
        return 0.5 * (a + b)

    i, j = starts[k], stops[k]
    x0 = x[i] if i == 0 else crossing(x[i - 1], x[i])
    x1 = x[j] if j == len(x) - 1 else crossing(x[j + 1], x[j])
    return (x0, x1) if x1 > x0 else None


def _method_of_slices(xm: np.ndarray, b: np.ndarray, top: np.ndarray, xc: np.ndarray,
                      yc: np.ndarray, R: np.ndarray, soil: Soil, method: str,
                      column_points: int) -> np.ndarray:
    """F of C circles from their slices; inf where the circle is not admissible.

    Slice centres ``xm`` and widths ``b`` (C, n) [m], ground level ``top`` (C, n) [m] above
    them.
    """
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return _slices(xm, b, top, xc, yc, R, soil, method, column_points)


def _slices(xm: np.ndarray, b: np.ndarray, top: np.ndarray, xc: np.ndarray, yc: np.ndarray,
            R: np.ndarray, soil: Soil, method: str, column_points: int) -> np.ndarray:
    # an arc through ground that cannot be cut (cohesion inf), checked at 4 points a slice
    t4 = (np.arange(4) + 0.5) / 4.0
    xd = (xm - 0.5 * b)[..., None] + t4 * b[..., None]
    yd = yc[:, None, None] - np.sqrt(np.maximum(R[:, None, None] ** 2
                                                - (xd - xc[:, None, None]) ** 2, 0.0))
    blocked = np.any(np.isinf(soil(xd, yd)[1]), axis=(1, 2))
    base = yc[:, None] - np.sqrt(np.maximum(R[:, None] ** 2 - (xm - xc[:, None]) ** 2, 0.0))
    height = np.maximum(top - base, 0.0)  # 0 where the arc runs in the air
    t = (np.arange(column_points) + 0.5) / column_points
    ys = base[..., None] + t * height[..., None]
    gamma = soil(np.broadcast_to(xm[..., None], ys.shape), ys)[0].mean(axis=-1)
    weight = b * height * gamma  # [kN/m]
    _, c, phi = soil(xm, base)
    c = np.where(height > 0.0, c, 0.0)  # no strength along the arc where it is in the air
    tan_phi = np.tan(np.radians(phi))
    lever = (xm - xc[:, None]) / R[:, None]
    sin_a = np.where(np.sum(weight * lever, axis=1) > 0, 1.0, -1.0)[:, None] * lever
    cos_a = np.sqrt(np.maximum(1.0 - sin_a**2, 0.0))
    driving = np.sum(weight * sin_a, axis=1)
    valid = (driving > 0.0) & np.all(cos_a > 0.0, axis=1) & ~blocked
    c = np.where(np.isfinite(c), c, 0.0)
    cos_a = np.where(cos_a > 0.0, cos_a, 1.0)
    safe = np.where(valid, driving, 1.0)
    F = np.sum(c * b / cos_a + weight * cos_a * tan_phi, axis=1) / safe  # ordinary
    F = np.where(valid & np.isfinite(F) & (F > 0.0), F, 1.0)
    if method == "bishop":
        for _ in range(200):
            m_alpha = cos_a + sin_a * tan_phi / F[:, None]
            m_alpha = np.where(m_alpha > 0.0, m_alpha, 1.0)
            new = np.sum((c * b + weight * tan_phi) / m_alpha, axis=1) / safe
            done = np.all(np.abs(new - F) <= 1e-12 * np.abs(F))
            F = new
            if done:
                break
        # the m_alpha rule at the converged F, on the slices that carry soil
        m_alpha = cos_a + sin_a * tan_phi / F[:, None]
        valid &= ~np.any((weight > 0.0) & (m_alpha < _M_ALPHA_MIN), axis=1)
    return np.where(valid & np.isfinite(F), F, math.inf)


def _lowest(x0: Any, x1: Any, xc: Any, yc: Any, R: Any) -> Any:
    """Lowest level [m] of the lower arc between x0 and x1 (scalars or arrays)."""
    near = np.minimum((x0 - xc) ** 2, (x1 - xc) ** 2)
    inside = (x0 < xc) & (xc < x1)
    return np.where(inside, yc - R, yc - np.sqrt(np.maximum(R * R - near, 0.0)))


def circle_factor(surface: np.ndarray, soil: Soil, centre: tuple[float, float], radius: float,
                  *, method: str = "bishop", slices: int = 60, floor: float | None = None,
                  column_points: int = 16) -> float:
    """Factor of safety of one circular slip surface by the method of slices.

    ``surface``: the ground profile (n, 2) [m], x increasing; ``soil`` (:data:`Soil`);
    ``centre`` (x, y) and ``radius`` [m] of the circle; ``floor``: no slip below this level
    [m]. ``method``: ``"bishop"`` (Bishop 1955, simplified: moment equilibrium about the
    centre, interslice shear neglected, F = sum[(c b + W tan phi) / m_alpha] / sum W sin alpha,
    m_alpha = cos alpha + sin alpha tan phi / F, iterated) or ``"ordinary"`` (Fellenius:
    F = sum(c l + W cos alpha tan phi) / sum W sin alpha). Dry soil (no pore pressure).
    The sliding mass is the part above the arc where it lies below the surface (its widest
    stretch); slices are ``slices`` equal widths plus the surface's vertices; a slice weight
    integrates the unit weight over ``column_points`` points of its centre line.

    Returns inf for a circle that does not cut the ground, dips below ``floor`` or into
    ground that cannot be cut, drives no mass, or has m_alpha < 0.2 on a slice (Whitman &
    Bailey 1967).
    """
    pts = _surface(surface)
    xc, yc, R = float(centre[0]), float(centre[1]), float(radius)
    if not (math.isfinite(xc) and math.isfinite(yc) and R > 0 and math.isfinite(R)):
        raise ValueError(f"circle centre {centre} and radius {radius} must be finite, radius > 0")
    if method not in ("bishop", "ordinary"):
        raise ValueError(f"method = {method!r}: choose 'bishop' or 'ordinary'")
    span = _arc_interval(pts, xc, yc, R)
    if span is None:
        return math.inf
    x0, x1 = span
    if floor is not None and _lowest(x0, x1, xc, yc, R) < floor - 1e-9:
        return math.inf
    inner = pts[(pts[:, 0] > x0) & (pts[:, 0] < x1), 0]
    edges = np.union1d(np.linspace(x0, x1, slices + 1), inner)
    xm = 0.5 * (edges[:-1] + edges[1:])[None, :]
    return float(_method_of_slices(xm, np.diff(edges)[None, :], np.interp(xm, *pts.T),
                                   np.array([xc]), np.array([yc]), np.array([R]), soil,
                                   method, column_points)[0])


def critical_circle(surface: np.ndarray, soil: Soil, *, floor: float | None = None,
                    x_range: tuple[float, float] | None = None, method: str = "bishop",
                    slices: int = 60, grid: int = 40) -> SlipCircle:
    """The circle of least factor of safety (entry-and-exit search).

    Circles are parametrised by where they meet the ground (x_entry < x_exit, within
    ``x_range``, default the whole surface) and the half-angle beta (2 to 90 deg) that the
    arc subtends at its centre (centres above the ends: no overhanging arc). Every circle of
    a grid is evaluated with 40 equal slices: ``grid`` entries and the surface's corners
    (slope changes above 1 deg: toes, crests) as entries or exits, ``grid`` / 2 chord lengths
    from 1/64 of the range to all of it (log scale), 10 angles; the 40 best distinct ones are
    ranked again with ``slices`` equal slices plus the surface's vertices, and the 8 best
    refined by a pattern search (steps from a tenth of the chord, halved down to 1e-5 of it,
    restarted from where it stops while that still lowers F), whose value is returned: the F
    of the arc between ``entry`` and ``exit``. A circle must leave the ground at both ends
    (the circle just beyond them in the air).
    ``floor``, ``method``: as :func:`circle_factor`. Raises ValueError when no admissible
    circle exists.
    """
    pts = _surface(surface)
    lo, hi = (pts[0, 0], pts[-1, 0]) if x_range is None else map(float, x_range)
    if not pts[0, 0] <= lo < hi <= pts[-1, 0]:
        raise ValueError(f"x_range {x_range} must lie within the surface [{pts[0, 0]}, "
                         f"{pts[-1, 0]}] with x_min < x_max")
    if method not in ("bishop", "ordinary"):
        raise ValueError(f"method = {method!r}: choose 'bishop' or 'ordinary'")
    width = hi - lo
    beta_range = (math.radians(2.0), math.pi / 2)

    def circles(P: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        xa, xb, beta = P.T
        ya, yb = np.interp(xa, *pts.T), np.interp(xb, *pts.T)
        chord = np.hypot(xb - xa, yb - ya)
        chord = np.where(chord > 0, chord, 1.0)
        R = chord / (2.0 * np.sin(beta))
        d = R * np.cos(beta)
        xc = 0.5 * (xa + xb) - d * (yb - ya) / chord
        yc = 0.5 * (ya + yb) + d * (xb - xa) / chord
        ok = ((lo <= xa) & (xa < xb) & (xb <= hi) & (beta >= beta_range[0])
              & (beta <= beta_range[1]) & (yc >= np.maximum(ya, yb) - 1e-9))
        if floor is not None:
            ok &= _lowest(xa, xb, xc, yc, R) >= floor - 1e-9
        # the arc leaves the ground at its ends: just outside them the circle is in the air
        # (else the ground it cuts beyond an end belongs to the sliding mass too)
        for x_end, side in ((xa, -1.0), (xb, 1.0)):
            x = x_end + side * 1e-6 * width
            arc = yc - np.sqrt(np.maximum(R * R - (x - xc) ** 2, 0.0))
            ok &= (np.abs(x - xc) >= R) | (arc >= np.interp(x, *pts.T) - 1e-9 * width)
        return xc, yc, R, ok

    def factors(P: np.ndarray, n: int = 40, column: int = 8,
                vertices: bool = False) -> np.ndarray:
        """F of the circles P (C, 3) with n equal slices between where they meet the ground.

        With ``vertices``, the surface's vertices between them are slice boundaries too (as
        :func:`circle_factor`: a slice then never straddles a toe or a crest).
        """
        out = np.full(len(P), math.inf)
        with np.errstate(divide="ignore", invalid="ignore"):
            geometry = circles(P)
        for k in range(0, len(P), 400):
            xc, yc, R, ok = (g[k:k + 400] for g in geometry)
            if not ok.any():
                continue
            q = P[k:k + 400][ok]
            edges = q[:, 0:1] + (q[:, 1:2] - q[:, 0:1]) * np.linspace(0.0, 1.0, n + 1)[None, :]
            if vertices:  # vertices outside the arc collapse onto its ends: empty slices
                inner = np.clip(pts[None, :, 0], q[:, 0:1], q[:, 1:2])
                edges = np.sort(np.concatenate([edges, inner], axis=1), axis=1)
            xm = 0.5 * (edges[:, :-1] + edges[:, 1:])
            out[k + np.flatnonzero(ok)] = _method_of_slices(
                xm, np.diff(edges, axis=1), np.interp(xm, *pts.T), xc[ok], yc[ok], R[ok],
                soil, method, column)
        return out

    def fine(P: np.ndarray) -> np.ndarray:
        return factors(P, slices, 16, vertices=True)

    # entries on a grid and at the surface's corners (toes, crests), chords on a log scale
    # (small and large circles alike), angles; circles also ending at a corner
    slope = np.degrees(np.arctan2(np.diff(pts[:, 1]), np.diff(pts[:, 0])))
    corners = pts[1:-1, 0][np.abs(np.diff(slope)) > 1.0]
    corners = corners[(corners > lo) & (corners < hi)]
    chords = np.geomspace(width / 64.0, width, grid // 2)
    betas = np.radians([5.0, 10.0, 15.0, 20.0, 30.0, 40.0, 50.0, 60.0, 75.0, 90.0])
    x0, L, beta = np.meshgrid(np.union1d(np.linspace(lo, hi, grid), corners), chords, betas,
                              indexing="ij")
    xc_, Lc, bc = np.meshgrid(corners, chords, betas, indexing="ij")
    P = np.concatenate([np.column_stack([x0.ravel(), (x0 + L).ravel(), beta.ravel()]),
                        np.column_stack([(xc_ - Lc).ravel(), xc_.ravel(), bc.ravel()])])
    P = P[(P[:, 0] >= lo) & (P[:, 1] <= hi)]
    F = factors(P)
    order = np.argsort(F)
    order = order[np.isfinite(F[order])]
    if not order.size:
        raise ValueError("no admissible slip circle: check the surface, the floor and x_range")
    starts: list[np.ndarray] = []
    for i in order:  # the best circles that are not neighbours of a better one
        if all(np.abs(P[i] - s)[:2].max() > 1.5 * width / grid or
               abs(P[i, 2] - s[2]) > math.radians(10.0) for s in starts):
            starts.append(P[i])
        if len(starts) == 40:
            break
    # the coarse slices can miss a thin unbreakable layer the arc grazes: rank again with the
    # fine ones and refine the 8 best
    ranked = fine(np.array(starts))
    starts = [starts[i] for i in np.argsort(ranked)[:8] if math.isfinite(ranked[i])]
    if not starts:
        raise ValueError("no admissible slip circle: check the surface, the floor and x_range")
    moves = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1],
                      [1, 1, 0], [-1, -1, 0], [1, -1, 0], [-1, 1, 0]], dtype=float)
    best_p, best_f = starts[0], math.inf
    for p in starts:
        f = float(fine(p[None, :])[0])
        for _ in range(4):  # restarted from where it stopped: a corner of F can stall it
            start_f = f
            size = 0.1 * (p[1] - p[0])  # steps on the scale of the circle
            step = np.array([size, size, math.radians(5.0)])
            while step[0] > 1e-4 * size:
                trial = p[None, :] + moves * step[None, :]
                ft = fine(trial)
                k = int(np.argmin(ft))
                if ft[k] < f:
                    p, f = trial[k], float(ft[k])
                else:
                    step *= 0.5
            if not f < start_f:
                break
        if f < best_f:
            best_p, best_f = p, f
    if not math.isfinite(best_f):
        raise ValueError("no admissible slip circle: check the surface, the floor and x_range")
    xc, yc, R, _ = circles(best_p[None, :])
    return SlipCircle(best_f, (float(xc[0]), float(yc[0])), float(R[0]), float(best_p[0]),
                      float(best_p[1]), method)
