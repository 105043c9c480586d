"""The discrete engine's state: one dataclass of contiguous arrays (structure of arrays).

Every element owns its nodes (an interior mesh vertex shared by four elements is four nodes at
one place); coincident nodes are *tied* (they share one velocity) while the material between
them is intact. Units: m, kN, kPa, s, t/m3; per unit thickness (plane strain).
Sign convention: tension positive. Stress in Voigt order (xx, yy, zz, xy).
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np

from hybrid.constitutive.softening import characteristic_length
from hybrid.constitutive.table import (
    BULK_MODULUS,
    SHEAR_MODULUS,
    TABLE_WIDTH,
    kernel_table,
    tension_cutoff,
)
from hybrid.materials import GRAVITY, Material

__all__ = ["DiscreteState", "from_mesh", "material_rows", "check_elements", "read_checkpoint",
           "groups_csr", "Q4_GAUSS"]

#: Default of the engine's work arrays: ``__post_init__`` makes them to the state's size.
MADE_ON_CREATION: Any = None

# Q4 2x2 Gauss points, point k next to node k (counter-clockwise corner order).
_G = 1.0 / math.sqrt(3.0)
Q4_GAUSS = np.array([[-_G, -_G], [_G, -_G], [_G, _G], [-_G, _G]])

# Slots of ``DiscreteState.ledger``, the energy accumulators of the run [kJ/m] (see
# ``hybrid.discrete.ledger`` for what each term means).
LEDGER_FRICTION = 0  # minus the work of the tangential contact forces
LEDGER_CONTACT_DAMPING = 1  # minus the work of the contact damping forces
LEDGER_GROUPS = slice(2, 6)  # group_energy's four columns, folded in when groups change
LEDGER_CONTACT_NORMAL = 6  # minus the work of the elastic normal contact forces


def material_rows(materials: Sequence[Material], element_size: float):
    """The state's material tables from a sequence of ``Material``.

    Returns (material_table (n, 7) and elastic_only (n,) from ``kernel_table``, density (n,)
    [t/m3], interface_table (n, 3) [bond cohesion kPa, tan phi, tensile strength kPa] and
    contact_table (n, 5) [k_n kPa/m, k_t kPa/m, mu, zeta, c kPa]); ``element_size`` [m] sets
    the default contact stiffness k_n = 10 E / size. A bond left unset follows the material's
    own strength when it is plastic and never breaks when it is elastic (``Bond``); the
    contact strength left unset is the material's residual strength (c_r, phi_r) when it
    softens, else its phi without cohesion (``Contact``).
    """
    mt, el = kernel_table(materials)
    n = len(materials)
    dens = np.zeros(n)
    it = np.zeros((n, 3))
    ct = np.zeros((n, 5))
    for i, m in enumerate(materials):
        if not m.density > 0.0:
            raise ValueError(f"materials[{i}] ('{m.name}') has unit_weight {m.unit_weight}: the "
                             "discrete engine needs mass, give unit_weight > 0 kN/m3 (or "
                             "density > 0 t/m3)")
        dens[i] = m.density
        bond, contact = m.bond, m.contact
        if m.is_plastic:
            own = (m.cohesion, m.phi, tension_cutoff(m.peak))
        else:  # no strength: unbreakable unless given
            own = (math.inf, m.phi, math.inf)
        c = own[0] if bond.cohesion is None else bond.cohesion
        phi = own[1] if bond.phi is None else bond.phi
        ft = own[2] if bond.tensile_strength is None else bond.tensile_strength
        it[i] = [c, math.tan(math.radians(phi)), ft]
        kn = (contact.normal_stiffness if contact.normal_stiffness is not None
              else 10.0 * m.E / element_size)
        kt = contact.shear_stiffness if contact.shear_stiffness is not None else kn
        # a crack in a softening material carries its residual strength (Contact)
        own_c, own_phi = (0.0, m.phi) if m.residual is None else (m.residual.cohesion,
                                                                  m.residual.phi)
        phic = contact.phi if contact.phi is not None else own_phi
        cc = contact.cohesion if contact.cohesion is not None else own_c
        ct[i] = [kn, kt, math.tan(math.radians(phic)), contact.damping, cc]
    return mt, dens, el, it, ct


@dataclass
class DiscreteState:
    """All arrays of the discrete engine (see module docstring; shapes and units per field)."""

    x: np.ndarray  # (n_nodes, 2) current coordinates [m]
    x_ref: np.ndarray  # (n_nodes, 2) coordinates at creation [m]
    v: np.ndarray  # (n_nodes, 2) velocity at t - dt/2 [m/s]
    mass: np.ndarray  # (n_nodes,) lumped mass [t per m thickness]
    element_nodes: np.ndarray  # (n_elements, nen) int64, counter-clockwise, nen 4 (Q4) or 3 (T3)
    element_material: np.ndarray  # (n_elements,) int32 index into the material tables
    stress: np.ndarray  # (n_elements, ngp, 4) Cauchy stress at Gauss points [kPa]
    plastic_strain: np.ndarray  # (n_elements, ngp) accumulated plastic strain measure [-]
    yielded: np.ndarray  # (n_elements, ngp) int8, 1 where the last update yielded
    node_group: np.ndarray  # (n_nodes,) int64 tie-group id of each node
    group_ptr: np.ndarray  # (n_groups + 1,) int64 CSR pointers into group_nodes
    group_nodes: np.ndarray  # (n_nodes,) int64 nodes of each group, ascending within a group
    interface_elements: np.ndarray  # (n_if, 2) int64 elements A, B sharing an edge
    interface_nodes: np.ndarray  # (n_if, 4) int64 [a0, a1, b0, b1]; b0 at a0, b1 at a1
    interface_intact: np.ndarray  # (n_if,) bool
    interface_splittable: np.ndarray  # (n_if,) bool, splitting checked only where True
    fixed: np.ndarray  # (n_nodes, 2) bool, velocity held at prescribed_velocity
    prescribed_velocity: np.ndarray  # (n_nodes, 2) [m/s]
    external_force: np.ndarray  # (n_nodes, 2) [kN/m]
    material_table: np.ndarray  # (n_mat, TABLE_WIDTH) kernel rows (hybrid.constitutive.table)
    density: np.ndarray  # (n_mat,) [t/m3]
    elastic_only: np.ndarray  # (n_mat,) bool, skip the Mohr-Coulomb return
    interface_table: np.ndarray  # (n_mat, 3) [cohesion kPa, tan_phi, tensile_strength kPa]
    contact_table: np.ndarray  # (n_mat, 5) [k_n kPa/m, k_t kPa/m, mu, zeta, c kPa]
    gravity: np.ndarray = field(default_factory=lambda: np.array([0.0, -GRAVITY]))  # (2,) [m/s2]
    time: float = 0.0  # [s]
    step: int = 0
    # engine work arrays (part of the state so that a checkpoint restarts bit for bit)
    internal_force: np.ndarray = MADE_ON_CREATION  # (n_nodes, 2) I = sum B^T sigma dA [kN/m]
    group_mass: np.ndarray = MADE_ON_CREATION  # (n_groups,) summed lumped mass per tie group [t/m]
    group_energy: np.ndarray = MADE_ON_CREATION  # (n_groups, 4) [work of loads and gravity, work of
    #     supports, mass-damping and dashpot dissipation, local-damping dissipation]
    #     accumulated per group [kJ/m]
    ledger: np.ndarray = MADE_ON_CREATION  # (8,) [friction, contact damping, then
    #     group_energy's four columns folded in when groups are renumbered, elastic normal
    #     contact work, -] [kJ/m]; slots LEDGER_FRICTION, LEDGER_CONTACT_DAMPING,
    #     LEDGER_GROUPS, LEDGER_CONTACT_NORMAL
    contact_pairs: np.ndarray = MADE_ON_CREATION  # (n_pairs, 2) int64 current candidate pairs
    contact_shear: np.ndarray = MADE_ON_CREATION  # (n_pairs, 2) tangential spring force [kN/m]
    primed: bool = False  # internal_force consistent with (x, stress)
    dt: float = 0.0  # time step of the last run [s] (reused on restart when dt is not given)
    rigid_links: np.ndarray = MADE_ON_CREATION  # (n_links, 2) int64 node pairs kept in one tie
    #     group whatever splits (``tie_rigidly``: a rigid, non-rotating platen such as a footing)
    element_length: np.ndarray = MADE_ON_CREATION  # (n_elements,) crack-band width of each
    #     element at creation [m] (sqrt(A) Q4, sqrt(2 A) T3), the length of strain softening
    fragment_cap: np.ndarray = MADE_ON_CREATION  # (n_elements,) plastic strain beyond which a
    #     fragment responds elastically [-]: inf until the element has distorted as far as an
    #     element follows the flow, then the largest plastic strain of its points at that
    #     moment, for good; its splittable bonds fail (``ties.DISTORTION_LIMIT``)
    walls: np.ndarray = MADE_ON_CREATION  # (n_walls, 5) smooth rigid walls [n_x, n_y, c, s_min,
    #     s_max]: the planes of the roller supports, frictionless contact for every element
    #     (``contact.walls``); none by default
    wall_nodes: np.ndarray = MADE_ON_CREATION  # (n, 2) int64 [wall row, node]: the support
    #     nodes each wall belongs to; a wall goes when none of them is held along its normal
    #     (a wall with none listed stands for good)
    dashpot: np.ndarray = MADE_ON_CREATION  # (n_nodes, 2) viscous dashpot on each component
    #     of a node of a transmitting boundary [kN s/m2: kN/m per m/s]: the force -dashpot v
    #     lets waves leave through a boundary that truncates a larger ground (Lysmer &
    #     Kuhlemeyer 1969; ``set_transmitting``); zero by default
    interface_mode: np.ndarray = MADE_ON_CREATION  # (n_if,) int8 how each failed interface
    #     failed at a splitting check of a run (``ties.FAIL_TENSION`` ... ``FAIL_DISTORTED``);
    #     0 while intact, and for one failed otherwise (at creation, or by the caller)
    interface_failure_time: np.ndarray = MADE_ON_CREATION  # (n_if,) state time at the
    #     splitting check that failed each interface [s]; nan while intact, and for one failed
    #     otherwise (as interface_mode)

    def __post_init__(self) -> None:
        n = self.x.shape[0]
        ct = np.asarray(self.contact_table)
        if ct.ndim != 2 or ct.shape[1] != 5:
            raise ValueError(f"contact_table has shape {ct.shape}: give (n_materials, 5) rows "
                             "[k_n kPa/m, k_t kPa/m, mu, zeta, c kPa] (material_rows)")
        if self.internal_force is None:
            self.internal_force = np.zeros((n, 2))
        if self.group_mass is None:
            self.group_mass = np.zeros(self.n_groups)
            self.refresh_groups()
        if self.group_energy is None:
            self.group_energy = np.zeros((self.n_groups, 4))
        if self.ledger is None:
            self.ledger = np.zeros(8)
        if self.contact_pairs is None:
            self.contact_pairs = np.zeros((0, 2), dtype=np.int64)
        if self.contact_shear is None:
            self.contact_shear = np.zeros((0, 2))
        if self.rigid_links is None:
            self.rigid_links = np.zeros((0, 2), dtype=np.int64)
        if self.element_length is None:
            self.element_length = characteristic_length(self.x_ref, self.element_nodes)
        if self.fragment_cap is None:
            self.fragment_cap = np.full(self.element_nodes.shape[0], np.inf)
        if self.dashpot is None:
            self.dashpot = np.zeros((n, 2))
        if self.walls is None:
            self.walls = np.zeros((0, 5))
        if self.wall_nodes is None:
            self.wall_nodes = np.zeros((0, 2), dtype=np.int64)
        if self.interface_mode is None:
            self.interface_mode = np.zeros(self.interface_elements.shape[0], dtype=np.int8)
        if self.interface_failure_time is None:
            self.interface_failure_time = np.full(self.interface_elements.shape[0], np.nan)
        if self.material_table.ndim != 2 or self.material_table.shape[1] != TABLE_WIDTH:
            raise ValueError(f"material_table has shape {self.material_table.shape}; need "
                             f"(n_mat, {TABLE_WIDTH}) rows from kernel_table (a checkpoint "
                             "of an older version: restart from the handover)")

    # -- sizes ------------------------------------------------------------------------------
    @property
    def n_nodes(self) -> int:
        """Number of nodes (every element owns its own)."""
        return int(self.x.shape[0])

    @property
    def n_elements(self) -> int:
        """Number of elements."""
        return int(self.element_nodes.shape[0])

    @property
    def nen(self) -> int:
        """Nodes per element: 4 (Q4) or 3 (T3)."""
        return int(self.element_nodes.shape[1])

    @property
    def n_groups(self) -> int:
        """Number of tie groups (nodes sharing one velocity)."""
        return int(self.group_ptr.shape[0] - 1)

    def refresh_groups(self) -> None:
        """Recompute group_mass from mass and the tie groups.

        Called after the groups or masses changed; group_energy is folded into the ledger if
        the group count changed.
        """
        ng = self.n_groups
        self.group_mass = np.add.reduceat(self.mass[self.group_nodes], self.group_ptr[:-1]) \
            if ng else np.zeros(0)
        if self.group_energy is not None and self.group_energy.shape[0] != ng:
            self.ledger[LEDGER_GROUPS] += self.group_energy.sum(axis=0)
            self.group_energy = np.zeros((ng, 4))

    def tie_rigidly(self, nodes) -> None:
        """Give the ``nodes`` (indices or a bool mask) one common velocity for good.

        Everything tied to them joins: a rigid platen that translates without rotating (a
        rough rigid footing, a loading plate). Their forces and masses are summed; the common
        velocity is the mass-weighted mean (momentum kept). Interface failures never separate
        them.
        """
        idx = np.asarray(nodes)
        idx = np.flatnonzero(idx) if idx.dtype == bool else idx.astype(np.int64)
        if idx.size < 2:
            return
        if idx.min() < 0 or idx.max() >= self.n_nodes:
            raise ValueError("tie_rigidly: node indices out of range 0..n_nodes-1")
        links = np.column_stack([idx[:-1], idx[1:]])
        self.rigid_links = np.concatenate([self.rigid_links, links]).astype(np.int64)
        groups = np.unique(self.node_group[idx])
        members = np.flatnonzero(np.isin(self.node_group, groups))
        m = self.mass[members]
        self.v[members] = (m[:, None] * self.v[members]).sum(axis=0) / m.sum()
        node_group = self.node_group.copy()
        node_group[members] = groups[0]
        _, node_group = np.unique(node_group, return_inverse=True)  # compact, order kept
        self.node_group = node_group.astype(np.int64)
        self.group_ptr, self.group_nodes = groups_csr(self.node_group,
                                                      int(self.node_group.max()) + 1)
        self.refresh_groups()
        self.primed = False

    # -- convenience ------------------------------------------------------------------------
    def fix(self, mask, *, x: bool = True, y: bool = True, velocity=(0.0, 0.0)) -> None:
        """Hold the velocity of the nodes in ``mask`` at ``velocity`` [m/s].

        ``mask`` is a bool (n_nodes,) array or node indices; ``x`` and ``y`` choose the
        directions held.
        """
        idx = np.flatnonzero(mask) if np.asarray(mask).dtype == bool else np.asarray(mask)
        for d, on in enumerate((x, y)):
            if on:
                self.fixed[idx, d] = True
                self.prescribed_velocity[idx, d] = velocity[d]
                self.v[idx, d] = velocity[d]
        self.primed = False

    def set_transmitting(self, edges: np.ndarray, axis: int, *, normal: bool = False) -> None:
        """Give boundary edges viscous dashpots on component ``axis`` (0: x, 1: y).

        ``edges`` (m, 3) rows (node a, node b, element): each edge of length L gets the
        dashpot rho V L / 2 on component ``axis`` of both its nodes, with the density rho
        and wave speed V of its element: the shear wave's, sqrt(G rho) L / 2, when ``axis``
        is the boundary's tangent; the pressure wave's, sqrt((K + 4 G / 3) rho) L / 2, with
        ``normal`` (``axis`` the boundary's normal). A plane wave meeting the boundary along
        its normal leaves without reflection (Lysmer & Kuhlemeyer 1969, ASCE J. Eng. Mech.
        Div. 95(4)); waves meeting it obliquely are partly reflected. Meant for the free
        component of a roller boundary that truncates a larger ground; repeated calls add up.
        """
        edges = np.asarray(edges, dtype=np.int64).reshape(-1, 3)
        if axis not in (0, 1):
            raise ValueError(f"axis = {axis!r}: 0 (x) or 1 (y)")
        if edges.size and (edges[:, :2].min() < 0 or edges[:, :2].max() >= self.n_nodes
                           or edges[:, 2].min() < 0 or edges[:, 2].max() >= self.n_elements):
            raise ValueError("edges name nodes or elements that do not exist")
        mat = self.element_material[edges[:, 2]]
        shear = self.material_table[mat, SHEAR_MODULUS]
        modulus = self.material_table[mat, BULK_MODULUS] + 4.0 * shear / 3.0 if normal else shear
        impedance = np.sqrt(modulus * self.density[mat])
        length = np.linalg.norm(self.x[edges[:, 0]] - self.x[edges[:, 1]], axis=1)
        for end in (0, 1):
            np.add.at(self.dashpot[:, axis], edges[:, end], 0.5 * impedance * length)

    def element_centroids(self) -> np.ndarray:
        """(n_elements, 2) mean of each element's node coordinates [m]."""
        return self.x[self.element_nodes].mean(axis=1)

    def copy(self) -> DiscreteState:
        """Deep copy (all arrays copied)."""
        kw: dict[str, Any] = {}
        for f in fields(self):
            v = getattr(self, f.name)
            kw[f.name] = v.copy() if isinstance(v, np.ndarray) else v
        return DiscreteState(**kw)

    # -- checkpoints (npz, no pickle) -----------------------------------------------------------
    def arrays(self) -> dict[str, np.ndarray]:
        """Every field as an array, by name (what ``save`` writes)."""
        return {f.name: np.asarray(getattr(self, f.name)) for f in fields(self)}

    def save(self, path: str | Path) -> Path:
        """Write every field to an ``.npz`` file (no pickle); ``load`` restarts bit for bit."""
        path = Path(path)
        np.savez(path, **self.arrays())
        return path if path.suffix == ".npz" else path.with_suffix(path.suffix + ".npz")

    @classmethod
    def load(cls, path: str | Path) -> DiscreteState:
        """Read a checkpoint written by ``save``, checked before any kernel sees it.

        Shapes, dtypes, sizes and index ranges are checked against each other; a file that
        is not a checkpoint, or one whose arrays would not fit the state they claim, is
        refused with a ValueError naming the field.
        """
        return cls(**read_checkpoint(path)[0])


#: a checkpoint may hold at most this many bytes of arrays (uncompressed) per byte on disk,
#: above ``_SMALL_CHECKPOINT``: ``save`` stores arrays uncompressed (ratio ~1); a small file
#: that inflates into a huge array is refused before it is read
_INFLATION = 50.0
_SMALL_CHECKPOINT = 64 * 2**20  # [bytes]

#: the checkpoint's fields: (dtype kind, shape in the state's sizes); sizes: N nodes,
#: E elements, G gauss points per element (4 Q4, 1 T3), K nodes per element (4 Q4, 3 T3),
#: M materials, S tie groups, I interfaces, P contact pairs, L rigid links, W table width,
#: B walls, BN wall nodes
_LAYOUT: dict[str, tuple[str, tuple[str | int, ...]]] = {
    "x": ("f8", ("N", 2)), "x_ref": ("f8", ("N", 2)), "v": ("f8", ("N", 2)),
    "mass": ("f8", ("N",)), "element_nodes": ("i8", ("E", "K")),
    "element_material": ("i4", ("E",)), "stress": ("f8", ("E", "G", 4)),
    "plastic_strain": ("f8", ("E", "G")), "yielded": ("i1", ("E", "G")),
    "node_group": ("i8", ("N",)), "group_ptr": ("i8", ("S+1",)),
    "group_nodes": ("i8", ("N",)), "interface_elements": ("i8", ("I", 2)),
    "interface_nodes": ("i8", ("I", 4)), "interface_intact": ("b1", ("I",)),
    "interface_splittable": ("b1", ("I",)), "fixed": ("b1", ("N", 2)),
    "prescribed_velocity": ("f8", ("N", 2)), "external_force": ("f8", ("N", 2)),
    "material_table": ("f8", ("M", "W")), "density": ("f8", ("M",)),
    "elastic_only": ("b1", ("M",)), "interface_table": ("f8", ("M", 3)),
    "contact_table": ("f8", ("M", 5)), "gravity": ("f8", (2,)), "time": ("f8", ()),
    "step": ("i8", ()), "internal_force": ("f8", ("N", 2)), "group_mass": ("f8", ("S",)),
    "group_energy": ("f8", ("S", 4)), "ledger": ("f8", (8,)),
    "contact_pairs": ("i8", ("P", 2)), "contact_shear": ("f8", ("P", 2)),
    "primed": ("b1", ()), "dt": ("f8", ()), "rigid_links": ("i8", ("L", 2)),
    "element_length": ("f8", ("E",)), "fragment_cap": ("f8", ("E",)),
    "walls": ("f8", ("B", 5)), "wall_nodes": ("i8", ("BN", 2)),
    "dashpot": ("f8", ("N", 2)),
    "interface_mode": ("i1", ("I",)), "interface_failure_time": ("f8", ("I",)),
}
#: index arrays and the size their entries index
_INDEX_RANGE = {"element_nodes": "N", "element_material": "M", "node_group": "S",
                "group_nodes": "N", "interface_elements": "E", "interface_nodes": "N",
                "contact_pairs": "E", "rigid_links": "N", "wall_nodes": "N"}


def _headers(path: Path, fh: Any) -> dict[str, tuple[tuple[int, ...], np.dtype]]:
    """Shape and dtype of every array of the npz file open as ``fh``, from the headers only."""
    import zipfile

    try:
        size_on_disk = os.fstat(fh.fileno()).st_size
        with zipfile.ZipFile(fh) as zf:
            infos = [i for i in zf.infolist() if i.filename.endswith(".npy")]
            inflated = sum(i.file_size for i in infos)
            if inflated > max(_INFLATION * size_on_disk, _SMALL_CHECKPOINT):
                raise ValueError(f"checkpoint {path} would inflate to {inflated / 2**20:.0f} "
                                 f"MiB from {size_on_disk / 2**20:.2g} MiB on disk: not a "
                                 "checkpoint written by DiscreteState.save; use another one")
            out = {}
            for info in infos:
                with zf.open(info) as f:
                    version = np.lib.format.read_magic(f)
                    read = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                            else np.lib.format.read_array_header_2_0)
                    shape, _, dtype = read(f)
                if dtype.hasobject:
                    raise ValueError(f"checkpoint {path}: field {info.filename[:-4]!r} holds "
                                     "Python objects; a checkpoint holds plain arrays only")
                out[info.filename[:-4]] = (tuple(shape), dtype)
    except (OSError, EOFError, zipfile.BadZipFile) as err:
        raise ValueError(f"checkpoint {path} cannot be read ({err}): it is missing, truncated "
                         "or not an npz file; restart from the previous checkpoint "
                         "(checkpoint.prev.npz) or from the start") from None
    return out


def _sizes(path: Path, heads: dict[str, tuple[tuple[int, ...], np.dtype]]) -> dict[str, int]:
    """The state's sizes (N, E, ...) read from the arrays that define them."""
    def dim(name: str, axis: int) -> int:
        shape = heads[name][0]
        if len(shape) <= axis:
            raise ValueError(f"checkpoint {path}: field {name!r} has shape {shape}, expected "
                             f"{len(_LAYOUT[name][1])} dimensions")
        return int(shape[axis])

    k = dim("element_nodes", 1)
    if k not in (3, 4):
        raise ValueError(f"checkpoint {path}: element_nodes has {k} nodes per element, "
                         "expected 4 (Q4) or 3 (T3)")
    return {"N": dim("x", 0), "E": dim("element_nodes", 0), "K": k, "G": 4 if k == 4 else 1,
            "M": dim("material_table", 0), "S": dim("group_ptr", 0) - 1,
            "I": dim("interface_elements", 0),
            "P": dim("contact_pairs", 0) if "contact_pairs" in heads else 0,
            "L": dim("rigid_links", 0) if "rigid_links" in heads else 0, "W": TABLE_WIDTH,
            "B": dim("walls", 0) if "walls" in heads else 0,
            "BN": dim("wall_nodes", 0) if "wall_nodes" in heads else 0,
            "S+1": dim("group_ptr", 0)}


def read_checkpoint(path: str | Path) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """The state's fields of a checkpoint, checked, and its other arrays (the solver's).

    Raises ValueError naming the first field whose name, dtype, shape, size or indices do not
    fit the state the file describes; no array is read before its header is checked.
    """
    path = Path(path)
    try:
        fh = open(path, "rb")  # one open file: a checkpoint renamed meanwhile is not mixed in
    except OSError as err:
        raise ValueError(f"checkpoint {path} cannot be read ({err.strerror}): it is missing, "
                         "truncated or not an npz file; restart from the previous checkpoint "
                         "(checkpoint.prev.npz) or from the start") from None
    with fh:
        return _read_checkpoint(path, fh)


def _read_checkpoint(path: Path, fh: Any) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    heads = _headers(path, fh)
    # the engine's work arrays may be missing (a checkpoint of an older layout): made anew
    names = [f.name for f in fields(DiscreteState)
             if f.name in heads or f.default is not MADE_ON_CREATION]
    missing = [n for n in names if n not in heads]
    if missing:
        raise ValueError(f"checkpoint {path} lacks the field(s) {', '.join(missing)}: not a "
                         "checkpoint of this version; restart from the handover")
    sizes = _sizes(path, heads)
    for name in names:
        kind, dims = _LAYOUT[name]
        shape, dtype = heads[name]
        expected = tuple(sizes[d] if isinstance(d, str) else d for d in dims)
        if name == "contact_table" and shape == (sizes["M"], 4):
            raise ValueError(f"checkpoint {path} was written by an older version (contacts "
                             "without cohesion, elements beside failed bonds held at their "
                             "residual): it cannot be continued with this one; restart from "
                             "the handover")
        if dtype.str.lstrip("<>|=") != kind:
            raise ValueError(f"checkpoint {path}: field {name!r} has dtype {dtype}, expected "
                             f"{np.dtype(kind)}; the file is damaged or not written by "
                             "DiscreteState.save")
        if shape != expected:
            raise ValueError(f"checkpoint {path}: field {name!r} has shape {shape}, expected "
                             f"{expected} for {sizes['N']} nodes and {sizes['E']} elements; "
                             "the file is damaged or not written by DiscreteState.save")
    try:
        fh.seek(0)
        with np.load(fh, allow_pickle=False) as data:
            arrays = {n: data[n] for n in heads}
    except (OSError, EOFError, ValueError, KeyError) as err:
        raise ValueError(f"checkpoint {path} cannot be read ({err}): restart from the "
                         "previous checkpoint (checkpoint.prev.npz) or from the start") from None
    arrays = {n: a if a.ndim == 0 else np.ascontiguousarray(a) for n, a in arrays.items()}
    for name, size in _INDEX_RANGE.items():
        if name not in arrays:
            continue
        a = arrays[name]
        if a.size and (a.min() < 0 or a.max() >= sizes[size]):
            raise ValueError(f"checkpoint {path}: field {name!r} holds indices outside "
                             f"0..{sizes[size] - 1} (values {a.min()}..{a.max()}); the file is "
                             "damaged")
    ptr = arrays["group_ptr"]
    if ptr[0] != 0 or ptr[-1] != sizes["N"] or np.any(np.diff(ptr) < 0):
        raise ValueError(f"checkpoint {path}: group_ptr is not a CSR pointer over "
                         f"{sizes['N']} nodes (0, non-decreasing, ending at n_nodes); the file "
                         "is damaged")
    if not np.array_equal(np.sort(arrays["group_nodes"]), np.arange(sizes["N"])):
        raise ValueError(f"checkpoint {path}: group_nodes is not a permutation of the nodes; "
                         "the file is damaged")
    for name in ("time", "dt"):
        if not np.isfinite(arrays[name]) or arrays[name] < 0:
            raise ValueError(f"checkpoint {path}: {name} = {arrays[name]} must be finite and "
                             ">= 0; the file is damaged")
    if arrays["step"] < 0:
        raise ValueError(f"checkpoint {path}: step = {arrays['step']} must be >= 0")
    if "walls" in arrays and not np.isfinite(arrays["walls"]).all():
        raise ValueError(f"checkpoint {path}: walls hold non-finite values; the file is "
                         "damaged")
    if "wall_nodes" in arrays and arrays["wall_nodes"].size and (
            arrays["wall_nodes"][:, 0].max() >= sizes["B"]):
        raise ValueError(f"checkpoint {path}: wall_nodes name walls beyond the "
                         f"{sizes['B']} walls; the file is damaged")
    kw: dict[str, Any] = {}
    for name in names:
        a = arrays.pop(name)
        kw[name] = (float(a) if name in ("time", "dt") else int(a) if name == "step"
                    else bool(a) if name == "primed" else a)
    return kw, arrays


# --------------------------------------------------------------------------------------------
# construction from a mesh
# --------------------------------------------------------------------------------------------
def _signed_areas(p: np.ndarray) -> np.ndarray:
    """Shoelace signed area of polygons p (n, nen, 2), positive when counter-clockwise."""
    xs, ys = p[..., 0], p[..., 1]
    return 0.5 * np.sum(xs * np.roll(ys, -1, axis=1) - np.roll(xs, -1, axis=1) * ys, axis=1)


def _q4_detj(p: np.ndarray) -> np.ndarray:
    """The Jacobian determinant at the 2x2 Gauss points of Q4 elements p (n, 4, 2) -> (n, 4)."""
    out = np.empty((p.shape[0], 4))
    for g, (xi, eta) in enumerate(Q4_GAUSS):
        dxi = 0.25 * np.array([-(1 - eta), (1 - eta), (1 + eta), -(1 + eta)])
        deta = 0.25 * np.array([-(1 - xi), -(1 + xi), (1 + xi), (1 - xi)])
        j11 = p[:, :, 0] @ dxi
        j12 = p[:, :, 0] @ deta
        j21 = p[:, :, 1] @ dxi
        j22 = p[:, :, 1] @ deta
        out[:, g] = j11 * j22 - j12 * j21
    return out


def _lumped_mass(p: np.ndarray, rho_e: np.ndarray) -> np.ndarray:
    """Row-sum lumped nodal masses (n, nen) = rho * integral of N_a over the element [t/m]."""
    nen = p.shape[1]
    if nen == 3:
        return np.repeat((rho_e * _signed_areas(p) / 3.0)[:, None], 3, axis=1)
    m = np.zeros((p.shape[0], 4))
    det = _q4_detj(p)
    for g, (xi, eta) in enumerate(Q4_GAUSS):
        n = 0.25 * np.array([(1 - xi) * (1 - eta), (1 + xi) * (1 - eta),
                             (1 + xi) * (1 + eta), (1 - xi) * (1 + eta)])
        m += (rho_e * det[:, g])[:, None] * n[None, :]
    return m


def check_elements(x: np.ndarray, element_nodes: np.ndarray) -> None:
    """Raise ValueError naming the first NaN node or inverted / zero-area element."""
    bad = np.flatnonzero(~np.isfinite(x).all(axis=1))
    if bad.size:
        raise ValueError(f"node {bad[0]} has non-finite coordinates {x[bad[0]]}: "
                         "fix the mesh coordinates (no NaN/inf)")
    p = x[element_nodes]
    area = _signed_areas(p)
    scale = np.maximum(np.ptp(p[..., 0], axis=1), np.ptp(p[..., 1], axis=1)) ** 2
    if element_nodes.shape[1] == 4:
        det = _q4_detj(p).min(axis=1) * 4.0
    else:
        det = area
    e = np.flatnonzero(det <= 1e-12 * scale)
    if e.size:
        k = int(e[0])
        kind = "zero-area" if abs(area[k]) <= 1e-12 * scale[k] else "inverted"
        raise ValueError(
            f"element {k} is {kind} (signed area {area[k]:.3g} m2, nodes {p[k].tolist()}): "
            "elements must be counter-clockwise and convex with positive area "
            "(pass fix_orientation=True to reverse clockwise elements)")


def from_mesh(points, cells, cell_material, materials, *, gravity=(0.0, -GRAVITY),
              fix_orientation: bool = False) -> DiscreteState:
    """Build a DiscreteState from a conforming mesh.

    points (n_points, 2) [m]; cells (n_elements, nen) point indices, nen 4 (Q4, counter-
    clockwise) or 3 (T3); cell_material (n_elements,) indices into ``materials`` (a sequence of
    ``Material``). Every element gets its own nodes; all nodes at one mesh point form one
    tie group; every edge shared by two elements becomes an intact, splittable interface.
    """
    points = np.ascontiguousarray(np.asarray(points, dtype=float)[:, :2])
    cells = np.ascontiguousarray(np.asarray(cells, dtype=np.int64))
    cell_material = np.ascontiguousarray(np.asarray(cell_material, dtype=np.int32))
    if cells.ndim != 2 or cells.shape[1] not in (3, 4):
        raise ValueError(f"cells has shape {cells.shape}: expected (n, 4) Q4 or (n, 3) T3")
    ne, nen = cells.shape
    if ne == 0:
        raise ValueError("cells is empty: need at least one element")
    if cells.min() < 0 or cells.max() >= points.shape[0]:
        raise ValueError("cells refer to points that do not exist")
    if cell_material.shape != (ne,):
        raise ValueError(f"cell_material has shape {cell_material.shape}: expected ({ne},)")
    if cell_material.min() < 0 or cell_material.max() >= len(materials):
        raise ValueError("cell_material holds an index outside the materials list")
    if fix_orientation:
        cw = _signed_areas(points[cells]) < 0
        cells[cw] = cells[cw, ::-1]
    x = points[cells].reshape(-1, 2).copy()
    element_nodes = np.arange(ne * nen, dtype=np.int64).reshape(ne, nen)
    check_elements(x, element_nodes)

    size = float(np.sqrt(np.mean(np.abs(_signed_areas(points[cells])))))
    mt, dens, el, it, ct = material_rows(materials, size)
    mass = _lumped_mass(points[cells], dens[cell_material]).reshape(-1)

    # tie groups: nodes at one mesh point
    pt = cells.reshape(-1)
    uniq, node_group = np.unique(pt, return_inverse=True)
    node_group = node_group.astype(np.int64)
    group_ptr, group_nodes = groups_csr(node_group, len(uniq))

    # interfaces: edges shared by two elements
    loc0 = np.tile(np.arange(nen), ne)
    e_of = np.repeat(np.arange(ne), nen)
    p0 = cells[e_of, loc0]
    p1 = cells[e_of, (loc0 + 1) % nen]
    key = np.minimum(p0, p1) * (points.shape[0] + 1) + np.maximum(p0, p1)
    order = np.argsort(key, kind="stable")
    ks = key[order]
    same = np.flatnonzero(ks[1:] == ks[:-1])
    if np.unique(ks, return_counts=True)[1].max() > 2:
        raise ValueError("an edge is shared by more than two elements: the mesh is not conforming")
    ia, ib = order[same], order[same + 1]
    ea, eb = e_of[ia], e_of[ib]
    a0 = element_nodes[ea, loc0[ia]]
    a1 = element_nodes[ea, (loc0[ia] + 1) % nen]
    # B's edge runs the other way (both counter-clockwise): B's edge start is at A's a1
    b1 = element_nodes[eb, loc0[ib]]
    b0 = element_nodes[eb, (loc0[ib] + 1) % nen]
    if np.any(pt[b0] != pt[a0]) or np.any(pt[b1] != pt[a1]):
        raise ValueError("two elements sharing an edge traverse it in the same direction: "
                         "an element is clockwise (use fix_orientation=True)")
    n_if = ea.size
    st = DiscreteState(
        x=x, x_ref=x.copy(), v=np.zeros_like(x), mass=mass,
        element_nodes=element_nodes, element_material=cell_material,
        stress=np.zeros((ne, 4 if nen == 4 else 1, 4)),
        plastic_strain=np.zeros((ne, 4 if nen == 4 else 1)),
        yielded=np.zeros((ne, 4 if nen == 4 else 1), dtype=np.int8),
        node_group=node_group, group_ptr=group_ptr, group_nodes=group_nodes,
        interface_elements=np.stack([ea, eb], axis=1).astype(np.int64),
        interface_nodes=np.stack([a0, a1, b0, b1], axis=1).astype(np.int64),
        interface_intact=np.ones(n_if, dtype=bool),
        interface_splittable=np.ones(n_if, dtype=bool),
        fixed=np.zeros((x.shape[0], 2), dtype=bool),
        prescribed_velocity=np.zeros_like(x), external_force=np.zeros_like(x),
        material_table=mt, density=dens, elastic_only=el, interface_table=it,
        contact_table=ct, gravity=np.asarray(gravity, dtype=float).copy(),
    )
    return st


def groups_csr(node_group: np.ndarray, n_groups: int) -> tuple[np.ndarray, np.ndarray]:
    """CSR (group_ptr, group_nodes) of the groups in node_group (ids 0..n_groups-1)."""
    group_nodes = np.argsort(node_group, kind="stable").astype(np.int64)
    counts = np.bincount(node_group, minlength=n_groups)
    group_ptr = np.zeros(n_groups + 1, dtype=np.int64)
    np.cumsum(counts, out=group_ptr[1:])
    return group_ptr, group_nodes
