"""The verification registry behind ``hybrid verify``: the continuum C1-C10, the run-out R1.

Each entry names a case script (``cases/*.py``, a ``main(out=..., **overrides)`` returning a
:class:`hybrid.io.CaseSummary` whose ``checks`` map names to :class:`hybrid.io.Check`), the
reduced overrides the default (fast) run uses and those of the full run. Adding a case is one
entry in :data:`CASES`; a case whose script does not exist yet is listed as "not yet available"
(not failed).

What a case summary may carry in its ``results``, besides its ``checks``, and how the report
uses it:

- ``"cells"``, ``"dofs"``, ``"steps"``, ``"load_steps"``, ``"iterations"``,
  ``"newton_iterations"``, ``"wall_time_s"``, and any scalar in ``"stats"``: shown
  in the case's section of the report (the wall time of the whole run, mesh and plots
  included, is always measured: ``total_wall_time_s``).
- ``"load_settlement"``: ``{"settlement": [m], "pressure": [kPa], "references": {name: kPa}}``
  (or a dict of such curves by name): plotted with
  :func:`hybrid.report.plot_load_settlement` unless the case wrote ``load_settlement*.png``.
- ``"thrust_translation"``: ``{"translation": [m], "thrust": [kN/m], "references": {...}}``
  (or a dict of them): plotted with :func:`hybrid.report.plot_thrust_translation`.
- PNG files the case writes into its output folder are kept (copied into the report).
"""

from __future__ import annotations

import argparse
import dataclasses
import logging
import math
import time
import traceback
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from hybrid.io import CaseSummary, Check

__all__ = ["VerificationCase", "CASES", "CASES_DIR", "SERIES", "STATUSES", "run_case",
           "run_cases", "select", "exit_code", "add_arguments", "report_folder", "command",
           "DEFAULT_OUT", "DOCS_REPORT"]

log = logging.getLogger(__name__)

ROOT = Path(__file__).resolve().parent.parent
CASES_DIR = ROOT / "cases"
# the report of a plain `hybrid verify` (outside the repository's tracked files) and the
# committed one that `hybrid verify --full --update-docs` (make verify) rewrites
DEFAULT_OUT = Path("results/verify")
DOCS_REPORT = ROOT / "docs" / "verification"

# passed: every row with a bar passes; failed: a row misses its bar; reported: rows without
# bars only; error: the case raised; not yet available: its script is not in cases/ yet.
STATUSES = ("passed", "failed", "reported", "error", "not yet available")

_STAT_KEYS = ("cells", "dofs", "steps", "load_steps", "iterations", "newton_iterations",
              "wall_time_s")


@dataclass(frozen=True)
class VerificationCase:
    """One row group of the verification report.

    Attributes:
        id: "C1" ...
        title: the problem in a few words.
        case_script: path of the case script relative to the cases folder.
        overrides: parameters of the default (fast) run.
        full_overrides: parameters of the ``--full`` run.
        reference: the closed form / published value, in words.
        bar: the acceptance bar, in words.
        slow: True when even the fast run is long (tests mark it slow).
        checks: names of the summary's checks that become rows (None: all of them).
        extra: function(summary) -> {name: Check}, more rows from the case's
            :class:`~hybrid.io.CaseSummary`.
        figures: function(summary, case out dir) -> PNG paths, more figures from its results.
        keep: glob patterns of the PNGs that go into the report (the rest stay in the case's
            output folder).
    """

    id: str
    title: str
    case_script: str
    overrides: Mapping[str, Any] = field(default_factory=dict)
    full_overrides: Mapping[str, Any] = field(default_factory=dict)
    reference: str = ""
    bar: str = ""
    slow: bool = False
    checks: tuple[str, ...] | None = None
    extra: Callable[[CaseSummary], dict[str, Check]] | None = None
    figures: Callable[[CaseSummary, Path], list[Path]] | None = None
    keep: tuple[str, ...] = ("*.png",)

    def script_path(self, cases_dir: Path | None = None) -> Path:
        """Path of the case script in ``cases_dir`` (default: the repository's ``cases/``)."""
        return Path(cases_dir or CASES_DIR) / self.case_script


def _c3_extra(summary: CaseSummary) -> dict[str, Check]:
    conv = summary.results.get("settlement_convergence")
    if not conv:
        return {}
    return {"settlement_change_on_halving_mesh": Check(
        float(conv["relative_change"]), None, None, "-",
        f"footing-edge settlement, {conv['cells'][0]} -> {conv['cells'][1]} cells (reported)")}


def _c4_extra(summary: CaseSummary) -> dict[str, Check]:
    conv = summary.results.get("mesh_convergence")
    if not conv:
        return {}
    # reference 0 makes the error the change itself; 2 % as the far-field bar
    return {"stress_change_on_halving_mesh": Check(
        float(conv["max_change_over_max_stress"]), 0.0, 0.02, "-",
        "max |stress change| / max |stress| at 3 points inside the slope")}


def _footing_estimates(summary: CaseSummary) -> dict[str, float]:
    """Prandtl and the Terzaghi / Meyerhof / Vesic / Hansen estimates for the case's soil."""
    from hybrid.references import strip_footing_estimates

    p = summary.parameters
    return strip_footing_estimates(p["cohesion"], p["phi"], p["unit_weight"],
                                   p["footing_width"])


def _footing_curve(summary: CaseSummary) -> tuple[Any, Any] | None:
    curve = summary.results.get("curve") or {}
    if "settlement_m" in curve and "pressure_kPa" in curve:
        return curve["settlement_m"], curve["pressure_kPa"]
    return None


def _footing_figures(summary: CaseSummary, out: Path) -> list[Path]:
    """Load-settlement curve with the Prandtl / Terzaghi / Meyerhof / Vesic lines."""
    from hybrid import report

    curve = _footing_curve(summary)
    if curve is None:
        return []
    refs = _footing_estimates(summary)
    if summary.parameters.get("unit_weight", 0.0) == 0.0:
        refs = {"Prandtl": refs["Prandtl (weightless)"]}  # the others coincide without weight
    else:
        refs["thesis 5.4.1 collapse (approx.)"] = 1200.0
    return [report.plot_load_settlement(out / "load_settlement_references.png", *curve,
                                        references=refs,
                                        title=f"{summary.case}: load-settlement")]


def _c7_extra(summary: CaseSummary) -> dict[str, Check]:
    """The limit pressure beside each classical estimate (reported, no bar)."""
    limit = summary.checks["limit_pressure"].computed
    return {f"limit_pressure_vs_{name.split()[0].lower()}": Check(
        limit, value, None, "kPa", f"{name}: c N_c + 0.5 gamma B N_gamma (reported)")
        for name, value in _footing_estimates(summary).items() if "Prandtl" not in name}


def _wall_figures(summary: CaseSummary, out: Path) -> list[Path]:
    """Thrust-translation curve with the Rankine and at-rest lines."""
    from hybrid import report
    from hybrid.references import k0_elastic, k0_jaky, rankine_active_thrust, rankine_passive_thrust

    curve = summary.results.get("curve") or {}
    if "translation_m" not in curve or "thrust_kN_per_m" not in curve:
        return []
    p = summary.parameters
    gamma, H, phi, c = p["unit_weight"], p["height"], p["phi"], p.get("cohesion", 0.0)
    refs = {"Rankine active" if p["mode"] == "active" else "Rankine passive":
            (rankine_active_thrust(gamma, H, phi, c) if p["mode"] == "active"
             else rankine_passive_thrust(gamma, H, phi, c)),
            "at rest, elastic K0 = nu/(1 - nu)": 0.5 * k0_elastic(p["nu"]) * gamma * H**2,
            "at rest, Jaky K0 = 1 - sin phi": 0.5 * k0_jaky(phi) * gamma * H**2}
    return [report.plot_thrust_translation(
        out / f"thrust_translation_{p['mode']}.png", curve["translation_m"],
        curve["thrust_kN_per_m"], references=refs,
        title=f"{summary.case}: thrust-translation")]


def _below_one_extra(summary: CaseSummary) -> dict[str, Check]:
    """The weak slope: F below 1 and within 5 % of the Bishop value of its section."""
    vs = summary.checks["factor_of_safety_vs_bishop"]
    return {"below_one": Check(float(summary.results["below_one"]), 1.0, 0.0, "-",
                               "the strength search reports F < 1"),
            "factor_of_safety_within_5_percent_of_bishop": Check(
                vs.computed, vs.reference, 0.05, "-",
                "F of the finest mesh against Bishop's simplified method, same section")}


# reduced mesh / steps of the footing runs (about 4 s each here; full about 10 s)
_FOOTING_FAST = {"fine": 0.06, "coarse": 0.8, "steps": 20}

#: the experiments' bar on run-out and final height of the granular collapse (relative)
RUNOUT_BAR = 0.15
#: the bar on the change of run-out between grains of L0 / n and L0 / 2n (relative)
RUNOUT_MESH_BAR = 0.10

_COLLAPSE_LAWS = (("rods2015", RUNOUT_BAR, "the aluminium rods (arXiv:1512.05180)"),
                  ("lube2005", None, "Lube et al.'s (2005) sand laws as quoted"))
_COLLAPSE_MEASURES = (("runout", "normalised_runout", "runout", "(L_inf - L0) / L0"),
                      ("final_height", "height_over_H0", "height", "H_inf / H0"))


def _collapse_extra(summary: CaseSummary) -> dict[str, Check]:
    """Run-out and final height against the rods (bar) and Lube's sand laws (reported).

    A law the source does not state at this aspect ratio leaves the row without reference; a
    deposit that was still moving when the run stopped is compared with nothing (the case's
    rest check fails then).
    """
    dep = summary.results["deposit"]
    aspect = summary.parameters["aspect"]
    rows = {}
    for law, bar, words in _COLLAPSE_LAWS:
        for name, key, ref_key, what in _COLLAPSE_MEASURES:
            ref = dep["references"][f"{law}_{ref_key}"]
            if not dep["at_rest"]:
                rows[f"{name}_vs_{law}"] = Check(
                    float(dep[key]), None, None, "-",
                    f"{what}: not compared, the deposit had not come to rest")
                continue
            rows[f"{name}_vs_{law}"] = (
                Check(float(dep[key]), float(ref), bar, "-",
                      f"{what} against {words}" + (" (reported)" if bar is None else ""))
                if ref is not None else
                Check(float(dep[key]), None, None, "-",
                      f"{what}: {words} give no law at a = {aspect:g} (reported)"))
    return rows


def _collapse_mesh_extra(summary: CaseSummary) -> dict[str, Check]:
    """:func:`_collapse_extra` and the run-out's change when the grains are twice as large.

    Runs the case script of :data:`CASES_DIR` again with ``nx`` halved, into the ``nx<n>``
    folder of the case's output.
    """
    from hybrid.case import load_case

    p = summary.parameters
    nx = int(p["nx"])
    coarse = load_case(CASES_DIR / "granular_collapse.py").main(
        out=summary.out / f"nx{nx // 2}", **{**p, "nx": nx // 2})
    fine_m = summary.results["deposit"]["runout_m"]
    coarse_m = coarse.results["deposit"]["runout_m"]
    what = (f"|L_inf(L0/{nx // 2}) - L_inf(L0/{nx})| / L_inf(L0/{nx}): the run-out on grains "
            "twice as large")
    both = summary.results["deposit"]["at_rest"] and coarse.results["deposit"]["at_rest"]
    change = abs(coarse_m - fine_m) / fine_m
    return {**_collapse_extra(summary), "runout_change_on_halving_mesh": (
        Check(change, 0.0, RUNOUT_MESH_BAR, "-", what) if both else
        Check(change, None, None, "-", f"{what}: not compared, a deposit had not come to "
                                        "rest"))}


def _collapse_case(aspect: float, reduced_nx: int, title: str, mesh: bool = False
                   ) -> VerificationCase:
    """The granular column collapse at one aspect ratio (R1): reduced runs on coarse grains."""
    from hybrid import references as ref

    runout = (f"(L_inf - L0) / L0 = {ref.granular_runout_rods2015(aspect):.3g}"
              if aspect > ref.RODS2015_BREAK
              else f"no run-out law for a <= {ref.RODS2015_BREAK:g}")
    return VerificationCase(
        f"R1-a{aspect:g}", title, "granular_collapse.py",
        overrides={"aspect": aspect, "nx": reduced_nx, "progress": False},
        full_overrides={"aspect": aspect, "progress": False},
        reference=f"aluminium rods (arXiv:1512.05180): {runout}, H_inf / H0 = "
                  f"{ref.granular_final_height_rods2015(aspect):.3g}; Lube et al. (2005) sand laws "
                  "as quoted, reported",
        bar="15 % on run-out and final height against the rods"
            + (f"; run-out within {100 * RUNOUT_MESH_BAR:g} % when the grains are twice as "
               "large" if mesh else ""),
        checks=("energy_excess_over_sources", "rest_kinetic_ratio", "rest_drift_ratio"),
        extra=_collapse_mesh_extra if mesh else _collapse_extra, keep=("final.png",))


#: introductions of the report's series, by the letter of their ids: (title, text)
SERIES: dict[str, tuple[str, str]] = {
    "R": ("Run-out (R-series)",
          "A plane column of cohesionless grains (aluminium bars: L0 = 0.2 m long, H0 = a L0 "
          "high, friction angle 19.8 deg) stands against a back wall behind a gate; the gate "
          "is removed and the column spreads over a smooth floor to rest (the experiments' "
          "floor is not known; on a rough one, a sawtooth standing in for grains fixed to "
          "it, the run-out is shorter by more than the bar: docs/hybrid.md). The model is a "
          "packing of elastic triangular grains (unstructured, of size L0 / 20 in the full "
          "run) bonded by interfaces with no cohesion and no tensile strength: they fail as "
          "soon as they open or slide, and from then on the grains meet by contact with "
          "Coulomb friction at the contact angle whose packing has a critical-state bulk "
          "angle of 19.8 deg in a plane-strain biaxial test (hybrid.discrete.biaxial). The "
          "grains stay elastic; collisions lose energy "
          "through a normal contact damping ratio of 0.3 (assumed). The run-out L_inf is the "
          "far end of the continuous deposit from the back wall and a = H0 / L0. The bar is "
          "15 % against the aluminium-rod laws of arXiv:1512.05180; Lube et al.'s (2005) sand "
          "laws, known only as quoted by others, are reported beside them. In the full run the "
          "bar is met for the final height at every aspect ratio; the run-out is one packing's "
          "(docs/hybrid.md compares three packings, whose run-outs scatter up to as much as "
          "the bar), and runs beyond the rods' law at a = 2 (the table gives by how much; "
          "the rods give no run-out law at a = 0.5). Over the contact angle's calibration "
          "uncertainty (about 2 deg either side: the standard error of the calibration's mean "
          "curve) the run-out moves by more than the bar. It grows as the grains get finer, "
          "down to about L0 / 40 at a = 0.5 and 1: on grains of L0 / 20 it is not converged "
          "(the report's row on its change from grains twice as large), and on the finer "
          "grains where it stops growing it runs beyond the experiments on this flat floor by "
          "more than the bar at a = 0.5 and 1 too (docs/hybrid.md); the report's runs are "
          "those of L0 / 20. The reduced run (`hybrid verify` without `--full`) uses coarser "
          "grains."),
}

CASES: dict[str, VerificationCase] = {c.id: c for c in (
    VerificationCase(
        "C1", "Uniform load on a 12 m block, 3x3 Q4 (thesis 3.4.1)", "uniform_load.py",
        reference="sigma_yy = -q = -5 kPa, sigma_xx = tau_xy = 0 everywhere; settlement "
                  "q (1 - nu^2) H / E", bar="1e-6 relative",
        keep=("sigma_yy.png",)),
    VerificationCase(
        "C2", "Elastic column under gravity, laterally confined (oedometric)", "oedometer.py",
        reference="sigma_v = -gamma z, sigma_h = nu/(1 - nu) sigma_v; settlement gamma H^2/(2M)",
        bar="0.5 %",
        keep=("stress_profile.png",)),
    VerificationCase(
        "C3", "Flexible strip footing B = 12 m, q = 100 kPa, E = 10 MPa, nu = 0.4 (thesis 3.4.2)",
        "flexible_footing.py", overrides={"fine": 0.4, "coarse": 3.0},
        reference="centreline sigma_z = -(q/pi)(alpha + sin alpha) for z <= B/2 (Poulos & "
                  "Davis 1974); edge settlement beside the thesis's 0.101 m",
        bar="5 % stress; settlement reported", extra=_c3_extra,
        keep=("centreline_stress.png", "sigma_yy.png", "vertical_displacement.png")),
    VerificationCase(
        "C4", "Gravity switch-on in a 10 m high 30 deg slope (thesis 3.4.4)", "slope_gravity.py",
        overrides={"size": 1.5},
        reference="far field sigma_v = -gamma z, sigma_h = K0 sigma_v, K0 = nu/(1 - nu); "
                  "stresses mesh-converged", bar="2 %", extra=_c4_extra,
        keep=("sigma_yy.png", "sigma_xx.png")),
    # Continuum plasticity (the Mohr-Coulomb solver): parameter names of the overrides are
    # those of each script's Parameters; an unknown one is reported as an error naming it.
    VerificationCase(
        "C5", "Rigid smooth strip footing, weightless Tresca soil, c_u = 50 kPa",
        "bearing_capacity.py",
        overrides={"cohesion": 50.0, "phi": 0.0, "case_id": "C5", **_FOOTING_FAST},
        full_overrides={"cohesion": 50.0, "phi": 0.0, "case_id": "C5"},
        reference="Prandtl q_u = (2 + pi) c_u = 257.1 kPa", bar="3 %",
        figures=_footing_figures,
        keep=("load_settlement_references.png", "plastic_strain.png")),
    VerificationCase(
        "C6", "Rigid smooth strip footing, weightless MC soil c = 69 kPa, phi = 20 deg, "
        "psi = phi (thesis 5.4.1)", "bearing_capacity.py",
        overrides={"case_id": "C6", **_FOOTING_FAST}, full_overrides={"case_id": "C6"},
        reference="Prandtl q_u = c N_c = 1023.6 kPa", bar="3 %", figures=_footing_figures,
        keep=("load_settlement_references.png", "plastic_strain.png")),
    VerificationCase(
        "C6-psi0", "C6 with psi = 0 (non-associated)", "bearing_capacity.py",
        overrides={"case_id": "C6-psi0", "psi": 0.0, **_FOOTING_FAST},
        full_overrides={"case_id": "C6-psi0", "psi": 0.0},
        reference="load plateau reported beside Prandtl 1023.6 kPa", bar="report",
        figures=_footing_figures,
        keep=("load_settlement_references.png", "plastic_strain.png")),
    VerificationCase(
        "C7", "C6 footing with soil weight (gamma = 20 kN/m3 assumed)", "bearing_capacity.py",
        overrides={"case_id": "C7", "unit_weight": 20.0, **_FOOTING_FAST},
        full_overrides={"case_id": "C7", "unit_weight": 20.0},
        reference="between the Terzaghi / Meyerhof / Vesic estimates; thesis ~1200 kPa",
        bar="report", extra=_c7_extra, figures=_footing_figures,
        keep=("load_settlement_references.png", "plastic_strain.png")),
    VerificationCase(
        "C8-active", "Smooth rigid wall H = 10 m, sand phi = 30 deg, moved away from the "
        "backfill (thesis 5.4.2)", "retaining_wall.py", overrides={"mode": "active"},
        full_overrides={"mode": "active"},
        reference="Rankine K_a = 1/3, P_a = 0.5 K_a gamma H^2 = 275 kN/m", bar="5 %",
        figures=_wall_figures,
        keep=("thrust_translation_*.png", "*plastic_strain.png")),
    VerificationCase(
        "C8-passive", "The same wall pushed toward the backfill", "retaining_wall.py",
        overrides={"mode": "passive"}, full_overrides={"mode": "passive"},
        reference="Rankine K_p = 3, P_p = 0.5 K_p gamma H^2 = 2475 kN/m", bar="10 %",
        figures=_wall_figures,
        keep=("thrust_translation_*.png", "*plastic_strain.png")),
    VerificationCase(
        "C9", "Slope factor of safety by strength reduction (Griffiths & Lane 1999, ex. 1), "
        "psi = 0, three meshes", "slope_fos.py",
        overrides={"meshes": "8,12"}, full_overrides={"meshes": "16,24,32"},
        reference="Bishop & Morgenstern (1960) charts F = 1.38 (Griffiths & Lane FE: 1.4); "
                  "this project's Bishop simplified search beside it",
        bar="3 % each mesh; meshes within 2 % of each other; Bishop search 1 %",
        keep=("strength_reduction_curve.png", "mechanism_displacement.png")),
    VerificationCase(
        "C9-associated", "The same slope with psi = phi = 20 deg", "slope_fos.py",
        overrides={"meshes": "8,12", "psi": 20.0},
        full_overrides={"meshes": "16,24,32", "psi": 20.0},
        reference="Bishop & Morgenstern (1960) charts F = 1.38; Bishop search beside it",
        bar="3 % each mesh; meshes within 2 % of each other; Bishop search 1 %",
        keep=("strength_reduction_curve.png", "mechanism_displacement.png")),
    VerificationCase(
        "C9-weak", "A slope too weak to stand: c = 5 kPa, phi = 10 deg (F < 1)",
        "slope_fos.py", overrides={"meshes": "8,12", "cohesion": 5.0, "phi": 10.0},
        full_overrides={"meshes": "16,24,32", "cohesion": 5.0, "phi": 10.0},
        reference="this project's Bishop simplified search of the same section",
        bar="F < 1 within 5 % of Bishop (no published value for these parameters)",
        extra=_below_one_extra,
        keep=("strength_reduction_curve.png", "mechanism_displacement.png")),
    VerificationCase(
        "C10", "Staged construction: a confined fill column placed in 4 lifts",
        "staged_embankment.py",
        reference="sigma_v = -gamma z, sigma_h = K0 sigma_v at the end; closed-form staged "
                  "settlement of each lift top; zero stress in lifts not yet placed", bar="1 %"),
    # Run-out: the granular column collapse at three aspect ratios (full: grains of L0 / 20)
    _collapse_case(0.5, 16, "Granular column collapse, a = H0 / L0 = 0.5 (aluminium bars), "
                   "and its run-out on grains twice as large", mesh=True),
    _collapse_case(1.0, 8, "Granular column collapse, a = 1"),
    _collapse_case(2.0, 8, "Granular column collapse, a = 2"),
)}


def _rows(checks: Mapping[str, Check]) -> list[dict[str, Any]]:
    rows = []
    for name, check in checks.items():
        error = check.error
        rows.append({"name": name, "computed": float(check.computed),
                     "reference": None if check.reference is None else float(check.reference),
                     "error": None if error is None else float(error),
                     "bar": check.bar, "unit": check.unit, "source": check.source,
                     "passed": check.passed})
    return rows


def _status(rows: Sequence[Mapping[str, Any]]) -> str:
    verdicts = [r["passed"] for r in rows if r["passed"] is not None]
    if any(v is False for v in verdicts):
        return "failed"
    return "passed" if verdicts else "reported"


def _stats(summary: CaseSummary) -> dict[str, Any]:
    results = summary.results
    stats = {k: results[k] for k in _STAT_KEYS if _is_scalar(results.get(k))}
    extra = results.get("stats")
    if isinstance(extra, Mapping):
        stats.update({str(k): v for k, v in extra.items() if _is_scalar(v)})
    return stats


def _is_scalar(value: Any) -> bool:
    try:
        return value is not None and not isinstance(value, bool) and math.isfinite(float(value))
    except (TypeError, ValueError):
        return False


def _curves(value: Any, keys: tuple[str, str]) -> dict[str, Mapping[str, Any]]:
    if not isinstance(value, Mapping):
        return {}
    if all(k in value for k in keys):
        return {"": value}
    return {str(name): v for name, v in value.items()
            if isinstance(v, Mapping) and all(k in v for k in keys)}


def _curve_figures(summary: CaseSummary, out: Path, case_id: str) -> list[Path]:
    from hybrid import report

    made = []
    for key, keys, plot in (
            ("load_settlement", ("settlement", "pressure"), report.plot_load_settlement),
            ("thrust_translation", ("translation", "thrust"), report.plot_thrust_translation)):
        if list(out.glob(f"{key}*.png")):
            continue  # the case drew it itself
        for name, curve in _curves(summary.results.get(key), keys).items():
            stem = f"{key}_{name}" if name else key
            title = f"{case_id}: {key.replace('_', ' ')}" + (f" ({name})" if name else "")
            made.append(plot(out / f"{stem}.png", curve[keys[0]], curve[keys[1]],
                             references=curve.get("references"), title=title))
    return made


def _base(case: VerificationCase, full: bool) -> dict[str, Any]:
    return {"id": case.id, "title": case.title, "case_script": f"cases/{case.case_script}",
            "reference": case.reference, "bar": case.bar, "slow": case.slow, "full": full,
            "overrides": dict(case.full_overrides if full else case.overrides),
            "status": "not yet available", "message": "", "rows": [], "figures": [],
            "stats": {}, "out": None}


def run_case(case_id: str, out_dir: str | Path, full: bool = False, *,
             cases_dir: str | Path | None = None) -> dict[str, Any]:
    """Run one registered case into ``out_dir/<id>``; returns its report entry.

    The entry holds ``rows`` (name, computed, reference, error, bar, unit, source, passed),
    ``status`` (one of :data:`STATUSES`), ``figures`` (PNG paths), ``stats`` (cells, steps,
    iterations, wall time ...) and the overrides used. A case that raises is an ``error``
    entry with the message (the traceback goes to the log), never an exception.
    """
    if case_id not in CASES:
        raise ValueError(f"unknown verification case '{case_id}'; known: {', '.join(CASES)}")
    case = CASES[case_id]
    result = _base(case, full)
    script = case.script_path(Path(cases_dir) if cases_dir else None)
    if not script.is_file():
        result["message"] = f"{result['case_script']} does not exist yet"
        return result
    out = Path(out_dir) / case.id
    result["out"] = str(out)
    start = time.perf_counter()
    try:
        from hybrid.case import load_case

        module = load_case(script)
        overrides = dict(result["overrides"])
        known = {f.name for f in dataclasses.fields(module.Parameters)}
        unknown = sorted(set(overrides) - known)
        if unknown:
            raise ValueError(f"override(s) {', '.join(unknown)} not parameters of "
                             f"{result['case_script']} (known: {', '.join(sorted(known))}); "
                             f"fix CASES['{case.id}'] in hybrid/verification.py")
        for stale in out.glob("*.png"):  # an earlier run's figure must not stand for this one's
            stale.unlink()
        summary = module.main(out=out, **overrides)
        if not isinstance(summary, CaseSummary):
            raise TypeError(f"{result['case_script']}: main() returned a "
                            f"{type(summary).__name__}, not a CaseSummary")
        checks = dict(summary.checks)
        if case.checks is not None:
            missing = [n for n in case.checks if n not in checks]
            if missing:
                raise ValueError(f"the case returned no check(s) {', '.join(missing)}")
            checks = {n: checks[n] for n in case.checks}
        if case.extra is not None:
            checks.update(case.extra(summary))
        result["rows"] = _rows(checks)
        result["stats"] = _stats(summary)
        figures = list(out.glob("*.png"))
        figures += [p for p in _curve_figures(summary, out, case.id) if p not in figures]
        if case.figures is not None:
            figures += [Path(p) for p in case.figures(summary, out) if Path(p) not in figures]
        result["figures"] = [str(p) for p in sorted(figures)
                             if any(p.match(pattern) for pattern in case.keep)]
        result["status"] = _status(result["rows"])
    except Exception as err:  # a broken case is a result of the report, not a crash
        log.error("%s failed:\n%s", case.id, traceback.format_exc())
        result["status"] = "error"
        result["message"] = f"{type(err).__name__}: {err}"
    result["stats"]["total_wall_time_s"] = round(time.perf_counter() - start, 3)
    return result


def select(ids: Sequence[str]) -> list[str]:
    """Registered ids matching ``ids``: "C8" selects "C8" and its variants "C8-active", ..."""
    chosen: list[str] = []
    for want in ids:
        found = [k for k in CASES if k == want or k.startswith(f"{want}-")]
        if not found:
            raise ValueError(f"unknown verification case '{want}'; known: {', '.join(CASES)}")
        chosen += [k for k in found if k not in chosen]
    return chosen


def run_cases(ids: Sequence[str] | None, out_dir: str | Path, full: bool = False, *,
              cases_dir: str | Path | None = None,
              progress: Callable[[dict[str, Any]], None] | None = None) -> list[dict[str, Any]]:
    """Run the cases ``ids`` (all registered ones when None) in order; see :func:`run_case`."""
    ids = list(CASES) if ids is None else select(ids)
    results = []
    for case_id in ids:
        result = run_case(case_id, out_dir, full, cases_dir=cases_dir)
        results.append(result)
        if progress is not None:
            progress(result)
    return results


def exit_code(results: Sequence[Mapping[str, Any]]) -> int:
    """1 when a case failed a bar or raised, else 0 (cases not yet available do not count)."""
    return int(any(r["status"] in ("failed", "error") for r in results))


# --- command line ---------------------------------------------------------------------------

def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``hybrid verify``."""
    parser.add_argument("--only", default=None, metavar="C1,C3",
                        help=f"comma-separated case ids (default: all of {', '.join(CASES)})")
    parser.add_argument("--json", type=Path, default=None, metavar="PATH",
                        help="also write the machine-readable results here")
    parser.add_argument("--out", type=Path, default=None, metavar="DIR",
                        help=f"report folder (default: {DEFAULT_OUT})")
    parser.add_argument("--results", type=Path, default=DEFAULT_OUT, metavar="DIR",
                        help=f"where the cases write their own outputs (default: {DEFAULT_OUT})")
    parser.add_argument("--full", action="store_true",
                        help="full-size runs (default: reduced, fast overrides)")
    parser.add_argument("--update-docs", action="store_true",
                        help="write the report into the committed docs/verification "
                             "(with --full, every case: `make verify`)")


def report_folder(args: argparse.Namespace) -> Path:
    """Where ``hybrid verify`` writes its report.

    ``--out``; the committed :data:`DOCS_REPORT` with ``--update-docs`` (a full run of every
    case only); else :data:`DEFAULT_OUT`.
    """
    if not args.update_docs:
        return args.out or DEFAULT_OUT
    if args.out is not None:
        raise ValueError("--update-docs writes docs/verification: leave out --out")
    if args.only or not args.full:
        raise ValueError("--update-docs rewrites the committed report, which is one full run of "
                         "every case: use `hybrid verify --full --update-docs` (make verify), "
                         "without --only")
    return DOCS_REPORT


def command(args: argparse.Namespace) -> int:
    """Run ``hybrid verify``: run the cases, write the report, print the table."""
    from hybrid import report

    out = report_folder(args)
    ids = None if not args.only else [s.strip() for s in args.only.split(",") if s.strip()]

    def progress(result: dict[str, Any]) -> None:
        wall = result["stats"].get("total_wall_time_s")
        took = f" ({wall:.1f} s)" if wall is not None and result["out"] else ""
        print(f"{result['id']}: {result['status']}{took}", flush=True)

    results = run_cases(ids, args.results, args.full, progress=progress)
    md = report.write_report(results, out, full=args.full, json_path=args.json)
    print()
    print(report.format_table(results))
    print(f"\nreport: {md}")
    return exit_code(results)
