"""The continuum's load steps, stages or strength-reduction trials as an XDMF time series.

:class:`ContinuumSeries` observes a :class:`~hybrid.continuum.plastic.PlasticSolver`
(``solver.observers``): every committed step (or every ``every``-th) becomes a frame, its
"time" the load factor, the gravity factor, the strength factor F or the step count (what it
means is written in the file and in :meth:`ContinuumSeries.report`). The layout is the
discrete phase's (:mod:`hybrid.xdmf`), with the same field names: point field
``displacement`` [m]; cell fields ``sigma_xx``, ``sigma_yy``, ``sigma_zz``, ``sigma_xy``
(cell means) [kPa], ``plastic_strain`` [-], ``yielded`` (fraction of the cell's points on the
yield surface) and ``material`` (index into the names the file lists). Collective under MPI;
rank 0 writes.
"""

from __future__ import annotations

import shutil
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from hybrid.snapshot import STRESS_NAMES
from hybrid.xdmf import series_index, write_frame, write_index, write_mesh

if TYPE_CHECKING:
    from hybrid.continuum.plastic import PlasticSolver, StepRecord
    from hybrid.continuum.state import ContinuumState

__all__ = ["ContinuumFields", "ContinuumSeries", "continuum_fields", "TIMES", "CELL_FIELDS"]

#: the series' "time" by name: what it means
TIMES = {"load_factor": "load factor: the loads and prescribed displacements as given times "
                        "this [-]",
         "gravity_factor": "gravity factor: the fraction of the self-weight switched on [-]",
         "strength_factor": "strength reduction factor F: c and tan(phi) divided by F [-]",
         "step": "committed steps of the continuum solver since the series started [-]"}

#: the cell fields of every frame (``material`` is the mesh's)
CELL_FIELDS = (*STRESS_NAMES, "plastic_strain", "yielded")


class ContinuumFields(NamedTuple):
    """A continuum state as the outputs write it, gathered on rank 0.

    ``points`` (n, 2) [m] the first-order mesh's nodes, ``cells`` (n_cells, 3|4) their
    indices, ``displacement`` (n, 2) [m] at the nodes, ``cell_data`` :data:`CELL_FIELDS` by
    name, ``material`` (n_cells,) index into the model's ``material_names``.
    """

    points: np.ndarray
    cells: np.ndarray
    displacement: np.ndarray
    cell_data: dict[str, np.ndarray]
    material: np.ndarray


def continuum_fields(state: ContinuumState) -> ContinuumFields | None:
    """The fields of ``state`` gathered on rank 0 (None on the other ranks; collective)."""
    from hybrid.io import displacement_at_geometry_nodes

    md = state.model.mesh
    x, cells = md.cell_vertices()
    global_ids = np.asarray(md.mesh.geometry.input_global_indices, dtype=np.int64)
    u_nodes = displacement_at_geometry_nodes(md.mesh, state.u)
    stress = state.cell_stress()
    cell_data = {name: stress[:, i] for i, name in enumerate(STRESS_NAMES)}
    cell_data["plastic_strain"] = state.cell_plastic_strain()
    cell_data["yielded"] = np.mean(state.yielded > 0, axis=1).astype(float)
    material = state.model.material_ids()
    gathered = state.comm.gather((global_ids, x, u_nodes, global_ids[cells], cell_data,
                                  material), root=0)
    if state.comm.rank != 0:
        return None
    n_points = 1 + max(int(g[0].max()) for g in gathered if len(g[0]))
    points, displacement = np.zeros((n_points, 2)), np.zeros((n_points, 2))
    for ids, coords, disp, *_ in gathered:
        points[ids] = coords
        displacement[ids] = disp
    return ContinuumFields(points, np.concatenate([g[3] for g in gathered]), displacement,
                           {name: np.concatenate([g[4][name] for g in gathered])
                            for name in cell_data},
                           np.concatenate([g[5] for g in gathered]))


class ContinuumSeries:
    """XDMF series ``path`` of a solver's committed steps, readable after every frame.

    The state when the series is made is its first frame; then every ``every``-th committed
    step, and at :meth:`close` the last one. ``time``: a name of :data:`TIMES`, or a function
    of the solver with its ``meaning`` (e.g. the stage index of a staged construction). The
    series is a path of increasing time: a step whose time is not above the last frame's
    replaces the frames from that time on (a solver restored to an earlier state, a stage that
    does not move the time). Files: ``path`` (the index), ``<stem>.h5`` (the mesh, material
    names) and ``<stem>_frames/frame_NNNNN.h5`` (per frame its fields, time, step and load,
    gravity and strength factors). Use it as a context manager, or call :meth:`close`.
    """

    def __init__(self, path: str | Path, solver: PlasticSolver, *,
                 time: str | Callable[[PlasticSolver], float] = "load_factor",
                 meaning: str | None = None, every: int = 1) -> None:
        """Attach to ``solver`` and write its current state as the first frame."""
        if isinstance(time, str):
            if time not in TIMES:
                raise ValueError(f"time = {time!r}: choose one of {', '.join(TIMES)}, or give "
                                 "a function of the solver with its meaning")
            name = time
            self._time: Callable[[PlasticSolver], float] = (
                (lambda s: float(self._commits)) if name == "step"
                else (lambda s: float(getattr(s, name))))
            meaning = meaning or TIMES[name]
        elif meaning is None:
            raise ValueError("ContinuumSeries: a time given as a function needs its meaning "
                             "(what the time is, with its unit)")
        else:
            self._time = time
        if int(every) != every or every < 1:
            raise ValueError(f"every = {every!r}: must be an integer >= 1 (committed steps "
                             "between frames)")
        self.path = Path(path)
        self.meaning = meaning
        self.every = int(every)
        self.solver = solver
        self.frames: list[tuple[float, str]] = []  # time, frame file (relative to the index)
        self._commits = 0
        self._written = True  # the last committed state is in the series
        self._root = solver.disc.V.mesh.comm.rank == 0
        self._folder = self.path.parent / f"{self.path.stem}_frames"
        self.files = [self.path, self.path.with_suffix(".h5"), self._folder]
        self._mesh: tuple[int, int, int] | None = None
        self._names = list(solver.model.material_names)
        if self._root:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            if self._folder.exists():
                shutil.rmtree(self._folder)
            self._folder.mkdir()
        self._emit()
        solver.observers.append(self)

    def __call__(self, solver: PlasticSolver, record: StepRecord) -> None:
        """A committed step: a frame every ``every`` of them."""
        self._commits += 1
        self._written = False
        if self._commits % self.every == 0:
            self._emit()

    def _emit(self) -> None:
        solver = self.solver
        time = self._time(solver)
        while self.frames and self.frames[-1][0] >= time:
            self.frames.pop()
        fields = continuum_fields(solver.state())
        self._written = True
        if fields is None:  # not rank 0
            self.frames.append((time, ""))
            return
        if self._mesh is None:
            write_mesh(self.files[1], fields.points, fields.cells, fields.material,
                       self._names, time=self.meaning)
            self._mesh = (fields.cells.shape[0], fields.cells.shape[1], fields.points.shape[0])
        name = f"{self._folder.name}/frame_{len(self.frames):05d}.h5"
        write_frame(self.path.parent / name,
                    {"displacement": fields.displacement, **fields.cell_data}, time=time,
                    step=len(solver.history), load_factor=solver.load_factor,
                    gravity_factor=solver.gravity_factor,
                    strength_factor=solver.strength_factor)
        self.frames.append((time, name))
        ne, nen, nn = self._mesh
        names = "; ".join(f"{i}: {n}" for i, n in enumerate(self._names))
        write_index(self.path, series_index(
            mesh=self.files[1].name, cells=ne, nodes_per_cell=nen, points=nn,
            point_fields={"displacement": 2}, cell_fields=CELL_FIELDS, frames=self.frames,
            information={"material_names": names, "time": self.meaning}))

    def close(self) -> list[Path]:
        """Write the last committed state if it is not in the series yet; detach.

        Frame files of replaced frames are removed. Returns the files.
        """
        if self in self.solver.observers:
            if not self._written:
                self._emit()
            self.solver.observers.remove(self)
            if self._root:
                keep = {self.path.parent / name for _, name in self.frames}
                for old in self._folder.glob("frame_*.h5"):
                    if old not in keep:
                        old.unlink()
        return self.files

    def report(self) -> dict[str, Any]:
        """The series for a summary: file, what the time is, frames and their times."""
        return {"file": self.path.name, "time": self.meaning, "frames": len(self.frames),
                "times": [t for t, _ in self.frames]}

    def __enter__(self) -> ContinuumSeries:
        """The series itself."""
        return self

    def __exit__(self, *exc: Any) -> None:
        """:meth:`close`."""
        self.close()
