"""D10: a 100-element vertical face topples with no-tension splitting (thesis 4.9.3).

Objective
    Splitting and contact together: a tied face that cannot carry tension breaks along its
    element interfaces where its stress turns tensile, topples and comes to rest as a pile.
Problem
    A 1.6 m wide, 10 m high face of 4 x 25 Q4 elements bonded to a ground strip 6 H long
    (one row of 0.4 m Q4, held), leaning 0.8 m over its base (x shifted by 0.08 y).
    E = 100 000 kPa, nu = 0.25, rho = 2 t/m3; interfaces: no tension, no cohesion,
    phi = 35 deg; contact friction 35 deg, contact damping ratio 0.3; gravity 9.81 m/s2.
Set-up
    The face starts from its elastic gravity state, solved by dolfinx (Q2) on the same mesh
    (``meshes/face.py``) and handed over (``hybrid.handover``: every cell an element, the cell
    mean stress at its Gauss points, the ground held); the face's interfaces and its bonded base
    may split (no tension, no cohesion). Mass damping alpha = 0.5 1/s (light: a dynamic run). Every
    10 steps each intact interface is checked (thesis section 4.5: tension if sigma_N > 0,
    shear if tau > sigma_N' tan phi) and failed ones untie; every failure is recorded with its
    mode and the principal stresses at the interface (the Gauss points next to the edge, as
    the failure check). Until rest (E_kin <= 1e-4 of its peak) or t_end.
Verification
    * Splitting only where tension exists: every tension failure has a tensile major principal
      stress s1 > 0 (tension positive; the thesis's "minor principal stress tensile" in its
      compression-positive convention). Exact (a consequence of s1 >= sigma_N > 0; checks the
      bookkeeping of modes and interfaces).
    * It completes, splits and settles: at rest before t_end; number of failed interfaces,
      of bodies, and the final height of the face are reported.
    * Energy bounded: E_kin + E_strain (+ the elastic contact energy) <= E(0) + work of
      gravity (excess bar 1 % of the supply).
References
    G. S. Bala (2008), thesis, sections 4.5 and 4.9.3.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hybrid.continuum import solve_elastic
from hybrid.discrete import ties
from hybrid.discrete.energy import energy_excess, energy_peak_ratio
from hybrid.discrete.outputs import standard_outputs
from hybrid.discrete.runs import require_serial
from hybrid.discrete.solver import ExplicitSolver, RunOptions
from hybrid.geometry import build_mesh, load_builder
from hybrid.handover import Region, residual_force, to_discrete
from hybrid.io import CaseSummary, Check, save_figure
from hybrid.materials import GRAVITY, Bond, Contact, Material
from hybrid.model import Fixed, Model
from hybrid.parameters import CaseParameters, param
from hybrid.report import plot_energy

MESHES = Path(__file__).resolve().parent.parent / "meshes"


@dataclass
class Parameters(CaseParameters):
    E: float = 1.0e5  # Young's modulus [kPa]
    nu: float = 0.25  # Poisson's ratio [-]
    density: float = param(2.0, gt=0)  # [t/m3]
    width: float = param(1.6, gt=0)  # face width at its base [m]
    height: float = param(10.0, gt=0)  # face height [m]
    nx: int = param(4, ge=1)  # elements across the face
    ny: int = param(25, ge=1)  # elements up the face
    lean: float = 0.08  # overhang: x shifted by lean x y [-]
    interface_phi: float = 35.0  # interface friction angle (no tension, no cohesion) [deg]
    contact_phi: float = 35.0  # contact friction angle [deg]
    contact_damping: float = param(0.3, ge=0, le=1)  # contact normal damping ratio [-]
    mass_damping: float = param(0.5, ge=0)  # mass damping alpha [1/s]
    split_every: int = param(10, ge=1)  # steps between interface failure checks
    rest: float = param(1e-4, gt=0)  # stop when E_kin <= rest x max(peak E_kin, E_strain) [-]
    t_end: float = param(15.0, gt=0)  # time limit [s]
    output_every: int = param(1000, ge=0)  # steps between XDMF frames and PNG snapshots
    progress: bool = True  # show a progress bar


def _edge_principal(st, idx: np.ndarray) -> np.ndarray:
    """Major principal in-plane stress s1 [kPa] of the interfaces ``idx``: the stress averaged
    over the Gauss points next to the edge in both elements (as ``ties.check_interfaces``)."""
    en = st.element_nodes
    s = np.zeros((idx.size, 4))
    cnt = 0
    for side, node_col in ((0, 0), (1, 3)):
        e = st.interface_elements[idx, side]
        k = np.argmax(en[e] == st.interface_nodes[idx, node_col][:, None], axis=1)
        for gp in (k, (k + 1) % en.shape[1]):
            s += st.stress[e, gp]
            cnt += 1
    s /= cnt
    return 0.5 * (s[:, 0] + s[:, 1]) + np.hypot(0.5 * (s[:, 0] - s[:, 1]), s[:, 3])


def _n_bodies(st) -> int:
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    ie = st.interface_elements[st.interface_intact]
    ne = st.n_elements
    g = coo_matrix((np.ones(len(ie)), (ie[:, 0], ie[:, 1])), shape=(ne, ne))
    return int(connected_components(g, directed=False)[0])


def _plot_failures(path: Path, st, modes: np.ndarray, s1: np.ndarray, face: np.ndarray
                   ) -> Path:
    """The face in its reference shape with every failed interface drawn by mode and sign."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PolyCollection

    fig, ax = plt.subplots(figsize=(4.0, 7.0), dpi=100)
    ax.add_collection(PolyCollection(st.x_ref[st.element_nodes[face]], facecolors="0.9",
                                     edgecolors="0.6", linewidths=0.3))
    failed = np.flatnonzero(modes > 0)
    seg = st.x_ref[st.interface_nodes[failed][:, :2]]
    for mode, sign, colour, label in ((1, True, "C3", "tension, s1 > 0"),
                                      (2, True, "C1", "shear, s1 > 0"),
                                      (2, False, "C0", "shear, s1 <= 0")):
        pick = (modes[failed] == mode) & ((s1[failed] > 0.0) == sign)
        if pick.any():
            ax.add_collection(LineCollection(seg[pick], colors=colour, linewidths=2.0,
                                             label=f"{label} ({int(pick.sum())})"))
    ax.autoscale()
    ax.set_aspect("equal")
    ax.set_title("failed interfaces (reference shape)")
    ax.legend(fontsize=7, loc="upper left")
    return save_figure(fig, path)


def main(out: str | Path = "results/toppling", **overrides) -> CaseSummary:
    """A leaning face with no-tension interfaces splits, topples and settles (D10)."""
    require_serial("toppling")
    p = Parameters(**overrides)
    out = Path(out)
    # 1. continuum: the elastic gravity state of the face bonded to the ground (dolfinx Q2)
    x0 = 0.5 * p.height  # face's lower-left corner [m]
    mesh = build_mesh(load_builder(MESHES / "face.py"), width=p.width, height=p.height,
                      nx=p.nx, ny=p.ny, lean=p.lean, x0=x0, ground_length=6.0 * p.height)
    gamma = p.density * GRAVITY
    rock = Material(name="face", E=p.E, nu=p.nu, unit_weight=gamma, plastic=False,
                    bond=Bond(cohesion=0.0, phi=p.interface_phi, tensile_strength=0.0),
                    contact=Contact(phi=p.contact_phi, damping=p.contact_damping))
    ground = Material(name="ground", E=p.E, nu=p.nu, unit_weight=gamma, plastic=False,
                      contact=Contact(phi=p.contact_phi, damping=p.contact_damping))
    state = solve_elastic(Model(mesh, {"face": rock, "ground": ground},
                                supports=[Fixed("base")]))
    # 2. handover: the face (and its bonded base) may split; the ground strip is held
    hand = to_discrete(state, region=Region(group="face"))
    st = hand.discrete
    face = hand.splittable
    ties.limit_splitting(st, face)
    st.fix(np.unique(st.element_nodes[~face]))
    face_nodes = np.unique(st.element_nodes[face])
    # the start is the continuum's equilibrium: out-of-balance force against the face weight
    weight = float(st.mass[face_nodes].sum()) * GRAVITY
    residual0 = float(np.linalg.norm(residual_force(st))) / weight

    # every failure recorded: mode and s1 at the moment of the check
    fail_mode = np.zeros(st.interface_elements.shape[0], dtype=np.int8)
    fail_s1 = np.zeros(st.interface_elements.shape[0])
    fail_time = np.full(st.interface_elements.shape[0], np.nan)

    def split(s) -> None:
        modes = ties.check_interfaces(s)
        idx = np.flatnonzero(modes)
        if idx.size:
            fail_mode[idx] = modes[idx]
            fail_s1[idx] = _edge_principal(s, idx)
            fail_time[idx] = s.time
            ties.split_interfaces(s, idx)

    # splitting done here (after each block of split_every steps, where the contact list is
    # refreshed on the next step as the solver does with its own split_every)
    options = RunOptions(mass_damping=p.mass_damping, contact=True, contact_refresh=p.split_every)
    outputs = standard_outputs(out, output_every=p.output_every, progress=p.progress,
                               material_names=hand.material_names)
    with ExplicitSolver(st, options, observers=outputs) as solver:
        res = solver.run(until_rest=p.rest, until_time=p.t_end, check_every=p.split_every,
                         on_check=split)
    h = res.history

    tension = fail_mode == ties.FAIL_TENSION
    shear = fail_mode == ties.FAIL_SHEAR
    n_failed = int((~st.interface_intact).sum())
    top0 = float(st.x_ref[face_nodes, 1].max())
    top1 = float(st.x[face_nodes, 1].max())
    checks = {
        "tension_failures_with_tensile_s1": Check(
            float((fail_s1[tension] > 0.0).mean()) if tension.any() else 0.0, 1.0, 0.0, "-",
            "fraction of tension failures where s1 > 0 (section 4.5)"),
        "energy_excess_over_sources": Check(
            energy_excess(h, res.start), 0.0, 0.01, "-",
            "E_kin + E_strain + E_contact <= E(0) + work of gravity"),
        **res.rest_checks(p.rest),
        "failed_interfaces": Check(float(n_failed), None, None, "-", "report"),
        "face_top_height": Check(top1, None, None, "m", f"report (initially {top0:.3g} m)"),
    }
    summary = CaseSummary("toppling (D10)", out, p, results={
        "dt": res.dt, "steps": res.steps, "time": res.time,
        "stop_reason": res.stop_reason, "wall_time": res.wall_time,
        "energy_peak_over_supply": energy_peak_ratio(h, res.start),
        "n_interfaces": int(st.interface_elements.shape[0]),
        "n_failed": n_failed, "n_failed_tension": int(tension.sum()),
        "n_failed_shear": int(shear.sum()),
        "n_failed_shear_s1_tensile": int((fail_s1[shear] > 0.0).sum()),
        "n_failed_shear_s1_compressive": int((fail_s1[shear] <= 0.0).sum()),
        "first_failure_time": float(np.nanmin(fail_time)) if n_failed else None,
        "n_face_pieces": _n_bodies(st) - 1, "face_top_height_initial": top0,
        "face_top_height_final": top1,
        "handover_residual_over_face_weight": residual0,
        "face_lowest_y": float(st.x[face_nodes, 1].min()),  # >= ~0: all on the ground
    }, checks=checks)
    plot_energy(out / "energy.png", h)
    _plot_failures(out / "failures.png", st, fail_mode, fail_s1, face)
    summary.write(out / "summary.json")
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
