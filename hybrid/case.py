"""Glue that makes a case script runnable as ``python cases/x.py`` and ``hybrid run``.

A case script defines a dataclass ``Parameters`` (each field documented with its unit) and
``main(out=..., **overrides) -> CaseSummary`` (:class:`hybrid.io.CaseSummary`, also written to
summary.json); ``--set name=value`` overrides one field.
"""

from __future__ import annotations

import argparse
import dataclasses
import inspect
import shutil
import signal
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

from hybrid.discrete.outputs import CASE_PARAMETERS, CHECKPOINT, RESUME
from hybrid.errors import OutputError, StageIncomplete, run_command
from hybrid.io import CaseSummary
from hybrid.parameters import field_kind
from hybrid.scripts import import_script

__all__ = ["CaseError", "parse_overrides", "find_case", "load_case", "run_case", "case_arguments",
           "uses_defaults", "describe", "parameter_notes"]


class CaseError(ValueError):
    """A case script or one of its overrides is invalid."""


def _convert(field: dataclasses.Field, text: str) -> Any:
    """Convert ``text`` to the field's annotated type (bool, int, float, str, optional None)."""
    kind_name, optional = field_kind(field)
    if optional and text.lower() == "none":
        return None
    try:
        if kind_name == "bool":
            if text.lower() in ("1", "true", "yes", "on"):
                return True
            if text.lower() in ("0", "false", "no", "off"):
                return False
            raise ValueError(text)
        if kind_name == "int":
            return int(text)
        if kind_name == "float":
            return float(text)
    except ValueError:
        raise CaseError(f"--set {field.name}={text}: expected a {kind_name}") from None
    return text


def uses_defaults(parameters: Any, names: Sequence[str]) -> bool:
    """True when the fields ``names`` of a case's ``parameters`` keep their defaults.

    The defaults are the published problem the case reproduces, so its published references
    apply.
    """
    defaults = {f.name: f.default for f in dataclasses.fields(parameters)}
    return all(getattr(parameters, n) == defaults[n] for n in names)


def parse_overrides(parameters: type, items: Sequence[str]) -> dict[str, Any]:
    """Turn ``["name=value", ...]`` into typed keyword overrides of the ``parameters`` class."""
    fields = {f.name: f for f in dataclasses.fields(parameters)}
    out: dict[str, Any] = {}
    for item in items:
        if "=" not in item:
            raise CaseError(f"--set expects name=value, got '{item}'")
        name, text = item.split("=", 1)
        name = name.strip()
        if name not in fields:
            raise CaseError(f"unknown case parameter '{name}'; known: {', '.join(fields)}")
        out[name] = _convert(fields[name], text.strip())
    return out


def find_case(path: str | Path) -> Path:
    """The case script at ``path``, or ``cases/<name>.py`` for a bare name (see load_case)."""
    path = Path(path)
    if path.is_file():
        return path
    if path.suffix == "" and path.parent == Path("."):
        for folder in (Path("cases"), Path(__file__).resolve().parent.parent / "cases"):
            if (folder / f"{path.name}.py").is_file():
                return folder / f"{path.name}.py"
    raise CaseError(f"case script '{path}' not found: give its path (cases/<name>.py) or the "
                    "name of a script in cases/")


def load_case(path: str | Path) -> ModuleType:
    """Import a case script by path or by name; it must define ``main`` and ``Parameters``.

    A bare name (``carsington``) is the script of that name in ``cases/`` of the current
    folder or, failing that, of the repository this package runs from.
    """
    path = find_case(path)
    module = import_script(path, "hybrid_case")
    for name in ("main", "Parameters"):
        if not hasattr(module, name):
            raise CaseError(f"case script '{path}' defines no '{name}'")
    return module


def case_arguments(parser: argparse.ArgumentParser) -> None:
    """The options every case accepts."""
    parser.add_argument("--out", help="output folder (default: results/<case name>)")
    parser.add_argument("--set", dest="overrides", action="append", default=[],
                        metavar="NAME=VALUE", help="override a case parameter (repeatable)")
    parser.add_argument("--list", action="store_true",
                        help="list the case's parameters: default, unit, meaning")
    folder = parser.add_mutually_exclusive_group()
    folder.add_argument("--overwrite", action="store_true",
                        help="clear a non-empty output folder first")
    folder.add_argument("--resume", action="store_true",
                        help="continue the discrete run from the checkpoint in the output folder")


def parameter_notes(parameters: type) -> dict[str, str]:
    """The comment after each field of ``parameters`` in its source (unit and meaning).

    A case documents a field on its line, ``cohesion: float = 69.0  # c [kPa]``, continued on
    comment-only lines indented past ``#`` (as a wrapped comment is). A field inherited from a
    base record (e.g. a published table of :mod:`hybrid.references`) has the comment written
    in the base's source, unless the class redeclares it; a field without one (or a class
    whose source is not available) maps to "".
    """
    names = [f.name for f in dataclasses.fields(parameters)]
    notes = dict.fromkeys(names, "")
    for cls in reversed(parameters.__mro__):  # bases first: a redeclared field's own note wins
        own = set(names) & set(vars(cls).get("__annotations__", {}))
        notes.update(_source_notes(cls, own))
    return notes


def _source_notes(cls: type, names: set[str]) -> dict[str, str]:
    """The comments of the fields ``names`` declared in ``cls``'s own source."""
    import inspect
    import io
    import tokenize

    notes = dict.fromkeys(names, "")
    if not names:
        return notes
    try:
        source = inspect.getsource(cls)
    except (OSError, TypeError):
        return notes
    first: dict[int, str] = {}  # line -> first name on it
    last = ""  # the field whose note a comment-only line indented past "# " continues
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        line = tok.start[0]
        if tok.type == tokenize.NAME and line not in first:
            first[line] = tok.string
            last = ""
        elif tok.type == tokenize.COMMENT and first.get(line) in names:
            last = first[line]
            notes[last] = tok.string.lstrip("#").strip()
        elif tok.type == tokenize.COMMENT and line not in first:
            if last and tok.string.startswith("#  "):
                notes[last] += " " + tok.string.lstrip("#").strip()
            else:
                last = ""
    return notes


def describe(parameters: type) -> str:
    """One line per parameter: name = default, then its unit and meaning (``--list``)."""
    notes = parameter_notes(parameters)
    rows = []
    for f in dataclasses.fields(parameters):
        default = f.default if f.default is not dataclasses.MISSING else "(required)"
        rows.append((f.name, repr(default), notes[f.name]))
    width = max((len(a) for a, _, _ in rows), default=0)
    value = max((len(b) for _, b, _ in rows), default=0)
    return "\n".join(f"  {a:<{width}} = {b:<{value}}  {c}".rstrip() for a, b, c in rows)


def _default_out(main: Callable[..., Any]) -> str:
    """The ``out`` default of a case's ``main``."""
    default = inspect.signature(main).parameters.get("out")
    if default is None or default.default is inspect.Parameter.empty:
        raise CaseError("the case's main has no default 'out': pass --out")
    return str(default.default)


#: written into every output folder a case run makes: --overwrite clears only such folders
OUTPUT_MARKER = ".hybrid-output"


def _hybrid_output(out: Path) -> bool:
    """Whether ``out`` is an output folder of hybrid (safe to clear).

    It holds the marker or a summary.json, and it is not a repository, the home folder, the
    current folder or a root.
    """
    resolved = out.resolve()
    if (resolved in (Path.home().resolve(), Path.cwd().resolve(), Path(resolved.anchor))
            or (out / ".git").exists()):
        return False
    return (out / OUTPUT_MARKER).exists() or (out / "summary.json").exists()


def prepare_output_folder(out: Path, *, overwrite: bool = False, resume: bool = False) -> None:
    """Refuse a non-empty output folder unless told to clear it or to resume from it."""
    if not out.exists() or not any(out.iterdir()):
        if resume:
            raise CaseError(f"--resume: {out} holds no run to resume; drop --resume")
        return
    if overwrite:
        if not _hybrid_output(out):
            raise CaseError(f"--overwrite: {out} does not look like an output folder of "
                            f"hybrid (no {OUTPUT_MARKER} or summary.json in it): it is not "
                            "cleared; choose a new or empty --out")
        for item in out.iterdir():
            if item.is_dir() and not item.is_symlink():
                shutil.rmtree(item)
            else:
                item.unlink()
        return
    if resume:
        if not any(out.rglob(CHECKPOINT)):
            raise CaseError(f"--resume: {out} holds no {CHECKPOINT} (the case writes "
                            "checkpoints only with checkpoint_every > 0); start again with "
                            "--overwrite")
        return
    raise CaseError(f"output folder {out} is not empty: pass --overwrite to clear it, "
                    "--resume to continue its run, or another --out")


def _terminate_as_interrupt() -> Any:
    """Make SIGTERM (a batch time limit) stop the run as Ctrl-C does; the old handler."""
    def handler(signum: int, frame: Any) -> None:
        raise KeyboardInterrupt

    try:
        return signal.signal(signal.SIGTERM, handler)
    except ValueError:  # not the main thread
        return None


def run_case(main: Callable[..., CaseSummary], parameters: type, argv: Sequence[str] | None = None,
             name: str | None = None) -> int:
    """Command-line entry of a case script."""
    parser = argparse.ArgumentParser(description=(main.__doc__ or "").strip().split("\n")[0])
    case_arguments(parser)
    args = parser.parse_args(argv)
    return run_command(lambda: execute(main, parameters, args, name))


def _make_out(out: Path, comm: Any) -> None:
    """Create the output folder on rank 0 and check it is writable, before the ranks diverge.

    A failure is raised on every rank (collective).
    """
    error = None
    if comm.rank == 0:
        try:
            out.mkdir(parents=True, exist_ok=True)
            (out / OUTPUT_MARKER).write_bytes(b"")  # also proves the folder writable
        except OSError as err:
            error = (f"output folder '{out}' cannot be written ({err.strerror}): choose "
                     "another --out")
    error = comm.bcast(error, root=0)
    if error is not None:
        raise CaseError(error)


def execute(main: Callable[..., CaseSummary], parameters: type, args: argparse.Namespace,
            name: str | None = None) -> int:
    """Run ``main`` with parsed options; print its checks and where the results are (rank 0).

    A non-empty output folder is refused unless ``--overwrite`` (clear it) or ``--resume``
    (the discrete run continues from its checkpoint) is given. SIGTERM stops the run as
    Ctrl-C does: the frames and checkpoints written so far stay readable.

    Returns 0; 3 when an analysis stage did not complete (its message on stderr); 4 when a
    check with a bar failed (reported checks, without a bar, do not count); 5 when an output
    could not be written (or a file could not be read); 130 when interrupted.
    """
    from mpi4py import MPI

    if args.list:
        print(describe(parameters))
        return 0
    overrides = parse_overrides(parameters, args.overrides)
    kwargs: dict[str, Any] = dict(overrides)
    if sys.stderr.isatty():  # stage and strength-search progress (a terminal only)
        from hybrid.progress import enable

        enable()
    if args.out:
        kwargs["out"] = args.out
    out = Path(kwargs.get("out") or _default_out(main))
    refused = None
    if MPI.COMM_WORLD.rank == 0:  # one rank decides, every rank hears why
        try:
            prepare_output_folder(out, overwrite=getattr(args, "overwrite", False),
                                  resume=getattr(args, "resume", False))
        except CaseError as err:
            refused = str(err)
    refused = MPI.COMM_WORLD.bcast(refused, root=0)
    if refused is not None:
        raise CaseError(refused)
    _make_out(out, MPI.COMM_WORLD)
    token = RESUME.set(bool(getattr(args, "resume", False)))
    given = CASE_PARAMETERS.set({k: v for k, v in dataclasses.asdict(parameters(**overrides))
                                 .items() if k != "progress"})
    previous = _terminate_as_interrupt()
    try:
        summary = main(**kwargs)
    except StageIncomplete as err:
        # collective: every rank met the same unconverged stage
        if MPI.COMM_WORLD.rank == 0:
            print(f"stage incomplete: {err}", file=sys.stderr)
        return 3
    except OutputError as err:
        if MPI.COMM_WORLD.size > 1:
            raise  # one rank's failure: run_command aborts the job (no rank left waiting)
        print(f"output error: {err}", file=sys.stderr)
        return 5
    except OSError as err:  # a continuum series, a figure: the file system said no
        if MPI.COMM_WORLD.size > 1:
            raise
        print(f"output error: {err.filename or ''} could not be written or read "
              f"({err.strerror or err}); free space or choose another --out", file=sys.stderr)
        return 5
    except KeyboardInterrupt:
        how = ("the checkpoint written so far; continue with --resume"
               if any(out.rglob(CHECKPOINT)) else
               "no checkpoint (set checkpoint_every to resume a long run); start again with "
               "--overwrite")
        print(f"interrupted: {out} keeps the frames and {how}", file=sys.stderr)
        return 130
    finally:
        RESUME.reset(token)
        CASE_PARAMETERS.reset(given)
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
    checks = summary.checks if isinstance(summary, CaseSummary) else {}
    failed = [key for key, check in checks.items() if check.passed is False]
    if MPI.COMM_WORLD.rank == 0:
        out = summary.out if isinstance(summary, CaseSummary) else args.out
        for key, check in checks.items():
            line = f"{key}: {check.computed:.6g} {check.unit}".rstrip()
            error = check.error  # None without a reference
            if error is not None:
                verdict = {None: "reported", True: "pass", False: "FAIL"}[check.passed]
                line += (f" (reference {check.reference:.6g}, error {100 * error:.3g} %, "
                         f"{verdict})")
            print(line)
        print(f"results written to {out}")
        if failed:
            print(f"checks failed: {', '.join(failed)}", file=sys.stderr)
    return 4 if failed else 0
