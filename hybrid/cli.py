"""The ``hybrid`` command: info, run, verify, bench (``--version``)."""

from __future__ import annotations

import argparse
import importlib
import os
import shutil
import sys
from collections.abc import Sequence
from types import ModuleType

import hybrid

__all__ = ["main"]


def _version(module: str) -> str:
    try:
        mod = importlib.import_module(module)
    except ImportError as err:
        return f"missing ({err})"
    if module == "petsc4py":
        from petsc4py import PETSc

        return f"{mod.__version__} (PETSc {'.'.join(map(str, PETSc.Sys.getVersion()))})"
    return str(getattr(mod, "__version__", "?"))


def _blas() -> str:
    """The BLAS and LAPACK libraries this process has loaded (numpy's and PETSc's)."""
    try:
        with open("/proc/self/maps") as maps:
            fields = [line.split(maxsplit=5) for line in maps]
    except OSError:
        return "unknown (no /proc/self/maps)"
    paths = {f[5].strip() for f in fields if len(f) == 6
             and any(word in f[5].rsplit("/", 1)[-1] for word in ("blas", "lapack"))}
    return ", ".join(sorted(paths)) or "none loaded"


def info() -> dict[str, str]:
    """Versions and runtime facts users report with a bug."""
    facts = {"hybrid": hybrid.__version__, "python": sys.version.split()[0],
             "executable": sys.executable}
    for module in ("dolfinx", "ufl", "basix", "ffcx", "petsc4py", "mpi4py", "numba", "numpy",
                   "gmsh", "meshio", "matplotlib", "tqdm"):
        facts[module] = _version(module)
    import numba
    from mpi4py import MPI

    facts["numba threads"] = str(numba.config.NUMBA_NUM_THREADS)
    facts["numba threading layer (configured)"] = str(numba.config.THREADING_LAYER)
    facts["numba cache dir"] = os.environ.get("NUMBA_CACHE_DIR", "")
    facts["MPI size"] = str(MPI.COMM_WORLD.size)
    facts["MPI library"] = MPI.Get_library_version().splitlines()[0].strip()
    facts["BLAS"] = _blas()
    facts["ffmpeg"] = shutil.which("ffmpeg") or "not found (animations as GIF only)"
    return facts


def _cmd_info(args: argparse.Namespace) -> int:
    facts = info()
    width = max(map(len, facts))
    for key, value in facts.items():
        print(f"{key:<{width}}  {value}")
    return 0


def _cmd_run(args: argparse.Namespace) -> int:
    from hybrid.case import execute, load_case

    module = load_case(args.case)
    return execute(module.main, module.Parameters, args)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``hybrid`` console script."""
    from hybrid.case import case_arguments

    parser = argparse.ArgumentParser(prog="hybrid", description=hybrid.__doc__.split("\n")[0])
    parser.add_argument("--version", action="version", version=f"hybrid {hybrid.__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("info", help="versions, threads, MPI, ffmpeg").set_defaults(func=_cmd_info)
    run = sub.add_parser("run", help="run a case script: hybrid run cases/x.py (or x) --out DIR")
    run.add_argument("case", help="path of the case script, or the name of one in cases/")
    case_arguments(run)
    run.set_defaults(func=_cmd_run)
    bench: ModuleType | None
    try:
        from hybrid import bench
    except ImportError:  # the discrete engine is optional until it lands
        bench = None
    if bench is not None:
        b = sub.add_parser("bench", help="discrete-engine throughput benchmark")
        bench.add_arguments(b)
        b.set_defaults(func=bench.run)
    from hybrid import verification

    verify = sub.add_parser("verify", help="run the verification cases, write the report")
    verification.add_arguments(verify)
    verify.set_defaults(func=verification.command)
    args = parser.parse_args(argv)
    from hybrid.errors import run_command

    return run_command(lambda: args.func(args))


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
