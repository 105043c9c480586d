"""A case killed mid-run continues with ``hybrid run --resume`` to the uninterrupted answer.

H2 on a coarse mesh writes checkpoints; a copy of the run is killed (SIGKILL: no clean-up)
while its discrete phase runs, then resumed into the same folder. The summary's discrete
figures (rest time, steps, settlements, heave, failed interfaces, energy ratios) and the last
frame of the series equal those of the uninterrupted run bit for bit: the loading program's
progress (``LoadProgram``), rest detection and monitors travel in the checkpoint.
"""

import json
import os
import signal
import subprocess
import sys
import time

import meshio
import numpy as np
import pytest
from conftest import ROOT

COARSE = ["--set", "fine=0.15", "--set", "coarse=0.6", "--set", "continuum_steps=12",
          "--set", "output_every=500", "--set", "checkpoint_every=500",
          "--set", "progress=False"]
TIMING = {"wall_time_s", "element_steps_per_s", "outputs"}


def _hybrid(out, *extra) -> list[str]:
    return [sys.executable, "-m", "hybrid", "run", str(ROOT / "cases" / "footing_failure.py"),
            "--out", str(out), *COARSE, *extra]


def _env() -> dict[str, str]:
    return {**os.environ, "NUMBA_NUM_THREADS": "1", "MPLBACKEND": "Agg"}


def _last_frame(out):
    reader = meshio.xdmf.TimeSeriesReader(out / "discrete" / "discrete.xdmf")
    points, _ = reader.read_points_cells()
    t, point_data, cell_data = reader.read_data(reader.num_steps - 1)
    return t, point_data["displacement"], cell_data["sigma_yy"][0]


@pytest.mark.slow
def test_h2_killed_mid_run_resumes_to_the_uninterrupted_answer(tmp_path):
    ref, cut = tmp_path / "ref", tmp_path / "cut"
    subprocess.run(_hybrid(ref), check=True, env=_env(), capture_output=True, cwd=ROOT)
    proc = subprocess.Popen(_hybrid(cut), env=_env(), cwd=ROOT, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    checkpoint = cut / "discrete" / "checkpoint.prev.npz"  # the second checkpoint is written
    deadline = time.monotonic() + 300
    while not checkpoint.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    assert checkpoint.exists() and not (cut / "summary.json").exists()  # killed mid-run

    # the frames written before the kill: a resumed run keeps them, a fresh start would not
    before = {f: f.stat().st_mtime_ns for f in (cut / "discrete" / "discrete_series").iterdir()}
    assert before
    again = subprocess.run(_hybrid(cut), env=_env(), cwd=ROOT, capture_output=True, text=True)
    assert again.returncode == 2 and "not empty" in again.stderr  # no silent overwrite
    subprocess.run(_hybrid(cut, "--resume"), check=True, env=_env(), capture_output=True,
                   cwd=ROOT)
    assert all(f.stat().st_mtime_ns == t for f, t in before.items())
    a = json.loads((ref / "summary.json").read_text())["discrete"]
    b = json.loads((cut / "summary.json").read_text())["discrete"]
    assert {k: v for k, v in a.items() if k not in TIMING} == \
        {k: v for k, v in b.items() if k not in TIMING}
    for x, y in zip(_last_frame(ref), _last_frame(cut), strict=True):
        np.testing.assert_array_equal(x, y)


@pytest.mark.slow
def test_sigterm_stops_a_case_as_ctrl_c_does(tmp_path):
    """SIGTERM (a batch system's time limit) during the discrete phase: exit code 130 with a
    one-line message naming --resume, every frame written so far readable, and the run then
    resumes to completion."""
    out = tmp_path / "h2"
    proc = subprocess.Popen(_hybrid(out), env=_env(), cwd=ROOT, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)
    checkpoint = out / "discrete" / "checkpoint.prev.npz"
    deadline = time.monotonic() + 300
    while not checkpoint.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "interrupted" in err and "--resume" in err and "Traceback" not in err
    reader = meshio.xdmf.TimeSeriesReader(out / "discrete" / "discrete.xdmf")
    reader.read_points_cells()
    assert reader.num_steps >= 1
    for k in range(reader.num_steps):
        reader.read_data(k)
    subprocess.run(_hybrid(out, "--resume"), check=True, env=_env(), capture_output=True,
                   cwd=ROOT)
    assert json.loads((out / "summary.json").read_text())["discrete"]["stop"] == "rest"


def test_load_program_ramps_holds_removes_and_restores_its_progress():
    """LoadProgram: 100 -> 300 over 0.1 s, held until the measure reaches 1, removed over
    0.1 s (exact values at the checks); its state() restored into a fresh program continues
    identically."""
    from types import SimpleNamespace

    from hybrid.discrete.runs import LoadProgram

    applied, reach = [], {"now": 0.0}

    def program() -> LoadProgram:
        return LoadProgram(apply=applied.append, measure=lambda: reach["now"], start=100.0,
                           peak=300.0, target=1.0, ramp_time=0.1, max_time=10.0, t_start=1.0)

    a = program()
    assert not a(SimpleNamespace(time=1.05)) and applied[-1] == pytest.approx(200.0)
    reach["now"] = 1.0
    assert not a(SimpleNamespace(time=1.2))  # target reached: unloading starts at t = 0.2 s
    assert applied[-1] == pytest.approx(300.0) and a.t_unload == pytest.approx(0.2)
    b = program()
    b.restore(a.state())
    for p in (a, b):
        assert not p(SimpleNamespace(time=1.25))
        assert applied[-1] == pytest.approx(150.0)
        assert p(SimpleNamespace(time=1.31)) and applied[-1] == 0.0 and p.removed
    assert a.curve == b.curve and a.at_unloading == b.at_unloading == 1.0


def test_load_program_removes_the_load_it_had_reached():
    """A target reached while the load is still being raised (100 -> 300 over 0.1 s, the
    target at 0.05 s, at 200): the load falls from 200 to 0 over 0.1 s, never up to the
    peak of the ramp it had not reached."""
    from types import SimpleNamespace

    from hybrid.discrete.runs import LoadProgram

    applied, reach = [], {"now": 0.0}
    p = LoadProgram(apply=applied.append, measure=lambda: reach["now"], start=100.0,
                    peak=300.0, target=1.0, ramp_time=0.1, max_time=10.0, t_start=1.0)
    reach["now"] = 1.0
    assert not p(SimpleNamespace(time=1.05)) and p.t_unload == pytest.approx(0.05)
    assert applied[-1] == pytest.approx(200.0)
    assert not p(SimpleNamespace(time=1.10)) and applied[-1] == pytest.approx(100.0)
    assert p(SimpleNamespace(time=1.16)) and applied[-1] == 0.0
    assert max(applied) == pytest.approx(200.0)


def test_a_checkpointed_callback_state_needs_a_stateful_on_check():
    """A checkpoint that holds an on_check's progress refuses a plain function in its place."""
    from hybrid.discrete.solver import _restore_callback

    with pytest.raises(ValueError, match="pass an on_check with state"):
        _restore_callback(lambda s: False, {"phase": np.array(1)})
    _restore_callback(lambda s: False, {})  # nothing saved: any on_check
