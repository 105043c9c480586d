"""Outputs of discrete runs: observers of an :class:`~hybrid.discrete.solver.ExplicitSolver`.

An observer is attached to a solver for its lifetime, so one series covers all the solver's
runs (a loading run and the rest run that follows it make one XDMF series and one
animation). Its schedule counts the solver's steps (``ExplicitSolver.steps``). Closing the
solver writes the final state where it was not written yet, and the animation.

- :class:`XdmfSeries`: XDMF time series ``discrete.xdmf``, the mesh in ``discrete.h5`` and one
  HDF5 file per frame in ``discrete_series/``; each frame file and the index are written to a
  temporary file and renamed, so the series opens (ParaView, ``meshio.xdmf.TimeSeriesReader``)
  after every frame, also after a kill;
- :class:`Animation`: at close, ``discrete.mp4`` (ffmpeg) or ``discrete.gif`` and the PNG
  frames ``frames/frame_NNNN.png`` from the series, with fixed axes and colour range;
- :class:`Checkpoints`: ``checkpoint.npz`` (the state and the solver's progress,
  ``ExplicitSolver.checkpoint_arrays``) every N steps and at the end of each run, written to
  a temporary file and renamed, the previous one kept as ``checkpoint.prev.npz``; with
  ``resume`` the solver continues from it (``ExplicitSolver.restore``) and the series
  appends;
- :class:`ProgressBar`: a tqdm bar per run.

:func:`standard_outputs` builds the usual set from the cases' parameters; :func:`frame_interval`
spaces a number of frames over a run. A write that fails (a full disk) raises
:class:`~hybrid.errors.OutputError` naming the last good frame and checkpoint.
"""

from __future__ import annotations

import abc
import contextvars
import json
import os
import shutil
import subprocess
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hybrid.discrete.ledger import EnergyLedger
from hybrid.discrete.options import RunResult, require_same_settings, settings_text
from hybrid.discrete.solver import ExplicitSolver, Observer
from hybrid.discrete.state import DiscreteState
from hybrid.errors import OutputError
from hybrid.snapshot import STRESS_NAMES
from hybrid.xdmf import replace_file, series_index, write_frame, write_index, write_mesh

__all__ = ["XdmfSeries", "Animation", "Checkpoints", "ProgressBar", "standard_outputs",
           "frame_interval", "RESUME", "CASE_PARAMETERS", "CHECKPOINT", "PREVIOUS_CHECKPOINT"]

#: file names of the checkpoint and of the one before it
CHECKPOINT = "checkpoint.npz"
PREVIOUS_CHECKPOINT = "checkpoint.prev.npz"

#: default of ``standard_outputs(resume=...)``: ``hybrid run --resume`` sets it for the case
RESUME: contextvars.ContextVar[bool] = contextvars.ContextVar("RESUME", default=False)
#: the case's parameters (``hybrid run`` sets them): a checkpoint records them and a resumed
#: run must have the same
CASE_PARAMETERS: contextvars.ContextVar[dict | None] = contextvars.ContextVar(
    "CASE_PARAMETERS", default=None)


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
    def _start(self, solver: ExplicitSolver) -> None:
        """Open the series (files, folders) for the first state."""

    @abc.abstractmethod
    def _write(self, solver: ExplicitSolver) -> None:
        """Add the solver's state to the series."""

    def _finish(self) -> None:
        """Close the series (after the final state)."""

    def _emit(self, solver: ExplicitSolver) -> None:
        if not self._started:
            self.out.mkdir(parents=True, exist_ok=True)
            self._start(solver)
            self._started = True
        self._write(solver)
        self._last = solver.state.step

    def run_started(self, solver: ExplicitSolver, total_steps: int | None) -> None:
        """Start the series with the state at the solver's first run."""
        if not self._started:
            self._emit(solver)

    def stepped(self, solver: ExplicitSolver) -> None:
        """Write every ``every`` steps of the solver."""
        if solver.steps % self.every == 0:
            self._emit(solver)

    def close(self, solver: ExplicitSolver, final: bool) -> None:
        """Write the final state if it is not written yet, and close the series."""
        if final and self._last != solver.state.step:
            self._emit(solver)
        if self._started:
            self._finish()


class XdmfSeries(_Periodic):
    """XDMF time series ``discrete.xdmf`` in ``out_dir``, readable after every frame.

    Every element with its own nodes (splits are visible) at its reference coordinates
    (``discrete.h5``, with the material index per element and the material names). Per
    frame (``discrete_series/frame_NNNNN.h5``, with its time, step and run phase as
    attributes): point fields ``displacement`` (from the start of the discrete phase) [m],
    ``velocity`` [m/s] and ``contact_force`` [kN/m]; cell fields ``sigma_xx``, ``sigma_yy``,
    ``sigma_zz``, ``sigma_xy`` (element means) [kPa], ``plastic_strain`` [-], ``yielded``
    (fraction of the Gauss points), ``failed_interfaces`` (the element's failed edges) and
    ``material``. The names are those of the continuum's XDMF.
    """

    def __init__(self, out_dir: str | Path, every: int, *,
                 material_names: Sequence[str] = ()) -> None:
        """Files in ``out_dir``, every ``every`` steps; ``material_names`` by material index."""
        super().__init__(out_dir, every)
        self.material_names = tuple(str(n) for n in material_names)
        self.path = self.out / "discrete.xdmf"
        self.frames: list[tuple[float, int, str, str]] = []  # time, step, phase, file

    def _start(self, solver: ExplicitSolver) -> None:
        st = solver.state
        series = self.out / "discrete_series"
        if series.exists():
            shutil.rmtree(series)
        series.mkdir()
        mesh = write_mesh(self.out / "discrete.h5", st.x_ref, st.element_nodes,
                          st.element_material, self.material_names)
        self._nen, self._ne, self._nn = st.nen, st.n_elements, st.n_nodes
        self.files += [self.path, mesh, series]

    def _write(self, solver: ExplicitSolver) -> None:
        st = solver.state
        name = f"discrete_series/frame_{len(self.frames):05d}.h5"
        path = self.out / name
        try:
            write_frame(path, frame_fields(st, solver.contact_force), time=st.time,
                        step=st.step, phase=solver.phase)
            self.frames.append((st.time, st.step, solver.phase, name))
            self._write_index()
        except OSError as err:
            raise OutputError(_lost(path, err, self.frames)) from None

    def _write_index(self) -> None:
        write_index(self.path, _xdmf_index(self._nen, self._ne, self._nn,
                                           self.material_names, self.frames))

    def state(self) -> dict[str, np.ndarray]:
        """The number of frames written."""
        return {"frames": np.array(len(self.frames))}

    def restore(self, saved: dict[str, np.ndarray]) -> None:
        """Keep the frames the checkpoint had seen, drop the later ones, append from there."""
        import h5py

        n = int(saved.get("frames", 0))
        if n == 0:
            return
        series = self.out / "discrete_series"
        self.frames = []
        for i in range(n):
            name = f"discrete_series/frame_{i:05d}.h5"
            try:
                with h5py.File(self.out / name, "r") as f:
                    self.frames.append((float(f.attrs["time"]), int(f.attrs["step"]),
                                        str(f.attrs["phase"]), name))
            except OSError as err:
                raise ValueError(f"cannot resume the series in {self.out}: frame {i} of the "
                                 f"checkpoint's {n} is unreadable ({err}); start again with "
                                 "--overwrite") from None
        for old in series.glob("frame_*.h5*"):
            if old.name.endswith(".tmp") or int(old.stem.split("_")[1]) >= n:
                old.unlink()
        with h5py.File(self.out / "discrete.h5", "r") as f:
            self._ne, self._nen = f["mesh/topology"].shape
            self._nn = f["mesh/geometry"].shape[0]
        self._write_index()
        self._started = True
        self._last = self.frames[-1][1]
        self.files += [self.path, self.out / "discrete.h5", series]

    def read_frame(self, i: int) -> dict[str, np.ndarray]:
        """The fields of frame ``i``."""
        import h5py

        with h5py.File(self.out / self.frames[i][3], "r") as f:
            return {k: f[k][()] for k in f}


def frame_fields(state: DiscreteState, contact_force: np.ndarray) -> dict[str, np.ndarray]:
    """The fields of one frame of the discrete series (see :class:`XdmfSeries`)."""
    s = state.stress.mean(axis=1)
    failed = state.interface_elements[~state.interface_intact].ravel()
    out = {"displacement": state.x - state.x_ref, "velocity": state.v.copy(),
           "contact_force": contact_force.copy()}
    out.update({name: s[:, i] for i, name in enumerate(STRESS_NAMES)})
    out["plastic_strain"] = state.plastic_strain.mean(axis=1)
    out["yielded"] = state.yielded.mean(axis=1).astype(float)
    out["failed_interfaces"] = np.bincount(failed, minlength=state.n_elements).astype(float)
    return out


_POINT_FIELDS = ("displacement", "velocity", "contact_force")
_CELL_FIELDS = (*STRESS_NAMES, "plastic_strain", "yielded", "failed_interfaces")


def _xdmf_index(nen: int, ne: int, nn: int, material_names: Sequence[str],
                frames: Sequence[tuple[float, int, str, str]]) -> str:
    """The XDMF 3 text of the series: the mesh, then one grid per frame file."""
    return series_index(
        mesh="discrete.h5", cells=ne, nodes_per_cell=nen, points=nn,
        point_fields={f: 2 for f in _POINT_FIELDS}, cell_fields=_CELL_FIELDS,
        frames=[(time, name) for time, _, _, name in frames],
        information={"material_names": "; ".join(f"{i}: {n}"
                                                 for i, n in enumerate(material_names))})


def _lost(path: Path, err: OSError, frames: Sequence[tuple[float, int, str, str]]) -> str:
    last = (f"the last good frame (t = {frames[-1][0]:.6g} s, step {frames[-1][1]})"
            if frames else "no frame")
    return (f"writing {path} failed ({err.strerror or err}): {last} and the last checkpoint "
            "stay readable; free space (or choose another --out) and continue with --resume")


class Animation(Observer):
    """At close: the series' frames as ``discrete.mp4`` (ffmpeg) or ``discrete.gif`` and PNGs.

    sigma_yy per element on the deformed elements; the axes span every frame and the colour
    range is the 1st to 99th percentile of all frames, both fixed for the whole animation;
    each frame is titled with its run phase and time. The PNG frames go to ``frames/``,
    cleared of older ones when they are rendered; ``animation.json`` lists each frame's
    time, phase, colour range and axes.
    """

    def __init__(self, series: XdmfSeries) -> None:
        """The animation of ``series`` (attached before it, closed after it)."""
        self.series = series
        self.files: list[Path] = []
        self.limits: list[tuple[tuple[float, float], ...]] = []  # per frame: clim, xlim, ylim

    def close(self, solver: ExplicitSolver, final: bool) -> None:
        """Render the frames of the series."""
        if not self.series.frames:
            return
        self.files = self.render(solver.state)

    def render(self, state: DiscreteState) -> list[Path]:
        """Write the PNG frames and the animation; returns their paths.

        The axes, ticks and colour bar are drawn once; each frame redraws only the elements,
        the axes' frame and the title over them (blitting) and is written from the canvas
        buffer: the PNG frame, then the movie from the same pixels.
        """
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.collections import PolyCollection
        from PIL import Image

        series = self.series
        out = series.out
        frames_dir = out / "frames"
        _clear_frames(frames_dir)
        data = [series.read_frame(i) for i in range(len(series.frames))]
        nodes = state.element_nodes
        polys = [(state.x_ref + d["displacement"])[nodes] for d in data]
        values = np.concatenate([d["sigma_yy"] for d in data])
        lo, hi = np.percentile(values, [1.0, 99.0])
        if hi <= lo:
            lo, hi = lo - 1.0, hi + 1.0
        allx = np.concatenate([p.reshape(-1, 2) for p in polys])
        pmin, pmax = allx.min(axis=0), allx.max(axis=0)
        pad = 0.05 * float(np.max(pmax - pmin))
        xlim, ylim = (pmin[0] - pad, pmax[0] + pad), (pmin[1] - pad, pmax[1] + pad)
        fig, ax = plt.subplots(figsize=(7, 5), dpi=90)
        pc = PolyCollection(polys[0], array=data[0]["sigma_yy"], cmap="viridis",
                            edgecolors="k", linewidths=0.2, animated=True)
        pc.set_clim(lo, hi)
        ax.add_collection(pc)
        fig.colorbar(pc, ax=ax, label="sigma_yy [kPa] (tension +)", extend="both")
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        def caption(i: int) -> str:
            time, step, phase, _ = series.frames[i]
            return f"{phase}: t = {time:.4g} s (step {step})"

        title = ax.set_title(caption(0), animated=True)
        fig.tight_layout()  # with a title in place, so that the layout leaves room for it
        fig.canvas.draw()
        background = fig.canvas.copy_from_bbox(fig.bbox)
        gif = shutil.which("ffmpeg") is None
        written, pictures = [], []
        self.limits = []
        for i, (d, p) in enumerate(zip(data, polys, strict=True)):
            pc.set_verts(p)
            pc.set_array(d["sigma_yy"])
            title.set_text(caption(i))
            fig.canvas.restore_region(background)
            for artist in (pc, *ax.spines.values(), title):
                ax.draw_artist(artist)
            picture = Image.fromarray(np.array(fig.canvas.buffer_rgba()))
            png = frames_dir / f"frame_{i:04d}.png"
            picture.save(png, compress_level=3)  # zlib level 3: 9 % larger, 40 % faster
            written.append(png)
            if gif:  # a palette per frame by fast octree quantisation (median cut: 10x slower)
                pictures.append(picture.convert("RGB").quantize(method=Image.Quantize.FASTOCTREE))
            self.limits.append((pc.get_clim(), ax.get_xlim(), ax.get_ylim()))
        plt.close(fig)
        movie = _movie(out, frames_dir, pictures if gif else None, fps=10)
        record = out / "animation.json"
        record.write_text(json.dumps({"movie": movie.name, "field": "sigma_yy", "frames": [
            {"time": f[0], "step": f[1], "phase": f[2], "colour_range": list(lim[0]),
             "xlim": list(lim[1]), "ylim": list(lim[2])}
            for f, lim in zip(series.frames, self.limits, strict=True)]}, indent=1))
        return [*written, movie, record]


def _movie(out: Path, frames_dir: Path, pictures: Sequence[Any] | None, fps: int) -> Path:
    """The movie of the frames: ``discrete.gif`` or ``discrete.mp4``.

    The GIF from ``pictures`` (palette images); with None the MP4 from the PNG frames by
    ffmpeg. The other kind, left by an older run, is removed.
    """
    movie = out / ("discrete.gif" if pictures is not None else "discrete.mp4")
    (out / ("discrete.mp4" if pictures is not None else "discrete.gif")).unlink(missing_ok=True)
    if pictures is not None:
        first, *rest = pictures
        first.save(movie, save_all=True, append_images=rest, duration=1000 // fps, loop=0)
        return movie
    pattern = str(frames_dir).replace("%", "%%") + "/frame_%04d.png"  # a % in --out is literal
    subprocess.run([str(shutil.which("ffmpeg")), "-nostdin", "-y", "-loglevel", "error",
                    "-framerate", str(fps), "-i", pattern, "-pix_fmt", "yuv420p",
                    "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", str(movie)],
                   check=True, stdin=subprocess.DEVNULL)
    return movie


def _clear_frames(folder: Path) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for old in folder.glob("frame_*.png"):
        old.unlink()


class Checkpoints(Observer):
    """``checkpoint.npz`` in ``out_dir`` every ``every`` steps and after each run.

    The file holds the state and the solver's progress (``ExplicitSolver.checkpoint_arrays``);
    it is written to a temporary file and renamed, the previous one kept as
    ``checkpoint.prev.npz``. With ``resume`` and a checkpoint in ``out_dir``, the solver
    continues from it when it is made (``ExplicitSolver.restore``).
    """

    def __init__(self, out_dir: str | Path, every: int, *, resume: bool = False) -> None:
        """Checkpoint in ``out_dir``, every ``every`` steps of the solver."""
        self.path = Path(out_dir) / CHECKPOINT
        self.every = _check_every("checkpoint_every", every)
        self.resume = resume
        self.files: list[Path] = []

    def attached(self, solver: ExplicitSolver) -> None:
        """Resume the solver from the checkpoint (with ``resume``; refused without one)."""
        if self.resume:
            if not self.path.exists():
                raise ValueError(f"resume: no checkpoint at {self.path}; start again with "
                                 "--overwrite")
            solver.restore(self.path)
            self.files.append(self.path)

    def state(self) -> dict[str, np.ndarray]:
        """The case's parameters the run was started with (:data:`CASE_PARAMETERS`)."""
        return {"parameters": np.array(settings_text(CASE_PARAMETERS.get() or {}))}

    def restore(self, saved: dict[str, np.ndarray]) -> None:
        """Refuse a resume with other case parameters than the checkpoint's."""
        require_same_settings(self.path, "case parameters", saved.get("parameters"),
                              CASE_PARAMETERS.get() or {})

    def _save(self, solver: ExplicitSolver) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        tmp = self.path.with_name(self.path.name + ".tmp")
        try:
            with open(tmp, "wb") as f:
                np.savez(f, **solver.checkpoint_arrays())
            if self.path.exists():  # the previous one stays: hard link, then rename
                prev = self.path.with_name(PREVIOUS_CHECKPOINT)
                link = prev.with_name(prev.name + ".tmp")
                link.unlink(missing_ok=True)
                try:
                    os.link(self.path, link)
                except OSError:
                    shutil.copy2(self.path, link)
                os.replace(link, prev)
            replace_file(tmp, self.path)
        except OSError as err:
            tmp.unlink(missing_ok=True)
            raise OutputError(
                f"writing the checkpoint {self.path} failed ({err.strerror or err}): the "
                f"previous checkpoint stays readable; free space (or choose another --out) "
                "and continue with --resume") from None
        if not self.files:
            self.files.append(self.path)

    def stepped(self, solver: ExplicitSolver) -> None:
        """Save every ``every`` steps of the solver."""
        if solver.steps % self.every == 0:
            self._save(solver)

    def run_ended(self, solver: ExplicitSolver, result: RunResult | None) -> None:
        """Save at the end of a run that did not raise."""
        if result is not None:
            self._save(solver)


class ProgressBar(Observer):
    """A tqdm progress bar per run (steps; updated at the checks).

    The bar opens at the run's first check, with the steps done before it as its start: its
    rate and ETA count from there, so the time numba takes to compile the kernels in the
    first steps of a first run is not read as the speed of the run.
    """

    def __init__(self) -> None:
        """No bar until a run reaches its first check."""
        self._bar: Any = None
        self._shown = 0
        self._first = 0
        self._total: int | None = None

    def run_started(self, solver: ExplicitSolver, total_steps: int | None) -> None:
        """Note where the run starts; the bar opens at its first check."""
        self._first = solver.steps
        self._total = total_steps
        self._shown = 0

    def checked(self, solver: ExplicitSolver, ledger: EnergyLedger) -> None:
        """Open the bar at the run's first check, then advance it to the steps done."""
        done = solver.steps - self._first
        if self._bar is None:
            from tqdm.auto import tqdm

            self._bar = tqdm(total=self._total, initial=done, unit="step", desc="discrete",
                             mininterval=0.5)
        else:
            self._bar.update(done - self._shown)
        self._shown = done

    def run_ended(self, solver: ExplicitSolver, result: RunResult | None) -> None:
        """Close the bar."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None


def standard_outputs(out_dir: str | Path | None, *, output_every: int = 0,
                     snapshots: bool = True, checkpoint_every: int = 0,
                     progress: bool = True, material_names: Sequence[str] = (),
                     resume: bool | None = None) -> list[Observer]:
    """The usual observers: XDMF series and animation, checkpoints, a progress bar.

    Args:
        out_dir: folder of the files (needed when output_every or checkpoint_every > 0).
        output_every: steps between XDMF frames; 0: none.
        snapshots: the animation and its PNG frames along with the XDMF series.
        checkpoint_every: steps between checkpoints (and one after each run); 0: none.
        progress: a tqdm progress bar per run.
        material_names: the materials' names by index, for the series.
        resume: continue from the checkpoint in ``out_dir`` (None: as ``hybrid run
            --resume`` says, :data:`RESUME`).
    """
    for name, val in (("output_every", output_every), ("checkpoint_every", checkpoint_every)):
        if int(val) != val or val < 0:
            raise ValueError(f"{name} = {val!r}: must be an integer >= 0")
    if (output_every or checkpoint_every) and out_dir is None:
        raise ValueError("output_every / checkpoint_every need out_dir")
    resume = RESUME.get() if resume is None else resume
    obs: list[Observer] = []
    if out_dir is not None and output_every:
        series = XdmfSeries(out_dir, output_every, material_names=material_names)
        obs.append(series)
        if snapshots:
            obs.append(Animation(series))
    if out_dir is not None and checkpoint_every:
        obs.append(Checkpoints(out_dir, checkpoint_every, resume=resume))
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
