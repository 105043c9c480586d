"""Restarts that continue and outputs that survive: a run interrupted (an exception, kill -9
in a child process) and resumed from its checkpoint ends bit for bit as the uninterrupted
one, rest detection included; the series reads up to its last frame; a non-empty output
folder is refused unless told to overwrite or resume; a full disk is one clear message."""

import errno
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import meshio
import numpy as np
import pytest

from hybrid.discrete import rectangle, ties
from hybrid.discrete.outputs import Checkpoints, XdmfSeries, standard_outputs
from hybrid.discrete.solver import ExplicitSolver, RunOptions
from hybrid.discrete.state import DiscreteState
from hybrid.errors import OutputError
from hybrid.materials import Material, Strength

# softening: the bonds that fail where the material has softened, and the cohesive contacts
# they leave, are part of what a resumed run must restore
MAT = Material(name="clay", E=1.0e5, nu=0.3, density=2.0, cohesion=5.0, phi=20.0,
               residual=Strength(cohesion=1.0, phi=20.0), softening_displacement=0.01)
OPTS = RunOptions(mass_damping=5.0, split_every=10)
FIELDS = ("x", "v", "stress", "plastic_strain", "internal_force", "group_energy", "ledger",
          "node_group", "interface_intact", "contact_shear", "interface_mode",
          "interface_failure_time")


def _column():
    st = rectangle(1.0, 2.0, 2, 4, material=MAT)
    st.fix(np.isclose(st.x_ref[:, 1], 0.0))
    st.external_force[np.isclose(st.x_ref[:, 1], 2.0), 1] = -20.0
    return st


def _runs(solver, stop_at=None):
    """A loading run, then a run to rest: the script the restart repeats."""
    def stopper(s):
        if s.step == 200 and s.interface_intact[0]:  # a callback that splits, at a checkpoint
            ties.split_interfaces(s, [0])
        if stop_at is not None and s.step >= stop_at:
            raise KeyboardInterrupt
    first = solver.run(max_steps=300, check_every=20, on_check=stopper, phase="loading")
    solver.state.external_force[:] = 0.0
    second = solver.run(until_rest=1e-3, max_steps=20_000, check_every=20, rest_min_steps=100,
                        on_check=stopper, phase="rest")
    return first, second


def _outputs(out, resume=False):
    return standard_outputs(out, output_every=60, checkpoint_every=100, progress=False,
                            resume=resume, material_names=["clay"])


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    out = tmp_path_factory.mktemp("whole")
    st = _column()
    with ExplicitSolver(st, OPTS, observers=_outputs(out)) as solver:
        first, second = _runs(solver)
    assert second.stop_reason == "rest"
    return st, first, second, out


@pytest.mark.parametrize("stop_at", [160, 520])  # in the loading run, in the rest run
def test_resumed_run_ends_bit_for_bit(reference, tmp_path, stop_at):
    ref, first, second, ref_out = reference
    with pytest.raises(KeyboardInterrupt), \
            ExplicitSolver(_column(), OPTS, observers=_outputs(tmp_path)) as solver:
        _runs(solver, stop_at=stop_at)
    st = _column()
    with ExplicitSolver(st, OPTS, observers=_outputs(tmp_path, resume=True)) as solver:
        assert solver.steps == (stop_at // 100) * 100  # the last checkpoint's step
        again = _runs(solver)
    for name in FIELDS:
        assert np.array_equal(getattr(st, name), getattr(ref, name), equal_nan=True), name
    assert (~np.isnan(st.interface_failure_time)).sum() == (st.interface_mode > 0).sum() > 0
    assert st.step == ref.step and st.time == ref.time
    for a, b in zip(again, (first, second), strict=True):
        assert (a.stop_reason, a.steps, a.time, a.n_split, a.peak_kinetic) == (
            b.stop_reason, b.steps, b.time, b.n_split, b.peak_kinetic)
        for key in b.history:
            assert np.array_equal(a.history[key], b.history[key]), key
    _same_series(tmp_path, ref_out)


def _same_series(out, ref_out):
    """The resumed series holds the uninterrupted one's frames, bit for bit."""
    with meshio.xdmf.TimeSeriesReader(out / "discrete.xdmf") as a, \
            meshio.xdmf.TimeSeriesReader(ref_out / "discrete.xdmf") as b:
        a.read_points_cells()
        b.read_points_cells()
        assert a.num_steps == b.num_steps > 5
        for k in range(b.num_steps):
            ta, pa, ca = a.read_data(k)
            tb, pb, cb = b.read_data(k)
            assert ta == tb
            for name in ("displacement", "velocity", "contact_force"):
                assert np.array_equal(pa[name], pb[name]), name
            for name in ("sigma_yy", "failed_interfaces", "material"):
                assert np.array_equal(ca[name][0], cb[name][0]), name


def test_series_fields_and_animation_limits(reference):
    """The series: same names as the continuum, material names in the index; the last frame
    is the final state; the animation keeps one colour range and one set of axes."""
    ref, _, second, out = reference
    with meshio.xdmf.TimeSeriesReader(out / "discrete.xdmf") as r:
        r.read_points_cells()
        t, pd, cd = r.read_data(r.num_steps - 1)
    assert t == second.time == ref.time
    assert set(cd) >= {"sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy", "plastic_strain",
                       "yielded", "failed_interfaces", "material"}
    np.testing.assert_array_equal(cd["sigma_yy"][0], ref.stress[:, :, 1].mean(axis=1))
    np.testing.assert_array_equal(pd["velocity"][:, :2], ref.v)
    assert 'Value="0: clay"' in (out / "discrete.xdmf").read_text()
    frames = sorted((out / "frames").glob("frame_*.png"))
    assert len(frames) == r.num_steps and (out / "discrete.gif").is_file()


def test_animation_limits_fixed(tmp_path):
    from hybrid.discrete.outputs import Animation

    st = _column()
    series = XdmfSeries(tmp_path, 50)
    anim = Animation(series)
    with ExplicitSolver(st, OPTS, observers=[series, anim]) as solver:
        solver.run(max_steps=200, phase="loading")
    assert len(anim.limits) == len(series.frames) == 5
    assert all(lim == anim.limits[0] for lim in anim.limits)


def test_checkpoint_keeps_the_previous_one(tmp_path):
    st = _column()
    with ExplicitSolver(st, OPTS, observers=[Checkpoints(tmp_path, 50)]) as solver:
        solver.run(max_steps=120)
    assert DiscreteState.load(tmp_path / "checkpoint.npz").step == 120  # end of the run
    assert DiscreteState.load(tmp_path / "checkpoint.prev.npz").step == 100
    assert not list(tmp_path.glob("*.tmp"))


def test_resume_with_other_runs_refused(tmp_path):
    with ExplicitSolver(_column(), OPTS, observers=_outputs(tmp_path)) as solver:
        solver.run(max_steps=150, phase="loading")
    with pytest.raises(ValueError, match="call the runs as the interrupted script did"), \
            ExplicitSolver(_column(), OPTS, observers=_outputs(tmp_path, resume=True)) as s:
        s.run(max_steps=200, phase="loading")
    other = rectangle(1.0, 1.0, 1, 1, material=MAT)
    with pytest.raises(ValueError, match="a checkpoint of another model"):
        ExplicitSolver(other, OPTS, observers=_outputs(tmp_path, resume=True))
    with pytest.raises(ValueError, match=r"other run options: dt = None then, 1e-05 now"):
        ExplicitSolver(_column(), RunOptions(dt=1e-5), observers=_outputs(tmp_path, True))


def test_resume_with_other_case_parameters_refused(tmp_path):
    """``hybrid run --resume --set cohesion=60`` on a run started with 69: refused, naming the
    parameter (the discrete state in the checkpoint was made with the old value)."""
    from hybrid.discrete.outputs import CASE_PARAMETERS

    token = CASE_PARAMETERS.set({"cohesion": 69.0, "mass_damping": 2.0})
    try:
        with ExplicitSolver(_column(), OPTS, observers=_outputs(tmp_path)) as solver:
            solver.run(max_steps=150, phase="loading")
        CASE_PARAMETERS.set({"cohesion": 60.0, "mass_damping": 2.0})
        with pytest.raises(ValueError, match=r"other case parameters: cohesion = 69.0 then, "
                                             r"60.0 now; resume with the same values"):
            ExplicitSolver(_column(), OPTS, observers=_outputs(tmp_path, resume=True))
        CASE_PARAMETERS.set({"cohesion": 69.0, "mass_damping": 2.0})
        ExplicitSolver(_column(), OPTS, observers=_outputs(tmp_path, resume=True)).close()
    finally:
        CASE_PARAMETERS.reset(token)


def test_full_disk_is_one_clear_message(tmp_path, monkeypatch):
    """The disk fills during a frame and then during a checkpoint: one message naming the
    last good frame; the series and the previous checkpoint stay readable."""
    import h5py

    st = _column()
    outputs = _outputs(tmp_path)
    with ExplicitSolver(st, OPTS, observers=outputs) as solver:
        solver.run(max_steps=200)
        real = h5py.File

        def full(name, mode="r", *a, **k):
            if mode == "w":
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            return real(name, mode, *a, **k)

        monkeypatch.setattr(h5py, "File", full)
        with pytest.raises(OutputError, match=r"No space left on device\): the last good frame "
                                              r"\(t = .* s, step 180\) and the last checkpoint "
                                              "stay readable"):
            solver.run(max_steps=100)
        monkeypatch.undo()
        with meshio.xdmf.TimeSeriesReader(tmp_path / "discrete.xdmf") as r:
            r.read_points_cells()
            assert r.read_data(r.num_steps - 1)[0] == pytest.approx(180 * solver.dt,
                                                                    rel=1e-12)
        assert DiscreteState.load(tmp_path / "checkpoint.npz").step == 200

    def full_save(*a, **k):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    with ExplicitSolver(DiscreteState.load(tmp_path / "checkpoint.npz"), OPTS,
                        observers=[Checkpoints(tmp_path, 10)]) as solver:
        monkeypatch.setattr(np, "savez", full_save)
        with pytest.raises(OutputError, match="checkpoint .* failed .*No space left.*previous "
                                              "checkpoint stays readable"):
            solver.run(max_steps=20)
    monkeypatch.undo()
    assert DiscreteState.load(tmp_path / "checkpoint.npz").step == 200
    assert not list(tmp_path.glob("*.tmp"))


# -- the output folder of `hybrid run` ------------------------------------------------------
def test_non_empty_output_folder_refused_unless_told(tmp_path):
    from hybrid.case import CaseError, prepare_output_folder

    out = tmp_path / "out"
    prepare_output_folder(out)  # missing: fine
    out.mkdir()
    prepare_output_folder(out)  # empty: fine
    (out / "frames").mkdir()
    (out / "frames" / "frame_0000.png").write_bytes(b"old")
    (out / "summary.json").write_text("{}")
    with pytest.raises(CaseError, match="is not empty: pass --overwrite to clear it, --resume"):
        prepare_output_folder(out)
    with pytest.raises(CaseError, match="--resume: .* holds no checkpoint.npz"):
        prepare_output_folder(out, resume=True)
    (out / "discrete").mkdir()
    (out / "discrete" / "checkpoint.npz").write_bytes(b"")
    prepare_output_folder(out, resume=True)
    assert (out / "summary.json").exists()  # resume keeps everything
    prepare_output_folder(out, overwrite=True)
    assert out.is_dir() and not any(out.iterdir())
    with pytest.raises(CaseError, match="--resume: .* holds no run to resume"):
        prepare_output_folder(out, resume=True)


# -- fault injection: kill -9 in a child process ---------------------------------------------
_CHILD = textwrap.dedent("""
    import sys, numpy as np
    sys.path.insert(0, {tests!r})
    from test_discrete_restart import _column, _outputs, _runs, OPTS
    from hybrid.discrete.solver import ExplicitSolver
    out, resume = sys.argv[1], sys.argv[2] == "1"
    st = _column()
    with ExplicitSolver(st, OPTS, observers=_outputs(out, resume)) as solver:
        _runs(solver)
    np.savez(out + "/final.npz", **st.arrays())
""")


def _child(out: Path, resume: bool) -> subprocess.Popen:
    script = _CHILD.format(tests=str(Path(__file__).parent))
    return subprocess.Popen([sys.executable, "-c", script, str(out), "1" if resume else "0"],
                            env=dict(os.environ, PYTHONPATH=str(Path(__file__).parents[1])),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)


@pytest.mark.slow
@pytest.mark.parametrize("when", ["mid_run", "checkpoint_write"])
def test_kill_9_then_resume_ends_bit_for_bit(reference, tmp_path, when):
    """kill -9 mid-run, or while a checkpoint is being written: the last checkpoint loads,
    the series reads up to its last frame, and the resumed run ends as the uninterrupted."""
    ref, _, _, ref_out = reference
    proc = _child(tmp_path, False)
    ck = tmp_path / "checkpoint.npz"
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and proc.poll() is None:
        if when == "mid_run" and ck.exists() and DiscreteState.load(ck).step >= 300:
            break
        if (when == "checkpoint_write" and ck.exists()
                and (tmp_path / "checkpoint.npz.tmp").exists()):
            break
    assert proc.poll() is None, proc.stderr.read().decode()
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    DiscreteState.load(ck if ck.exists() else tmp_path / "checkpoint.prev.npz")
    with meshio.xdmf.TimeSeriesReader(tmp_path / "discrete.xdmf") as r:
        r.read_points_cells()
        for k in range(r.num_steps):
            r.read_data(k)
    assert ck.exists()  # a checkpoint is never removed: a kill leaves one to resume from
    again = _child(tmp_path, True)
    _, err = again.communicate(timeout=600)
    assert again.returncode == 0, err.decode()
    with np.load(tmp_path / "final.npz") as final:
        for name in FIELDS:
            assert np.array_equal(final[name], getattr(ref, name)), name
    _same_series(tmp_path, ref_out)


def test_overwrite_clears_only_an_output_folder_of_hybrid(tmp_path, monkeypatch):
    """--overwrite refuses a folder without the marker or a summary.json (a user's folder), a
    repository, and the current folder, whatever they hold; it clears a marked one."""
    from hybrid.case import OUTPUT_MARKER, CaseError, prepare_output_folder

    mine = tmp_path / "thesis"
    mine.mkdir()
    (mine / "chapter1.tex").write_text("years of work")
    with pytest.raises(CaseError, match="does not look like an output folder of hybrid"):
        prepare_output_folder(mine, overwrite=True)
    repo = tmp_path / "repo"
    (repo / ".git").mkdir(parents=True)
    (repo / "summary.json").write_text("{}")
    with pytest.raises(CaseError, match="is not cleared"):
        prepare_output_folder(repo, overwrite=True)
    monkeypatch.chdir(repo.parent)
    here = tmp_path
    (here / OUTPUT_MARKER).write_bytes(b"")
    with pytest.raises(CaseError, match="is not cleared"):
        prepare_output_folder(here, overwrite=True)
    assert (mine / "chapter1.tex").exists() and (repo / ".git").exists()
    run = tmp_path / "run"
    run.mkdir()
    (run / OUTPUT_MARKER).write_bytes(b"")
    (run / "frames").mkdir()
    prepare_output_folder(run, overwrite=True)
    assert not any(run.iterdir())


def test_a_checkpoint_without_failure_times_resumes_with_none(reference, tmp_path):
    """A checkpoint written before the failure time of each bond was recorded resumes with
    none recorded (nan), not with the times the solver's state held before it."""
    ref, _, _, ref_out = reference
    with np.load(ref_out / "checkpoint.npz") as saved:
        older = {k: saved[k] for k in saved.files if k != "interface_failure_time"}
    np.savez(tmp_path / "older.npz", **older)
    st = _column()
    st.interface_failure_time[:] = 7.0
    with ExplicitSolver(st, OPTS) as solver:
        solver.restore(tmp_path / "older.npz")
    assert np.isnan(st.interface_failure_time).all()
    assert st.interface_mode.any() and not st.interface_intact.all()  # the rest restored
