"""Case summaries: the CaseSummary dataclass, its JSON form and its round trip."""

import json
import math
from dataclasses import asdict, dataclass

import numpy as np
import pytest

from hybrid.io import CaseSummary, Check


@dataclass
class Parameters:
    q: float = 5.0  # [kPa]
    n: int = 3
    cells: str = "triangle"
    psi: float | None = None


def _summary(tmp_path):
    p = Parameters(n=4)
    checks = {"settlement": Check(0.0125, 0.0125, 1e-6, "m", "closed form"),
              "reported": Check(3, None, None, "-", "no reference"),
              "not_finite": Check(float("nan"), 1.0, 0.1, "deg", "no wedge found"),
              "infinite_bar": Check(2.0, 2.0, float("inf"))}
    summary = CaseSummary("demo (X1)", tmp_path / "demo", p, checks, {
        "cells": 16, "curve": {"settlement_m": np.linspace(0.0, 0.1, 3),
                               "pressure_kPa": [0.0, 1.5, np.float64(2.25)]},
        "K0": np.float64(0.42), "first_failure_time": None})
    summary["discrete"] = {"elements": np.int64(16), "final_settlement_m": 0.031,
                           "wedge_angle_deg": float("nan"), "stop": "rest"}
    return p, summary


def test_json_layout(tmp_path):
    """The JSON form: case, out, parameters, the sections given at construction, checks, then
    the sections added later; checks as dicts with error and passed; non-finite floats and
    numpy values made plain."""
    p, summary = _summary(tmp_path)
    path = summary.write(tmp_path / "demo" / "summary.json")
    data = json.loads(path.read_text())
    assert list(data) == ["case", "out", "parameters", "cells", "curve", "K0",
                          "first_failure_time", "checks", "discrete"]
    assert data["out"] == str(tmp_path / "demo") and data["parameters"] == asdict(p)
    assert data["checks"]["settlement"] == {**asdict(summary.checks["settlement"]),
                                            "error": 0.0, "passed": True}
    assert data["checks"]["not_finite"]["computed"] == "nan"
    assert data["checks"]["not_finite"]["error"] == "nan"
    assert data["checks"]["not_finite"]["passed"] is False
    assert data["checks"]["infinite_bar"]["bar"] == "inf"
    assert data["curve"]["settlement_m"] == [0.0, 0.05, 0.1] and data["K0"] == 0.42
    assert data["discrete"]["wedge_angle_deg"] == "nan"
    assert data == summary.to_json() == json.loads(json.dumps(summary.to_json()))


def test_round_trip(tmp_path):
    """write -> read gives the same fields, checks, parameters and sections (as JSON holds
    them), and writes the same file again."""
    p, summary = _summary(tmp_path)
    path = summary.write(tmp_path / "summary.json")
    back = CaseSummary.read(path)
    assert back.case == summary.case and back.out == summary.out
    assert back.parameters == summary.parameters == asdict(p)
    assert list(back.checks) == list(summary.checks)
    for name in ("settlement", "reported", "infinite_bar"):
        assert back.checks[name] == summary.checks[name], name
    nan = back.checks["not_finite"]
    assert isinstance(nan, Check) and math.isnan(nan.computed) and nan.passed is False
    assert back.checks["infinite_bar"].passed is True
    assert list(back.results) == list(summary.results)
    assert back.results["curve"]["settlement_m"] == [0.0, 0.05, 0.1]
    assert back.results["discrete"]["wedge_angle_deg"] == "nan"  # as written
    assert back.to_json() == summary.to_json() and list(back) == list(summary)
    again = back.write(tmp_path / "again.json")
    assert again.read_text() == path.read_text()
    # plain finite values come back equal as a whole
    plain = CaseSummary("plain", tmp_path, Parameters(), {"a": Check(1.0, 1.0, 0.0, "m")},
                        {"curve": {"x": [0.0, 1.0]}})
    plain["after"] = {"stop": "rest"}
    assert CaseSummary.read(plain.write(tmp_path / "plain.json")) == plain


def test_mapping_access(tmp_path):
    """The summary is a mapping over its top-level names: fields and sections."""
    _, summary = _summary(tmp_path)
    assert summary["case"] == "demo (X1)" and summary["checks"] is summary.checks
    assert summary["parameters"]["n"] == 4 and summary["discrete"]["stop"] == "rest"
    assert "curve" in summary and "checks" in summary and "handover" not in summary
    assert summary.get("handover") is None and summary.get("cells") == 16
    assert len(summary) == len(list(summary)) == 9
    summary.update({"handover": {"elements": 16},
                    "checks": {**summary["checks"], "extra": Check(1.0)}})
    assert list(summary)[-3:] == ["checks", "discrete", "handover"]
    assert "extra" in summary.checks
    del summary["handover"]
    assert "handover" not in summary.results
    with pytest.raises(KeyError, match="field"):
        del summary["checks"]
    with pytest.raises(ValueError, match="not sections"):
        CaseSummary("x", tmp_path, {}, results={"checks": {}})
    with pytest.raises(ValueError, match="not a case summary"):
        CaseSummary.from_json({"case": "x", "checks": {}})


def test_case_summary_round_trip(tmp_path, case):
    """A case's summary.json reads back into the summary its main returned."""
    summary = case("oedometer").main(out=tmp_path, nx=1, ny=4)
    assert isinstance(summary, CaseSummary) and summary.out == tmp_path
    back = CaseSummary.read(tmp_path / "summary.json")
    assert back.to_json() == summary.to_json()
    assert back.checks == summary.checks and back.parameters == summary.parameters
