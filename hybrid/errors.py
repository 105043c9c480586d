"""Errors a case reports to its user as one message, and how a command reports them."""

from __future__ import annotations

import sys
import traceback
from collections.abc import Callable

__all__ = ["OutputError", "RunUnstable", "StageIncomplete", "run_command"]


class StageIncomplete(RuntimeError):
    """An analysis stage (gravity, a load ramp, a lift, a strength search) did not complete.

    No figure may be computed from the half-loaded state it leaves: the message says how far
    the stage went and what to do.
    """


class RunUnstable(RuntimeError):
    """A discrete run stopped because it turned unstable (the message names the cause).

    Like an incomplete stage, it leaves no figure to compute: ``hybrid run`` prints it and
    exits with code 3.
    """


class OutputError(RuntimeError):
    """An output could not be written (a full disk, a read-only folder).

    The message names the file, the last good frame and checkpoint, and how to continue.
    """


def run_command(command: Callable[[], int | None]) -> int:
    """Run a command-line action; its input errors become one line on stderr (exit 2).

    Under MPI any exception on any rank aborts the whole job (``MPI_Abort``) after printing
    that rank's message, so the other ranks never wait for it in a collective call; the job
    exits non-zero. A serial run keeps the traceback of an unexpected error (a bug).
    """
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    try:
        return int(command() or 0)
    except RunUnstable as err:
        print(f"hybrid: stopped: {err}", file=sys.stderr, flush=True)
        if comm.size > 1:
            comm.Abort(3)
        return 3
    except ValueError as err:  # input errors (materials, geometry, case overrides)
        prefix = "hybrid: error" if comm.size == 1 else f"hybrid: error (rank {comm.rank})"
        print(f"{prefix}: {err}", file=sys.stderr, flush=True)
        if comm.size > 1:
            comm.Abort(2)
        return 2
    except Exception as err:
        if comm.size == 1:
            raise
        traceback.print_exc()
        print(f"hybrid: error (rank {comm.rank}): {type(err).__name__}: {err}",
              file=sys.stderr, flush=True)
        comm.Abort(1)
        raise  # pragma: no cover - Abort does not return
