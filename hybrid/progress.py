"""Progress of the continuum's stages and the strength search, on MPI rank 0.

A tqdm bar when tqdm is installed, else a plain line on stderr at most every few seconds. Off
by default (the library is quiet): ``hybrid run`` and ``python cases/x.py`` switch it on when
stderr is a terminal (:func:`enable`). The discrete engine has its own bar
(``hybrid.discrete.outputs.ProgressBar``).
"""

from __future__ import annotations

import sys
import time
from typing import Any

__all__ = ["Progress", "enable", "progress"]

_ENABLED = False


def enable(on: bool = True) -> None:
    """Show progress from now on (``on`` False: hide it again)."""
    global _ENABLED
    _ENABLED = bool(on)


class Progress:
    """One stage's progress: ``update(done, **facts)`` then ``close()``.

    ``total`` None counts updates (a search whose end is not known in advance).
    """

    def __init__(self, desc: str, total: float | None = None, unit: str = "",
                 *, every: float = 5.0) -> None:
        """Open the bar (tqdm) or the line reporter (every ``every`` seconds)."""
        self.desc, self.total, self.unit, self.every = desc, total, unit, every
        self._bar: Any = None
        self._last = time.perf_counter()
        self._start = self._last
        self._shown = 0.0
        try:
            from tqdm.auto import tqdm
        except ImportError:
            return
        self._bar = tqdm(total=total, desc=desc, unit=unit, mininterval=0.5, leave=False,
                         bar_format=None if total is None else
                         "{desc}: {percentage:3.0f}%|{bar}| {elapsed}<{remaining}{postfix}")

    def update(self, done: float, **facts: Any) -> None:
        """Progress to ``done`` (of ``total``; with no total, one more step) with ``facts``."""
        text = ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                         for k, v in facts.items())
        if self._bar is not None:
            step = 1 if self.total is None else done - self._shown
            self._bar.update(step)
            if text:
                self._bar.set_postfix_str(text, refresh=False)
        else:
            now = time.perf_counter()
            if now - self._last >= self.every:
                self._last = now
                of = "" if self.total is None else f"{done:.4g} / {self.total:.4g} {self.unit}"
                print(f"{self.desc}: {of} {text} ({now - self._start:.0f} s)".replace("  ", " "),
                      file=sys.stderr, flush=True)
        self._shown = done

    def close(self) -> None:
        """Close the bar."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None


class _Silent(Progress):
    def __init__(self) -> None:
        self._bar = None

    def update(self, done: float, **facts: Any) -> None:
        pass


def progress(desc: str, total: float | None = None, unit: str = "") -> Progress:
    """A :class:`Progress` on rank 0 when progress is on, else one that shows nothing."""
    if not _ENABLED:
        return _Silent()
    from mpi4py import MPI

    if MPI.COMM_WORLD.rank != 0:
        return _Silent()
    return Progress(desc, total, unit)
