"""``hybrid bench``: throughput of the discrete engine on problems it builds itself.

Problems (element-steps per second = elements x steps / wall time of the stepping loop):

- ``tied``: a tied elastic Q4 assembly (square block, fixed base, gravity, mass damping);
- ``mc``: the same block, Mohr-Coulomb (Tresca c = 10 kPa) prestressed on the yield surface,
  every node driven in isochoric plane-strain compression, so every Gauss point yields every
  step (the full return map each time);
- ``collapse``: a column with no-tension cohesionless interfaces on a rigid base, under tilted
  gravity, splitting every 10 steps and with contact (only when hybrid.discrete.contact exists).

Each problem is stepped by ``ExplicitSolver.step`` (contact refresh and forces, the update,
the contact terms of the energy ledger, splitting: what a run does per step, without its
checks). Each figure is the median of ``--repeats`` timed runs after one warm-up run (compilation),
for every size in ``--sizes`` and thread count in ``--threads``. Peak RSS from getrusage.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import resource
import statistics
import time
from pathlib import Path

import numpy as np

__all__ = ["add_arguments", "run", "build_problem", "measure"]

PROBLEMS = ("tied", "mc", "collapse")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``hybrid bench``."""
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000],
                        help="numbers of elements (default: 1e3 1e4 1e5)")
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2],
                        help="numba thread counts (default: 1 2)")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs per figure (median)")
    parser.add_argument("--problems", nargs="+", default=list(PROBLEMS), choices=PROBLEMS)
    parser.add_argument("--element-steps", type=float, default=2.0e7,
                        help="work per timed run, elements x steps (default 2e7)")
    parser.add_argument("--collapse-max", type=int, default=10000,
                        help="largest size for the collapse problem (default 1e4; the bar)")
    parser.add_argument("--json", type=Path, default=None, help="write the results here")


def build_problem(kind: str, n_elements: int):
    """(state, ``RunOptions`` fields) of one benchmark problem with about n_elements elements."""
    from hybrid.discrete import rectangle
    from hybrid.materials import Bond, Contact, Material

    if kind in ("tied", "mc"):
        nx = max(int(round(math.sqrt(n_elements))), 1)
        ny = max(int(round(n_elements / nx)), 1)
        size = 1.0
        if kind == "tied":
            mat = Material(name="block", E=1.0e5, nu=0.3, density=2.0)
            st = rectangle(nx * size, ny * size, nx, ny, material=mat)
            st.fix(np.isclose(st.x_ref[:, 1], 0.0))
            return st, {"mass_damping": 2.0, "contact": False}
        mat = Material(name="block", E=1.0e5, nu=0.3, density=2.0, plastic=True, cohesion=10.0)
        st = rectangle(nx * size, ny * size, nx, ny, material=mat, gravity=(0.0, 0.0))
        st.stress[:] = [-50.0, -70.0, -60.0, 0.0]  # sigma_1 - sigma_3 = 2c: on the yield surface
        # isochoric plane-strain compression imposed on every node: every Gauss point flows
        rate = 1.0e-2  # 1/s
        vel = np.stack([rate * st.x[:, 0], -rate * st.x[:, 1]], axis=1)
        st.fix(np.ones(st.n_nodes, dtype=bool))
        st.prescribed_velocity[:] = vel
        st.v[:] = vel
        return st, {"mass_damping": 0.0, "contact": False}
    if kind == "collapse":
        ny = max(int(round(math.sqrt(4 * n_elements))), 2)
        nx = max(int(round(n_elements / ny)), 1)
        mat = Material(name="block", E=1.0e5, nu=0.3, density=2.0,
                       bond=Bond(tensile_strength=0.0, cohesion=0.0, phi=30.0),
                       contact=Contact(phi=30.0, damping=0.1))
        st = rectangle(float(nx), float(ny), nx, ny, material=mat, gravity=(-3.0, -9.81))
        base = st.element_nodes[:nx].ravel()  # bottom row: a rigid base (all nodes fixed)
        st.fix(base)
        return st, {"mass_damping": 0.0, "split_every": 10, "contact": True}
    raise ValueError(f"unknown problem {kind!r}: choose from {PROBLEMS}")


def measure(kind: str, n_elements: int, threads: int, repeats: int,
            element_steps: float) -> dict:
    """Median element-steps/s of ``repeats`` timed runs (after a warm-up) of one problem."""
    import numba

    from hybrid.discrete import integrate
    from hybrid.discrete.solver import ExplicitSolver, RunOptions, has_contact_module

    numba.set_num_threads(threads)
    rates = []
    extra: dict = {}
    import gc

    for rep in range(repeats + 1):
        gc.collect()
        rss_before = _current_rss_mb()
        st, opt = build_problem(kind, n_elements)
        n = st.n_elements
        steps = max(int(element_steps / n), 20) if rep else 5
        use_contact = opt.get("contact", False) and has_contact_module()
        if opt.get("contact", False) and not use_contact:
            return {"problem": kind, "skipped": "hybrid.discrete.contact not available"}
        dt = 0.5 * integrate.stable_time_step(st, contact=use_contact)
        solver = ExplicitSolver(st, RunOptions(dt=dt, **opt))  # the engine's own step
        # with contact: let it collapse a little first so that contacts are active when timed
        warm_steps = 300 if use_contact and rep else 0
        t0 = 0.0
        for k in range(warm_steps + steps):
            if k == warm_steps:
                t0 = time.perf_counter()
            solver.step()
        wall = time.perf_counter() - t0
        n_active = solver.active_contacts
        if not np.isfinite(st.x).all():
            raise RuntimeError(f"benchmark problem {kind} went unstable")
        if rep:
            rates.append(n * steps / wall)
            extra = {"steps": steps, "yielded_fraction": float(st.yielded.mean()),
                     "active_contacts": int(n_active),
                     "broken_interfaces": int((~st.interface_intact).sum()),
                     "state_bytes_per_element": _state_bytes(st) / n,
                     "rss_growth_bytes_per_element":
                         (_current_rss_mb() - rss_before) * 2**20 / n}
    return {"problem": kind, "elements": n, "threads": threads,
            "element_steps_per_s": statistics.median(rates), "runs": rates,
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
            **extra}


def _current_rss_mb() -> float:
    """Resident set size now [MB] (Linux /proc; 0 elsewhere)."""
    try:
        with open("/proc/self/statm") as f:
            pages = int(f.read().split()[1])
        return pages * resource.getpagesize() / 2**20
    except (OSError, ValueError, IndexError):
        return 0.0


def _state_bytes(st) -> int:
    return int(sum(v.nbytes for v in vars(st).values() if isinstance(v, np.ndarray)))


def run(args: argparse.Namespace) -> int:
    """Run the benchmark, print a table, optionally write JSON; returns the exit code."""
    import numba

    from hybrid.discrete.solver import has_contact_module

    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    old = numba.get_num_threads()
    results = []
    try:
        for kind in args.problems:
            if kind == "collapse" and not has_contact_module():
                print("collapse: skipped (hybrid.discrete.contact not available)")
                continue
            for n in args.sizes:
                if kind == "collapse" and n > args.collapse_max:
                    continue
                for t in args.threads:
                    if t > numba.config.NUMBA_NUM_THREADS:
                        print(f"threads={t}: skipped (NUMBA_NUM_THREADS = "
                              f"{numba.config.NUMBA_NUM_THREADS})")
                        continue
                    r = measure(kind, n, t, args.repeats, args.element_steps)
                    results.append(r)
                    print(_row(r), flush=True)
    finally:
        numba.set_num_threads(old)
    layer = numba.threading_layer()
    info = {"threading_layer": layer, "numba": numba.__version__, "numpy": np.__version__,
            "machine": platform.machine(), "cpus": numba.config.NUMBA_NUM_THREADS,
            "baseline_rss_mb": rss0, "results": results}
    print(f"numba {numba.__version__}, threading layer: {layer}, "
          f"baseline RSS {rss0:.0f} MB")
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(info, indent=2))
        print(f"wrote {args.json}")
    return 0


def _row(r: dict) -> str:
    if "skipped" in r:
        return f"{r['problem']:9s} skipped: {r['skipped']}"
    return (f"{r['problem']:9s} {r['elements']:>8d} el  {r['threads']} thr  "
            f"{r['element_steps_per_s']:10.3e} el-steps/s  (runs "
            f"{', '.join(f'{x:.3g}' for x in r['runs'])})  peak RSS {r['peak_rss_mb']:.0f} MB  "
            f"state {r['state_bytes_per_element']:.0f} B/el (RSS +"
            f"{r['rss_growth_bytes_per_element']:.0f} B/el)  yielded {r['yielded_fraction']:.2f}"
            f"  contacts {r['active_contacts']}")


def main(argv: list[str] | None = None) -> int:
    """Stand-alone entry: ``python -m hybrid.bench``."""
    parser = argparse.ArgumentParser(prog="hybrid bench", description=__doc__)
    add_arguments(parser)
    return run(parser.parse_args(argv))


if __name__ == "__main__":
    raise SystemExit(main())
