"""The explicit loop: stepping, contact refresh, splitting, outputs, monitor, checkpoints.

Orchestration only (no physics here): each step calls the kernels of ``integrate`` (tie-group
update, element stress update and internal forces), ``contact`` (when present) and, every
``split_every`` steps, ``ties``. Energy ledger (kJ per m thickness):

    E_kin + E_strain + E_contact + D_damping + D_friction + D_contact_damping + residual
        = E_kin(0) + E_strain(0) + E_contact(0) + W_loads + W_supports,

where E_contact is the elastic energy stored in the contacts (``contact.contact_energy``:
k_n A^2 / (2 L_c) + |F_t|^2 / (2 k_t L_c) per pair), D_contact_damping minus the work of the
contact damping forces as applied (after the no-adhesion clamp) on the mid-step velocity
(``contact.mid_step_work``: the kinetic energy of the central-difference update changes by
exactly F(t) . v_mid dt), D_friction minus the work of the tangential contact forces on the
mid-step velocity less the energy still stored in the tangential springs (in steady sliding
it is mu N x slip), and the residual holds plastic dissipation, the approximation of the
normal contact energy and time-integration error. D_normal_defect is minus the work of the
elastic normal contact forces on the mid-step velocity less the stored k_n A^2 / (2 L_c):
energy the overlap-area normal force absorbs (> 0) or gives (< 0) over a contact episode,
because it is not exactly conservative (corner contacts with a varying contact length, the
O(dt^2) error of stiff contacts) and U_n is approximate (D5: +2.8 % of the work of gravity
with contact damping 0.2, -1.0 % without). state.ledger[0], [1], [6] accumulate minus the work
of the tangential, damping and elastic normal contact forces.
"""

from __future__ import annotations

import logging
import math
import time as _time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from hybrid.discrete import integrate, ties
from hybrid.discrete.elements import strain_energy
from hybrid.discrete.state import DiscreteState

__all__ = ["RunResult", "run", "energy_ledger", "has_contact_module"]

log = logging.getLogger(__name__)


def has_contact_module() -> bool:
    """True when ``hybrid.discrete.contact`` can be imported."""
    try:
        import hybrid.discrete.contact  # noqa: F401
    except ImportError:
        return False
    return True


@dataclass
class RunResult:
    """What ``run`` returns: why it stopped, counts, the energy history and files written."""

    stop_reason: str  # "time", "steps" or "rest"
    steps: int  # steps taken by this call
    time: float  # state time at the end [s]
    dt: float  # time step [s]
    wall_time: float  # [s]
    element_steps_per_s: float
    n_split: int  # interfaces broken during this call
    history: dict[str, np.ndarray] = field(default_factory=dict)  # energy ledger per check
    files: list[Path] = field(default_factory=list)


def energy_ledger(state: DiscreteState) -> dict[str, float]:
    """Current energy terms [kJ/m]: kinetic, strain, contact elastic (stored in the current
    contact pairs, see ``contact.contact_energy``) and the accumulated works/dissipations."""
    ge = state.group_energy.sum(axis=0) + state.ledger[2:6]
    u_n = u_t = 0.0
    if state.contact_pairs.shape[0] and has_contact_module():
        from hybrid.discrete import contact as cmod

        u_n, u_t = cmod.contact_energy(state.x, state.element_nodes, state.element_material,
                                       state.contact_table, state.contact_pairs,
                                       state.contact_shear)
    return {
        "kinetic": integrate.kinetic_energy(state),
        "strain": strain_energy(state),
        "contact_elastic": u_n + u_t,
        "contact_normal_defect": float(state.ledger[6]) - u_n,
        "work_loads": float(ge[0]),
        "work_supports": float(ge[1]),
        "damping": float(ge[2] + ge[3]),
        "friction": float(state.ledger[0]) - u_t,
        "contact_damping": float(state.ledger[1]),
    }


def _n_bodies(state: DiscreteState) -> int:
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    ie = state.interface_elements[state.interface_intact]
    ne = state.n_elements
    g = coo_matrix((np.ones(len(ie)), (ie[:, 0], ie[:, 1])), shape=(ne, ne))
    return int(connected_components(g, directed=False)[0])


def run(state: DiscreteState, *, until_time: float | None = None, max_steps: int | None = None,
        until_rest: float | None = None, dt: float | None = None, safety: float = 0.5,
        damping: float = 0.0, local_damping: float = 0.0, split_every: int = 0,
        contact: bool | None = None, contact_refresh: int = 10, margin_factor: float = 2.0,
        contact_bounds: tuple[float, float, float, float] | None = None,
        check_every: int = 100, rest_min_steps: int = 200, output_every: int = 0,
        out_dir: str | Path | None = None, snapshots: bool = True,
        checkpoint_every: int = 0, progress: bool = True,
        on_check: Callable[[DiscreteState], bool | None] | None = None,
        bbar: bool = True, split_plastic_strain: float | None = None,
        plastic_strain_cap: float | None = None, contact_hinges: bool = True) -> RunResult:
    """Advance ``state`` in place until a time, a step count or rest (whichever comes first).

    until_time [s] (absolute state time), max_steps (steps of this call), until_rest: stop when
    E_kin <= until_rest * max(peak E_kin of this call, E_strain) (checked every check_every
    steps after rest_min_steps). dt: None reuses state.dt or takes safety x the stable step;
    a dt above the stable step is refused. damping: alpha [1/s] (thesis eq 3.12);
    local_damping: Cundall's d in [0, 1). split_every: check interfaces every N steps (0: never).
    contact: None uses contact when hybrid.discrete.contact exists and there are several bodies
    or splitting; contact_bounds (xmin, ymin, xmax, ymax) [m]: an element leaving them stops the
    run with a ValueError. output_every: XDMF/PNG every K steps into out_dir (with a GIF at
    the end); checkpoint_every: npz checkpoints into out_dir. on_check(state), if given, is
    called every check_every steps: it may change loads (``external_force``, load histories)
    and returns True to stop the run (stop reason "callback"). bbar: Q4 with the
    mean-dilatation B-bar (default, no volumetric locking) or full 2x2 integration (False, as
    dolfinx Q1). split_plastic_strain: interfaces also fail where the adjacent Gauss points'
    mean plastic strain exceeds it (see ``ties``). plastic_strain_cap: a Gauss point whose
    accumulated plastic strain reaches it responds elastically from then on: the element has
    handed its failure to its failed interfaces and slides on them instead of flowing further
    (without it a psi = 0 element under the footing edge of H2 flowed to a plastic
    strain of 43 at one Gauss point and turned inside out at t = 0.06 s). contact_hinges: also
    take as contact candidates the element pairs still tied at a single vertex
    (``find_contact_pairs(..., hinges=True)``): after a partial split two elements whose common
    edge failed rotate about that vertex and otherwise interpenetrate without any contact force,
    then repel with a deep overlap when the last tie fails (the retaining-wall collapse
    gained ~1 600 kJ/m through the normal contact forces by t = 0.2 s without it, 0.006 kJ/m
    with it).
    Raises RuntimeError if the run turns unstable (non-finite numbers or energy growing
    without a source).
    """
    if until_time is None and max_steps is None and until_rest is None:
        raise ValueError("give at least one of until_time, max_steps, until_rest")
    if max_steps is not None and (int(max_steps) != max_steps or max_steps < 0):
        raise ValueError(f"max_steps = {max_steps!r}: must be an integer >= 0")
    if not (math.isfinite(damping) and damping >= 0.0):
        raise ValueError(f"damping = {damping!r}: alpha must be >= 0 [1/s]")
    if not 0.0 <= local_damping < 1.0:
        raise ValueError(f"local_damping = {local_damping!r}: must be in [0, 1)")
    cap = math.inf if plastic_strain_cap is None else float(plastic_strain_cap)
    if not cap > 0.0:
        raise ValueError(f"plastic_strain_cap = {plastic_strain_cap!r}: must be > 0 (None: no "
                         "cap)")
    if until_rest is not None and not until_rest > 0.0:
        raise ValueError(f"until_rest = {until_rest!r}: must be a positive energy ratio")
    if (output_every or checkpoint_every) and out_dir is None:
        raise ValueError("output_every / checkpoint_every need out_dir")
    for name, val in (("split_every", split_every), ("contact_refresh", contact_refresh),
                      ("check_every", check_every), ("output_every", output_every),
                      ("checkpoint_every", checkpoint_every)):
        if int(val) != val or val < 0:
            raise ValueError(f"{name} = {val!r}: must be an integer >= 0")
    check_every = max(int(check_every), 1)
    contact_refresh = max(int(contact_refresh), 1)

    cmod = None
    if contact is None:
        contact = has_contact_module() and (split_every > 0 or _n_bodies(state) > 1)
    if contact:
        try:
            from hybrid.discrete import contact as cmod
            from hybrid.discrete.contact.forces import ContactBuffers, add_contact_forces
        except ImportError as err:
            raise ValueError("contact=True but hybrid.discrete.contact is not available") from err

    if dt is None:
        dt = state.dt if state.dt > 0.0 else safety * integrate.stable_time_step(
            state, contact=bool(contact))
    integrate.check_dt(state, float(dt), contact=bool(contact))
    dt = float(dt)
    state.dt = dt
    if not state.primed:
        integrate.prime(state)

    n_total = max_steps if max_steps is not None else None
    if until_time is not None:
        n_time = max(int(math.ceil((until_time - state.time) / dt - 1e-9)), 0)
        n_total = n_time if n_total is None else min(n_total, n_time)
    out = Path(out_dir) if out_dir is not None else None
    writer = None
    files: list[Path] = []
    frames: list[Path] = []
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
    if output_every and out is not None:
        writer = _XdmfSeries(out / "discrete.xdmf", state)
        files += [out / "discrete.xdmf", out / "discrete.h5"]

    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=n_total, unit="step", desc="discrete", mininterval=0.5)

    led0 = energy_ledger(state)
    e_start = led0["kinetic"] + led0["strain"] + led0["contact_elastic"]
    src0 = led0["work_loads"] + led0["work_supports"]
    mass_tot = float(np.sum(state.mass))
    cmax = float(np.max(np.sqrt((state.material_table[:, 0]
                                 + 4.0 * state.material_table[:, 1] / 3.0) / state.density)))
    tol_e = 1e-12 * mass_tot * cmax**2 + 1e-6 * abs(e_start)
    hist: dict[str, list[float]] = {k: [] for k in
                                    ("time", "step", *led0.keys(), "residual")}
    e_prev = e_start
    peak_ke = led0["kinetic"]
    n_split = 0
    cforce = np.zeros_like(state.x) if contact else None
    # ledger: damping and tangential parts of the contact forces, start-of-step velocity
    split = np.zeros((2, *state.x.shape)) if contact else None
    v_start = np.zeros_like(state.v) if contact else None
    cmass = cmod.rigid_contact_mass(state.mass, state.fixed, state.element_nodes) if contact \
        else None
    cbuf = ContactBuffers() if contact else None  # the contact loop's work arrays, reused
    has_ext = bool(np.any(state.external_force))
    stop = "steps"
    k = 0
    t0 = _time.perf_counter()
    try:
        if writer is not None:
            writer.write(state)
            if snapshots:
                frames.append(_snapshot(state, out, len(frames)))
        while True:
            if n_total is not None and k >= n_total:
                stop = "time" if (until_time is not None and state.time >= until_time - 0.5 * dt
                                  ) else "steps"
                break
            if contact:
                # refresh on schedule, and after each splitting check (new free edges)
                if state.step % contact_refresh == 0 or (split_every and
                                                         state.step % split_every == 0):
                    if not (np.isfinite(state.x).all() and np.isfinite(state.v).all()):
                        _monitor(state, energy_ledger(state), e_start, src0, e_prev, tol_e, dt)
                    vmax = float(np.max(np.abs(state.v))) if state.n_nodes else 0.0
                    margin = margin_factor * vmax * contact_refresh * dt
                    margin = max(margin, 1e-6 * math.sqrt(mass_tot / float(state.density.max())))
                    # hinges: elements still tied at one vertex of a failed edge
                    pairs = cmod.find_contact_pairs(state.x, state.element_nodes,
                                                    state.node_group, margin, contact_bounds,
                                                    hinges=contact_hinges)
                    state.contact_shear = cmod.carry_contact_history(
                        state.contact_pairs, state.contact_shear, pairs)
                    state.contact_pairs = pairs
                cforce[:] = 0.0
                n_pairs = state.contact_pairs.shape[0]
                if n_pairs:
                    split[:] = 0.0
                    v_start[:] = state.v
                    add_contact_forces(  # unchecked: state, dt and pairs checked already
                        state.x, state.v, cmass, state.element_nodes, state.element_material,
                        state.contact_table, state.contact_pairs, state.contact_shear, dt, cforce,
                        split, cbuf)
            integrate.step(state, dt, alpha=damping, local_damping=local_damping,
                           contact_force=cforce, bbar=bbar, external=has_ext,
                           plastic_cap=cap)
            if contact and n_pairs:
                # minus the work of the tangential / damping forces on the mid-step velocity
                w_t = cmod.mid_step_work(split[1], v_start, state.v, dt)
                w_d = cmod.mid_step_work(split[0], v_start, state.v, dt)
                w_all = cmod.mid_step_work(cforce, v_start, state.v, dt)
                state.ledger[0] -= w_t
                state.ledger[1] -= w_d
                state.ledger[6] -= w_all - w_t - w_d  # the elastic normal forces
            k += 1
            if split_every and state.step % split_every == 0:
                modes = ties.check_interfaces(
                    state, math.inf if split_plastic_strain is None else split_plastic_strain)
                if modes.any():
                    n_split += ties.split_interfaces(state, modes > 0)
            if k % check_every == 0 or (n_total is not None and k == n_total):
                led = energy_ledger(state)
                _monitor(state, led, e_start, src0, e_prev, tol_e, dt)
                _check_distortion(state, dt, bool(contact))
                e_now = led["kinetic"] + led["strain"] + led["contact_elastic"]
                e_prev = e_now
                peak_ke = max(peak_ke, led["kinetic"])
                _record(hist, state, led, led0)
                if bar is not None:
                    bar.update(check_every if k % check_every == 0 else k % check_every)
                if (until_rest is not None and k >= rest_min_steps
                        and led["kinetic"] <= until_rest * max(peak_ke, led["strain"])):
                    stop = "rest"
                    break
                if on_check is not None and on_check(state):
                    stop = "callback"
                    break
            if writer is not None and k % output_every == 0:
                writer.write(state)
                if snapshots:
                    frames.append(_snapshot(state, out, len(frames)))
            if checkpoint_every and k % checkpoint_every == 0:
                state.save(out / "checkpoint.npz")
    finally:
        if bar is not None:
            bar.close()
        if writer is not None:
            writer.close()
    wall = _time.perf_counter() - t0
    if not hist["step"] or hist["step"][-1] != state.step:
        led = energy_ledger(state)
        _monitor(state, led, e_start, src0, e_prev, tol_e, dt)
        _record(hist, state, led, led0)
    if checkpoint_every and out is not None:
        files.append(state.save(out / "checkpoint.npz"))
    if frames:
        files += frames
        gif = _gif(frames, out / "discrete.gif")
        if gif is not None:
            files.append(gif)
    log.info("discrete run: %d steps, stop=%s, %.3g s wall", k, stop, wall)
    return RunResult(stop_reason=stop, steps=k, time=state.time, dt=dt, wall_time=wall,
                     element_steps_per_s=k * state.n_elements / wall if wall > 0 else 0.0,
                     n_split=n_split, history={kk: np.asarray(v) for kk, v in hist.items()},
                     files=files)


def _balance(led) -> float:
    """Energy held and dissipated minus the work done on the system (its change over a run is
    minus the ledger's residual: residual > 0 when energy is missing)."""
    return (led["kinetic"] + led["strain"] + led["contact_elastic"] + led["damping"]
            + led["friction"] + led["contact_damping"] + led["contact_normal_defect"]
            - led["work_loads"] - led["work_supports"])


def _record(hist, state, led, led0) -> None:
    hist["time"].append(state.time)
    hist["step"].append(float(state.step))
    for key, val in led.items():
        hist[key].append(val)
    # relative to the start of this run (the works and dissipations are totals since the
    # state was made; a continued run starts with them non-zero)
    hist["residual"].append(_balance(led0) - _balance(led))


def _monitor(state, led, e_start, src0, e_prev, tol_e, dt) -> None:
    """Stop an unstable run: non-finite numbers, or mechanical energy far above its sources
    and still growing fast."""
    e_now = led["kinetic"] + led["strain"] + led["contact_elastic"]
    if not (np.isfinite(e_now) and np.isfinite(state.x).all() and np.isfinite(state.v).all()):
        raise RuntimeError(
            f"discrete run unstable at step {state.step} (t = {state.time:.6g} s): non-finite "
            f"coordinates/velocities/energy. Likely cause: dt = {dt:.4g} s too large for the "
            "current mesh or contact stiffness (reduce dt or the safety factor), or an element "
            "inverted under a too large deformation.")
    supply = e_start + abs(led["work_loads"] - src0) + abs(led["work_supports"]) + abs(src0)
    if e_now > 2.0 * supply + tol_e and e_now > 10.0 * e_prev + tol_e:
        raise RuntimeError(
            f"discrete run unstable at step {state.step} (t = {state.time:.6g} s): mechanical "
            f"energy {e_now:.4g} kJ/m grew over 10x since the last check and exceeds twice its "
            f"sources ({supply:.4g} kJ/m). Likely cause: dt = {dt:.4g} s too large "
            "(reduce dt or the safety factor) or a too stiff contact.")


def _check_distortion(state: DiscreteState, dt: float, contact: bool) -> None:
    """Stop with a clear message when the elements have distorted so much that the run's time
    step is no longer stable (it would otherwise end in NaN a few steps later)."""
    crit = integrate.stable_time_step(state, contact=contact)
    if dt > crit:
        raise RuntimeError(
            f"discrete run stopped at step {state.step} (t = {state.time:.6g} s): the elements "
            f"have distorted so much that the stable time step fell to {crit:.4g} s, below the "
            f"run's dt = {dt:.4g} s (large plastic flow pancakes an element). Continue with a "
            "smaller dt (run(..., dt=...)), let the flowing region split "
            "(split_plastic_strain) or stop the flow inside elements beyond a plastic strain "
            "(plastic_strain_cap, e.g. 0.3).")


class _XdmfSeries:
    """meshio XDMF time series: every element with its own nodes (splits are visible), the
    reference coordinates plus a displacement field, stress averaged per cell."""

    def __init__(self, path: Path, state: DiscreteState) -> None:
        import os

        import meshio

        # meshio 5.0 opens the .h5 file relative to the working directory: open it from the
        # output folder so that discrete.h5 lands beside discrete.xdmf
        self._w = meshio.xdmf.TimeSeriesWriter(path.name)
        cwd = os.getcwd()
        try:
            os.chdir(path.parent)
            self._w.__enter__()
        finally:
            os.chdir(cwd)
        self._w.filename = path.resolve()
        ctype = "quad" if state.nen == 4 else "triangle"
        self._w.write_points_cells(state.x_ref, [(ctype, state.element_nodes)])

    def write(self, state: DiscreteState) -> None:
        s = state.stress.mean(axis=1)
        self._w.write_data(
            state.time,
            point_data={"displacement": state.x - state.x_ref, "velocity": state.v},
            cell_data={"stress_xx": [s[:, 0]], "stress_yy": [s[:, 1]], "stress_zz": [s[:, 2]],
                       "stress_xy": [s[:, 3]],
                       "plastic_strain": [state.plastic_strain.mean(axis=1)],
                       "yielded": [state.yielded.mean(axis=1).astype(float)]})

    def close(self) -> None:
        self._w.__exit__(None, None, None)


def _snapshot(state: DiscreteState, out: Path, i: int) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    (out / "frames").mkdir(exist_ok=True)
    path = out / "frames" / f"frame_{i:04d}.png"
    polys = state.x[state.element_nodes]
    fig, ax = plt.subplots(figsize=(6, 5), dpi=80)
    pc = PolyCollection(polys, array=state.stress[:, :, 1].mean(axis=1), cmap="viridis",
                        edgecolors="k", linewidths=0.2)
    ax.add_collection(pc)
    fig.colorbar(pc, ax=ax, label="sigma_yy [kPa]")
    lo = state.x_ref.min(axis=0)
    hi = state.x_ref.max(axis=0)
    pad = 0.05 * float(np.max(hi - lo))
    ax.set_xlim(min(lo[0], state.x[:, 0].min()) - pad, max(hi[0], state.x[:, 0].max()) + pad)
    ax.set_ylim(min(lo[1], state.x[:, 1].min()) - pad, max(hi[1], state.x[:, 1].max()) + pad)
    ax.set_aspect("equal")
    ax.set_title(f"t = {state.time:.4g} s, step {state.step}")
    fig.savefig(path)
    plt.close(fig)
    return path


def _gif(frames: list[Path], path: Path) -> Path | None:
    try:
        from PIL import Image
    except ImportError:  # pragma: no cover
        return None
    imgs = [Image.open(f).convert("P") for f in frames]
    imgs[0].save(path, save_all=True, append_images=imgs[1:], duration=100, loop=0)
    return path
