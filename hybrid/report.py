"""The verification report: Markdown table + one section per case, results.json, PNG figures.

:func:`write_report` takes the entries of :func:`hybrid.verification.run_cases` and writes
``report.md``, ``results.json`` and ``figures/`` (the cases' PNGs, copied and kept under
200 KB). The plotting helpers draw the curves the continuum-plasticity cases produce, with the
closed-form references as horizontal lines; each also writes a JSON next to the PNG with the
plotted data and the reference values.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
import shutil
import subprocess
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

import hybrid
from hybrid.io import save_figure

__all__ = ["write_report", "format_table", "plot_load_settlement", "plot_thrust_translation",
           "plot_curve", "MAX_PNG_BYTES"]

MAX_PNG_BYTES = 200_000

_MARK = {"passed": "pass", "failed": "**FAIL**", "reported": "report", "error": "**ERROR**",
         "not yet available": "not yet available"}


# --- plots -------------------------------------------------------------------------------------

def plot_curve(path: str | Path, x: Sequence[float], y: Sequence[float], *, xlabel: str,
               ylabel: str, title: str = "", label: str = "hybrid",
               references: Mapping[str, float] | None = None,
               reference_unit: str = "",
               more: Mapping[str, tuple[Sequence[float], Sequence[float]]] | None = None,
               xscale: str = "linear", origin: bool = True) -> Path:
    """PNG of a curve y(x) with each reference drawn as a labelled horizontal line.

    ``more`` curves {label: (x, y)} are drawn beside it. ``xscale``: "linear" or "log"
    (points with x <= 0 are then left out); ``origin``: the axes include x = 0 and y = 0.

    Writes ``path`` (PNG) and ``path.with_suffix('.json')``: {x, y, xlabel, ylabel, references}.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    xs = np.asarray(x, dtype=float)
    ys = np.asarray(y, dtype=float)
    if xs.shape != ys.shape or xs.ndim != 1:
        raise ValueError(f"x and y must be 1-D of the same length, got {xs.shape} and {ys.shape}")
    if xscale not in ("linear", "log"):
        raise ValueError(f"xscale = {xscale!r}: choose 'linear' or 'log'")
    refs = {str(k): float(v) for k, v in (references or {}).items()}
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=100)
    shown = xs > 0 if xscale == "log" else np.ones(xs.shape, bool)
    ax.plot(xs[shown], ys[shown], "o-", ms=3, lw=1.5, color="C0", label=label)
    extra = {str(k): (np.asarray(a, float), np.asarray(b, float))
             for k, (a, b) in (more or {}).items()}
    for j, (name, (xa, ya)) in enumerate(extra.items()):
        keep = xa > 0 if xscale == "log" else np.ones(xa.shape, bool)
        ax.plot(xa[keep], ya[keep], "-", lw=1.2, color=f"C{len(refs) + j + 1}", label=name)
    styles = ("--", "-.", ":", (0, (5, 1)), (0, (3, 1, 1, 1)))
    for i, (name, value) in enumerate(refs.items()):
        ax.axhline(value, color=f"C{i + 1}", ls=styles[i % len(styles)], lw=1.2,
                   label=f"{name}: {value:.4g} {reference_unit}".rstrip())
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title)
    ax.set_xscale(xscale)
    if origin and xscale == "linear":
        ax.set_xlim(left=min([0.0, *(float(a.min())
                                     for a in [xs, *(e[0] for e in extra.values())] if a.size)]))
    if origin:
        ax.set_ylim(bottom=min([0.0, *(float(b.min())
                                       for b in [ys, *(e[1] for e in extra.values())] if b.size)]))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    save_figure(fig, path)
    data = {"x": xs.tolist(), "y": ys.tolist(), "xlabel": xlabel, "ylabel": ylabel,
            "title": title, "references": refs,
            "more": {k: {"x": a.tolist(), "y": b.tolist()} for k, (a, b) in extra.items()}}
    path.with_suffix(".json").write_text(json.dumps(data, indent=1) + "\n")
    return path


def plot_profile(path: str | Path, depth: Sequence[float],
                 curves: Mapping[str, tuple[Sequence[float], str]], *, xlabel: str,
                 ylabel: str = "depth z [m]", title: str = "") -> Path:
    """PNG of quantities against depth (depth downward).

    ``curves`` = {label: (values, style)} with a matplotlib style such as "k-" for a closed
    form or "o" for computed points.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(5, 5.5), dpi=100)
    for label, (values, style) in curves.items():
        ax.plot(np.asarray(values, float), np.asarray(depth, float), style, ms=4, label=label)
    ax.invert_yaxis()
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save_figure(fig, path)


def plot_energy(path: str | Path, history: Mapping[str, Any], *,
                marks: Mapping[str, float] | None = None, title: str = "") -> Path:
    """PNG of a discrete run's energy ledger and the total dissipation against time [kJ/m].

    ``history``: ``RunResult.history``, every term the engine records, or the history of a
    whole phase (:func:`hybrid.discrete.energy.phase_history`); ``marks``: {label: time [s]}
    drawn as dotted vertical lines (e.g. where the rest run starts).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hybrid.discrete.energy import DISSIPATION, LABELS

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=100)
    for key, y in history.items():
        if key not in ("time", "step") and np.any(np.asarray(y) != 0.0):
            ax.plot(history["time"], y, lw=1.2, label=LABELS.get(key, key))
    ax.plot(history["time"], sum(history[k] for k in DISSIPATION if k in history), "k--",
            lw=1.5, label="total dissipation")
    for i, (label, time) in enumerate((marks or {}).items()):
        ax.axvline(time, color=("0.2", "0.5", "0.7")[i % 3], ls=":", lw=1.2, label=label)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("energy [kJ/m]")
    if title:
        ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    return save_figure(fig, path)


def plot_load_settlement(path: str | Path, settlement: Sequence[float],
                         pressure: Sequence[float], references: Mapping[str, float] | None = None,
                         *, title: str = "Footing: load-settlement", label: str = "hybrid",
                         more: Mapping[str, tuple[Sequence[float], Sequence[float]]] | None = None
                         ) -> Path:
    """Footing pressure [kPa] against settlement [m], with limit loads as horizontal lines.

    ``references``: e.g. {"Prandtl": 1023.6, "Terzaghi": ..., "Meyerhof": ..., "Vesic": ...}
    (kPa), see :func:`hybrid.references.strip_footing_estimates`. Settlement positive downward.
    """
    return plot_curve(path, settlement, pressure, xlabel="footing settlement [m]",
                      ylabel="mean footing pressure [kPa]", title=title, references=references,
                      reference_unit="kPa", label=label, more=more)


def plot_thrust_translation(path: str | Path, translation: Sequence[float],
                            thrust: Sequence[float],
                            references: Mapping[str, float] | None = None, *,
                            title: str = "Wall: thrust-translation", label: str = "hybrid",
                            more: Mapping[str, tuple[Sequence[float], Sequence[float]]]
                            | None = None) -> Path:
    """Horizontal thrust on the wall [kN/m] against wall translation [m], Rankine lines.

    ``references``: e.g. {"Rankine active": 275.0, "at rest": ..., "Rankine passive": 2475.0}
    (kN/m), see :mod:`hybrid.references`. Translation as a magnitude (away from or toward the
    backfill).
    """
    return plot_curve(path, translation, thrust, xlabel="wall translation [m]",
                      ylabel="horizontal thrust on the wall [kN/m]", title=title,
                      references=references, reference_unit="kN/m", label=label, more=more)


# --- report ------------------------------------------------------------------------------------

def _fmt(value: Any, digits: int = 5) -> str:
    if value is None:
        return "-"
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, int | np.integer):
        return str(int(value))
    value = float(value)
    if not math.isfinite(value):
        return str(value)
    if value == 0.0:
        return "0"
    if 1e-3 <= abs(value) < 1e6:
        return f"{value:.{digits}g}"
    return f"{value:.3e}"


def _error(row: Mapping[str, Any]) -> str:
    if row["error"] is None:
        return "-"
    # a zero reference makes the error absolute (hybrid.io.Check): no per cent sign then
    if row["reference"] == 0:
        return _fmt(row["error"], 3)
    return f"{100 * row['error']:.3g} %"


def _bar(row: Mapping[str, Any]) -> str:
    if row["bar"] is None:
        return "report"
    return _fmt(row["bar"], 3) if row["reference"] == 0 else f"{100 * row['bar']:.3g} %"


def _verdict(row: Mapping[str, Any]) -> str:
    return {True: "pass", False: "**FAIL**", None: "report"}[row["passed"]]


def _table_rows(results: Sequence[Mapping[str, Any]]) -> list[list[str]]:
    rows = []
    for r in results:
        if not r["rows"]:
            detail = _first_line(r["message"]) or r["status"]
            rows.append([r["id"], r["title"], "-", r["reference"], "-", r["bar"],
                         _MARK[r["status"]] + (f" ({detail})" if r["status"] == "error" else "")])
            continue
        for i, row in enumerate(r["rows"]):
            unit = f" {row['unit']}" if row["unit"] and row["unit"] != "-" else ""
            problem = (f"{r['title']}: " if i == 0 else "") + f"`{row['name']}`"
            rows.append([r["id"], problem, _fmt(row["computed"]) + unit,
                         _fmt(row["reference"]) + (unit if row["reference"] is not None else ""),
                         _error(row), _bar(row), _verdict(row)])
    return rows


def _first_line(text: str) -> str:
    return text.strip().splitlines()[0] if text.strip() else ""


def _md_escape(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def format_table(results: Sequence[Mapping[str, Any]]) -> str:
    """Plain-text table of every row (the console output of ``hybrid verify``)."""
    header = ["id", "check", "computed", "reference", "error", "bar", "pass"]
    body = []
    for r in results:
        if not r["rows"]:
            body.append([r["id"], r["title"][:50], "-", "-", "-", "-",
                         r["status"] + (f": {_first_line(r['message'])}"
                                        if r["status"] == "error" else "")])
        for row in r["rows"]:
            unit = f" {row['unit']}" if row["unit"] and row["unit"] != "-" else ""
            body.append([r["id"], row["name"], _fmt(row["computed"]) + unit,
                         _fmt(row["reference"]), _error(row), _bar(row),
                         _verdict(row).replace("*", "")])
    widths = [max(len(line[i]) for line in [header, *body]) for i in range(len(header) - 1)]
    lines = []
    for line in [header, *body]:
        lines.append("  ".join(c.ljust(w) for c, w in zip(line, widths)) + "  " + line[-1])
    return "\n".join(lines)


def _git_commit(root: Path) -> str | None:
    try:
        out = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root,
                             capture_output=True, text=True, timeout=10, check=True)
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.strip() or None


def _copy_png(src: Path, dst: Path, max_bytes: int = MAX_PNG_BYTES) -> Path:
    """Copy a PNG; above ``max_bytes`` re-encode it (palette, then half size) to fit."""
    shutil.copyfile(src, dst)
    if dst.stat().st_size <= max_bytes:
        return dst
    from PIL import Image

    with Image.open(src) as im:
        image = im.convert("RGB")
    scale = 1.0
    for _ in range(4):
        size = (max(1, int(image.width * scale)), max(1, int(image.height * scale)))
        small = image.resize(size, Image.LANCZOS) if scale < 1 else image
        small.quantize(colors=256).save(dst, optimize=True)
        if dst.stat().st_size <= max_bytes:
            break
        scale *= 0.7
    return dst


def _collect_figures(results: list[dict[str, Any]], out_dir: Path) -> None:
    fig_dir = out_dir / "figures"
    fig_dir.mkdir(parents=True, exist_ok=True)
    sources = {Path(f).resolve() for r in results for f in r.get("figures", [])}
    sources |= {p.with_suffix(".json") for p in sources}
    for old in (*fig_dir.glob("*.png"), *fig_dir.glob("*.json")):  # the report is one run
        if old.resolve() not in sources:
            old.unlink()
    for r in results:
        kept = []
        for fig in r.get("figures", []):
            src = Path(fig)
            if not src.is_file():
                continue
            dst = fig_dir / f"{r['id']}_{src.name}"
            if src.resolve() != dst.resolve():
                _copy_png(src, dst)
            side = src.with_suffix(".json")
            if side.is_file() and src.resolve() != dst.resolve():
                shutil.copyfile(side, dst.with_suffix(".json"))
            kept.append(dst.relative_to(out_dir).as_posix())
        r["figures"] = kept


def _counts(results: Sequence[Mapping[str, Any]]) -> dict[str, int]:
    counts = {s: 0 for s in ("passed", "failed", "reported", "error", "not yet available")}
    for r in results:
        counts[r["status"]] = counts.get(r["status"], 0) + 1
    return counts


def _series(case_id: str) -> str:
    """The series of a case id: its leading letters ("C" for "C6-psi0", "R" for "R1-a2")."""
    return case_id[:len(case_id) - len(case_id.lstrip("ABCDEFGHIJKLMNOPQRSTUVWXYZ"))]


def _section(r: Mapping[str, Any]) -> list[str]:
    lines = [f"## {r['id']}: {r['title']}", "",
             f"- status: {_MARK[r['status']]}"
             + (f" ({_md_escape(r['message'])})" if r["message"] else ""),
             f"- reference: {r['reference']}", f"- bar: {r['bar']}",
             f"- script: `{r['case_script']}`"
             + (f", overrides {json.dumps(r['overrides'])}" if r["overrides"] else "")]
    if r["stats"]:
        stats = ", ".join(f"{k[:-2].replace('_', ' ')} {_fmt(v, 3)} s" if k.endswith("_s")
                          else f"{k.replace('_', ' ')} {_fmt(v)}" for k, v in r["stats"].items())
        lines.append(f"- run: {stats}")
    for row in r["rows"]:
        if row["source"]:
            lines.append(f"- `{row['name']}`: {row['source']}")
    lines.append("")
    for fig in r["figures"]:
        name = Path(fig).stem.removeprefix(f"{r['id']}_").replace("_", " ")
        lines += [f"![{r['id']} {name}]({fig})", ""]
    return lines


def write_report(results: Sequence[Mapping[str, Any]],
                 out_dir: str | Path = Path("results/verify"), *, full: bool = False,
                 json_path: str | Path | None = None,
                 series: Mapping[str, tuple[str, str]] | None = None) -> Path:
    """Write ``report.md``, ``results.json`` and ``figures/`` into ``out_dir``.

    ``results``: entries of :func:`hybrid.verification.run_cases`. Figures are copied to
    ``figures/<id>_<name>.png`` (re-encoded above 200 KB) and the entries' ``figures`` become
    paths relative to ``out_dir``. ``json_path``: a second copy of results.json. ``series``:
    {letter of the ids: (title, text)}, an introduction written before the first section of
    the series (default: :data:`hybrid.verification.SERIES`). Returns the path of report.md.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    entries: list[dict[str, Any]] = [dict(r) for r in results]
    _collect_figures(entries, out_dir)
    if series is None:
        from hybrid.verification import SERIES

        series = SERIES
    intros = {k: v for k, v in series.items() if any(_series(e["id"]) == k for e in entries)}
    root = Path(hybrid.__file__).resolve().parent.parent
    counts = _counts(entries)
    meta = {"generated_utc": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M:%S"),
            "hybrid": hybrid.__version__, "git_commit": _git_commit(root),
            "mode": "full" if full else "fast (reduced overrides)", "counts": counts,
            "series": {k: {"title": t, "text": x} for k, (t, x) in intros.items()}}
    payload = _finite({"meta": meta, "cases": entries})
    text = json.dumps(payload, indent=1, default=_json_default, allow_nan=False) + "\n"
    (out_dir / "results.json").write_text(text)
    if json_path is not None:
        json_path = Path(json_path)
        json_path.parent.mkdir(parents=True, exist_ok=True)
        json_path.write_text(text)

    lines = ["# Verification report", "",
             f"Generated by `hybrid verify{' --full' if full else ''}` on "
             f"{meta['generated_utc']} UTC (hybrid {meta['hybrid']}"
             + (f", commit {meta['git_commit']}" if meta["git_commit"] else "") + "), "
             f"{meta['mode']}. Units m, kN, kPa; tension "
             "positive. The error is relative to the reference, or absolute where the "
             "reference is 0.", "",
             "Cases: " + ", ".join(f"{n} {s}" for s, n in counts.items() if n) + ".", "",
             "| id | problem | computed | reference | error | bar | pass |",
             "|---|---|---|---|---|---|---|"]
    for row in _table_rows(entries):
        lines.append("| " + " | ".join(_md_escape(c) for c in row) + " |")
    lines.append("")
    for r in entries:
        letter = _series(r["id"])
        if letter in intros and r is next(e for e in entries if _series(e["id"]) == letter):
            title, text = intros[letter]
            lines += [f"## {title}", "", text, ""]
        lines += _section(r)
    md = out_dir / "report.md"
    md.write_text("\n".join(lines).rstrip() + "\n")
    return md


def _json_default(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, Path):
        return str(value)
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")


def _finite(value: Any) -> Any:
    """Non-finite floats become strings ("nan", "inf"): results.json stays strict JSON."""
    if isinstance(value, Mapping):
        return {str(k): _finite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(v) for v in value]
    if isinstance(value, float | np.floating) and not math.isfinite(value):
        return str(float(value))
    return value
