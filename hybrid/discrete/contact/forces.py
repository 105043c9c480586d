"""Contact forces of the candidate pairs.

The parallel loop over the pairs and the public entry point that checks its inputs.

``contact_forces`` validates its arguments and calls ``add_contact_forces``; the explicit
loop (``ExplicitSolver.step``) calls ``add_contact_forces`` itself every step, with the
``ContactBuffers`` it made once, and pays no O(n) check per step.

Determinism: every pair is computed into a per-pair buffer (``prange`` over interleaved
blocks of pairs, no reductions) and scattered to the nodes serially in pair order, so the
results are bit-identical for any number of threads.

Speed: element boxes and reflex vertices are computed once per call (not per pair) and a
pair whose boxes do not overlap returns before its coordinates are gathered; scratch and
per-pair outputs are passed as whole arrays with an index (an array view such as
``shear[p]`` costs numba an atomic reference count per pair, and the threads contend for
it); two convex elements are clipped without copying them into pieces; the work items take
interleaved blocks of pairs (numba's static schedule otherwise gives one thread most of the
active pairs, which cluster because the pairs are sorted by element).  Every work array
belongs to the caller (``ContactBuffers``): a step allocates nothing.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

import hybrid  # noqa: F401  (sets NUMBA_CACHE_DIR / OMP_WAIT_POLICY before numba compiles)
from hybrid.discrete.contact.law import pair_contact
from hybrid.discrete.contact.polygon import MAXV, boxes_apart, check_mesh, element_box_reflex

_CHUNK = 64  # pairs per block of consecutive pairs
_N_ITEMS = 64  # parallel work items; item i takes blocks i, i + 64, ... (load balance)
_NO_SPLIT = np.zeros((2, 1, 2))  # stands in for split_force when none is asked for


class ContactBuffers:
    """Work arrays of ``add_contact_forces``.

    Made once by the caller, reused every step and grown (never shrunk) when the mesh or the
    pair list outgrows them.

    Per element: ``boxes`` (box [xmin, ymin, xmax, ymax]) and ``reflex`` (reflex vertex, -1:
    convex).  Per pair (the first ``n_pairs`` rows are used): ``f_pair`` (force on B),
    ``w_a``/``w_b`` (shape-function weights at the contact point), ``diss`` (friction,
    damping dissipation), ``f_split`` (damping and tangential parts), ``active``.  Per
    parallel work item: ``xy`` (the two elements' vertices) and ``clip`` (four clipping
    buffers).
    """

    def __init__(self) -> None:
        self.boxes = np.empty((0, 4))
        self.reflex = np.empty(0, dtype=np.int64)
        self._alloc_pairs(0)
        self.xy = np.empty((_N_ITEMS, 2, 4, 2))
        self.clip = np.empty((_N_ITEMS, 4, MAXV, 3))

    def _alloc_pairs(self, capacity: int) -> None:
        self.f_pair = np.empty((capacity, 2))
        self.w_a = np.empty((capacity, 4))
        self.w_b = np.empty((capacity, 4))
        self.diss = np.empty((capacity, 2))
        self.f_split = np.empty((capacity, 4))
        self.active = np.empty(capacity, dtype=np.int8)

    def fit(self, n_elements: int, n_pairs: int) -> None:
        """Make room for ``n_elements`` elements and ``n_pairs`` pairs (O(1) when there is)."""
        if self.boxes.shape[0] < n_elements:
            self.boxes = np.empty((n_elements, 4))
            self.reflex = np.empty(n_elements, dtype=np.int64)
        capacity = self.active.shape[0]
        if capacity < n_pairs:
            self._alloc_pairs(max(n_pairs, capacity + capacity // 4))


@njit(parallel=True, cache=True)
def _contact_kernel(x, v, mass, element_nodes, element_material, contact_table, pairs, shear, dt,
                    force, split_force, with_split, boxes, reflex, f_pair, w_a, w_b, diss,
                    f_split, active, xy, clip):
    """``add_contact_forces`` (see there) with the work arrays of ``ContactBuffers``.

    With ``with_split`` the damping part of the normal forces (as applied, after the clamp)
    is also added to ``split_force[0]`` and the tangential part to ``split_force[1]``.
    """
    n_pairs = pairs.shape[0]
    n_el = element_nodes.shape[0]
    nen = element_nodes.shape[1]
    for e in prange(n_el):  # per element, once per call (not once per pair)
        element_box_reflex(x, element_nodes, e, boxes, reflex)
    n_blocks = (n_pairs + _CHUNK - 1) // _CHUNK
    n_items = min(_N_ITEMS, n_blocks)
    for item in prange(n_items):
        pa = xy[item, 0]
        pb = xy[item, 1]
        piece_a = clip[item, 0]
        piece_b = clip[item, 1]
        out = clip[item, 2]
        tmp = clip[item, 3]
        for blk in range(item, n_blocks, n_items):
            start = blk * _CHUNK
            stop = min(n_pairs, start + _CHUNK)
            for p in range(start, stop):
                a = pairs[p, 0]
                b = pairs[p, 1]
                if boxes_apart(boxes, a, b):  # most candidate pairs: no overlap, no force
                    active[p] = 0
                    shear[p, 0] = 0.0
                    shear[p, 1] = 0.0
                    continue
                act, fx, fy, d_f, d_d, fd, nx, ny = pair_contact(
                    a, b, reflex[a], reflex[b], x, v, mass, element_nodes, element_material,
                    contact_table, shear, p, dt, pa, pb, piece_a, piece_b, out, tmp, w_a, w_b)
                active[p] = act
                f_pair[p, 0] = fx
                f_pair[p, 1] = fy
                diss[p, 0] = d_f
                diss[p, 1] = d_d
                if with_split and act:
                    f_split[p, 0] = fd * nx
                    f_split[p, 1] = fd * ny
                    f_split[p, 2] = shear[p, 0]
                    f_split[p, 3] = shear[p, 1]
    n_active = 0
    diss_f = 0.0
    diss_d = 0.0
    for p in range(n_pairs):  # serial scatter in pair order: deterministic sums
        if active[p] == 0:
            continue
        n_active += 1
        diss_f += diss[p, 0]
        diss_d += diss[p, 1]
        a = pairs[p, 0]
        b = pairs[p, 1]
        fx = f_pair[p, 0]
        fy = f_pair[p, 1]
        for k in range(nen):
            na_ = element_nodes[a, k]
            nb_ = element_nodes[b, k]
            force[na_, 0] -= w_a[p, k] * fx
            force[na_, 1] -= w_a[p, k] * fy
            force[nb_, 0] += w_b[p, k] * fx
            force[nb_, 1] += w_b[p, k] * fy
        if with_split:
            for c in range(2):
                dx = f_split[p, 2 * c]
                dy = f_split[p, 2 * c + 1]
                for k in range(nen):
                    na_ = element_nodes[a, k]
                    nb_ = element_nodes[b, k]
                    split_force[c, na_, 0] -= w_a[p, k] * dx
                    split_force[c, na_, 1] -= w_a[p, k] * dy
                    split_force[c, nb_, 0] += w_b[p, k] * dx
                    split_force[c, nb_, 1] += w_b[p, k] * dy
    return n_active, diss_f, diss_d


def add_contact_forces(x: np.ndarray, v: np.ndarray, mass: np.ndarray, element_nodes: np.ndarray,
                       element_material: np.ndarray, contact_table: np.ndarray,
                       pairs: np.ndarray, shear: np.ndarray, dt: float, force: np.ndarray,
                       split_force: np.ndarray | None,
                       buffers: ContactBuffers) -> tuple[int, float, float]:
    """``contact_forces`` without the input checks, with the caller's work arrays.

    The hot path of the explicit loop (arguments and return as ``contact_forces``).

    Nothing is checked here: wrong shapes, dtypes or indices read or write out of bounds.
    """
    buffers.fit(element_nodes.shape[0], pairs.shape[0])
    b = buffers
    with_split = split_force is not None
    return _contact_kernel(x, v, mass, element_nodes, element_material, contact_table, pairs,
                           shear, dt, force, split_force if with_split else _NO_SPLIT,
                           with_split, b.boxes, b.reflex, b.f_pair, b.w_a, b.w_b, b.diss,
                           b.f_split, b.active, b.xy, b.clip)


def _in_place(name: str, arr: np.ndarray, shape: tuple[int, ...]) -> None:
    """Check an array that ``contact_forces`` updates in place."""
    if not isinstance(arr, np.ndarray) or arr.dtype != np.float64 or not arr.flags.writeable:
        raise ValueError(
            f"{name} is updated in place: it must be a writeable float64 numpy array of shape "
            f"{shape} (e.g. np.zeros({shape})), got {type(arr).__name__} "
            f"{getattr(arr, 'dtype', '')}"
        )
    if arr.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {arr.shape}")


def _indices(name: str, arr: np.ndarray, what: str) -> np.ndarray:
    """An index array as int64 (a ValueError unless it holds integers)."""
    arr = np.asarray(arr)
    if arr.size and arr.dtype.kind not in "iu":
        raise ValueError(f"{name} must hold integer indices of {what}, got dtype {arr.dtype}")
    return np.ascontiguousarray(arr, dtype=np.int64)


def contact_forces(
    x: np.ndarray,
    v: np.ndarray,
    mass: np.ndarray,
    element_nodes: np.ndarray,
    element_material: np.ndarray,
    contact_table: np.ndarray,
    pairs: np.ndarray,
    shear: np.ndarray,
    dt: float,
    force: np.ndarray,
    split_force: np.ndarray | None = None,
) -> tuple[int, float, float]:
    """Add the contact forces of the candidate ``pairs`` to ``force`` (n_nodes, 2) in place.

    Arguments (state layout of ``DiscreteState``): ``x``, ``v`` (n_nodes, 2) [m, m/s];
    ``mass`` (n_nodes,) lumped masses [t] (``inf`` on rigid elements, see
    ``rigid_contact_mass``); ``element_nodes`` (n_el, 3 or 4) ccw; ``element_material``
    (n_el,); ``contact_table`` (n_mat, 5) = [k_n kPa/m, k_t kPa/m, mu, zeta, c kPa] (4
    columns: c = 0, a cohesionless contact); ``pairs``
    (n_pairs, 2) from ``find_contact_pairs``; ``shear`` (n_pairs, 2) tangential force
    history on B [kN/m], updated in place (zeroed for separated pairs); ``dt`` [s].
    ``split_force`` (2, n_nodes, 2), if given, receives (added) two parts of the nodal
    contact forces for the energy ledger: [0] the damping part of the normal forces as
    applied (after the no-adhesion clamp), [1] the tangential (friction spring) forces;
    their work with the mid-step velocity (``mid_step_work``) is the energy the
    central-difference update exchanges with them.  ``force``, ``shear`` and
    ``split_force`` must be writeable float64 arrays.

    Returns ``(n_active, dissipated_friction, dissipated_damping)``: number of pairs in
    contact and the energy dissipated during this step [kJ/m], both evaluated with the
    velocity ``v`` given (the start-of-step velocity v(t - dt/2) in the explicit loop: for
    damping this overestimates the dissipation when the contact vibrates near the time-step
    frequency, see ``mid_step_work``).  The inputs are checked (a ValueError says what is
    wrong); a loop calling this every step can call ``add_contact_forces`` instead, with
    ``ContactBuffers`` made once.
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    element_nodes = _indices("element_nodes", element_nodes, "nodes")
    check_mesh(x, element_nodes)
    n_nodes = x.shape[0]
    n_el = element_nodes.shape[0]
    v = np.ascontiguousarray(v, dtype=np.float64)
    mass = np.ascontiguousarray(mass, dtype=np.float64)
    element_material = _indices("element_material", element_material, "contact_table rows")
    pairs = _indices("pairs", pairs, "elements")
    for name, arr, shape in (
        ("v", v, (n_nodes, 2)),
        ("mass", mass, (n_nodes,)),
        ("element_material", element_material, (n_el,)),
    ):
        if arr.shape != shape:
            raise ValueError(f"{name} must have shape {shape}, got {arr.shape}")
    if pairs.ndim != 2 or pairs.shape[1] != 2:
        raise ValueError(f"pairs must have shape (n_pairs, 2), got {pairs.shape}")
    _in_place("shear", shear, (pairs.shape[0], 2))
    _in_place("force", force, (n_nodes, 2))
    if split_force is not None:
        _in_place("split_force", split_force, (2, n_nodes, 2))
    if not np.isfinite(v).all():
        raise ValueError("v (velocities) contains NaN or inf: the run is unstable")
    if np.isnan(mass).any() or (mass < 0).any():
        raise ValueError("mass must be >= 0 (inf marks rigid elements), got NaN or negative")
    ct = np.ascontiguousarray(contact_table, dtype=np.float64)
    if ct.ndim != 2 or ct.shape[1] not in (4, 5):
        raise ValueError(f"contact_table must have shape (n_materials, 5) (or 4: no cohesion), "
                         f"got {ct.shape}")
    if ct.shape[1] == 4:
        ct = np.hstack([ct, np.zeros((ct.shape[0], 1))])
    if not np.isfinite(ct).all() or (ct < 0).any():
        raise ValueError(f"contact_table entries [k_n, k_t, mu, zeta, c] must be finite and "
                         f">= 0, got {ct.tolist()}")
    if element_material.size and (
        element_material.min() < 0 or element_material.max() >= ct.shape[0]
    ):
        raise ValueError(f"element_material must index contact_table rows 0..{ct.shape[0] - 1}")
    if pairs.size and (pairs.min() < 0 or pairs.max() >= n_el):
        raise ValueError(f"pairs must index elements 0..{n_el - 1}")
    dt = float(dt)
    if not (np.isfinite(dt) and dt > 0.0):
        raise ValueError(f"dt must be a finite time step > 0 [s], got {dt}")
    return add_contact_forces(x, v, mass, element_nodes, element_material, ct, pairs, shear, dt,
                              force, split_force, ContactBuffers())


def rigid_contact_mass(
    mass: np.ndarray, fixed: np.ndarray, element_nodes: np.ndarray
) -> np.ndarray:
    """Nodal masses for ``contact_forces``.

    ``inf`` on the nodes of elements whose nodes are all fixed in both directions (rigid
    ground, walls), the lumped mass elsewhere.
    """
    mass = np.asarray(mass, dtype=np.float64)
    fixed = np.asarray(fixed, dtype=bool)
    if fixed.shape != (mass.shape[0], 2):
        raise ValueError(f"fixed must have shape (n_nodes, 2) = ({mass.shape[0]}, 2)")
    rigid = fixed.all(axis=1)[element_nodes].all(axis=1)
    out = mass.copy()
    out[element_nodes[rigid].ravel()] = np.inf
    return out
