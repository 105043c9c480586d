"""Interface failure checks and splitting of tie groups (thesis section 4.5).

For every intact, splittable interface (edge a0-a1 of element A shared with element B) the
Cauchy stress averaged over the Gauss points next to the edge in both elements (the two
points nearest the edge for Q4, the single point for T3) gives the traction t = sigma n on the
edge's unit normal n (outward from A). With sigma_N = t.n (tension positive) and
tau = |t - sigma_N n| the interface fails

- in tension if sigma_N > tensile_strength, or
- in shear if tau > c + max(-sigma_N, 0) tan(phi)  (compressive normal stress p = -sigma_N;
  strictly greater, so that an unloaded cohesionless interface, tau = 0 = c, stays intact),

with the strength of the weaker of the two materials at that normal stress: the shear
strength min(c_a + p tan phi_a, c_b + p tan phi_b) and the smaller tensile strength (as for
a contact, ``hybrid.discrete.contact.law.point_law``). An interface also fails where the
material beside it has softened to its residual strength (``hybrid.constitutive.softening``):
when the Gauss points next to the edge on either side have all reached the residual slip,
the softened band becomes a discontinuity, and the failed interface is from then on a
contact that carries the residual strength, c_r + sigma_n tan(phi_r) while its sides press
on each other (``Contact`` defaults to the residual cohesion and angle).
An interface likewise fails in tension where the material beside it has cracked: where the
Gauss points next to the edge on either side have all yielded, at their last update, with the
in-plane major principal stress on the tension cut-off (a given tensile strength below the
Mohr-Coulomb apex, such as a no-tension fill's 0), and the edge lies nearer the crack's plane
than its normal (sigma_N at least the in-plane mean of the averaged stress: the edge's normal
within 45 deg of the major principal direction). Inside an element on its cut-off the stress
is capped at the tensile strength, so the traction on an edge never exceeds it and the
tension test above alone would leave the crack smeared in the elements, stretching them,
whatever the bond's own tensile strength. (A softening material whose residual cut-off is the
apex, c_r = 0, leaves this rule at residual, where the softened test above takes over.)
Optionally (``split_plastic_strain``, an addition to the thesis) an interface also fails when
the mean accumulated plastic strain of those Gauss points exceeds the limit: inside a
perfectly plastic element the stress is capped on the yield surface, so the traction on a mesh
edge not aligned with the critical plane never reaches the bond strength, and a flowing region
would otherwise distort its elements until they invert.
An element also parts from its neighbours when it has distorted as far as an element can
follow the flow: when its time-step scale (the smaller of the ratios of its least altitude
and of sqrt(1 / longest edge) to their values at creation: ``stable_step_ratio``) has fallen
below ``DISTORTION_LIMIT``, or a Q4 has folded towards a corner (the least ratio of a
corner's Jacobian to its value at creation, ``corner_ratio``, below ``CORNER_LIMIT``), at a
splitting check, it becomes a fragment for good
(``DiscreteState.fragment_cap``, ``mark_fragments``): its splittable bonds fail and its
points yield no further than its most strained one had then (``plastic_cap``), since a
fragment flowing further inside would pancake and stop the explicit run. The
corner check is needed besides the time-step scale: an isochoric flow can fold a Q4 into a dart
(one corner's two edges turning into line, then past it) while its area and longest edge, so
its time-step scale, barely change; the folded element then inverts between two checks and ends
the run in non-finite numbers. A failed interface unties: the tie groups of the edge's two
vertices are rebuilt as the connected components of the graph "node - intact interface -
node" among the group's members.
"""

from __future__ import annotations

import math

import numpy as np

import hybrid  # noqa: F401
from hybrid.constitutive.softening import softening_fraction, strength_at
from hybrid.constitutive.table import NO_TENSION_CUTOFF
from hybrid.discrete.integrate import element_held, step_lengths
from hybrid.discrete.state import LEDGER_GROUPS, DiscreteState, groups_csr

import numba  # isort: skip

__all__ = ["check_interfaces", "split_interfaces", "limit_splitting", "FAIL_TENSION",
           "FAIL_SHEAR", "FAIL_PLASTIC", "FAIL_SOFTENED", "FAIL_DISTORTED", "DISTORTION_LIMIT",
           "CORNER_LIMIT", "stable_step_ratio", "corner_ratio", "mark_fragments",
           "plastic_cap", "failure_modes", "mode_counts", "MODE_NAMES"]

FAIL_TENSION = 1
FAIL_SHEAR = 2
FAIL_PLASTIC = 3
FAIL_SOFTENED = 4
FAIL_DISTORTED = 5
#: The failure modes by name, as ``failure_modes`` counts them (index: the mode).
MODE_NAMES = ("not_recorded", "tension", "shear", "plastic_strain", "softened", "distorted")

#: An element parts from its neighbours once its time-step scale has fallen below this
#: fraction of its value at creation [-]. With the run's time step half the smallest initial
#: one (``RunOptions.safety`` = 0.5, the default) an element stopped here keeps a margin of
#: half again over the time step for the elastic response of the fragment it becomes, as the
#: scale is estimated (one contact spring per node); a fragment pinched on two sides
#: sees about twice that stiffness, which this margin does not cover (a known limit). A
#: safety above the limit lets the smallest elements reach the run's step first: the run then
#: stops as distorted (``monitor.check_distortion``).
DISTORTION_LIMIT = 0.75
#: A Q4 also parts from its neighbours once the Jacobian at one of its corners (twice the
#: area of the triangle of that corner's two edges) has fallen below this fraction of its
#: value at creation [-]: the element is folding towards a dart at that corner, which its
#: time-step scale does not show (see module). A simple shear keeps every corner's Jacobian and a
#: uniform squash scales all four alike (meeting ``DISTORTION_LIMIT`` first), so this limit is
#: met by a fold, not by the flow a parallelogram follows. For a T3 every corner's Jacobian is
#: twice its area.
CORNER_LIMIT = 0.25
#: A Gauss point is on its tension cut-off when its major principal stress is within this
#: fraction of its stress scale of the cut-off [-]: the return puts it there to rounding.
CUTOFF_TOLERANCE = 1.0e-9


@numba.njit(cache=True, inline="always")
def _local_index(element_nodes, e, node):
    for k in range(element_nodes.shape[1]):
        if element_nodes[e, k] == node:
            return k
    return -1


@numba.njit(cache=True, parallel=True)
def _stable_step_ratio_kernel(x, x_ref, element_nodes, fixed, out):
    """out[e] = min(h(x) / h(x_ref), sqrt(L(x_ref) / L(x))): h least altitude, L longest edge.

    1 for an element whose nodes are all held (it does not move; ``integrate._critical_dt``
    leaves it out too).
    """
    for e in numba.prange(element_nodes.shape[0]):
        if element_held(element_nodes, fixed, e):
            out[e] = 1.0
            continue
        h, lmax = step_lengths(x, element_nodes, e)
        h0, lmax0 = step_lengths(x_ref, element_nodes, e)
        out[e] = min(h / h0, math.sqrt(lmax0 / lmax)) if h > 0.0 else 0.0


@numba.njit(cache=True, parallel=True)
def _corner_ratio_kernel(x, x_ref, element_nodes, fixed, out):
    """out[e] = min over corners a of J_a(x) / J_a(x_ref): the least corner Jacobian ratio.

    J_a is the cross product of the edges into and out of corner a (counter-clockwise); 1 for
    an element whose nodes are all held.
    """
    nen = element_nodes.shape[1]
    for e in numba.prange(element_nodes.shape[0]):
        if element_held(element_nodes, fixed, e):
            out[e] = 1.0
            continue
        worst = math.inf
        for a in range(nen):
            i = element_nodes[e, (a + nen - 1) % nen]
            j = element_nodes[e, a]
            k = element_nodes[e, (a + 1) % nen]
            jac = ((x[j, 0] - x[i, 0]) * (x[k, 1] - x[j, 1])
                   - (x[j, 1] - x[i, 1]) * (x[k, 0] - x[j, 0]))
            jac0 = ((x_ref[j, 0] - x_ref[i, 0]) * (x_ref[k, 1] - x_ref[j, 1])
                    - (x_ref[j, 1] - x_ref[i, 1]) * (x_ref[k, 0] - x_ref[j, 0]))
            worst = min(worst, jac / jac0)
        out[e] = worst


@numba.njit(cache=True, inline="always")
def _cracked_point(stress, yielded, material_table, e, gp, m, xi):
    """Whether Gauss point ``gp`` of ``e`` has cracked: yielded onto its tension cut-off.

    The last update yielded and the in-plane major principal stress is at the tension cut-off
    in force at its softening fraction ``xi`` (``softening.strength_at``). Only a cut-off
    below the Mohr-Coulomb apex counts (a given tensile strength: a Rankine plane, whose
    normal is the crack's); at the apex every direction is alike and the rule does not apply.
    """
    if yielded[e, gp] == 0:
        return False
    c, sin_phi, cos_phi, _, t = strength_at(material_table, m, xi)
    if t >= NO_TENSION_CUTOFF or (sin_phi > 0.0 and t >= c * cos_phi / sin_phi * (1.0 - 1e-10)):
        return False
    sxx = stress[e, gp, 0]
    syy = stress[e, gp, 1]
    sxy = stress[e, gp, 3]
    h = 0.5 * (sxx - syy)
    rad = math.sqrt(h * h + sxy * sxy)
    s1 = 0.5 * (sxx + syy) + rad
    scale = abs(sxx) + abs(syy) + abs(stress[e, gp, 2]) + abs(sxy) + c + abs(t)
    return s1 >= t - CUTOFF_TOLERANCE * scale


@numba.njit(cache=True, parallel=True)
def _failure_kernel(x, element_nodes, element_material, stress, interface_elements,
                    interface_nodes, interface_intact, interface_splittable, interface_table,
                    material_table, element_length, plastic_strain, yielded, plastic_limit,
                    fragment, out):
    """out[i]: 0 holds, 1 tension, 2 shear, 3 plastic strain, 4 softened, 5 distorted.

    Mode 5: an element beside the interface is a fragment (``mark_fragments``).
    """
    n_if = interface_elements.shape[0]
    ngp = stress.shape[1]
    for i in numba.prange(n_if):
        out[i] = 0
        if not (interface_intact[i] and interface_splittable[i]):
            continue
        ea = interface_elements[i, 0]
        eb = interface_elements[i, 1]
        a0 = interface_nodes[i, 0]
        a1 = interface_nodes[i, 1]
        sxx = 0.0
        syy = 0.0
        sxy = 0.0
        eps_p = 0.0
        cnt = 0.0
        softened = 0.0  # the larger of the two sides' mean softening fractions
        cracked = False  # every point next to the edge on one side at least has cracked
        for side in range(2):
            e = ea if side == 0 else eb
            m = element_material[e]
            # the edge starts at a0 in A and at b1 in B (both counter-clockwise)
            k = _local_index(element_nodes, e, a0 if side == 0 else interface_nodes[i, 3])
            xi = 0.0
            side_cracked = True
            if ngp == 1:
                sxx += stress[e, 0, 0]
                syy += stress[e, 0, 1]
                sxy += stress[e, 0, 3]
                eps_p += plastic_strain[e, 0]
                xi = softening_fraction(material_table, m, plastic_strain[e, 0],
                                        element_length[e])
                side_cracked = _cracked_point(stress, yielded, material_table, e, 0, m, xi)
                cnt += 1.0
            else:
                for gp in (k, (k + 1) % 4):
                    sxx += stress[e, gp, 0]
                    syy += stress[e, gp, 1]
                    sxy += stress[e, gp, 3]
                    eps_p += plastic_strain[e, gp]
                    xi_gp = softening_fraction(material_table, m, plastic_strain[e, gp],
                                               element_length[e])
                    xi += 0.5 * xi_gp
                    side_cracked = side_cracked and _cracked_point(
                        stress, yielded, material_table, e, gp, m, xi_gp)
                    cnt += 1.0
            softened = max(softened, xi)
            cracked = cracked or side_cracked
        sxx /= cnt
        syy /= cnt
        sxy /= cnt
        dx = x[a1, 0] - x[a0, 0]
        dy = x[a1, 1] - x[a0, 1]
        ln = math.sqrt(dx * dx + dy * dy)
        nx = dy / ln
        ny = -dx / ln
        tx = sxx * nx + sxy * ny
        ty = sxy * nx + syy * ny
        sn = tx * nx + ty * ny
        tau = math.sqrt((tx - sn * nx) ** 2 + (ty - sn * ny) ** 2)
        ma = element_material[ea]
        mb = element_material[eb]
        p = max(-sn, 0.0)  # thesis 4.5, the weaker side's Mohr-Coulomb strength at p
        strength = min(interface_table[ma, 0] + p * interface_table[ma, 1],
                       interface_table[mb, 0] + p * interface_table[mb, 1])
        ft = min(interface_table[ma, 2], interface_table[mb, 2])
        # a crack's plane (normal along the major principal stress) is followed by the edges
        # nearer to it than to its normal: sn at least the in-plane mean stress (every edge
        # where the two principal stresses are equal, as at a biaxial crack)
        mean = 0.5 * (sxx + syy)
        facing = sn >= mean - CUTOFF_TOLERANCE * (abs(sxx) + abs(syy) + abs(sxy))
        if sn > ft or (cracked and facing):
            out[i] = FAIL_TENSION
        elif tau > strength:
            out[i] = FAIL_SHEAR
        elif softened >= 1.0 - 1.0e-12:
            out[i] = FAIL_SOFTENED
        elif eps_p / cnt > plastic_limit:
            out[i] = FAIL_PLASTIC
        elif fragment[ea] or fragment[eb]:
            out[i] = FAIL_DISTORTED
        else:
            out[i] = 0


def stable_step_ratio(state: DiscreteState) -> np.ndarray:
    """Each element's time-step scale now over its value at creation (n_elements,) [-].

    The smaller of h / h_ref and sqrt(L_ref / L) (h the least altitude, L the longest edge:
    the mesh and the contact bounds of ``integrate.stable_time_step``); 1 for an undeformed
    element or one whose nodes are all held, 0 for one turned inside out.
    """
    out = np.ones(state.n_elements)
    if state.n_elements:
        _stable_step_ratio_kernel(state.x, state.x_ref, state.element_nodes, state.fixed, out)
    return out


def corner_ratio(state: DiscreteState) -> np.ndarray:
    """Each element's least corner Jacobian now over its value at creation (n_elements,) [-].

    The Jacobian at a corner is the cross product of the edges into and out of it
    (counter-clockwise: positive while the element is convex there). 1 for an undeformed
    element, a parallelogram sheared at constant area or one whose nodes are all held; 0 at
    a corner folded flat, negative past it.
    """
    out = np.ones(state.n_elements)
    if state.n_elements:
        _corner_ratio_kernel(state.x, state.x_ref, state.element_nodes, state.fixed, out)
    return out


def mark_fragments(state: DiscreteState, limit: float = DISTORTION_LIMIT,
                   corner_limit: float = CORNER_LIMIT) -> int:
    """Make fragments of the elements distorted beyond the limits.

    Distorted: the time-step scale ratio below ``limit``, or a Q4 folding at a corner
    (``corner_ratio`` below ``corner_limit``). A new fragment's ``state.fragment_cap`` is the
    largest plastic strain of its points now; a fragment stays one with that cap. Returns how
    many became fragments.
    """
    distorted = (stable_step_ratio(state) < limit) | (corner_ratio(state) < corner_limit)
    new = distorted & np.isinf(state.fragment_cap)
    if new.any():
        state.fragment_cap[new] = state.plastic_strain[new].max(axis=1)
    return int(new.sum())


def check_interfaces(state: DiscreteState, split_plastic_strain: float = math.inf
                     ) -> np.ndarray:
    """Failure mode per interface (n_if,) int8.

    0 holds, 1 tension, 2 shear, 3 plastic strain above ``split_plastic_strain``, 4 the
    material beside it softened to residual, 5 an element beside it is a fragment (see
    module).
    """
    out = np.zeros(state.interface_elements.shape[0], dtype=np.int8)
    if out.size:
        _failure_kernel(state.x, state.element_nodes, state.element_material, state.stress,
                        state.interface_elements, state.interface_nodes,
                        state.interface_intact, state.interface_splittable,
                        state.interface_table, state.material_table, state.element_length,
                        state.plastic_strain, state.yielded, float(split_plastic_strain),
                        np.isfinite(state.fragment_cap), out)
    return out


def failure_modes(state: DiscreteState) -> dict[str, int]:
    """How many failed interfaces failed by each mode: {name in ``MODE_NAMES``: count}.

    From ``DiscreteState.interface_mode``; "not_recorded" counts those failed other than at
    a run's splitting check (at creation, or by the caller).
    """
    return {**dict.fromkeys(MODE_NAMES, 0),
            **mode_counts(state.interface_mode[~state.interface_intact])}


def mode_counts(modes: np.ndarray) -> dict[str, int]:
    """{name in ``MODE_NAMES``: count} of the modes that occur in ``modes`` (mode numbers)."""
    return {MODE_NAMES[k]: int((modes == k).sum()) for k in np.unique(modes)}


def split_interfaces(state: DiscreteState, failed) -> int:
    """Mark the interfaces ``failed`` (indices or bool mask) as broken and re-split groups.

    The tie groups of their vertices are split into connected components over the intact
    interfaces.

    Returns the number of interfaces newly broken. Group ids are renumbered compactly in
    order of first appearance (deterministic); the CSR arrays are rebuilt.
    """
    failed = np.asarray(failed)
    idx = np.flatnonzero(failed) if failed.dtype == bool else failed.astype(np.int64)
    idx = idx[state.interface_intact[idx]]
    if idx.size == 0:
        return 0
    state.interface_intact[idx] = False
    groups = np.unique(state.node_group[state.interface_nodes[idx].ravel()])
    # intact interfaces touching the affected groups: their node pairs (a0-b0, a1-b1)
    ifn = state.interface_nodes[state.interface_intact]
    # plus the permanent links of rigid platens (``DiscreteState.tie_rigidly``)
    links = np.concatenate([ifn[:, [0, 2]], ifn[:, [1, 3]], state.rigid_links])
    touch = np.isin(state.node_group[links[:, 0]], groups)
    links = links[touch]
    ng_old = state.n_groups
    node_group = state.node_group.copy()
    parent: dict[int, int] = {}

    def find(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    next_id = ng_old
    for g in groups:
        members = state.group_nodes[state.group_ptr[g]:state.group_ptr[g + 1]]
        for m in members:
            parent[int(m)] = int(m)
    for a, b in links:
        ra, rb = find(int(a)), find(int(b))
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    for g in groups:
        members = state.group_nodes[state.group_ptr[g]:state.group_ptr[g + 1]]
        roots = [find(int(m)) for m in members]
        # the component holding the group's first member keeps the old id
        ids = {roots[0]: int(g)}
        for r in roots[1:]:
            if r not in ids:
                ids[r] = next_id
                next_id += 1
        for m, r in zip(members, roots):
            node_group[m] = ids[r]
    state.node_group = node_group
    state.group_ptr, state.group_nodes = groups_csr(node_group, next_id)
    # masses of the new groups; the energy accumulators are folded into the ledger
    state.ledger[LEDGER_GROUPS] += state.group_energy.sum(axis=0)
    state.group_energy = np.zeros((next_id, 4))
    state.refresh_groups()
    return int(idx.size)


def plastic_cap(state: DiscreteState, cap: float = math.inf) -> np.ndarray:
    """Plastic strain beyond which each element's Gauss points respond elastically [-].

    ``cap`` (``RunOptions.plastic_strain_cap``, an expert option; inf: none) for every
    element, and a fragment's ``state.fragment_cap`` (see module). An element beside a failed
    interface goes on yielding: a softened band at its residual and the crack that opened in
    it carry the same residual strength (``Contact``), and where the band's elements distort
    as far as an element can follow, they become fragments. Returns (n_elements,).
    """
    return np.minimum(np.full(state.element_nodes.shape[0], float(cap)), state.fragment_cap)


def limit_splitting(state: DiscreteState, elements) -> int:
    """Allow splitting only on interfaces touching the given elements.

    ``elements``: indices or a bool mask over elements, e.g. the handover's yielded region.
    Returns how many interfaces stay splittable.
    """
    elements = np.asarray(elements)
    mask = np.zeros(state.n_elements, dtype=bool)
    if elements.dtype == bool:
        if elements.shape != (state.n_elements,):
            raise ValueError(f"element mask has shape {elements.shape}: expected "
                             f"({state.n_elements},)")
        mask = elements.copy()
    else:
        if elements.size and (elements.min() < 0 or elements.max() >= state.n_elements):
            raise ValueError("element indices out of range 0..n_elements-1")
        mask[elements] = True
    ie = state.interface_elements
    state.interface_splittable = mask[ie[:, 0]] | mask[ie[:, 1]]
    return int(state.interface_splittable.sum())
