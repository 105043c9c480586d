"""``hybrid verify``, the verification registry and the report writer."""

import dataclasses
import json
import subprocess
import sys

import numpy as np
import pytest

from hybrid import references, report, verification
from hybrid.io import Check

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

FAKE_CASE = '''
from dataclasses import dataclass
from hybrid.io import CaseSummary, Check


@dataclass
class Parameters:
    computed: float = 1.0


def main(out="x", **overrides):
    p = Parameters(**overrides)
    if p.computed < 0:
        raise RuntimeError("negative")
    if p.computed == 0:
        return {"checks": {}}  # not a CaseSummary
    # reference 2.0, bar 1 %: fails unless computed is within 1 % of 2
    return CaseSummary("fake", out, p, {"q": Check(p.computed, 2.0, 0.01, "kPa", "fake")},
                       {"cells": 7})
'''


def _is_png(path):
    return path.is_file() and path.read_bytes()[:8] == PNG_SIGNATURE


def test_verify_c1_subprocess(tmp_path):
    """`hybrid verify --only C1 --json PATH`: exit 0, C1 rows pass with error < 1e-6 (C1 is a
    patch test: the stresses are exact to rounding, ~1e-15), report row and figures written."""
    out, json_path = tmp_path / "report", tmp_path / "c1.json"
    proc = subprocess.run(
        [sys.executable, "-m", "hybrid", "verify", "--only", "C1", "--json", str(json_path),
         "--out", str(out), "--results", str(tmp_path / "runs")],
        capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    data = json.loads(json_path.read_text())
    assert json.loads((out / "results.json").read_text()) == data
    (c1,) = data["cases"]
    assert c1["id"] == "C1" and c1["status"] == "passed"
    names = {row["name"] for row in c1["rows"]}
    assert {"sigma_yy_max_deviation_over_q", "settlement_top"} <= names
    for row in c1["rows"]:
        assert row["passed"] is True and row["error"] < 1e-6, row
    assert data["meta"]["counts"]["passed"] == 1
    md = (out / "report.md").read_text()
    assert "| C1 | Uniform load on a 12 m block" in md
    assert "`settlement_top` | 0.00156 m | 0.00156 m |" in md
    assert "C1" in proc.stdout and "settlement_top" in proc.stdout
    assert c1["figures"] and all(_is_png(out / f) for f in c1["figures"])


def test_plot_load_settlement(tmp_path):
    """PNG written; the JSON beside it holds the curve and the exact reference values."""
    refs = references.strip_footing_estimates(69.0, 20.0, 20.0, 1.2)
    settlement = np.linspace(0.0, 0.03, 11)
    pressure = 1100.0 * (1 - np.exp(-settlement / 0.008))
    path = report.plot_load_settlement(tmp_path / "ls.png", settlement, pressure, refs)
    assert _is_png(path)
    data = json.loads(path.with_suffix(".json").read_text())
    assert data["references"] == refs  # floats survive JSON exactly (repr round trip)
    assert data["references"]["Prandtl (weightless)"] == pytest.approx(1023.6, abs=0.05)
    np.testing.assert_array_equal(data["y"], pressure)
    assert "[kPa]" in data["ylabel"] and "[m]" in data["xlabel"]


def test_plot_thrust_translation(tmp_path):
    """Rankine lines of C8 (gamma 16.5, H 10, phi 30): 275 and 2475 kN/m in the JSON."""
    refs = {"Rankine active": references.rankine_active_thrust(16.5, 10.0, 30.0),
            "Rankine passive": references.rankine_passive_thrust(16.5, 10.0, 30.0)}
    path = report.plot_thrust_translation(tmp_path / "wall.png", [0.0, 0.01, 0.02],
                                          [600.0, 300.0, 280.0], refs)
    assert _is_png(path)
    data = json.loads(path.with_suffix(".json").read_text())
    assert data["references"]["Rankine active"] == pytest.approx(275.0, rel=1e-14)
    assert data["references"]["Rankine passive"] == pytest.approx(2475.0, rel=1e-14)
    with pytest.raises(ValueError, match="same length"):
        report.plot_thrust_translation(tmp_path / "bad.png", [0.0, 1.0], [1.0], refs)


def _tree(root):
    """git status and the bytes of every file of the committed report."""
    status = subprocess.run(["git", "status", "--porcelain", "--untracked-files=all"],
                            cwd=root, capture_output=True, text=True, check=True).stdout
    docs = root / "docs" / "verification"
    return status, {p.relative_to(docs).as_posix(): p.read_bytes()
                    for p in sorted(docs.rglob("*")) if p.is_file()}


def test_verify_leaves_the_repository_alone(tmp_path):
    """`hybrid verify --only C6` (as the README suggests) writes its report under
    results/verify (ignored by git) and changes no file of the repository: git status and the
    committed docs/verification are the same before and after. --update-docs refuses a partial
    or fast run (the committed report is one full run of every case)."""
    root = verification.ROOT
    if not (root / ".git").exists():
        pytest.skip("not a git checkout")
    before = _tree(root)
    proc = subprocess.run([sys.executable, "-m", "hybrid", "verify", "--only", "C6"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert _tree(root) == before
    report_md = tmp_path / "results" / "verify" / "report.md"
    assert "| C6 |" in report_md.read_text()
    assert list((tmp_path / "results" / "verify" / "figures").glob("C6_*.png"))
    ignored = subprocess.run(["git", "check-ignore", "-q", "results/verify/report.md"],
                             cwd=root)
    assert ignored.returncode == 0, "results/ must stay ignored by git"
    for argv in (["--only", "C6", "--full", "--update-docs"], ["--update-docs"]):
        proc = subprocess.run([sys.executable, "-m", "hybrid", "verify", *argv], cwd=tmp_path,
                              capture_output=True, text=True, timeout=60)
        assert proc.returncode == 2 and "hybrid verify --full --update-docs" in proc.stderr
        assert proc.stderr.count("\n") == 1, proc.stderr
    assert _tree(root) == before


def test_failing_row_gives_exit_code_1(tmp_path, monkeypatch):
    """C1 with one extra row whose reference is wrong (1 vs 2, bar 1 %): status failed, the
    row is marked FAIL in the report, and `hybrid verify` exits 1."""
    from hybrid import cli

    wrong = dataclasses.replace(
        verification.CASES["C1"],
        extra=lambda summary: {"wrong": Check(1.0, 2.0, 0.01, "kPa", "wrong on purpose")})
    monkeypatch.setitem(verification.CASES, "C1", wrong)
    result = verification.run_case("C1", tmp_path / "runs")
    assert result["status"] == "failed"
    bad = [r for r in result["rows"] if r["passed"] is False]
    assert [r["name"] for r in bad] == ["wrong"] and bad[0]["error"] == pytest.approx(0.5)
    assert verification.exit_code([result]) == 1
    md = report.write_report([result], tmp_path / "report").read_text()
    assert "| `wrong` | 1 kPa | 2 kPa | 50 % | 1 % | **FAIL** |" in md
    code = cli.main(["verify", "--only", "C1", "--out", str(tmp_path / "r2"),
                     "--results", str(tmp_path / "runs2")])
    assert code == 1


def test_statuses_of_missing_broken_and_reported_cases(tmp_path, monkeypatch):
    """A missing script is 'not yet available' (exit 0); a raising case is 'error' (exit 1), as
    is one whose main returns no CaseSummary; an unknown override names the parameter; a row
    without bar is 'reported'."""
    script = tmp_path / "fake.py"
    script.write_text(FAKE_CASE)
    base = verification.VerificationCase("X1", "fake", str(script), reference="2", bar="1 %")
    cases = {"X1": base,
             "X2": dataclasses.replace(base, id="X2", case_script=str(tmp_path / "nope.py")),
             "X3": dataclasses.replace(base, id="X3", overrides={"computed": -1.0}),
             "X4": dataclasses.replace(base, id="X4", overrides={"bogus": 1.0}),
             "X5": dataclasses.replace(base, id="X5", overrides={"computed": 2.01}),
             "X6": dataclasses.replace(base, id="X6", overrides={"computed": 0.0})}
    for key, case in cases.items():
        monkeypatch.setitem(verification.CASES, key, case)
    res = {r["id"]: r for r in verification.run_cases(list(cases), tmp_path / "runs")}
    assert res["X1"]["status"] == "failed"  # 1 vs 2
    assert res["X1"]["stats"]["cells"] == 7
    assert res["X2"]["status"] == "not yet available"
    assert verification.exit_code([res["X2"]]) == 0
    assert res["X3"]["status"] == "error" and "negative" in res["X3"]["message"]
    assert verification.exit_code([res["X2"], res["X3"]]) == 1
    assert res["X4"]["status"] == "error" and "bogus" in res["X4"]["message"]
    assert res["X5"]["status"] == "passed"  # 2.01 vs 2: 0.5 % < 1 %
    assert res["X6"]["status"] == "error" and "not a CaseSummary" in res["X6"]["message"]
    table = report.format_table(list(res.values()))
    assert "not yet available" in table and "error" in table
    with pytest.raises(ValueError, match="unknown verification case"):
        verification.run_cases(["C99"], tmp_path)
    # an id selects its variants too
    assert verification.select(["C8", "C1"]) == ["C8-active", "C8-passive", "C1"]
    assert verification.select(["C6"]) == ["C6", "C6-psi0"]


def test_every_registered_case_is_complete():
    """Every entry has a title, reference and bar text, and names a script in cases/."""
    for key, case in verification.CASES.items():
        assert case.id == key and case.title and case.reference and case.bar
        assert case.case_script.endswith(".py")
    for key in ("C1", "C2", "C3", "C4"):
        assert verification.CASES[key].script_path().is_file(), key


def test_large_png_is_reencoded_under_the_cap(tmp_path):
    """A noisy 900x900 PNG (~2.4 MB) is re-encoded under 200 KB and stays a PNG."""
    from PIL import Image

    rng = np.random.default_rng(0)
    src = tmp_path / "noise.png"
    Image.fromarray(rng.integers(0, 255, (900, 900, 3), dtype=np.uint8)).save(src)
    assert src.stat().st_size > report.MAX_PNG_BYTES
    dst = report._copy_png(src, tmp_path / "small.png")
    assert dst.stat().st_size <= report.MAX_PNG_BYTES and _is_png(dst)


@pytest.mark.slow
def test_verify_whole_registry(tmp_path):
    """Every registered case (fast overrides) meets its bar or is reported: exit code 0."""
    results = verification.run_cases(None, tmp_path / "runs")
    bad = [(r["id"], r["status"], r["message"]) for r in results
           if r["status"] in ("failed", "error")]
    assert not bad
    assert verification.exit_code(results) == 0
    md = report.write_report(results, tmp_path / "report").read_text()
    assert all(f"| {r['id']} |" in md for r in results)
