"""Outputs of discrete runs: observers of an :class:`~hybrid.discrete.solver.ExplicitSolver`.

An observer is attached to a solver for its lifetime, so one series covers all the solver's
runs (a loading run and the rest run that follows it make one XDMF series and one set of
frames). Its schedule counts the solver's steps (``ExplicitSolver.steps``). Closing the
solver writes the final state where it was not written yet, and the GIF.

- :class:`XdmfSeries`: meshio XDMF time series ``discrete.xdmf`` (+ ``discrete.h5``);
- :class:`Frames`: PNG frames ``frames/frame_NNNN.png`` and ``discrete.gif`` at close;
- :class:`Checkpoints`: ``state.save`` to ``checkpoint.npz`` every N steps and at the end of
  each run (a restart is bit for bit);
- :class:`ProgressBar`: a tqdm bar per run.

:func:`standard_outputs` builds the usual set from the cases' parameters; :func:`frame_interval`
spaces a number of frames over a run.
"""

from __future__ import annotations

import abc
from pathlib import Path

import numpy as np

from hybrid.discrete.ledger import EnergyLedger
from hybrid.discrete.solver import ExplicitSolver, Observer, RunResult
from hybrid.discrete.state import DiscreteState

__all__ = ["XdmfSeries", "Frames", "Checkpoints", "ProgressBar", "standard_outputs",
           "frame_interval"]


def _check_every(name: str, every: int) -> int:
    if int(every) != every or every < 1:
        raise ValueError(f"{name} = {every!r}: must be an integer >= 1 (steps between outputs)")
    return int(every)


class _Periodic(Observer, abc.ABC):
    """Writes the state at the solver's first run, every ``every`` steps and at close.

    A subclass says how a series starts (``_start``) and how one state is written
    (``_write``); ``_finish`` closes the series.
    """

    def __init__(self, out_dir: str | Path, every: int) -> None:
        """Files in ``out_dir``, every ``every`` steps of the solver."""
        self.out = Path(out_dir)
        self.every = _check_every("output_every", every)
        self.files: list[Path] = []
        self._started = False
        self._last: int | None = None  # state step last written

    @abc.abstractmethod
    def _start(self, state: DiscreteState) -> None:
        """Open the series (files, folders) for the first state."""

    @abc.abstractmethod
    def _write(self, state: DiscreteState) -> None:
        """Add ``state`` to the series."""

    def _finish(self) -> None:
        """Close the series (after the final state)."""

    def _emit(self, state: DiscreteState) -> None:
        if not self._started:
            self.out.mkdir(parents=True, exist_ok=True)
            self._start(state)
            self._started = True
        self._write(state)
        self._last = state.step

    def run_started(self, solver: ExplicitSolver, total_steps: int | None) -> None:
        """Start the series with the state at the solver's first run."""
        if not self._started:
            self._emit(solver.state)

    def stepped(self, solver: ExplicitSolver) -> None:
        """Write every ``every`` steps of the solver."""
        if solver.steps % self.every == 0:
            self._emit(solver.state)

    def close(self, solver: ExplicitSolver, final: bool) -> None:
        """Write the final state if it is not written yet, and close the series."""
        if final and self._last != solver.state.step:
            self._emit(solver.state)
        if self._started:
            self._finish()


class XdmfSeries(_Periodic):
    """meshio XDMF time series ``discrete.xdmf`` with its ``discrete.h5`` in ``out_dir``.

    Every element with its own nodes (splits are visible), the reference coordinates plus a
    displacement and a velocity field, stress, plastic strain and the yielded fraction
    averaged per cell.
    """

    def _start(self, state: DiscreteState) -> None:
        import os

        import meshio

        path = self.out / "discrete.xdmf"
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
        self.files += [path, self.out / "discrete.h5"]

    def _write(self, state: DiscreteState) -> None:
        s = state.stress.mean(axis=1)
        self._w.write_data(
            state.time,
            point_data={"displacement": state.x - state.x_ref, "velocity": state.v},
            cell_data={"stress_xx": [s[:, 0]], "stress_yy": [s[:, 1]], "stress_zz": [s[:, 2]],
                       "stress_xy": [s[:, 3]],
                       "plastic_strain": [state.plastic_strain.mean(axis=1)],
                       "yielded": [state.yielded.mean(axis=1).astype(float)]})

    def _finish(self) -> None:
        self._w.__exit__(None, None, None)


class Frames(_Periodic):
    """PNG frames ``frames/frame_NNNN.png`` (sigma_yy per element) and ``discrete.gif``.

    Stale frames of an earlier series in the same folder are removed when the series starts;
    the GIF of all frames is written at close.
    """

    def _start(self, state: DiscreteState) -> None:
        frames = self.out / "frames"
        frames.mkdir(exist_ok=True)
        for old in frames.glob("frame_*.png"):
            old.unlink()
        self._frames: list[Path] = []

    def _write(self, state: DiscreteState) -> None:
        path = _snapshot(state, self.out / "frames" / f"frame_{len(self._frames):04d}.png")
        self._frames.append(path)
        self.files.append(path)

    def _finish(self) -> None:
        gif = _gif(self._frames, self.out / "discrete.gif")
        if gif is not None:
            self.files.append(gif)


class Checkpoints(Observer):
    """``state.save`` to ``out_dir/checkpoint.npz`` every ``every`` steps and after each run."""

    def __init__(self, out_dir: str | Path, every: int) -> None:
        """Checkpoint in ``out_dir``, every ``every`` steps of the solver."""
        self.path = Path(out_dir) / "checkpoint.npz"
        self.every = _check_every("checkpoint_every", every)
        self.files: list[Path] = []

    def _save(self, state: DiscreteState) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        state.save(self.path)
        if not self.files:
            self.files.append(self.path)

    def stepped(self, solver: ExplicitSolver) -> None:
        """Save every ``every`` steps of the solver."""
        if solver.steps % self.every == 0:
            self._save(solver.state)

    def run_ended(self, solver: ExplicitSolver, result: RunResult | None) -> None:
        """Save at the end of a run that did not raise."""
        if result is not None:
            self._save(solver.state)


class ProgressBar(Observer):
    """A tqdm progress bar per run (steps; updated at the checks)."""

    def __init__(self) -> None:
        """No bar until a run starts."""
        self._bar = None
        self._shown = 0
        self._first = 0

    def run_started(self, solver: ExplicitSolver, total_steps: int | None) -> None:
        """Open the bar."""
        from tqdm.auto import tqdm

        self._bar = tqdm(total=total_steps, unit="step", desc="discrete", mininterval=0.5)
        self._first = solver.steps
        self._shown = 0

    def checked(self, solver: ExplicitSolver, ledger: EnergyLedger) -> None:
        """Advance the bar to the steps done."""
        done = solver.steps - self._first
        if self._bar is not None:
            self._bar.update(done - self._shown)
        self._shown = done

    def run_ended(self, solver: ExplicitSolver, result: RunResult | None) -> None:
        """Close the bar."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None


def standard_outputs(out_dir: str | Path | None, *, output_every: int = 0,
                     snapshots: bool = True, checkpoint_every: int = 0,
                     progress: bool = True) -> list[Observer]:
    """The usual observers: XDMF series and PNG frames, checkpoints, a progress bar.

    Args:
        out_dir: folder of the files (needed when output_every or checkpoint_every > 0).
        output_every: steps between XDMF frames (and PNG frames with ``snapshots``); 0: none.
        snapshots: PNG frames and the GIF along with the XDMF series.
        checkpoint_every: steps between checkpoints (and one after each run); 0: none.
        progress: a tqdm progress bar per run.
    """
    for name, val in (("output_every", output_every), ("checkpoint_every", checkpoint_every)):
        if int(val) != val or val < 0:
            raise ValueError(f"{name} = {val!r}: must be an integer >= 0")
    if (output_every or checkpoint_every) and out_dir is None:
        raise ValueError("output_every / checkpoint_every need out_dir")
    obs: list[Observer] = []
    if out_dir is not None and output_every:
        obs.append(XdmfSeries(out_dir, output_every))
        if snapshots:
            obs.append(Frames(out_dir, output_every))
    if out_dir is not None and checkpoint_every:
        obs.append(Checkpoints(out_dir, checkpoint_every))
    if progress:
        obs.append(ProgressBar())
    return obs


def frame_interval(duration: float, dt: float, frames: int) -> int:
    """Steps between outputs for about ``frames`` frames over ``duration`` [s] in steps of ``dt``.

    At least 1; 0 (no outputs) when ``frames`` is 0.
    """
    if int(frames) != frames or frames < 0:
        raise ValueError(f"frames = {frames!r}: must be an integer >= 0")
    return max(int(duration / dt) // int(frames), 1) if frames else 0


def _snapshot(state: DiscreteState, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

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
    if not frames:
        return None
    try:
        from PIL import Image
    except ImportError:  # pragma: no cover
        return None
    imgs = [Image.open(f).convert("P") for f in frames]
    imgs[0].save(path, save_all=True, append_images=imgs[1:], duration=100, loop=0)
    return path
