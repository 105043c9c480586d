"""One explicit step of the discrete engine and the stable time step.

Central differences with lumped mass and velocity ties (thesis eqs 3.4-3.17, 4.27-4.29):
for every tie group (a loop over disjoint groups, ``prange`` without races) the forces
R = F_ext + m g + F_contact - I and masses of its members are summed, one acceleration is
taken, and every member gets the same velocity (thesis eq 3.12, mass-proportional damping):

    v(t+dt/2) = ((2 - alpha dt) / (2 + alpha dt)) v(t-dt/2) + (2 dt / (2 + alpha dt)) R / m,

optionally with Cundall's local non-viscous damping R_i -= d |R_i| sign(v_i) (quasi-static
phases); a component with boundary dashpots (``DiscreteState.dashpot``, summed over the group
to C) takes the same central difference with the force -C v:
v(t+dt/2) = (((2 - alpha dt) m - C dt) v(t-dt/2) + 2 dt R) / ((2 + alpha dt) m + C dt);
fixed components take their prescribed velocity; then x += dt v. The element kernel
then updates the stresses for du = dt v and computes I on the new configuration.
"""

from __future__ import annotations

import functools
import math

import numpy as np

import hybrid  # noqa: F401  (numba environment first)
from hybrid.discrete.elements import StrengthMemo, element_forces
from hybrid.discrete.state import DiscreteState

import numba  # isort: skip

__all__ = ["stable_time_step", "critical_time_step", "element_frequencies", "CRITICAL_MARGIN",
           "damped_contact_step", "damped_contact_fault", "default_dt",
           "DAMPED_CONTACT_MARGIN", "step", "prime", "kinetic_energy", "check_dt"]


@numba.njit(cache=True, inline="always")
def _new_velocity(v_old, force, m, dashpot, alpha, dt, c1, c2):
    """v(t+dt/2) of a free component (the module docstring's damped central difference).

    With the group's dashpot C > 0 on the component the update with -C v; otherwise the
    mass-damped one with its coefficients c1, c2 (the same arithmetic as before dashpots).
    """
    if dashpot > 0.0:
        return ((((2.0 - alpha * dt) * m - dashpot * dt) * v_old + 2.0 * dt * force)
                / ((2.0 + alpha * dt) * m + dashpot * dt))
    return c1 * v_old + c2 * force / m


@numba.njit(cache=True, parallel=True)
def _group_update(group_ptr, group_nodes, group_mass, internal_force, contact_force,
                  use_contact, external_force, use_external, gravity, fixed,
                  prescribed_velocity, alpha, local_damping, dt, v, x, group_energy, dashpot):
    """Tie-group reduction + damped central-difference update; writes v, x, group_energy.

    group_energy[g] += [work of loads and gravity, work of the supports (reactions of fixed /
    prescribed-velocity components), mass-damping and boundary-dashpot dissipation,
    local-damping dissipation] over the step, with the step velocity v(t+dt/2) (dissipation
    with the mean velocity).
    """
    ng = group_ptr.shape[0] - 1
    c1 = (2.0 - alpha * dt) / (2.0 + alpha * dt)
    c2 = 2.0 * dt / (2.0 + alpha * dt)
    gx = gravity[0]
    gy = gravity[1]
    for gi in numba.prange(ng):
        s = group_ptr[gi]
        t = group_ptr[gi + 1]
        m = group_mass[gi]
        ex = m * gx
        ey = m * gy
        fx = 0.0
        fy = 0.0
        fixx = False
        fixy = False
        pvx = 0.0
        pvy = 0.0
        cx = 0.0  # the group's boundary dashpots [kN s/m2]
        cy = 0.0
        for k in range(s, t):
            i = group_nodes[k]
            cx += dashpot[i, 0]
            cy += dashpot[i, 1]
            if use_external:
                ex += external_force[i, 0]
                ey += external_force[i, 1]
            fx -= internal_force[i, 0]
            fy -= internal_force[i, 1]
            if use_contact:
                fx += contact_force[i, 0]
                fy += contact_force[i, 1]
            if fixed[i, 0] and not fixx:
                fixx = True
                pvx = prescribed_velocity[i, 0]
            if fixed[i, 1] and not fixy:
                fixy = True
                pvy = prescribed_velocity[i, 1]
        fx += ex
        fy += ey
        first = group_nodes[s]
        vox = v[first, 0]
        voy = v[first, 1]
        dlx = 0.0
        dly = 0.0
        if local_damping > 0.0:  # on free components only: a held one moves as prescribed
            if vox > 0.0 and not fixx:
                dlx = -local_damping * abs(fx)
            elif vox < 0.0 and not fixx:
                dlx = local_damping * abs(fx)
            if voy > 0.0 and not fixy:
                dly = -local_damping * abs(fy)
            elif voy < 0.0 and not fixy:
                dly = local_damping * abs(fy)
        vnx = pvx if fixx else _new_velocity(vox, fx + dlx, m, cx, alpha, dt, c1, c2)
        vny = pvy if fixy else _new_velocity(voy, fy + dly, m, cy, alpha, dt, c1, c2)
        for k in range(s, t):
            i = group_nodes[k]
            v[i, 0] = vnx
            v[i, 1] = vny
            x[i, 0] += dt * vnx
            x[i, 1] += dt * vny
        # energy of the step; dissipation with the mean velocity of the step
        vax = 0.5 * (vox + vnx)
        vay = 0.5 * (voy + vny)
        wsup = 0.0  # support reaction r from v+ = c1 v- + c2 (f + r) / m, times v+ dt
        if fixx:
            wsup += (m * (vnx - c1 * vox) / c2 - fx) * vnx * dt
        if fixy:
            wsup += (m * (vny - c1 * voy) / c2 - fy) * vny * dt
        group_energy[gi, 0] += (ex * vnx + ey * vny) * dt
        group_energy[gi, 1] += wsup
        group_energy[gi, 2] += alpha * m * (vax * vax + vay * vay) * dt
        if cx > 0.0 and not fixx:
            group_energy[gi, 2] += cx * vax * vax * dt
        if cy > 0.0 and not fixy:
            group_energy[gi, 2] += cy * vay * vay * dt
        group_energy[gi, 3] -= (dlx * vax + dly * vay) * dt


@numba.njit(cache=True)
def element_held(element_nodes, fixed, e):
    """True when every node of element e is held in both directions (it does not move)."""
    held = True
    for a in range(element_nodes.shape[1]):
        i = element_nodes[e, a]
        held = held and fixed[i, 0] and fixed[i, 1]
    return held


@numba.njit(cache=True)
def step_lengths(x, element_nodes, e):
    """(least altitude, longest edge) of element e: A / longest edge (Q4), 2 A / longest (T3).

    The lengths of its stable time step (``stable_time_step``).
    """
    nen = element_nodes.shape[1]
    area = 0.0
    lmax = 0.0
    for a in range(nen):
        i = element_nodes[e, a]
        j = element_nodes[e, (a + 1) % nen]
        area += 0.5 * (x[i, 0] * x[j, 1] - x[j, 0] * x[i, 1])
        lmax = max(lmax, math.sqrt((x[j, 0] - x[i, 0]) ** 2 + (x[j, 1] - x[i, 1]) ** 2))
    return (area if nen == 4 else 2.0 * area) / lmax, lmax


@numba.njit(cache=True)
def contact_bound(x, element_nodes, element_material, contact_table, mass, e):
    """Contact time-step bound of element e [s]: sqrt(m_e / (k_n L_max)).

    That is 2 sqrt(m / k) of a quarter of its mass on the normal stiffness of an overlap
    along its longest edge.
    """
    me = 0.0
    for a in range(element_nodes.shape[1]):
        me += mass[element_nodes[e, a]]
    lmax = step_lengths(x, element_nodes, e)[1]
    return math.sqrt(me / (contact_table[element_material[e], 0] * lmax))


@numba.njit(cache=True)
def _critical_dt(x, element_nodes, element_material, material_table, density, contact_table,
                 mass, with_contact, fixed):
    """Time-step scale: the minimum over elements of L_min / c_p (:func:`stable_time_step`).

    L_min = A / longest edge (Q4), 2A / longest edge (T3), c_p = sqrt((K + 4G/3) / rho);
    with contact also sqrt(m_e / (k_n L_max)). Elements whose nodes are all held (frozen) do
    not move and are skipped (a pair's k_n is the smaller of the two, so the moving element's
    own contact bound covers its contacts with them).
    """
    best = np.inf
    for e in range(element_nodes.shape[0]):
        if element_held(element_nodes, fixed, e):
            continue
        lmin = step_lengths(x, element_nodes, e)[0]
        m = element_material[e]
        cp = math.sqrt((material_table[m, 0] + 4.0 * material_table[m, 1] / 3.0) / density[m])
        best = min(best, lmin / cp)
        if with_contact:
            best = min(best, contact_bound(x, element_nodes, element_material, contact_table,
                                           mass, e))
    return best


@numba.njit(cache=True)
def _damped_contact(x, element_nodes, element_material, contact_table, mass, fixed, dt):
    """The damped contacts' stability at ``dt`` over the moving elements.

    Returns (largest s^2 + 4 zeta s, its element, its t_c, the largest dt keeping it <= 1),
    s = dt / t_c with t_c = sqrt(m_e / (k_n L_max)) an element's contact bound.
    """
    worst, at, t_at, dt_max = 0.0, -1, np.inf, np.inf
    for e in range(element_nodes.shape[0]):
        if element_held(element_nodes, fixed, e):
            continue
        t_c = contact_bound(x, element_nodes, element_material, contact_table, mass, e)
        zeta = contact_table[element_material[e], 3]
        s = dt / t_c
        if s * s + 4.0 * zeta * s > worst:
            worst, at, t_at = s * s + 4.0 * zeta * s, e, t_c
        dt_max = min(dt_max, t_c * (math.sqrt(1.0 + 4.0 * zeta * zeta) - 2.0 * zeta))
    return worst, at, t_at, dt_max


def damped_contact_step(state: DiscreteState) -> float:
    """Largest time step [s] at which the damped contacts are stable (inf: nothing moves).

    An estimate under the assumption of the contact bound of :func:`stable_time_step` (one
    node, a quarter of the element's mass, on the stiffness of an overlap along the longest
    edge). Central differences with the damping force on the lagged velocity are stable for an
    oscillator of frequency omega and damping ratio xi only while
    dt <= (2 / omega) (sqrt(1 + xi^2) - xi) (Belytschko, Liu & Moran 2000, section 6.2).
    A contact (``contact.law``: c_n = 2 zeta sqrt(k_n L_c m_eff)) acting on one node of an
    element (a quarter of its mass) against a held or much heavier element has xi = 2 zeta
    at most, with 2 / omega = t_c = sqrt(m_e / (k_n L_max)), the contact bound of
    :func:`stable_time_step`: dt <= t_c (sqrt(1 + 4 zeta^2) - 2 zeta), i.e.
    (dt / t_c)^2 + 4 zeta dt / t_c <= 1. At half the contact bound that holds up to
    zeta = 0.375.
    """
    return float(_damped_contact(state.x, state.element_nodes, state.element_material,
                                 state.contact_table, state.mass, state.fixed, 0.0)[3])


def stable_time_step(state: DiscreteState, *, contact: bool | None = None) -> float:
    """The time-step scale [s] of the central-difference scheme for this state (Courant).

    Mesh: min over elements of L_min / c_p (L_min = A / longest edge for Q4, the smallest
    altitude 2A / longest edge for T3; c_p = sqrt((K + 4G/3) / rho)). Not a bound: it exceeds
    the critical step 2 / omega_max of an undistorted element by up to 1.2 at nu = 0.3 and
    1.4 at nu = 0.49 (:func:`critical_time_step` is the bound; a step above it is refused), so
    the solvers take half of it (:func:`default_dt`), which stays within 0.7 of the critical
    step; on distorted elements it can fall below the critical step. Contact (when
    ``contact`` is True, or None and the state has rigid bodies or several bodies):
    sqrt(m_e / (k_n L_e)), i.e. 2 sqrt(m/k) with a quarter of the element mass on a node and
    the normal stiffness k_n L_e of an overlap along one edge. Frozen elements (every node
    held) are left out. No safety factor is applied here.
    """
    contact = _with_contact(state, contact)
    args = (state.x, state.element_nodes, state.element_material, state.material_table,
            state.density, state.contact_table, state.mass, bool(contact))
    dt = float(_critical_dt(*args, state.fixed))
    if not math.isfinite(dt):  # everything held: the bound of the elements themselves
        dt = float(_critical_dt(*args, np.zeros_like(state.fixed)))
    return dt


#: a step chosen by :func:`default_dt` stays within this fraction of the damped contacts'
#: stability limit (:func:`damped_contact_step`, itself a worst case: one node against a held
#: element). Below 1 for a margin; at the default safety 0.5 it binds only above zeta = 0.34
#: (0.95 (sqrt(1 + 4 zeta^2) - 2 zeta) < 0.5), so it changes no such run with less damping
#: (with safety above 0.95 it binds even without damping).
DAMPED_CONTACT_MARGIN = 0.95


#: a step chosen by :func:`default_dt` stays within this fraction of :func:`critical_time_step`
#: (binds only for a safety above about 0.64: the scale exceeds the critical step by at most
#: about 1.4 on undistorted elements)
CRITICAL_MARGIN = 0.9


def default_dt(state: DiscreteState, safety: float = 0.5, *, contact: bool = True,
               bbar: bool = True, critical: float | None = None) -> float:
    """The step [s] a solver takes when given none.

    ``safety`` x the time-step scale (:func:`stable_time_step`), at most ``CRITICAL_MARGIN``
    x the critical step (:func:`critical_time_step`, or ``critical`` when already known), and
    with contact at most ``DAMPED_CONTACT_MARGIN`` x the damped contacts' limit.
    """
    crit = critical if critical is not None else critical_time_step(state, contact=contact,
                                                                     bbar=bbar)
    dt = min(safety * stable_time_step(state, contact=contact), CRITICAL_MARGIN * crit)
    return min(dt, DAMPED_CONTACT_MARGIN * damped_contact_step(state)) if contact else dt


def _with_contact(state: DiscreteState, contact: bool | None) -> bool:
    """``contact``, or when None whether the state has contact pairs (rigid bodies, bodies)."""
    if contact is None:
        assert state.contact_pairs is not None  # set in DiscreteState.__post_init__
        return bool(state.contact_pairs.shape[0] > 0)
    return bool(contact)


def element_frequencies(state: DiscreteState, *, bbar: bool = True) -> np.ndarray:
    """Highest natural frequency omega_e [rad/s] of every element alone (n_elements,).

    The largest eigenvalue of M_e^-1 K_e on the element's free components, with K_e the
    elastic tangent of the element kernel itself on the current configuration (B-bar Q4 or
    T3; columns by central differences of its internal force, each node moved by 1e-7 of the
    element's longest edge, about the element's centroid: exact to O(1e-7) for a linear
    element; the initial-stress stiffness, O(sigma / E), is left out) and M_e its lumped
    nodal masses. A tie group with a massless member shares its mass equally among its
    members (the groups' masses, and so the assembly, unchanged). Held components are left
    out; an element with nothing free, or no mass on a free component, gets 0.

    Raises:
        ValueError: non-finite coordinates, or an element inverted or degenerate.
    """
    x, nodes = state.x, state.element_nodes
    ne, nen = nodes.shape
    if ne == 0:
        return np.zeros(0)
    corners = x[nodes]  # (ne, nen, 2)
    bad = ~np.isfinite(corners).all(axis=(1, 2))
    if bad.any():
        raise ValueError(f"element {int(np.flatnonzero(bad)[0])} has non-finite coordinates: "
                         "no time step can be found for it")
    lmax = np.linalg.norm(np.roll(corners, -1, axis=1) - corners, axis=2).max(axis=1)
    h = 1e-7 * lmax  # (ne,)
    local = x.copy()  # each element about its own centroid (elements own their nodes)
    local[nodes] -= corners.mean(axis=1)[:, None, :]
    elastic = np.ones_like(state.elastic_only)
    cols = np.empty((ne, 2 * nen, 2 * nen))
    for a in range(nen):
        for c in range(2):
            forces = []
            for sign in (1.0, -1.0):
                v = np.zeros_like(x)
                v[nodes[:, a], c] = sign * h
                force = np.zeros_like(x)  # at the end of the increment du = v (dt = 1)
                element_forces(local + v, v, 1.0, nodes, state.element_material,
                               state.material_table, elastic, state.element_length,
                               np.zeros_like(state.stress), np.zeros_like(state.plastic_strain),
                               np.zeros_like(state.yielded), force, bbar)
                forces.append(force[nodes].reshape(ne, 2 * nen))
            cols[:, :, 2 * a + c] = (forces[0] - forces[1]) / (2.0 * h[:, None])
    bad = ~np.isfinite(cols).all(axis=(1, 2))
    if bad.any():
        raise ValueError(f"element {int(np.flatnonzero(bad)[0])} is inverted or degenerate "
                         "(zero or negative area): no time step can be found for it")
    k = 0.5 * (cols + cols.transpose(0, 2, 1))
    m = np.repeat(_member_masses(state)[nodes], 2, axis=1)  # (ne, 2 nen): x, y of each node
    free = ~state.fixed[nodes].reshape(ne, 2 * nen)
    k *= free[:, :, None] & free[:, None, :]  # held components stay put: left out
    movable = free.any(axis=1) & ((m > 0.0) | ~free).all(axis=1)
    w = np.zeros(ne)
    if movable.any():
        s = 1.0 / np.sqrt(np.where(free[movable], m[movable], 1.0))
        a = k[movable] * s[:, :, None] * s[:, None, :]
        w[movable] = np.sqrt(np.maximum(np.linalg.eigvalsh(a)[:, -1], 0.0))
    return w


def _member_masses(state: DiscreteState) -> np.ndarray:
    """Node masses [t/m] for the element bound.

    A tie group with a massless member shares its mass equally among its members; every
    other node keeps its own.
    """
    g = state.node_group
    group_mass = np.bincount(g, weights=state.mass, minlength=state.n_groups)
    size = np.bincount(g, minlength=state.n_groups)
    massless = np.bincount(g, weights=(state.mass <= 0.0).astype(float),
                           minlength=state.n_groups) > 0
    shared = massless[g]
    out = state.mass.astype(float).copy()
    out[shared] = group_mass[g[shared]] / size[g[shared]]
    return out


def critical_time_step(state: DiscreteState, *, contact: bool | None = None,
                       bbar: bool = True) -> float:
    """Critical time step [s] of the central-difference scheme for the elements.

    Mesh: 2 / max_e omega_e (:func:`element_frequencies`). The highest frequency of the
    assembled, tied mesh is at most the highest of its elements alone (the element eigenvalue
    theorem: Irons 1970; Hughes 1987, sec. 9.3), so this is a lower bound of the mesh's
    critical step, exact for a free element: a step above it is unstable for a free element
    and refused (:func:`check_dt`); plastic flow only softens the tangent. With contact also
    the contact bound of :func:`stable_time_step`, an estimate (where a node carries an
    element's and a contact's stiffness together the limit is lower, by up to 1 / sqrt(2)).
    ``bbar``: the element kernel's (``RunOptions.bbar``; full integration is stiffer). Costs
    about 10 microseconds per element (a solver computes it once, when it starts).
    """
    contact = _with_contact(state, contact)
    w = element_frequencies(state, bbar=bbar)
    w_max = float(w.max(initial=0.0))
    dt = 2.0 / w_max if w_max > 0.0 else math.inf
    if contact:
        args = (state.x, state.element_nodes, state.element_material, state.material_table,
                state.density, state.contact_table, state.mass)
        dt = min(dt, float(_contact_dt(*args, state.fixed)))
    return dt


@numba.njit(cache=True)
def _contact_dt(x, element_nodes, element_material, material_table, density, contact_table,
                mass, fixed):
    """The contact bound of :func:`stable_time_step` alone (min over moving elements)."""
    best = np.inf
    for e in range(element_nodes.shape[0]):
        if not element_held(element_nodes, fixed, e):
            best = min(best, contact_bound(x, element_nodes, element_material, contact_table,
                                           mass, e))
    return best


def check_dt(state: DiscreteState, dt: float, *, contact: bool | None = None,
             bbar: bool = True, critical: float | None = None) -> float:
    """Validate the time step of a solver that starts: refuse dt above the stable limit.

    The limit is the smaller of the critical step (:func:`critical_time_step`, or
    ``critical`` when already known) and the time-step scale (:func:`stable_time_step`:
    during the run the distortion check, ``monitor.check_distortion``, stops a run whose
    step is above it). Returns the critical step.
    """
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"dt = {dt!r}: must be a finite positive number [s]")
    crit = critical if critical is not None else critical_time_step(state, contact=contact,
                                                                     bbar=bbar)
    limit = min(crit, stable_time_step(state, contact=contact))
    if dt > limit:
        what = ("the critical time step (integrate.critical_time_step)" if limit == crit else
                "the time-step scale L_min / c_p of its distorted elements "
                "(integrate.stable_time_step)")
        raise ValueError(f"dt = {dt:.4g} s is above {what}, {limit:.4g} s, of this "
                         f"mesh/contact stiffness: use dt <= {limit:.4g} s (the solvers' "
                         "default, no dt, is 0.5 x the scale within 0.9 x the critical step)")
    return crit


def _down(value: float, digits: int) -> float:
    """``value`` rounded down to ``digits`` significant digits (a limit quoted safely)."""
    if not value > 0.0:
        return 0.0
    q = 10.0 ** (math.floor(math.log10(value)) - digits + 1)
    return math.nextafter(math.floor(value / q) * q, 0.0)  # below, were it the value itself


def damped_contact_fault(state: DiscreteState, dt: float) -> str | None:
    """Why the damped contacts are unstable at ``dt`` (None: they are not).

    The message names the largest damping ratio and time step that are stable
    (:func:`damped_contact_step`), rounded down. Contact damping ratios outside [0, 1] are
    left to the run's input check.
    """
    zeta = state.contact_table[:, 3]
    if not np.all((zeta >= 0.0) & (zeta <= 1.0)):
        return None
    worst, e, t_c, dt_max = _damped_contact(state.x, state.element_nodes,
                                            state.element_material, state.contact_table,
                                            state.mass, state.fixed, dt)
    if worst <= 1.0:
        return None
    m, s = int(state.element_material[e]), dt / t_c
    zeta_max = _down((1.0 - s * s) / (4.0 * s), 3)
    return (f"contact damping ratio {state.contact_table[m, 3]:g} of material {m} is too high "
            f"for dt = {dt:.4g} s: a damped contact is stable in the explicit scheme only while "
            "(dt/t_c)^2 + 4 zeta dt/t_c <= 1 (t_c its element's contact bound; "
            f"integrate.damped_contact_step), here zeta <= {zeta_max:g}. "
            f"Lower the contact damping to that, or give dt <= {_down(dt_max, 4):.4g} s (or no "
            "dt: the solver then keeps its step within that limit)")


def prime(state: DiscreteState) -> None:
    """Compute the internal force and the tie groups' masses on the current configuration.

    No stress increment: the stresses stay as they are.
    """
    state.refresh_groups()
    zero = np.zeros_like(state.v)
    no_return = np.zeros(state.element_nodes.shape[0])  # the stresses stay as they are
    element_forces(state.x, zero, 0.0, state.element_nodes, state.element_material,
                   state.material_table, state.elastic_only, state.element_length,
                   state.stress, state.plastic_strain, state.yielded, state.internal_force,
                   plastic_strain_cap=no_return)
    state.primed = True


def step(state: DiscreteState, dt: float, *, mass_damping: float = 0.0,
         local_damping: float = 0.0, contact_force: np.ndarray | None = None,
         bbar: bool = True, external: bool = True,
         plastic_strain_cap: float | np.ndarray = math.inf,
         memo: StrengthMemo | None = None) -> None:
    """Advance the state by one explicit step of size dt [s].

    Hot path: only scalar checks; ``ExplicitSolver`` checks dt against the stable step once.

    ``mass_damping`` is alpha [1/s] of thesis eq 3.12, ``local_damping`` Cundall's d in
    [0, 1). ``contact_force`` (n_nodes, 2), if given, holds the contact forces at the current
    configuration (from ``hybrid.discrete.contact.contact_forces``). ``external=False`` skips
    reading ``state.external_force`` (pass it only when that array is all zero).
    ``plastic_strain_cap``: Gauss points with this much plastic strain respond elastically
    (one value, or one per element). ``memo``: the Gauss points' strengths kept from step to
    step by a stepping loop (``elements.StrengthMemo``; the same result, faster).
    """
    if not (dt > 0.0 and math.isfinite(dt)):
        raise ValueError(f"dt = {dt!r}: must be a finite positive time step [s]")
    if not (mass_damping >= 0.0 and 0.0 <= local_damping < 1.0):
        raise ValueError(f"mass_damping = {mass_damping!r} must be >= 0 [1/s] and "
                         f"local_damping = {local_damping!r} in [0, 1)")
    if not state.primed:
        prime(state)
    use_c = contact_force is not None
    cf = contact_force if use_c else _EMPTY
    _group_update(state.group_ptr, state.group_nodes, state.group_mass, state.internal_force,
                  cf, use_c, state.external_force, bool(external), state.gravity, state.fixed,
                  state.prescribed_velocity, float(mass_damping), float(local_damping),
                  float(dt), state.v, state.x, state.group_energy, state.dashpot)
    element_forces(state.x, state.v, float(dt), state.element_nodes, state.element_material,
                   state.material_table, state.elastic_only, state.element_length,
                   state.stress, state.plastic_strain, state.yielded, state.internal_force,
                   bbar, _point_caps(plastic_strain_cap, state.element_nodes.shape[0]), memo)
    state.time += dt
    state.step += 1


_EMPTY = np.zeros((1, 2))


@functools.lru_cache(maxsize=8)
def _uniform_cap(value: float, n_elements: int) -> np.ndarray:
    """One cap for every element, made once per (value, size) and read-only."""
    out = np.full(n_elements, value)
    out.flags.writeable = False
    return out


def _point_caps(cap: float | np.ndarray, n_elements: int) -> np.ndarray:
    """The per-element plastic-strain cap of ``step`` (checked: the kernel does not)."""
    if isinstance(cap, np.ndarray):
        if cap.shape != (n_elements,) or cap.dtype != np.float64:
            raise ValueError(f"plastic_strain_cap: an array of shape ({n_elements},) float64 "
                             f"(one per element), not {cap.shape} {cap.dtype}")
        return cap
    return _uniform_cap(float(cap), n_elements)


def kinetic_energy(state: DiscreteState) -> float:
    """1/2 sum m v.v over the nodes (tied members share a velocity) [kJ/m]."""
    return 0.5 * float(np.dot(state.mass, np.einsum("ij,ij->i", state.v, state.v)))
