"""D1 + D2: a tied group of discrete elements in free fall (thesis 3.4.3).

Objective
    The simplest check of the explicit discrete engine: ties, lumped mass, central differences
    and mass-proportional damping on a body that only falls.
Problem
    A 4 m x 4 m block of 4 x 4 tied Q4 elements (E = 100 000 kPa, nu = 0.3, rho = 2 t/m3),
    nothing fixed, gravity g = 9.81 m/s2 downward.
Set-up
    Undamped (D1): a few steps, then one step measured: every node's acceleration
    (v(t + dt/2) - v(t - dt/2)) / dt. Damped (D2): mass damping C = alpha M with
    alpha = 3 1/s (thesis eq 3.12) from rest until t_end, written as a time series.
Verification
    D1: a_y = -g at every node (bar 1e-9 relative), a_x = 0 and no stress (bar 1e-9 of
    g and of rho g L); a rigid translation strains nothing.
    D2: m dv/dt = m g - alpha m v gives v(t) = (g / alpha)(1 - exp(-alpha t)), the terminal
    velocity g / alpha = 3.27 m/s (bar 0.5 %); the recorded v(t) follows the closed form
    (max deviation over the run, bar 0.5 % of g / alpha). The staggered velocity starts at
    v(-dt/2) = 0, so the closed form is started at -dt/2 as well (otherwise a start-up
    offset g dt / 2 appears; with it the deviation is O(dt^2)).
References
    G. S. Bala (2008), thesis, section 3.4.3 and eqs 3.4-3.17.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hybrid.discrete import integrate, rectangle
from hybrid.discrete.outputs import standard_outputs
from hybrid.discrete.runs import require_serial
from hybrid.discrete.solver import ExplicitSolver, RunOptions
from hybrid.io import CaseSummary, Check, save_figure
from hybrid.materials import GRAVITY, Material
from hybrid.parameters import CaseParameters, param
from hybrid.report import plot_energy


@dataclass
class Parameters(CaseParameters):
    E: float = 1.0e5  # Young's modulus [kPa]
    nu: float = 0.3  # Poisson's ratio [-]
    density: float = param(2.0, gt=0)  # [t/m3]
    size: float = param(4.0, gt=0)  # block width and height [m]
    n: int = param(4, ge=1)  # elements per side
    g: float = GRAVITY  # gravity [m/s2]
    mass_damping: float = param(3.0, ge=0)  # mass damping alpha of the D2 run [1/s]
    free_steps: int = param(50, ge=1)  # undamped steps before the D1 acceleration is measured
    t_end: float = param(6.0, gt=0)  # end of the damped run [s] (1 - exp(-alpha t_end) of g /
    #                                  alpha)
    safety: float = param(0.5, gt=0, le=1)  # dt = safety x the time-step scale, within the
    #                                        critical step (integrate.default_dt) [-]
    check_every: int = param(50, ge=1)  # steps between energy / velocity records
    output_every: int = param(200, ge=0)  # steps between XDMF frames and PNG snapshots
    progress: bool = True  # show a progress bar


def _plot_velocity(path: Path, t: np.ndarray, v: np.ndarray, v_exact: np.ndarray,
                   v_term: float) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=100)
    ax.plot(t, v, "o", ms=3, label="hybrid (mean over nodes)")
    ax.plot(t, v_exact, "-", label="(g / alpha)(1 - exp(-alpha (t + dt/2)))")
    ax.axhline(v_term, ls="--", color="C2", label=f"g / alpha = {v_term:.4g} m/s")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("downward velocity [m/s]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    return save_figure(fig, path)


def main(out: str | Path = "results/free_fall", **overrides) -> CaseSummary:
    """Free fall of a tied Q4 group (D1) and its terminal velocity under mass damping (D2)."""
    require_serial("free_fall")
    p = Parameters(**overrides)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    mat = Material(name="block", E=p.E, nu=p.nu, density=p.density)

    # --- D1: undamped fall, one step measured ----------------------------------------------
    st = rectangle(p.size, p.size, p.n, p.n, material=mat, gravity=(0.0, -p.g))
    dt = integrate.default_dt(st, p.safety, contact=False)
    with ExplicitSolver(st, RunOptions(dt=dt)) as solver:
        solver.run(max_steps=p.free_steps, check_every=p.free_steps)
    v0 = st.v.copy()
    integrate.step(st, dt)
    acc = (st.v - v0) / dt
    worst = int(np.argmax(np.abs(acc[:, 1] + p.g)))
    stress_d1 = float(np.max(np.abs(st.stress))) / (p.density * p.g * p.size)  # / rho g L
    vx_d1 = float(np.max(np.abs(st.v[:, 0])))

    # --- D2: damped fall from rest, written as a time series --------------------------------
    st = rectangle(p.size, p.size, p.n, p.n, material=mat, gravity=(0.0, -p.g))
    record: list[tuple[float, float]] = []

    def on_check(s) -> None:
        # v lives at t - dt/2 (staggered central differences); the run starts from
        # v(-dt/2) = 0, so the closed form below is started at -dt/2 too
        record.append((s.time - 0.5 * s.dt, -float(s.v[:, 1].mean())))

    outputs = standard_outputs(out, output_every=p.output_every, progress=p.progress,
                               material_names=[mat.name])
    with ExplicitSolver(st, RunOptions(dt=dt, mass_damping=p.mass_damping),
                        observers=outputs) as solver:
        res = solver.run(until_time=p.t_end, check_every=p.check_every, on_check=on_check)
    v_term = p.g / p.mass_damping
    t_rec, v_rec = (np.array(c) for c in zip(*record, strict=True))
    v_exact = v_term * (1.0 - np.exp(-p.mass_damping * (t_rec + 0.5 * dt)))
    v_end = -st.v[:, 1]
    worst_v = float(v_end[np.argmax(np.abs(v_end - v_term))])

    checks = {
        "D1_acceleration_y": Check(-float(acc[worst, 1]), p.g, 1e-9, "m/s2",
                                   "free fall: every node accelerates at g"),
        "D1_max_acceleration_x_over_g": Check(float(np.max(np.abs(acc[:, 0]))) / p.g, 0.0,
                                              1e-9, "-", "free fall: no horizontal motion"),
        "D1_max_stress_over_rho_g_L": Check(stress_d1, 0.0, 1e-9, "-",
                                            "free fall: a rigid translation strains nothing"),
        "D1_max_velocity_x": Check(vx_d1, 0.0, 1e-9, "m/s", "free fall: no horizontal drift"),
        "D2_terminal_velocity": Check(worst_v, v_term, 5e-3, "m/s",
                                      "g / alpha (m dv/dt = m g - alpha m v)"),
        "D2_velocity_history_max_deviation": Check(
            float(np.max(np.abs(v_rec - v_exact))) / v_term, 0.0, 5e-3, "-",
            "max |v - (g/alpha)(1 - exp(-alpha (t + dt/2)))| / (g/alpha) over the run"),
    }
    summary = CaseSummary("free_fall (D1, D2)", out, p, results={
        "dt": dt, "steps": res.steps, "stop_reason": res.stop_reason,
        "wall_time": res.wall_time}, checks=checks)
    plot_energy(out / "energy.png", res.history)
    _plot_velocity(out / "velocity.png", t_rec, v_rec, v_exact, v_term)
    summary.write(out / "summary.json")
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
