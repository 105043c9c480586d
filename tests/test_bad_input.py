"""Bad input gets a clear message (or a non-zero exit), never a traceback, a crash or a number.

One test per kind of fault: the discrete run's monitors, the continuum's singular systems,
meshes and loads, case parameters, and (slow) MPI jobs that must fail fast.
"""

from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import time

import numpy as np
import pytest
from conftest import CASES, PYTHON, ROOT

from hybrid.discrete.builders import blocks, rectangle
from hybrid.discrete.ledger import EnergyLedger
from hybrid.discrete.monitor import RUNAWAY_MARGIN, Monitor
from hybrid.discrete.solver import run
from hybrid.materials import Contact, Material
from hybrid.model import Displacement, Model, ModelError, Pressure, Roller, Traction

BLOCK = Material(name="block", E=1.0e5, nu=0.3, density=2.0,
                 contact=Contact(damping=0.2, phi=30.0))
SOIL = Material(name="soil", E=1.0e4, nu=0.3, unit_weight=20.0)


def _stacked():
    """A block resting 2 cm above a held one: contact, gravity, 4 elements."""
    st = blocks([(1.0, 0.5, 2, 1, (0.0, 0.0), 0), (1.0, 0.5, 2, 1, (0.0, 0.52), 0)], [BLOCK])
    st.fix(np.isclose(st.x_ref[:, 1], 0.0))
    return st


# -- discrete: monitors on the ledger ----------------------------------------------------------

@pytest.mark.parametrize("fault, message", [
    (lambda st: st.gravity.__setitem__(1, math.nan), "gravity holds non-finite values"),
    (lambda st: st.external_force.__setitem__((3, 0), math.inf),
     "external_force holds non-finite values at node 3"),
    (lambda st: st.prescribed_velocity.__setitem__((0, 1), math.nan),
     "prescribed_velocity holds non-finite values at node 0"),
    (lambda st: st.contact_table.__setitem__((0, 3), 1.5),
     r"contact damping ratio 1.5 of material 0 is outside \[0, 1\]"),
    (lambda st: st.contact_table.__setitem__((0, 4), -2.0),
     r"contact cohesion -2.0 of material 0 is not a finite number >= 0 kPa"),
])
def test_discrete_run_refuses_bad_inputs(fault, message):
    st = _stacked()
    fault(st)
    with pytest.raises(ValueError, match=f"discrete run refused: {message}"):
        run(st, max_steps=10)


def test_discrete_run_refuses_a_massless_free_tie_group():
    st = rectangle(1.0, 1.0, 1, 1, material=BLOCK)
    st.mass[:] = 0.0
    st.refresh_groups()
    with pytest.raises(ValueError, match=r"tie group\(s\) free to move have no mass"):
        run(st, max_steps=10)


def test_energy_without_a_source_stops_the_run_and_names_the_cause():
    """Contact damping of 1.5 slipped in after the start: the bodies are pushed apart, the
    energy grows past its sources and the run stops, blaming the damping ratio (not dt)."""
    st = _stacked()

    def corrupt(state):
        state.contact_table[:, 3] = 1.5

    with pytest.raises(RuntimeError, match=(
            r"unstable at step \d+ .*above the margin of 2 x.*Cause: contact damping ratio "
            r"1.5 of material 0")):
        run(st, max_steps=20_000, mass_damping=2.0, check_every=200, on_check=corrupt)


def test_nan_gravity_mid_run_is_named_not_dt():
    st = _stacked()

    def corrupt(state):
        state.gravity[1] = math.nan

    with pytest.raises(RuntimeError, match="non-finite .*Cause: gravity holds non-finite"):
        run(st, max_steps=2000, check_every=50, on_check=corrupt)


def test_nan_coordinates_between_checks_are_an_unstable_run_not_bad_input():
    """A coordinate that turns NaN between two checks of a run with contact: the run stops as
    unstable (RunUnstable, exit code 3), before the energy ledger's contact term reads the
    coordinates and would call them bad input (ValueError, exit code 2)."""
    from hybrid.errors import RunUnstable

    st = blocks([(1.0, 0.5, 2, 1, (0.0, 0.0), 0), (1.0, 0.5, 2, 1, (0.0, 0.5), 0)], [BLOCK])
    st.fix(np.isclose(st.x_ref[:, 1], 0.0))  # the upper block rests on the held one

    def corrupt(state):
        state.x[-1, 0] = math.nan  # a free node of the upper block

    with pytest.raises(RunUnstable, match="non-finite coordinates/velocities"):
        run(st, max_steps=400, check_every=150, contact_refresh=1000, split_every=0,
            on_check=corrupt)


def test_monitor_stops_slow_growth_beyond_the_margin():
    """The energy grows 1.2x per check (never 10x) and is stopped once above the margin."""
    st = rectangle(1.0, 1.0, 1, 1, material=BLOCK)
    terms = dict.fromkeys(EnergyLedger.__dataclass_fields__, 0.0)
    start = EnergyLedger(**{**terms, "kinetic": 1.0})
    monitor = Monitor(st, start, 1e-4)
    energy, checks = 1.0, 0
    with pytest.raises(RuntimeError, match="above the margin"):
        while checks < 100:
            energy *= 1.2
            monitor.check(st, EnergyLedger(**{**terms, "kinetic": energy}))
            monitor.e_prev = energy
            checks += 1
    assert RUNAWAY_MARGIN < energy <= 1.2 * RUNAWAY_MARGIN + 1e-9


def test_discrete_run_refuses_a_nan_end_time():
    with pytest.raises(ValueError, match="until_time = nan: must be a finite time"):
        run(rectangle(1.0, 1.0, 1, 1, material=BLOCK), until_time=math.nan)


# -- continuum: meshes, loads, singular systems ------------------------------------------------

def _block_with(move=None):
    """A gmsh builder: the 2 x 2 triangle block of meshes/block.py, one node then moved."""
    from hybrid.geometry import load_builder

    block = load_builder(ROOT / "meshes" / "block.py")

    def build(gmsh):
        block(gmsh, width=2.0, height=2.0, nx=2, ny=2, cells="triangle")
        if move is not None:
            tags, coords, _ = gmsh.model.mesh.getNodes()
            xy = coords.reshape(-1, 3)
            inner = int(tags[np.argmin(np.hypot(xy[:, 0] - 1.0, xy[:, 1] - 1.0))])
            gmsh.model.mesh.setNode(inner, [*move, 0.0], [])

    return build


@pytest.mark.parametrize("move, message", [
    ((math.nan, 1.0), r"have a non-finite coordinate"),
    ((3.0, 1.0), r"are inverted \(its nodes run the other way round"),
    ((0.0, 0.0), r"are of zero area"),
])
def test_bad_cells_are_refused_when_the_mesh_is_read(move, message):
    from hybrid.geometry import GeometryError, build_mesh

    with pytest.raises(GeometryError, match=message):
        build_mesh(_block_with(move))


def test_tangled_quadrilateral_is_refused():
    from hybrid.geometry import GeometryError, build_mesh, load_builder

    block = load_builder(ROOT / "meshes" / "block.py")

    def build(gmsh):
        block(gmsh, width=2.0, height=2.0, nx=1, ny=1, cells="quadrilateral")
        tags, coords, _ = gmsh.model.mesh.getNodes()
        xy = coords.reshape(-1, 3)
        corner = int(tags[np.argmin(np.hypot(xy[:, 0] - 2.0, xy[:, 1] - 2.0))])
        gmsh.model.mesh.setNode(corner, [-1.0, 2.5, 0.0], [])  # its edge crosses the left one

    with pytest.raises(GeometryError, match=r"tangled \(a self-intersecting quadrilateral\)"):
        build_mesh(build)


def test_unreadable_msh_and_unknown_cells_are_refused(tmp_path):
    from hybrid.geometry import GeometryError, build_mesh, read_msh

    bad = tmp_path / "bad.msh"
    bad.write_text("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\ngarbage\n")
    with pytest.raises(GeometryError, match="cannot be read by gmsh"):
        read_msh(bad)
    with pytest.raises(GeometryError, match="cells = 'hexagon': must be 'triangle' or"):
        build_mesh(_block_with(), cells="hexagon")


@pytest.mark.parametrize("load, message", [
    (lambda: Pressure("top", math.nan), "Pressure on 'top': value = nan must be a finite"),
    (lambda: Pressure("top", math.inf), "value = inf must be a finite number"),
    (lambda: Traction("top", ty=-math.inf), "Traction on 'top': ty = -inf must be"),
    (lambda: Displacement("top", uy=math.nan), "Displacement on 'top': uy = nan must be"),
    (lambda: Pressure("top", True), "value = True must be a finite number"),
])
def test_non_finite_loads_are_refused_at_the_model(load, message):
    with pytest.raises(ModelError, match=re.escape(message)):
        load()


@pytest.fixture(scope="module")
def block_mesh():
    from hybrid.geometry import build_mesh

    return build_mesh(_block_with())


@pytest.mark.parametrize("supports, free", [
    ([], "translation in x, translation in y, rotation"),
    ([Roller("base", "y")], "translation in x"),
    ([Roller("left", "x")], "translation in y"),
])
def test_missing_supports_are_refused_naming_the_free_motion(block_mesh, supports, free):
    from hybrid.continuum import PlasticSolver, solve_elastic

    model = Model(block_mesh, {"soil": SOIL}, supports=supports)
    with pytest.raises(ModelError, match=re.escape(f"free to move ({free})")):
        solve_elastic(model)
    with pytest.raises(ModelError, match="free to move"):
        PlasticSolver(model)


def test_singular_solve_is_refused_not_a_number(block_mesh, monkeypatch):
    """With the support check bypassed, the direct solve of a floating body is refused."""
    from hybrid.continuum import fields, solve_elastic

    monkeypatch.setattr(fields, "free_rigid_motions", lambda *a: [])
    with pytest.raises(ModelError, match="the stiffness is singular"):
        solve_elastic(Model(block_mesh, {"soil": SOIL}))


def test_handing_over_an_empty_region_with_freeze_layers_is_refused(case):
    from hybrid.handover import to_discrete

    m = case("slope_gravity")
    state = m.solve(m.Parameters(size=2.0, flat=30.0, degree=1, convergence=False))
    with pytest.raises(ValueError, match="freeze_layers = 2: the splittable region is empty"):
        to_discrete(state, freeze_layers=2)  # elastic: nothing yielded


# -- case parameters and the command line ------------------------------------------------------

@pytest.mark.parametrize("name, overrides, message", [
    ("block_drop", {"element_size": 0.0}, "element_size = 0.0: must be > 0"),
    ("block_drop", {"max_steps": 0}, "max_steps = 0: must be >= 1"),
    ("block_drop", {"contact_damping": 1.5}, "contact_damping = 1.5: must be >= 0 and <= 1"),
    ("uniform_load", {"cells": "hexagon"}, "cells = 'hexagon': must be one of 'triangle', "
                                           "'quadrilateral'"),
    ("uniform_load", {"degree": 3}, "degree = 3: must be one of 1, 2"),
    ("uniform_load", {"n": 2.5}, "n = 2.5: must be a whole number"),
    ("uniform_load", {"n": 2.0}, "n = 2.0: must be a whole number (an int, not 2.0)"),
    ("uniform_load", {"q": True}, "q = True: must be a finite number"),
    ("bearing_capacity", {"settlement": math.nan}, "settlement = nan: must be a finite"),
    ("retaining_wall", {"mode": "sideways"}, "mode = 'sideways': must be one of 'active'"),
    ("slope_fos", {"newton_tolerance": 2.0}, "newton_tolerance = 2.0: must be > 0 and < 1"),
    ("toppling", {"progress": "yes"}, "progress = 'yes': must be True or False"),
    ("carsington", {"layer_size": -1.0}, "layer_size = -1.0: must be > 0"),
    ("footing_failure", {"freeze_layers": -1}, "freeze_layers = -1: must be >= 0"),
])
def test_case_parameters_are_validated(case, name, overrides, message):
    from hybrid.parameters import ParameterError

    with pytest.raises(ParameterError, match=re.escape(message)):
        case(name).Parameters(**overrides)


def test_footing_freeze_layers_without_a_region_is_refused(case, tmp_path):
    """H2's ``freeze_layers`` holds the cells beyond a region of ``region_layers``: alone (every
    bond free to fail) it would hold nothing, so it is refused before anything runs."""
    from hybrid.parameters import ParameterError

    with pytest.raises(ParameterError, match="freeze_layers needs region_layers"):
        case("footing_failure").main(out=tmp_path, freeze_layers=2, progress=False)
    assert not any(tmp_path.iterdir())


def test_case_parameters_pick(case):
    """The named fields' values by name, in the order asked (what a mesh builder takes)."""
    p = case("carsington").Parameters(boot_length=30.0)
    assert p.pick(["boot_length", "lifts"]) == {"boot_length": 30.0, "lifts": p.lifts}
    assert p.pick([]) == {}
    with pytest.raises(AttributeError):
        p.pick(["no_such_field"])


def test_every_case_accepts_its_defaults(case):
    for path in sorted(CASES.glob("*.py")):
        case(path.stem).Parameters()


def _hybrid(*args, mpi=0, timeout=120):
    env = dict(os.environ, PYTHONPATH=str(ROOT), NUMBA_NUM_THREADS="1",
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    head = ["mpirun", "-n", str(mpi)] if mpi else []
    return subprocess.run([*head, PYTHON, *args], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=timeout)


@pytest.mark.parametrize("override, message", [
    ("element_size=0", "case parameter element_size = 0.0: must be > 0"),
    ("max_steps=0", "case parameter max_steps = 0: must be >= 1"),
    ("rest=nan", "case parameter rest = nan: must be a finite number"),
])
def test_hybrid_run_answers_bad_overrides_in_one_line(tmp_path, override, message):
    result = _hybrid("-m", "hybrid", "run", str(CASES / "block_drop.py"), "--out",
                     str(tmp_path), "--set", override)
    assert result.returncode == 2
    assert result.stderr.strip() == f"hybrid: error: {message} (--set {override.split('=')[0]}" \
                                    "=VALUE)"


def test_hybrid_run_exits_non_zero_when_a_check_fails(tmp_path, monkeypatch, capsys):
    """A check with a bar that fails gives exit code 4; reported checks do not count."""
    import argparse

    from hybrid.case import execute
    from hybrid.io import CaseSummary, Check

    def main(out, **_):
        return CaseSummary("demo", out, None, checks={
            "good": Check(1.0, 1.0, 0.01, "m"), "reported": Check(5.0, None, None, "m"),
            "bad": Check(2.0, 1.0, 0.01, "m")})

    args = argparse.Namespace(list=False, overrides=[], out=str(tmp_path))
    assert execute(main, type("P", (), {"__dataclass_fields__": {}}), args) == 4
    assert "checks failed: bad" in capsys.readouterr().err


def test_output_folder_that_cannot_be_written_is_refused(tmp_path):
    """An --out below a file (unwritable whoever runs it) is one line, exit 2."""
    (tmp_path / "file").write_text("")
    result = _hybrid("-m", "hybrid", "run", str(CASES / "uniform_load.py"), "--out",
                     str(tmp_path / "file" / "out"))
    assert result.returncode == 2
    assert result.stderr.strip() == (f"hybrid: error: output folder '{tmp_path}/file/out' "
                                     "cannot be written (Not a directory): choose another --out")


# -- MPI fails fast ----------------------------------------------------------------------------

@pytest.mark.mpi
@pytest.mark.skipif(shutil.which("mpirun") is None, reason="mpirun not installed")
def test_mpi_job_fails_fast_on_an_unwritable_out(tmp_path):
    (tmp_path / "file").write_text("")
    start = time.perf_counter()
    result = _hybrid("-m", "hybrid", "run", str(CASES / "uniform_load.py"), "--out",
                     str(tmp_path / "file" / "out"), mpi=2, timeout=60)
    assert result.returncode != 0
    assert "cannot be written (Not a directory)" in result.stderr
    assert time.perf_counter() - start < 60


@pytest.mark.mpi
@pytest.mark.skipif(shutil.which("mpirun") is None, reason="mpirun not installed")
def test_mpi_job_fails_fast_on_a_corrupted_msh(tmp_path):
    bad = tmp_path / "bad.msh"
    bad.write_text("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\ngarbage\n")
    script = ("from hybrid.errors import run_command\nfrom hybrid.geometry import read_msh\n"
              f"raise SystemExit(run_command(lambda: read_msh({str(bad)!r})))\n")
    start = time.perf_counter()
    result = _hybrid("-c", script, mpi=2, timeout=60)
    assert result.returncode != 0
    assert "cannot be read by gmsh" in result.stderr
    assert time.perf_counter() - start < 60


@pytest.mark.mpi
@pytest.mark.skipif(shutil.which("mpirun") is None, reason="mpirun not installed")
def test_mpi_job_fails_fast_on_an_error_of_one_rank(tmp_path):
    """An exception on rank 1 only (not a ValueError) aborts both ranks with its message."""
    script = ("from mpi4py import MPI\nfrom hybrid.errors import run_command\n"
              "def job():\n    if MPI.COMM_WORLD.rank == 1:\n"
              "        raise OSError('disk on fire')\n    MPI.COMM_WORLD.barrier()\n"
              "raise SystemExit(run_command(job))\n")
    result = _hybrid("-c", script, mpi=2, timeout=60)
    assert result.returncode != 0
    assert "hybrid: error (rank 1): OSError: disk on fire" in result.stderr


@pytest.mark.mpi
@pytest.mark.skipif(shutil.which("mpirun") is None, reason="mpirun not installed")
def test_discrete_case_under_mpirun_is_refused(tmp_path):
    result = _hybrid("-m", "hybrid", "run", str(CASES / "block_drop.py"), "--out",
                     str(tmp_path), mpi=2, timeout=60)
    assert result.returncode != 0
    assert "block_drop is a discrete-only case" in result.stderr
    assert not (tmp_path / "discrete.h5").exists()


def test_a_file_that_cannot_be_written_is_exit_5_not_a_traceback(tmp_path, capsys):
    """A case whose output write fails with an OSError (here: its folder is a file) ends with
    one line naming the file and exit code 5."""
    import argparse

    from hybrid.case import execute

    blocked = tmp_path / "blocked"

    def main(out=str(tmp_path / "out")):
        blocked.write_text("a file, not a folder")
        (blocked / "figure.png").write_bytes(b"")  # NotADirectoryError

    args = argparse.Namespace(list=False, overrides=[], out=None, overwrite=False,
                              resume=False)
    assert execute(main, type("P", (), {"__dataclass_fields__": {}}), args) == 5
    err = capsys.readouterr().err
    assert "output error:" in err and "figure.png" in err and "Traceback" not in err
