"""Errors a case reports to its user as one message (``hybrid run`` prints it, exit code 3)."""

from __future__ import annotations

__all__ = ["StageIncomplete", "OutputError"]


class StageIncomplete(RuntimeError):
    """An analysis stage (gravity, a load ramp, a lift, a strength search) did not complete.

    No figure may be computed from the half-loaded state it leaves: the message says how far
    the stage went and what to do.
    """


class OutputError(RuntimeError):
    """An output could not be written (a full disk, a read-only folder).

    The message names the file, the last good frame and checkpoint, and how to continue.
    """
