"""Every figure the user docs quote matches the committed results file it comes from.

The files: ``docs/verification/results.json`` (``make verify``: ``hybrid verify --full
--update-docs``) and ``docs/summaries/*.json`` (``make docs``: the cases' ``summary.json``).
Each quote below is a passage of a doc with ``{}`` where a number stands; the passage must
occur in the doc (line breaks and runs of spaces count as one space) and each number must
equal its value to the rounding it is quoted with (half a unit of its last digit). A figure
the docs quote without a file behind it does not belong in them: rephrase.
"""

import dataclasses
import json
import math
import re
import statistics
from collections.abc import Callable
from functools import cache
from typing import Any

import pytest
from conftest import CASES, ROOT
from test_carsington import MESH_CHANGE

from hybrid import references as ref
from hybrid.discrete import biaxial as bx

NUMBER = r"([-+]?\d+(?: \d{3})*(?:\.\d+)?(?:e[-+]?\d+)?)"


@cache
def _json(name: str) -> dict[str, Any]:
    return json.loads((ROOT / name).read_text())


def h2() -> dict[str, Any]:
    return _json("docs/summaries/h2.json")


def _h2_far_boundary() -> list[float]:
    """The far side reflecting against transmitting (the default): time to rest and steps of
    each, then settlement and heave of each and their differences [%]; nan unless the two
    runs differ in that parameter only and both reached rest."""
    a, b = _json("docs/summaries/h2_reflecting.json"), h2()
    if ({k: v for k, v in a["parameters"].items() if k != "far_boundary"}
            != {k: v for k, v in b["parameters"].items() if k != "far_boundary"}
            or a["parameters"]["far_boundary"] != "reflecting"
            or b["parameters"]["far_boundary"] != "transmitting"
            or not a["discrete"]["stop"] == b["discrete"]["stop"] == "rest"):
        return [math.nan]
    da, db = a["discrete"], b["discrete"]
    out = [da["time_to_rest_s"], da["steps"], db["time_to_rest_s"], db["steps"]]
    for key in ("final_settlement_m", "max_heave_beside_footing_m"):
        out += [da[key], db[key], 100 * abs(da[key] - db[key]) / db[key]]
    return out


def h3() -> dict[str, Any]:
    return _json("docs/summaries/h3.json")


def h3_unstructured() -> dict[str, Any]:
    return _json("docs/summaries/h3_unstructured.json")


def d10() -> dict[str, Any]:
    return _json("docs/summaries/d10.json")


def carsington() -> dict[str, Any]:
    return _json("docs/summaries/carsington.json")


def _cars_stage(lift: int) -> dict[str, Any]:
    return carsington()["construction"]["stages"][lift - 1]


def carsington_last_lift() -> dict[str, Any]:
    return _json("docs/summaries/carsington_last_lift.json")


def _cars_collapse() -> list[float]:
    """The fine run's last lift height, the level carried, the collapsing part's top, the
    fraction of its weight carried [%] and the level that fraction reaches."""
    s = carsington_last_lift()
    c, last = s["construction"], s["construction"]["stages"][-1]
    tops = s["mesh"]["lift_tops_m_OD"]
    return [tops[-1] - tops[-2], c["fill_level_m_od"], last["top_m_OD"],
            100 * last["weight_placed"], last["fill_level_m_OD"]]


def _cars_node_a() -> dict[float, float]:
    return dict(map(tuple, carsington()["core_displacement_mm"]["by_fill_level"]))


def _node_a(name: str) -> list[float]:
    candidate = carsington()["core_displacement_mm"]["candidates"][name]
    return [*candidate["point_m"], *(dx for z, dx in candidate["by_fill_level"]
                                     if z in (190.0, 198.0))]


def r1(run: str) -> dict[str, Any]:
    return _json(f"docs/summaries/r1_{run}.json")


def _r1_row(run: str) -> list[float]:
    s = r1(run)
    d, r = s["deposit"], s["deposit"]["references"]
    return [s["parameters"]["aspect"], d["normalised_runout"],
            *[v for v in (r["rods2015_runout"], r["lube2005_runout"]) if v is not None],
            d["height_over_H0"], r["rods2015_height"], r["lube2005_height"],
            s["discrete"]["column_elements"], s["discrete"]["time_s"]]


def _r1_gap(run: str) -> float:
    d = r1(run)["deposit"]
    return 100.0 * (1.0 - d["normalised_runout"] / d["references"]["rods2015_runout"])


def _r1_packings(a: str) -> tuple[str, str, str]:
    """The three packings of an aspect ratio: L0 0.1 % shorter, as given, 0.1 % longer."""
    return f"a{a}_L0.1998", f"a{a}", f"a{a}_L0.2002"


def _r1_height_gap(run: str) -> float:
    """A run's final height against the rods' law [%] (+: higher)."""
    d = r1(run)["deposit"]
    return 100.0 * (d["height_over_H0"] / d["references"]["rods2015_height"] - 1.0)


def _h2_sample(name: str, width: float) -> list[float]:
    """Collapse [kPa], final settlement and heave [m] of an H2 run on the default or the
    structured 0.08 m mesh; a ValueError unless its half-width is within 0.1 % of ``width``
    and nothing else differs from its mesh's base run."""
    s = _json(f"docs/summaries/{name}.json")
    base = _json("docs/summaries/h2_structured.json" if s["parameters"]["structured"]
                 else "docs/summaries/h2.json")
    changed = {k for k, v in s["parameters"].items() if base["parameters"][k] != v}
    if not (changed <= {"width"} and abs(s["parameters"]["width"] / width - 1.0) <= 1.0001e-3):
        raise ValueError(f"{name}: changes {changed}")
    d = s["discrete"]
    return [s["continuum"]["collapse_pressure_kPa"], d["final_settlement_m"],
            d["max_heave_beside_footing_m"]]


def _h2_sample_spread() -> list[float]:
    """The largest spread [%] of the final settlement and of the heave over the width
    samples of each mesh; [] unless both stay below the structured mesh's excess over the
    default one (the words: the mesh type's, not chance)."""
    groups = (("h2_W4.7952", "h2"), ("h2_structured_W4.7952", "h2_structured",
                                      "h2_structured_W4.8048"))
    spread = [max(100.0 * _rel_spread([_h2_sample(n, 4.8)[k] for n in g]) for g in groups)
              for k in (1, 2)]
    excess = [100.0 * (_h2_sample("h2_structured", 4.8)[k] / _h2_sample("h2", 4.8)[k] - 1.0)
              for k in (1, 2)]
    return spread if all(sp < ex for sp, ex in zip(spread, excess)) else []


def _h2_perfect() -> list[float]:
    """H2's perfectly plastic collapse load on triangles and quadrilaterals of the default
    size and their difference [%]; [] unless the runs are what the words say (c_r = c, the
    cell shapes, the default size) and within the 3 % bar of a limit load."""
    t, q = (_json(f"docs/summaries/h2_{r}.json") for r in ("triangle_perfect", "perfect"))
    if not all(s["parameters"]["residual_cohesion"] == s["parameters"]["cohesion"]
               and s["parameters"]["fine"] == h2()["parameters"]["fine"] for s in (t, q)):
        return []
    if (t["parameters"]["cells"], q["parameters"]["cells"]) != ("triangle", "quadrilateral"):
        return []
    pt, pq = (s["continuum"]["collapse_pressure_kPa"] for s in (t, q))
    gap = 100.0 * abs(pt / pq - 1.0)
    return [pt, pq, gap] if gap <= 3.0 else []


@cache
def _h2_base() -> dict[str, Any]:
    """The default H2 run's parameters, with the case's defaults for keys newer than its
    summary (a run of another part names every key)."""
    from hybrid.case import load_case

    defaults = dataclasses.asdict(load_case(CASES / "footing_failure.py").Parameters())
    return {**defaults, **h2()["parameters"]}


#: H2 under settlement control (docs-h2-settlement): run name -> the parameters it changes from
#: the default run besides the control itself
H2_SETTLEMENT: dict[str, dict[str, Any]] = {"default": {}, "W4.8048": {"width": 4.8048},
                 "structured": {"structured": True}, "fine0.04": {"fine": 0.04},
                 "triangle_steps100": {"cells": "triangle", "continuum_steps": 100}}


def _h2_settlement(name: str) -> float:
    """Collapse [kPa] of the H2 run ``h2_settlement_<name>``; a ValueError unless it ran
    under settlement control to at most 0.1 m, continuum only, and changes from the default
    run exactly what ``H2_SETTLEMENT`` says."""
    s = _json(f"docs/summaries/h2_settlement_{name}.json")
    par, base = s["parameters"], _h2_base()
    own = {"continuum_control", "continuum_settlement", "discrete"}
    changed = {k: v for k, v in par.items() if k not in own and base.get(k) != v}
    if (changed != H2_SETTLEMENT[name] or par["continuum_control"] != "settlement"
            or par["continuum_settlement"] != 0.1 or par["discrete"]):
        raise ValueError(f"h2_settlement_{name}: changes {changed}")
    return s["continuum"]["collapse_pressure_kPa"]


def _h2_settlement_agreement() -> list[float]:
    """Spread of the four quadrilateral collapses under settlement control [%], the largest
    gap to the same mesh's load-controlled collapse [%] and the wider mesh's gap to the
    default [%]; [] unless the spread is within the 3 % bar and the load-controlled wider
    mesh has no summary (it stalls)."""
    quads = [_h2_settlement(n) for n in ("default", "W4.8048", "structured", "fine0.04")]
    spread = 100.0 * _rel_spread(quads)
    pairs = (("default", "h2"), ("structured", "h2_structured"), ("fine0.04", "h2_fine0.04"))
    gap = max(100.0 * abs(_h2_settlement(n) / _json(f"docs/summaries/{m}.json")["continuum"][
        "collapse_pressure_kPa"] - 1.0) for n, m in pairs)
    wider = 100.0 * abs(_h2_settlement("W4.8048") / _h2_settlement("default") - 1.0)
    return [spread, gap, wider] if spread <= 3.0 and _h2_load_stopped("W4.8048") else []


def _h2_rest(name: str) -> dict[str, Any]:
    """The discrete measures at rest of ``h2_settlement_<name>_rest``; a ValueError unless it
    is the settlement-controlled run of ``h2_settlement_<name>`` followed to rest."""
    s = _json(f"docs/summaries/h2_settlement_{name}_rest.json")
    par, base = s["parameters"], _h2_base()
    own = {"continuum_control", "continuum_settlement"}
    changed = {k: v for k, v in par.items() if k not in own and base.get(k) != v}
    if (changed != H2_SETTLEMENT[name] or par["continuum_control"] != "settlement"
            or s["discrete"]["stop"] != "rest"):
        raise ValueError(f"h2_settlement_{name}_rest: changes {changed}")
    return s["discrete"]


def _h2_rest_figures() -> list[float]:
    """Settlement and heave at rest under settlement control: the default quadrilaterals and
    their distance from the load-controlled run's [%], then the triangles and their change from
    the quadrilaterals [%] and the failed interfaces of both; [] unless the settlement's
    change across the cell shapes is within the 10 % bar and the heave's is not."""
    q, t, load = _h2_rest("default"), _h2_rest("triangle_steps100"), h2()["discrete"]
    keys = ("final_settlement_m", "max_heave_beside_footing_m")
    to_load = [100.0 * abs(q[k] / load[k] - 1.0) for k in keys]
    across = [100.0 * (1.0 - t[k] / q[k]) for k in keys]
    if not (abs(across[0]) <= 10.0 < abs(across[1])):
        return []
    return [q[keys[0]], q[keys[1]], *to_load, t[keys[0]], across[0], t[keys[1]], across[1],
            t["interfaces_failed"], q["interfaces_failed"]]


def _h2_load_stopped(name: str) -> bool:
    """Whether H2 under load control stalled on ``h2_load_<name>`` (its message kept)."""
    stopped = ROOT / f"docs/summaries/h2_load_{name}.stopped.txt"
    return stopped.exists() and "did not run away" in stopped.read_text()


def _h2_triangle_gap() -> list[float]:
    """The triangles' collapse under settlement control [kPa] and how far below the default
    quadrilaterals' it lies [%]; [] unless outside the 3 % bar (the words)."""
    q = _h2_settlement("triangle_steps100")
    gap = 100.0 * (1.0 - q / _h2_settlement("default"))
    return [q, gap] if gap > 3.0 else []


def _h2_settlement_stopped(name: str) -> bool:
    """Whether the H2 run ``h2_settlement_<name>`` stopped before the peak (its message kept,
    no summary)."""
    stopped = ROOT / f"docs/summaries/h2_settlement_{name}.stopped.txt"
    return (stopped.exists() and "did not fall" in stopped.read_text()
            and not (ROOT / f"docs/summaries/h2_settlement_{name}.json").exists())


#: H2 with Newton's retry of cycling increments (docs-h2-settlement): run name -> the
#: parameters it changes from the default run besides the retry
H2_HOLD: dict[str, dict[str, Any]] = {
    "default": {}, "W4.8048": {"width": 4.8048},
    "structured_fine0.04": {"structured": True, "fine": 0.04, "continuum_steps": 48},
    "settlement_structured": {"continuum_control": "settlement", "structured": True}}


def _h2_hold(name: str) -> dict[str, Any]:
    """The continuum entry of ``h2_hold_<name>``; a ValueError unless it ran continuum only
    with the retry and changes from the default run exactly what ``H2_HOLD`` says."""
    s = _json(f"docs/summaries/h2_hold_{name}.json")
    par, base = s["parameters"], _h2_base()
    own = {"continuum_hold_flipping", "discrete"}
    changed = {k: v for k, v in par.items() if k not in own and base.get(k) != v}
    if changed != H2_HOLD[name] or not par["continuum_hold_flipping"] or par["discrete"]:
        raise ValueError(f"h2_hold_{name}: changes {changed}")
    return s["continuum"]


def _stopped_at(name: str, before: str, says: str) -> float:
    """The number after ``before`` in the stop message ``docs/summaries/<name>.stopped.txt``;
    nan unless the message says ``says`` (a stall: "did not run away", "Newton stalled")."""
    f = ROOT / f"docs/summaries/{name}.stopped.txt"
    text = f.read_text() if f.exists() else ""
    m = re.search(re.escape(before) + r" ([-+]?\d+(?:\.\d+)?)", text) if says in text else None
    return float(m.group(1)) if m else math.nan


def _h2_hold_steps(name: str) -> int:
    """The increments of the H2 run ``h2_hold_<name>``."""
    return int(_json(f"docs/summaries/h2_hold_{name}.json")["parameters"]["continuum_steps"])


#: the load-controlled stop message of a ramp whose displacement did not run away
RAN_AWAY_NOT = "did not run away"


def _h2_hold_wider() -> list[float]:
    """With the retry, the wider mesh's collapse [kPa] and its distance from the default
    mesh's [%]; [] unless its plain load ramp stalls and the collapse is within 0.1 % of its
    settlement-controlled one (the words)."""
    q = _h2_hold("W4.8048")["collapse_pressure_kPa"]
    if not (_h2_load_stopped("W4.8048") and abs(q / _h2_settlement("W4.8048") - 1.0) < 1e-3):
        return []
    return [q, 100.0 * abs(q / h2()["continuum"]["collapse_pressure_kPa"] - 1.0)]


def _h2_hold_refined() -> list[float]:
    """With the retry, the refined structured mesh's collapse [kPa] and how far below the
    structured 0.08 m and the default meshes' it lies [%]; [] unless both within 3 %."""
    q = _h2_hold("structured_fine0.04")["collapse_pressure_kPa"]
    below = [100.0 * (1.0 - q / _json(f"docs/summaries/{m}.json")["continuum"][
        "collapse_pressure_kPa"]) for m in ("h2_structured", "h2")]
    return [q, *below] if all(0.0 < b <= 3.0 for b in below) else []


def _h2_hold_fine_stop() -> list[float]:
    """The refined unstructured mesh with the retry: the last step's rate of settlement over
    the first's; [] unless it stopped within 0.1 % of the plain ramp's collapse load, that
    rate below the collapse test's 10."""
    q = _stopped_at("h2_hold_fine0.04", "load factor", RAN_AWAY_NOT)
    ratio = _stopped_at("h2_hold_fine0.04", "of the last step", RAN_AWAY_NOT)
    plain = _json("docs/summaries/h2_fine0.04.json")["continuum"]["collapse_pressure_kPa"]
    return [ratio] if abs(q / plain - 1.0) < 1e-3 and ratio < 10.0 else []


def _calibration_check() -> list[float]:
    """R1's calibration with its three check packings: the seven's largest range at one
    contact angle [deg], the largest move of the mean curve [deg], the contact angle for
    19.8 deg from the four and from the seven [deg]; [] unless that shift is below a quarter
    of the four's smallest standard error (far inside the curve's uncertainty) and the
    seven's range exceeds the four's (more widely still)."""
    pooled = tuple((c, a + b) for (c, a), (d, b) in zip(bx.CALIBRATION, bx.CALIBRATION_CHECK)
                   if c == d and len(b) == len(bx.CHECK_PACKINGS))
    if len(pooled) != len(bx.CALIBRATION):
        return []
    spans = [max(b) - min(b) for _, b in pooled]
    moves = [abs(statistics.fmean(b) - statistics.fmean(a))
             for (_, a), (_, b) in zip(bx.CALIBRATION, pooled)]
    # the four's standard error in bulk angle, as contact angle through the curve's slope
    slope = (bx.bulk_friction(15.0) - bx.bulk_friction(10.0)) / 5.0
    error = min(statistics.stdev(a) / math.sqrt(len(a)) for _, a in bx.CALIBRATION) / slope
    four, seven = bx.contact_friction(19.8), bx.contact_friction(19.8, pooled)
    wider = max(spans) > max(max(a) - min(a) for _, a in bx.CALIBRATION)
    return ([max(spans), max(moves), four, seven] if abs(seven - four) < 0.25 * error
            and wider else [])


#: H3's backfill lengths [m] of the runs on the 0.5 m meshes (``make docs``: H3_LENGTHS and 20)
H3_LENGTHS = (19.96, 19.97, 19.98, 19.99, 20.0, 20.01, 20.02, 20.03, 20.04)
#: and on the 0.25 m meshes, structured and unstructured, and the 0.125 m grid (``make docs``:
#: docs-h3-d10)
H3_REFINED_LENGTHS = (19.96, 19.98, 20.0, 20.02, 20.04)
#: the grid refined once more, to 0.125 m (five runs, H3_REFINED_LENGTHS)
H3_FINEST = "h3_size0.125"


def _h3_runs(stem: str, lengths: tuple[float, ...] = H3_LENGTHS) -> list[dict[str, Any]]:
    """H3's discrete summaries of one mesh (``stem``: "h3", "h3_unstructured", "h3_size0.25",
    "h3_unstructured_size0.25", "h3_size0.125")
    with the backfill ``lengths`` long [m], the 20 m run the mesh's own summary; ValueError
    unless each run differs from that one in its length alone, the one named."""
    base = _json(f"docs/summaries/{stem}.json")["parameters"]
    out = []
    for length in lengths:
        s = _json(f"docs/summaries/{stem}{'' if length == 20.0 else f'_L{length:g}'}.json")
        p = s["parameters"]
        if p["length"] != length or {**p, "length": 0} != {**base, "length": 0}:
            raise ValueError(f"{stem} at {length} m is not the mesh's run at that length")
        out.append(s["discrete"])
    return out


def _h3_runouts(stem: str, lengths: tuple[float, ...] = H3_LENGTHS) -> list[float]:
    return [d["runout_m"] for d in _h3_runs(stem, lengths)]


def _h3_row_runs(stem: str, lengths: tuple[float, ...] = H3_LENGTHS) -> list[float]:
    """One row of the table of runs: each run-out [m], their mean and standard deviation."""
    r = _h3_runouts(stem, lengths)
    return [*r, statistics.mean(r), statistics.stdev(r)]


def _h3_scatter() -> list[float]:
    """H3's run-out scatter on the grid and the unstructured mesh [%] (largest over smallest
    of the nine runs), then the wedge's [deg] on each."""
    runs = [_h3_runs(stem) for stem in ("h3", "h3_unstructured")]
    return ([100.0 * _rel_spread([d["runout_m"] for d in r]) for r in runs]
            + [max(d["wedge_angle_deg"] for d in r) - min(d["wedge_angle_deg"] for d in r)
               for r in runs])


def _h3_across() -> list[float]:
    """The unstructured mesh's mean run-out short of the grid's [%], the two means [m], the
    standard error of that shortfall [%] (first order, from the runs' standard deviations),
    the shortfall in standard errors from none and from the 10 % bar; [] unless it lies
    beyond the bar and more than three standard errors from none (the words)."""
    s = _h3_runouts("h3")
    mu, change, se = _h3_mean_change(s, _h3_runouts("h3_unstructured"))
    short = -change
    if not (short > 10.0 and short / se > 3.0):
        return []
    return [short, mu, statistics.mean(s), se, short / se, (short - 10.0) / se]


def _h3_mean_change(coarse: list[float], fine: list[float]) -> list[float]:
    """The mean of the ``fine`` runs [m], its change from the mean of the ``coarse`` ones [%]
    and that change's standard error [%] (first order, from the runs' standard deviations)."""
    mf, mc = statistics.mean(fine), statistics.mean(coarse)
    se = 100.0 * mf / mc * math.hypot(statistics.stdev(fine) / mf / math.sqrt(len(fine)),
                                      statistics.stdev(coarse) / mc / math.sqrt(len(coarse)))
    return [mf, pct(mf, mc), se]


def _h3_refined_means() -> list[float]:
    """The 0.25 m grid's mean run-out over its five runs [m], its change from the 0.5 m grid's
    mean over nine [%] and that change's standard error [%]; the same for the unstructured
    meshes; the unstructured run at 20 m's change [%]; the unstructured runs' standard
    deviations at 0.25 and 0.5 m [m]. [] unless both means' changes are within the 10 % bar,
    the unstructured one by less than a standard error, and that single run's beyond it (the
    words)."""
    grid = _h3_mean_change(_h3_runouts("h3"), _h3_runouts("h3_size0.25", H3_REFINED_LENGTHS))
    fine = _h3_runouts("h3_unstructured_size0.25", H3_REFINED_LENGTHS)
    coarse = _h3_runouts("h3_unstructured")
    unstructured = _h3_mean_change(coarse, fine)
    one = pct(*(_json(f"docs/summaries/{n}.json")["discrete"]["runout_m"]
                for n in ("h3_unstructured_size0.25", "h3_unstructured")))
    if (abs(grid[1]) > 10.0 or not 0.0 < 10.0 - abs(unstructured[1]) < unstructured[2]
            or abs(one) <= 10.0):
        return []
    return [*grid, *unstructured, abs(one), statistics.stdev(fine), statistics.stdev(coarse)]


def _h3_refined_across() -> list[float]:
    """On the 0.25 m meshes: the unstructured mesh's five-run mean short of the grid's [%], the
    two means [m], that shortfall's standard error [%], its distance from the 10 % bar and
    from none in standard errors; the run at 20 m on each: the unstructured one's shortfall
    [%] and the two run-outs [m]. [] unless the means' shortfall is within the bar by more
    than one standard error and less than two from none, and the single pair's beyond the
    bar (the words)."""
    grid = _h3_runouts("h3_size0.25", H3_REFINED_LENGTHS)
    mean, change, se = _h3_mean_change(grid, _h3_runouts("h3_unstructured_size0.25",
                                                         H3_REFINED_LENGTHS))
    pair = [_json(f"docs/summaries/{n}.json")["discrete"]["runout_m"]
            for n in ("h3_unstructured_size0.25", "h3_size0.25")]
    pair_short = 100.0 * (1.0 - pair[0] / pair[1])
    if not ((10.0 + change) / se > 1.0 and -change / se < 2.0 and pair_short > 10.0):
        return []
    return [-change, mean, statistics.mean(grid), se, (10.0 + change) / se, -change / se,
            pair_short, *pair]


def _h3_thrust(name: str) -> float:
    """An H3 run's active thrust in the continuum [kN/m]."""
    return _json(f"docs/summaries/{name}.json")["checks"]["active_thrust"]["computed"]


def _h3_thrusts() -> list[float]:
    """H3's active thrust [kN/m] on the unstructured 0.5 m mesh, the grid, the 0.25 m grid and
    the 0.25 m unstructured mesh."""
    return [_h3_thrust(n)
            for n in ("h3_unstructured", "h3", "h3_size0.25", "h3_unstructured_size0.25")]


def _cars_samples(size: str) -> list[dict[str, Any]]:
    """Carsington's design-height softening runs on one mesh (``size``: "" for 6 m, "_size4",
    "_size3") with the yellow clay 29.97, 30 and 30.03 m long: their discrete summaries; a
    ValueError unless the runs are what the table says."""
    runs = [_json(f"docs/summaries/carsington_design_height_softening{size}{tail}.json")
            for tail in ("_Y29.97", "", "_Y30.03")]
    if [r["parameters"]["yellow_clay_length"] for r in runs] != [29.97, 30.0, 30.03] or len(
            {r["parameters"]["size"] for r in runs}) != 1:
        raise ValueError(f"carsington_design_height_softening{size}*: not the three lengths")
    return [r["discrete"] for r in runs]


def _cars_sample_spreads() -> list[float]:
    """The toe's and then the crest drop's scatter [%] on the 6, 4 and 3 m meshes (largest
    over smallest of three runs), the toe's three-run means on the 4 and 3 m meshes [m] and
    their difference [%]; [] unless that difference exceeds both meshes' scatter (the
    words)."""
    toe = [100.0 * _rel_spread([d["toe_runout_m"] for d in _cars_samples(z)])
           for z in ("", "_size4", "_size3")]
    crest = [100.0 * _rel_spread([d["crest_drop_m"] for d in _cars_samples(z)])
             for z in ("", "_size4", "_size3")]
    means = [sum(d["toe_runout_m"] for d in _cars_samples(z)) / 3.0 for z in ("_size4", "_size3")]
    step = 100.0 * _rel_spread(means)
    return toe + crest + means + [step] if step > max(toe[1:]) else []


def _r1_variant(run: str, key: str, value: float) -> list[float]:
    """(L_inf - L0) / L0 and H_inf / H0 of R1's run ``a1_<run>`` and ``a2_<run>``, which
    change the case parameter ``key`` to ``value`` (the row's words) and nothing else."""
    out = []
    for a in ("1", "2"):
        s, base = r1(f"a{a}_{run}"), r1(f"a{a}")
        changed = {k for k, v in s["parameters"].items() if base["parameters"][k] != v}
        if changed != {key} or s["parameters"][key] != value:
            raise ValueError(f"r1_a{a}_{run} changes {changed}, not {key} = {value} alone")
        out += [s["deposit"]["normalised_runout"], s["deposit"]["height_over_H0"]]
    return out


def _r1_moved() -> list[float]:
    """The largest change of R1's run-out [%] at a = 1 and 2 when the contact damping or the
    grains' stiffness changes (``_r1_variant``), against the case's run."""
    return [max(abs(_r1_change(a, v)) for v in ("zeta0.1", "zeta0.6", "E8400"))
            for a in ("1", "2")]


def _r1_scatter(a: str) -> float:
    """The run-out's scatter [%] over R1's three packings at aspect ratio ``a``."""
    return 100.0 * _rel_spread([r1(run)["deposit"]["normalised_runout"]
                                for run in _r1_packings(a)])


def _r1_damping_moves() -> list[float]:
    """The quote on the restitution and the stiffness: their largest changes of the run-out
    and one packing's scatter at a = 1 and 2 [%]; [] unless at a = 1 the change exceeds the
    scatter and at a = 2 it is within 15 % of it."""
    moved, scatter = _r1_moved(), [_r1_scatter(a) for a in ("1", "2")]
    if moved[0] > scatter[0] and abs(moved[1] / scatter[1] - 1.0) <= 0.15:
        return moved + scatter
    return []


def _r1_angle_moves() -> list[float]:
    """The quote on the contact angle: the run-out's change [%] at 2 deg less and more than
    the calibrated angle and its gap to the rods, at a = 1 then 2, then the most damped
    contacts' change at a = 2; [] unless the angle moves it most at a = 1, the most damped
    contacts most at a = 2, and the signs are those of the words (less: further, beyond the
    rods; more: shorter, at a = 1 short of the rods and at a = 2 beyond)."""
    up, down = (lambda a: _r1_change(a, "phic9.1")), (lambda a: _r1_change(a, "phic13.1"))
    gap = _r1_gap
    if (_r1_most("1") == "phic9.1" and _r1_most("2") == "zeta0.6"
            and up("1") > 0.0 > down("1") and up("2") > 0.0 > down("2")
            and gap("a1_phic9.1") < 0.0 < gap("a1_phic13.1")
            and gap("a2_phic9.1") < 0.0 and gap("a2_phic13.1") < 0.0):
        return [up("1"), -gap("a1_phic9.1"), -down("1"), gap("a1_phic13.1"),
                up("2"), -down("2"), -gap("a2_phic9.1"), -gap("a2_phic13.1"),
                -_r1_change("2", "zeta0.6")]
    return []


def _r1_heights_ends() -> bool:
    """Whether R1's final height is lowest at 2 deg less than the calibrated contact angle
    and highest at 2 deg more, at a = 1 and 2 (the words of the quote)."""
    for a in ("1", "2"):
        h = [r1(f"a{a}{run}")["deposit"]["height_over_H0"]
             for run in ("_phic9.1", "", "_phic12.1", "_phic13.1")]
        if not h[0] < min(h[1:3]) <= max(h[1:3]) < h[3]:
            return False
    return True


def _r1_change(a: str, run: str) -> float:
    """Change of R1's run-out [%] in run ``a<a>_<run>`` from the case's run at that a."""
    return 100.0 * (r1(f"a{a}_{run}")["deposit"]["normalised_runout"]
                    / r1(f"a{a}")["deposit"]["normalised_runout"] - 1.0)


def _r1_most(a: str) -> str:
    """The assumed-parameter run that moves R1's run-out most at aspect ratio ``a``."""
    return max(("zeta0.1", "zeta0.6", "E8400", "phic9.1", "phic12.1", "phic13.1"),
               key=lambda run: abs(_r1_change(a, run)))


def _r1_angle_spans() -> list[float]:
    """How far R1's runs at 2 deg less and more than the calibrated contact angle differ [%]:
    run-out at a = 1 and 2, then final height; [] unless at each aspect ratio the run-out's
    difference exceeds the difference between the two contact damping ratios tried and the
    stiffer grains' change, and the height's is about as large, at least 0.8 of it (the words
    of the quote)."""
    spans = [100.0 * _rel_spread([r1(f"a{a}_phic{c}")["deposit"][k] for c in (9.1, 13.1)])
             for k in ("normalised_runout", "height_over_H0") for a in ("1", "2")]
    others = [max(100.0 * _rel_spread([r1(f"a{a}_zeta{z}")["deposit"]["normalised_runout"]
                                       for z in (0.1, 0.6)]), abs(_r1_change(a, "E8400")))
              for a in ("1", "2")]
    if all(spans[i] > others[i] and spans[i + 2] >= 0.8 * spans[i] for i in (0, 1)):
        return spans
    return []


def _r1_differ_only_in(run: str, base: str, key: str) -> bool:
    """Whether R1's runs ``run`` and ``base`` have the same parameters but for ``key``."""
    def rest(name: str) -> dict[str, Any]:
        # runs made before the floor could be chosen had the flat one (the same mesh)
        return {k: v for k, v in {"floor": "flat", **r1(name)["parameters"]}.items()
                if k != key}
    return rest(run) == rest(base)


def _bui_runout() -> float | None:
    """Bui et al.'s measured (L_inf - L0) / L0 (the end of the digitised final surface); None
    unless R1's a = 0.5 run is their column (the same L0)."""
    bui = ref.bui2008_collapse()
    if r1("a0.5")["parameters"]["length"] != bui.length:
        return None
    return ref.bui2008_final_surface()[-1][0] / bui.length - 1.0


def _r1_floor() -> list[float]:
    """R1 on the rough floor against the flat one: the run-out's shortening at a = 0.5, 1, 2 [%];
    [] unless the runs differ in the floor alone, each shortening is more than twice the 15 %
    bar and more than one packing's scatter, the height moves less than the run-out, the
    floor moves the run-out (larger over smaller) about as far as the +-2 deg contact angles
    do at a = 1 (within a tenth) and further at a = 2, and the rods (Bui's surface at
    a = 0.5) lie between the two floors (the words of the quote)."""
    same = all(_r1_differ_only_in(f"a{a}_rough", f"a{a}", "floor")
               and r1(f"a{a}_rough")["parameters"]["floor"] == "rough"
               for a in ("0.5", "1", "2"))
    flat = {a: r1(f"a{a}")["deposit"] for a in ("0.5", "1", "2")}
    rough = {a: r1(f"a{a}_rough")["deposit"] for a in ("0.5", "1", "2")}
    height_less = all(abs(rough[a]["height_over_H0"] / flat[a]["height_over_H0"] - 1.0)
                      < 1.0 - rough[a]["normalised_runout"] / flat[a]["normalised_runout"]
                      for a in ("0.5", "1", "2"))
    short = [100.0 * (1.0 - rough[a]["normalised_runout"] / flat[a]["normalised_runout"])
             for a in ("0.5", "1", "2")]
    scatter = [100.0 * _rel_spread([r1(run)["deposit"]["normalised_runout"]
                                    for run in _r1_packings(a)]) for a in ("0.5", "1", "2")]
    floor = {a: 100.0 * _rel_spread([flat[a]["normalised_runout"],
                                     rough[a]["normalised_runout"]]) for a in ("1", "2")}
    angle = {a: 100.0 * _rel_spread([r1(f"a{a}_phic{c}")["deposit"]["normalised_runout"]
                                     for c in (9.1, 13.1)]) for a in ("1", "2")}
    bui = ref.bui2008_final_surface()[-1][0]
    between = (all(rough[a]["normalised_runout"] < flat[a]["references"]["rods2015_runout"]
                   < flat[a]["normalised_runout"] for a in ("1", "2"))
               and rough["0.5"]["runout_m"] < bui < flat["0.5"]["runout_m"])
    if (same and height_less and between
            and all(v > 30.0 and v > w for v, w in zip(short, scatter))
            and floor["2"] > 1.1 * angle["2"] and abs(floor["1"] / angle["1"] - 1.0) <= 0.1):
        return short
    return []


def _r1_grain_growth(tail: str, a: str) -> list[float]:
    """L_inf's growth [%] at ``a`` from grains of L0 / 10 to L0 / 20, from L0 / 20 to L0 / 30,
    and from L0 / 10 to L0 / 30, of the runs ``r1_a<a>_nx<n><tail>``."""
    L = [r1(f"a{a}{n}{tail}")["deposit"]["runout_m"] for n in ("_nx10", "", "_nx30")]
    return [100.0 * (L[1] / L[0] - 1.0), 100.0 * (L[2] / L[1] - 1.0), 100.0 * (L[2] / L[0] - 1.0)]


def _r1_fine(a: str) -> dict[str, str]:
    """R1's runs on grains finer than L0 / 30 at ``a`` by name ("40" the L0 / 40 packing as
    given, "40-" and "40+" with L0 0.1 % shorter and longer, "50", "60", "60-", "60+"), those
    committed; ValueError unless each differs from the L0 / 20 run in nx (and the L0 variants
    from the run of their grain size in their length) alone."""
    runs = {"30": f"a{a}_nx30", "40": f"a{a}_nx40", "40-": f"a{a}_nx40_L0.1998",
            "40+": f"a{a}_nx40_L0.2002", "50": f"a{a}_nx50", "60": f"a{a}_nx60",
            "60-": f"a{a}_nx60_L0.1998", "60+": f"a{a}_nx60_L0.2002"}
    runs = {k: v for k, v in runs.items() if (ROOT / f"docs/summaries/r1_{v}.json").exists()}
    for k, run in runs.items():
        same = (_r1_differ_only_in(run, f"a{a}_nx{k[:2]}", "length") if k[-1] in "-+"
                else _r1_differ_only_in(run, f"a{a}", "nx"))
        if not same:
            raise ValueError(f"r1_{run} differs from its base in more than the run's name says")
    return runs


def _r1_fine_deposit(a: str, k: str) -> dict[str, Any]:
    """The deposit of the run ``k`` (a key of :func:`_r1_fine`) at ``a``."""
    return r1(_r1_fine(a)[k])["deposit"]


def _r1_fine_runout(a: str, k: str) -> float:
    return _r1_fine_deposit(a, k)["runout_m"]


def _r1_fine_row(a: str, keys: tuple[str, ...]) -> list[float]:
    """(L_inf - L0) / L0 and H_inf / H0 of the runs ``keys`` at ``a``: a row of the table."""
    return [v for k in keys for v in (_r1_fine_deposit(a, k)["normalised_runout"],
                                      _r1_fine_deposit(a, k)["height_over_H0"])]


def _r1_fine_converged() -> list[float]:
    """At a = 0.5 and 1: L_inf's change from L0 / 30 to L0 / 60 (the L0 = 0.2 m run) [%], its
    change from L0 / 10 to L0 / 20 [%], the three L0 / 40 packings' scatter (largest over
    smallest) [%], their mean [m] and its difference from the L0 / 60 run [%], each at a = 0.5
    then 1; [] unless every change from L0 / 30 to a run at L0 / 60 is within the 10 % bar and,
    at a = 0.5, the runs on finer grains end within the L0 / 40 packings' range (the words: the
    run-out stops growing beyond L0 / 40, within one packing's scatter; at a = 1 the
    packings' means: :func:`_r1_fine_packings`)."""
    out: dict[str, list[float]] = {}
    for a in ("0.5", "1"):
        forty = [_r1_fine_runout(a, k) for k in ("40-", "40", "40+")]
        mean = statistics.mean(forty)
        l60 = _r1_fine_runout(a, "60")
        out[a] = [100.0 * abs(l60 / _r1_fine_runout(a, "30") - 1.0),
                  _r1_grain_growth("", a)[0],
                  100.0 * _rel_spread(forty), mean, 100.0 * abs(mean / l60 - 1.0)]
        if max(100.0 * _rel_spread([_r1_fine_runout(a, "30"), _r1_fine_runout(a, k)])
               for k in _r1_fine(a) if k[:2] == "60") > 10.0:
            return []
    finer = [_r1_fine_runout("0.5", k) for k in ("50", "60")]
    forty = [_r1_fine_runout("0.5", k) for k in ("40-", "40", "40+")]
    if not all(min(forty) <= v <= max(forty) for v in finer):
        return []
    return [out[a][i] for i in range(5) for a in ("0.5", "1")]


def _r1_fine_packings() -> list[float]:
    """At a = 1: the three L0 / 60 packings' mean L_inf [m], its difference from the three
    L0 / 40 packings' mean [%], that mean [m] and the L0 / 60 packings' scatter [%]; [] unless
    the difference is within the L0 / 40 packings' scatter (the words: the run-out stops
    growing within one packing's scatter)."""
    sixty = [_r1_fine_runout("1", k) for k in ("60-", "60", "60+")]
    forty = [_r1_fine_runout("1", k) for k in ("40-", "40", "40+")]
    change = pct(statistics.mean(sixty), statistics.mean(forty))
    if abs(change) > 100.0 * _rel_spread(forty):
        return []
    return [statistics.mean(sixty), change, statistics.mean(forty), 100.0 * _rel_spread(sixty)]


def _r1_fine_height_trend() -> list[float]:
    """At a = 1: the final height's fall from the three L0 / 40 packings' mean to the three
    L0 / 60 packings' [%], the two means, the L0 / 60 and the L0 / 40 packings' ranges, the
    L0 / 60 packings' scatter [%]; [] unless (the words) at both aspect ratios every L0 / 60
    run lies below every L0 / 40 packing, at a = 1 the L0 / 40 mean is not below the L0 / 30
    run, and the fall is within the 10 % bar and no larger than the L0 / 60 packings' scatter
    (rounded)."""
    h40 = [_r1_fine_deposit("1", k)["height_over_H0"] for k in ("40-", "40", "40+")]
    h60 = [_r1_fine_deposit("1", k)["height_over_H0"] for k in ("60-", "60", "60+")]
    fall = -pct(statistics.mean(h60), statistics.mean(h40))
    scatter = 100.0 * _rel_spread(h60)
    for a in ("0.5", "1"):
        forty = [_r1_fine_deposit(a, k)["height_over_H0"] for k in ("40-", "40", "40+")]
        sixty = [_r1_fine_deposit(a, k)["height_over_H0"] for k in _r1_fine(a) if k[:2] == "60"]
        if max(sixty) >= min(forty):
            return []
    if statistics.mean(h40) < _r1_fine_deposit("1", "30")["height_over_H0"]:
        return []
    if not 0.0 < fall <= 10.0 or round(fall, 1) > round(scatter, 1):
        return []
    return [fall, statistics.mean(h40), statistics.mean(h60), min(h60), max(h60), min(h40),
            max(h40), scatter]


def _r1_fine_beyond() -> list[float]:
    """The converged run-out against the experiments: at L0 / 60, a = 0.5: (L_inf - L0) / L0,
    Bui et al.'s, the two L_inf [m] and how much further [%]; a = 1: (L_inf - L0) / L0, how far
    beyond the rods [%] and the rods' value, then the L0 / 40 packings' least and most [%];
    [] unless every one misses the 15 % bar."""
    bui = _bui_runout()
    if bui is None:
        return []
    d5 = _r1_fine_deposit("0.5", "60")
    L0 = r1("a0.5")["parameters"]["length"]
    bui_L = (1.0 + bui) * L0
    rods = r1("a1")["deposit"]["references"]["rods2015_runout"]
    sixty = [_r1_fine_deposit("1", k)["normalised_runout"] for k in ("60-", "60", "60+")]
    gaps = [pct(_r1_fine_deposit("1", k)["normalised_runout"], rods)
            for k in ("40-", "40", "40+", "60-", "60", "60+")]
    far = pct(d5["runout_m"], bui_L)
    if min(gaps) <= 15.0 or far <= 15.0:
        return []
    return [d5["normalised_runout"], bui, d5["runout_m"], bui_L, far, min(sixty), max(sixty),
            min(gaps[3:]), max(gaps[3:]), rods, min(gaps[:3]), max(gaps[:3])]


def _r1_fine_h(a: str) -> list[float]:
    """H_inf / H0 of the L0 / 40 and L0 / 60 runs at ``a`` (the packings committed)."""
    return [_r1_fine_deposit(a, k)["height_over_H0"] for k in _r1_fine(a)
            if k[:2] in ("40", "60")]


def _r1_fine_heights() -> list[float]:
    """Final heights on finer grains: a = 1, the least and most of L0 / 40 and L0 / 60 (three
    packings each) and the rods'; a = 0.5 at L0 / 60 and the rods'; [] unless a = 1's are all
    within 15 % of the rods (the words)."""
    h = _r1_fine_h("1")
    rods = r1("a1")["deposit"]["references"]["rods2015_height"]
    if max(abs(pct(v, rods)) for v in h) > 15.0:
        return []
    return [min(h), max(h), rods, _r1_fine_deposit("0.5", "60")["height_over_H0"],
            r1("a0.5")["deposit"]["references"]["rods2015_height"]]


def _r1_rough_grain_size() -> dict[str, dict[str, list[float]]]:
    """``_r1_grain_growth`` on the rough and the flat floor ("rough", "flat") at a = 0.5 and 1;
    {} unless the runs differ from the L0 / 20 rough ones in nx alone, from L0 / 10 to L0 / 30
    the rough floor's growth is smaller than the flat floor's at both aspect ratios, and a step
    of the rough floor's is above the 10 % bar at both (the words: part of the dependence taken
    out, not enough for the bar)."""
    same = all(_r1_differ_only_in(f"a{a}_nx{n}_rough", f"a{a}_rough", "nx")
               for a in ("0.5", "1") for n in (10, 30))
    growth = {floor: {a: _r1_grain_growth(tail, a) for a in ("0.5", "1")}
              for floor, tail in (("rough", "_rough"), ("flat", ""))}
    rough, flat = growth["rough"], growth["flat"]
    if same and all(rough[a][2] < flat[a][2] and max(rough[a][:2]) > 10.0
                    for a in ("0.5", "1")):
        return growth
    return {}


def _r1_rough_fine() -> dict[str, list[float]]:
    """The rough floor on grains of L0 / 20 to L0 / 60 where committed: L_inf [m] by grain
    size ("20", "30", "40", "60") at a = 0.5 and 1; ValueError unless each differs from the
    L0 / 20 rough run in nx alone."""
    out: dict[str, list[float]] = {}
    for a in ("0.5", "1"):
        runs = {"20": f"a{a}_rough", "30": f"a{a}_nx30_rough", "40": f"a{a}_nx40_rough",
                "60": f"a{a}_nx60_rough"}
        out[a] = []
        for k, run in runs.items():
            if not (ROOT / f"docs/summaries/r1_{run}.json").exists():
                continue
            if k != "20" and not _r1_differ_only_in(run, f"a{a}_rough", "nx"):
                raise ValueError(f"r1_{run} differs from r1_a{a}_rough in more than nx")
            out[a].append(r1(run)["deposit"]["runout_m"])
    return out


def _r1_rough_growth() -> list[float]:
    """The rough floor's L_inf at L0 / 40 and 60 and its growth from the size before [%], at
    a = 0.5 then 1; [] unless every step from L0 / 20 to L0 / 60 grows (the words)."""
    r = _r1_rough_fine()
    g = {a: [100.0 * (r[a][i + 1] / r[a][i] - 1.0) for i in range(len(r[a]) - 1)]
         for a in ("0.5", "1")}
    if not all(len(r[a]) == 4 and min(g[a]) > 0.0 for a in ("0.5", "1")):
        return []
    return [r["0.5"][2], r["0.5"][3], g["0.5"][1], g["0.5"][2],
            r["1"][2], r["1"][3], g["1"][1], g["1"][2]]


def _r1_rough_vs_bui() -> list[float]:
    """a = 0.5 on grains of L0 / 60: the rough floor's shortfall from Bui et al.'s measured
    L_inf [%], the two L_inf [m], the flat floor's excess over it [%] and its L_inf [m]; []
    unless the rough one is short of it by at most 5 % and the flat one 28 to 40 % beyond (the
    words: "short of ..., within ... overshoots it by a third")."""
    bui = _bui_runout()
    if bui is None:
        return []
    measured = (1.0 + bui) * r1("a0.5")["parameters"]["length"]
    rough, flat = _r1_rough_fine()["0.5"][3], _r1_fine_runout("0.5", "60")
    short, far = -pct(rough, measured), pct(flat, measured)
    if not (0.0 < short <= 5.0 and 28.0 <= far <= 40.0):
        return []
    return [short, rough, measured, far, flat]


def _r1_rough_vs_rods() -> list[float]:
    """a = 1 on grains of L0 / 40: the rough floor's (L_inf - L0) / L0, its shortfall from the
    rods [%] and the rods', the flat floor's least and most over three packings and their
    excess [%]; then on grains of L0 / 60 the rough floor's, its shortfall, the flat floor's
    least and most over three packings and their excess; [] unless the rods lie between the
    floors on both grain sizes."""
    rods = r1("a1")["deposit"]["references"]["rods2015_runout"]
    rough = r1("a1_nx40_rough")["deposit"]["normalised_runout"]
    flat = [_r1_fine_deposit("1", k)["normalised_runout"] for k in ("40-", "40", "40+")]
    rough60 = r1("a1_nx60_rough")["deposit"]["normalised_runout"]
    flat60 = [_r1_fine_deposit("1", k)["normalised_runout"] for k in ("60-", "60", "60+")]
    if not (rough < rods < min(flat) and rough60 < rods < min(flat60)):
        return []
    return [rough, -pct(rough, rods), rods, min(flat), max(flat), pct(min(flat), rods),
            pct(max(flat), rods), rough60, -pct(rough60, rods), min(flat60), max(flat60),
            pct(min(flat60), rods), pct(max(flat60), rods)]


def _restitution(zeta: float) -> float:
    """Coefficient of restitution of a linear contact of damping ratio ``zeta``."""
    return math.exp(-math.pi * zeta / math.sqrt(1.0 - zeta * zeta))


def verify(case: str) -> dict[str, Any]:
    """The case's entry of the committed verification results, rows by name."""
    (entry,) = [c for c in _json("docs/verification/results.json")["cases"] if c["id"] == case]
    return {"rows": {r["name"]: r for r in entry["rows"]}, "stats": entry["stats"]}


def row(case: str, name: str, key: str = "computed") -> float:
    return verify(case)["rows"][name][key]


def pct(computed: float, reference: float) -> float:
    """Signed difference in % of the reference."""
    return 100.0 * (computed - reference) / reference


def _wedge(mark: str, key: str) -> float:
    return h3()["discrete"]["moving_zone_back_by_face_movement_m"][mark][key]


Quote = tuple[str, str, Callable[[], list[float]]]

SOFT_ROW = "| {} | {} | {} | {} | lift {} (to {}), {} % | {} | {} | {} | {} |"
# the softening analysis's five runs on each of these meshes [m]: the yellow clay 35.94 to
# 36.06 m long (the 36 m run is the table's)
SOFT_SAMPLE_SIZES = ("4", "3", "2.5", "2")
SOFT_SAMPLE_LENGTHS = (35.94, 35.97, 36.0, 36.03, 36.06)


QUOTES: list[Quote] = [
    # --- README: the demo -------------------------------------------------------------------
    ("README.md", "a strip footing (B = {} m, c = {} kPa, phi = {} deg)",
     lambda: [h2()["parameters"][k] for k in ("footing_width", "cohesion", "phi")]),
    ("README.md", "the pressure is raised to {} kPa and held until the footing has settled {} m",
     lambda: [h2()["parameters"]["pressure"], h2()["parameters"]["target_settlement"]]),
    # --- docs/hybrid.md: options of the hybrid cases ----------------------------------------
    ("docs/hybrid.md", "ratio zeta; {} in H2 and H3",
     lambda: [h2()["parameters"]["contact_damping"]] * (
         h2()["parameters"]["contact_damping"] == h3()["parameters"]["contact_damping"])),
    # --- docs/carsington.md ----------------------------------------------------------------
    ("docs/carsington.md", "| 6 (default) | {} | default",
     lambda: [carsington()["mesh"]["cells"]]),
    ("docs/carsington.md", "**On this mesh the section carries the fill to {} m OD and collapses "
     "in the last lift** ({} % of its weight carried;",
     lambda: [carsington()["construction"]["fill_level_m_od"],
              100 * carsington()["construction"]["collapsing_lift"]["weight_carried"]]),
    ("docs/carsington.md", "| core at node A, 198 m OD | about 150 mm | {} mm ({} mm at 190 m OD)",
     lambda: [carsington()["core_displacement_mm"]["198"], _cars_stage(3)["node_A_dx_mm"]]),
    *[("docs/carsington.md", f"{before}; with the yellow clay {{}} or {{}} m long, {{}} to {{}} mm "
       "(Sensitivity) |",
       lambda level=level: [
           *(_yellow_clay_length(f"carsington_parts_size3_Y{y}") for y in (20, 25)),
           *(f(_node_a_at(f"carsington_parts_size{n}_Y{y}", level) for n in (3, 2)
               for y in (20, 25)) for f in (min, max))])
      for level, before in ((198.0, "mm at 190 m OD)"),
                            (200.5, "finite elements: 100-150 mm) | not reached"))],
    ("docs/carsington.md", "Default run: rest at t = {} s; {} interfaces failed;",
     lambda: [carsington()["discrete"]["time_s"], carsington()["discrete"]["interfaces_failed"]]),
    ("docs/carsington.md", "at least {} m (a crack, not a slip surface sliding closed), joined "
     "to the crest's top. None is found at any time (the check fails). The widest opening of a "
     "failed interface at the crest's top at any record is {} m, against the crack of {} mm "
     "reported on the crest on 4 June 1984 and {} mm that evening. At rest {} interfaces of a "
     "crack are joined to the crest",
     lambda: [carsington()["parameters"]["slip_min"],
              carsington()["discrete"]["crest_crack_during_slide_surface_opening_m"],
              *ref.CARSINGTON_CREST_CRACK_MM,
              carsington()["discrete"]["crest_crack_interfaces"]]
     if not carsington()["checks"]["crack_at_crest"]["passed"] and 0.0 < carsington()[
         "discrete"]["crest_crack_during_slide_surface_opening_m"] else [math.nan]),
    ("docs/carsington.md", "The run's first splitting check (t = {} s, 10 steps after the "
     "start) fails {} bonds: {} beside the yellow clay, all in shear, {} at the crest's top, in "
     "tension, and {} elsewhere (the boot's and the upstream shoulder's first bonds fail at this "
     "splitting check too, the core's at t = {} s)",
     lambda: _default_onset()[:5] + [_default_onset_core()]),
    ("docs/carsington.md", "All {} failed bonds at the crest's top fail in tension; of the "
     "run's {} failed bonds {} fail in tension, {} in shear and {} as distorted fragments.",
     lambda: _default_onset()[5:]),
    ("docs/carsington.md", "In every one of the {} committed runs with a discrete phase",
     lambda: _onset_everywhere()[:1]),
    ("docs/carsington.md", "(all of them do in {} runs; in the others some fail as softened); "
     "the crest's top fails at the first splitting check in {} of them and in the others "
     "within {} s of it. The first splitting check also fails {} to {} bonds elsewhere in every "
     "run, the core's among them in {} runs;", lambda: _onset_everywhere()[1:]),
    ("docs/carsington.md", "the upstream shoulder moves upstream, {} m on average, but its toe "
     "does not move",
     lambda: [-carsington()["discrete"]["upstream_shoulder_mean_dx_m"]]
     if carsington()["discrete"]["toe_runout_m"] == 0.0 else [math.nan]),
    ("docs/carsington.md", "through the yellow clay ({} interfaces), the core's boot ({}) and "
     "the core above the boot ({},",
     lambda: [carsington()["discrete"][f"slip_surface_{k}"]
              for k in ("yellow_clay", "boot", "core")]),
    ("docs/carsington.md", "one interface on the core's face; {} % of the core's boundary "
     "with Zone I upstream slips, by {} m at most (with softening, below: {}-{} %, metres) |",
     lambda: [_core_face_pct("carsington"), _core_face("carsington")["max_slip_m"],
              min(_core_face_pct(n) for n in SOFT_MESHES),
              max(_core_face_pct(n) for n in SOFT_MESHES)]
     if min(_core_face(n)["max_slip_m"] for n in SOFT_MESHES) > 1.0 else [math.nan]),
    ("docs/carsington.md", "(the core's face and the boot's top beneath Zone I: {} "
     "interfaces, {} m long) {} m slipped, by {} m at most;",
     lambda: [_core_face("carsington")[k] for k in ("interfaces", "length_m",
                                                     "slipped_length_m", "max_slip_m")]),
    ("docs/carsington.md", "boot's top beneath Zone I, {} m long; `slip_along_core_upstream_face` "
     "in the summaries): {}, {}, {}, {}, {}, {}, {} and {} % of its length slipped at least 0.1 m "
     "on the 8, 6, 5, 4, 3, 2.5, 2 and 1.5 m meshes, by {} to {} m at most. In the default run "
     "without softening {} % of it ({} m long: the dam a lift higher) slipped, by {} m at most; "
     "with softening in the discrete phase only {} %.", lambda: _core_face_softening()),
    ("docs/carsington.md", "| default: no mass damping | {} | {} | {} | {} |",
     lambda: _cars_discrete("carsington")),
    ("docs/carsington.md", "| mass damping {} /s | {} | {} | {} | {} |",
     lambda: [_json("docs/summaries/carsington_damping0.5.json")["parameters"]["mass_damping"],
              *_cars_discrete("carsington_damping0.5")]),
    ("docs/carsington.md", "| mass damping {} /s (the thesis's) | {} | {} | {} | {} |",
     lambda: [_json("docs/summaries/carsington_damping3.json")["parameters"]["mass_damping"],
              *_cars_discrete("carsington_damping3")]),
    ("docs/carsington.md", "| softening in the discrete phase only (u_r {} m; "
     "`discrete_softening=true`) | {} | {} | {} | {} |",
     lambda: [_json("docs/summaries/carsington_discrete_softening.json")["parameters"][
         "softening_displacement"], *_cars_discrete("carsington_discrete_softening")]),
    ("docs/carsington.md", "placed whole the shoulder then runs out about {} times as far as "
     "observed", lambda: [_soft_disc("carsington_discrete_softening")["toe_runout_m"]
                          / ref.CARSINGTON_POST_FAILURE["upstream_toe_movement"][0]]),
    ("docs/carsington.md", "the continuum stage {} s (of which the factors of safety {} s), "
     "the discrete stage {} s.",
     lambda: [carsington()["continuum_wall_time_s"],
              carsington()["factor_of_safety"]["wall_time_s"],
              carsington()["discrete"]["phase_wall_time_s"]]),
    ("docs/carsington.md", "| from the design height ({} m of yellow clay: the section stands "
     "to the crest in whole lifts) | {} | {} | {} | {} |",
     lambda: [_json("docs/summaries/carsington_design_height.json")["parameters"][
         "yellow_clay_length"], *_cars_discrete("carsington_design_height")]),
    ("docs/carsington.md", "| 6 | {} | {} | {} | {} | no | {} |\n"
     "  | 4 | {} | {} | {} | {} | no | {} |\n  | 3 | {} | {} | {} | {} | no | {} |\n"
     "  | 2 | {} | {} | {} | {} | no | {} |",
     lambda: [v for n in DESIGN_HEIGHT_MESHES for v in _design_height_row(n)]),
    ("docs/carsington.md", "shoulder runs out {} m, the crest drops {} m: both within {} % of the "
     "observed slide on this mesh, **but the toe not converged on finer ones**",
     lambda: [*_cars_discrete("carsington_design_height_softening")[:2], 30.0]),
    ("docs/carsington.md", "On the 4, 3 and 2 m meshes the toe advances {}, {} and {} m: within "
     "{} % of the observed {} m on the 4 and 2 m meshes but not on the 3 m one, and {} % apart "
     "from the 4 to the 3 m mesh; the crest drop is within {} % of the observed {} m on all "
     "three ({}, {} and {} m)", lambda: _design_height_finer()),
    ("docs/carsington.md", "on the 2 m mesh the section with {} m of yellow clay no longer "
     "stands to the crest (lift {}, to {} m OD, {} % of its weight carried), so that run starts "
     "from {} m OD",
     lambda: [_json("docs/summaries/carsington_design_height_softening_size2.json")[
                  "parameters"]["yellow_clay_length"],
              *_collapse_of("carsington_design_height_softening_size2")]),
    ("docs/carsington.md", "| from the design height, softening in the discrete phase | {} | {} | "
     "{} | {} |", lambda: _cars_discrete("carsington_design_height_softening")),
    ("docs/carsington.md", "With the yellow clay {} m long, the longest of the Sensitivity "
     "table's lengths that carries the fill to the crest on the 3 and 2 m meshes",
     lambda: [_yellow_clay_length("carsington_parts_size3_Y25")] * (
         _stands_on_both("_Y25") and not _stands_on_both("_Y30")
         and not _stands_on_both("_Y50"))),
    ("docs/carsington.md", "design height, is carried here only by the section with less yellow "
     "clay: {} m in whole lifts on the 6, 4 and 3 m meshes, {} m with the fill in parts on the 4, "
     "3 and 2 m meshes", lambda: _design_height_starts()),
    ("docs/carsington.md", "| 3 | without softening | {} | {} | {} | {}, {} | {} | {} |\n"
     "  | 4 | softening | {} | {} | {} | {}, {} | {} | {} |\n"
     "  | 3 | softening | {} | {} | {} | {}, {} | {} | {} |\n"
     "  | 2 | softening | {} | {} | {} | {}, {} | {} | {} |",
     lambda: [v for n in DESIGN_HEIGHT_PARTS for v in _design_height_parts_row(n)]),
    ("docs/carsington.md", "`crack_at_crest` passes in every one of these runs: during the "
     "slide a failed interface joined to the crest's top opens 0.1 m, first {} to {} s after the "
     "start. The crack is shallow: one interface, {} to {} m deep, within the last part placed. "
     "It fails in every run from the design height with {} m of yellow clay in whole lifts "
     "(above), and in the same section ({} m) placed in whole lifts (softening; on the 3 m "
     "mesh the widest opening at the crest's top {} m, the toe {} m, the crest drop {} m, on "
     "the 2 m mesh {}, {} and {} m; "
     "`docs/summaries/carsington_design_height_Y25_softening_size3.json` and `_size2.json`): on "
     "both meshes the crack comes with the fill placed in parts, which puts a lift boundary, "
     "and so a row of elements, every {} m where a whole top lift is {} m thick, not with the "
     "section. Whether it needs the parts' history of placement or only elements as thin as a "
     "part at the crest is not told apart here. The widest opening at the crest's "
     "top during the slide, {} to {} m, is wider than the crack surveyed on the crest before "
     "the slide ({} to {} mm).", lambda: _design_height_cracks()),
    ("docs/carsington.md", "(from the design height with {} m of yellow clay in parts, on the 4, "
     "3 and 2 m meshes: a failed interface at the crest's top opens 0.1 m, one interface {}-{} m "
     "deep; with the same section in whole lifts none)",
     lambda: [_yellow_clay_length(DESIGN_HEIGHT_PARTS[0]), *_design_height_cracks()[2:4]]),
    ("docs/carsington.md", "| size [m] | yellow clay 24.97 m | 25 m | 25.03 m |\n"
     "  |---|---|---|---|\n  | 4 | {}, {} | {}, {} | {}, {} |\n  | 3 | {}, {} | {}, {} | {}, {} |\n"
     "  | 2 | {}, {} | {}, {} | {}, {} |",
     lambda: [d[k] for z in ("4", "3", "2") for d in _parts_samples(z)
              for k in ("toe_runout_m", "crest_drop_m")]),
    ("docs/carsington.md", "The crack at the crest is found in all nine runs, its widest opening "
     "at the crest's top {} to {} m. One run's crest drop scatters by {}, {} and {} % on the 4, 3 "
     "and 2 m meshes (largest over smallest of three runs); the three runs' means, {}, {} and "
     "{} m, are {} and {} % apart from one mesh to the next", lambda: _parts_sample_spreads()),
    ("docs/carsington.md", "are {} and {} % apart from one mesh to the next, within the {} % "
     "mesh bar (the second by less than one run's scatter, so not a sign of convergence), and {} "
     "to {} % of the observed {} m: within the {} % bar on the 3 m mesh only. The toe is no "
     "measure across meshes: it advances {} to {} m on the 4 m mesh,",
     lambda: _parts_sample_means()),
    ("docs/carsington.md", "{} to {} m on the 3 m mesh and {} to {} m on the 2 m mesh; whether "
     "the berm's front is pushed out at all changes from one run to the next on the 2 m mesh",
     lambda: _parts_toe_ranges()),
    ("docs/carsington.md", "barely moves (the crest drops {} m). With softening the crest drops "
     "{}, {} and {} m on the 4, 3 and 2 m meshes: within {} % of the observed {} m on the 3 m "
     "mesh only, and {} and {} % apart from one mesh to the next (the second beyond the {} % "
     "mesh bar). The upstream toe advances {}, {} and {} m, short of the observed 11-13 m on "
     "every mesh and not converged, while the shoulder as a whole moves {}, {} and {} m "
     "upstream on average", lambda: _design_height_parts_movements()),
    ("docs/carsington.md", "| upstream toe movement | not measured | {} m (bar {} %: not met) |",
     lambda: _cars_observed("upstream_toe_movement")),
    ("docs/carsington.md", "| crest drop | not measured | {} m (bar {} %: not met) |",
     lambda: _cars_observed("crest_drop")),
    ("docs/carsington.md", "the crest drops {} % of what was observed",
     lambda: [100.0 * carsington()["discrete"]["crest_drop_m"]
              / ref.CARSINGTON_POST_FAILURE["crest_drop"][0]]),
    ("docs/carsington.md", "the\n  shoulder runs out {} m, the crest drops {} m: both within "
     "30 % of", lambda: [_soft_disc("carsington_design_height_softening")[k]
                        for k in ("toe_runout_m", "crest_drop_m")]),
    ("docs/carsington.md", "F after lift 4 is {}:",
     lambda: [_cars_stage(4)["factor_of_safety"]]),
    ("docs/carsington.md", "The last lift placed in {} m parts: the section carries the fill "
     "to {} m OD and collapses in the part to {} m OD with {} % of its weight carried, so at "
     "about **{} m OD**", _cars_collapse),
    ("docs/carsington.md", "(The complete lifts give node A within {} % of the default run's;",
     lambda: [max(100 * abs(dx / _cars_node_a()[z] - 1) for z, dx in map(tuple, (
         carsington_last_lift()["core_displacement_mm"]["by_fill_level"]))
         if z in _cars_node_a())]),
    ("docs/carsington.md", "fill level carried (Table 6.3) | 200.5 m OD (design crest) | "
     "**{} m OD**, collapse in the last lift; in {} m lifts, collapse at {} m OD",
     lambda: [carsington()["construction"]["fill_level_m_od"], _cars_collapse()[0],
              _cars_collapse()[4]]),
    ("docs/carsington.md", "in 0.5 m parts with the yellow clay {} m long instead of {} m, "
     "collapse at {} and {} m OD on those meshes, and with {} m none", lambda: [
         _yellow_clay_length("carsington_parts_size3_Y30"), _yellow_clay_length("carsington"),
         *(_sensitivity_row(f"carsington_parts_size{n}_Y30")[2] for n in (3, 2)),
         *[_yellow_clay_length("carsington_parts_size3_Y20")] * _stands_on_both("_Y20")]),
    ("docs/carsington.md", "| 6 (default) | {} | {} | lift {} (to {}), {} % | {} | {} |\n"
     "| 3 | {} | {} | lift {} (to {}), {} % | {} | {} |\n| 2 | {} | {} | lift {} (to {}), {} % | "
     "{} | {} |", lambda: [v for n in ("carsington", "carsington_size3", "carsington_size2")
                           for v in _continuum_mesh_row(n)]),
    ("docs/carsington.md", "on the 3 and 2 m meshes 190 m OD, lift 4 collapsing at {} and {} % of "
     "its weight", lambda: [_continuum_mesh_row(n)[4] for n in ("carsington_size3",
                                                               "carsington_size2")]),
    ("docs/carsington.md", "without softening the 3 and 2 m meshes collapse in lift 4 too, later "
     "in it: at {} and {} % of its weight", lambda: [_continuum_mesh_row(n)[4] for n in (
         "carsington_size3", "carsington_size2")]),
    ("docs/carsington.md", "on the finer meshes the collapse comes at about {}-{} m OD by that "
     "measure", lambda: [_continuum_mesh_row(n)[5] for n in ("carsington_size2",
                                                            "carsington_size3")]),
    ("docs/carsington.md", "\n".join(["| {} | {} | {} | to {}, {} % | {} | {} | {} |"] * 4),
     lambda: [v for n in PARTS_MESHES for v in _parts_row(n)]),
    ("docs/carsington.md", "fails in the part to {} m OD, at {} and {} m OD by the weight "
     "carried ({} m apart", lambda: [_parts_row(PARTS_MESHES[2])[3],
                                     *(_parts_row(n)[5] for n in PARTS_MESHES[2:]),
                                     abs(_parts_row(PARTS_MESHES[3])[5]
                                         - _parts_row(PARTS_MESHES[2])[5])]),
    ("docs/carsington.md", "the section carries the fill to {} m OD and fails", lambda: [
        _parts_row(PARTS_MESHES[2])[2]] * (_parts_row(PARTS_MESHES[2])[2:4]
                                            == _parts_row(PARTS_MESHES[3])[2:4])),
    ("docs/carsington.md", "grows by {} m in the part to {} m OD and by {} m in the part to {} m "
     "OD", lambda: [v for top in (194.5, 198.5) for v in (
         _part_growth("carsington_parts_size6", top), top)]),
    # the fill level against the yellow clay's extent (docs-carsington-sensitivity): one row
    # per run, "-" where the run has no such figure (no collapse; node A not reached)
    *[("docs/carsington.md", f"| {label} | {size} | {row}",
       lambda name=f"carsington_parts_size{size}{tail}", change=change: _sensitivity_row(
           name, change))
      for label, tail, change, row in (
          ("20 m long", "_Y20", {"yellow_clay_length": 20.0}, "{} | {} | - | {} | {} |"),
          ("25 m long", "_Y25", {"yellow_clay_length": 25.0}, "{} | {} | - | {} | {} |"),
          ("30 m long", "_Y30", {"yellow_clay_length": 30.0}, "{} | {} | {} | {} | - |"),
          ("36 m long (default)", "", {}, "{} | {} | {} | - | - |"),
          ("50 m long", "_Y50", {"yellow_clay_length": 50.0, "parts_above": 182.0},
           "{} | {} | {} | - | - |"))
      for size in (3, 2)],
    *[("docs/carsington.md", f"| {t} m thick | 3 | {{}} | {{}} | {{}} | - | - |",
       lambda name=f"carsington_parts_size3_T{t}", t=t: _sensitivity_row(
           name, {"yellow_clay_thickness": float(t)}))
      for t in ("1.0", "2.0")],
    ("docs/carsington.md", "{} or {} m long, the layer lets the section stand to the design "
     "crest on both meshes", lambda: [_yellow_clay_length(f"carsington_parts_size3_Y{y}")
                                      for y in (20, 25) if _stands_on_both(f"_Y{y}")]),
    ("docs/carsington.md", "{} m long, the section carries the fill to {} m OD on both and fails "
     "in the part above, at {} and {} m OD (3 and 2 m meshes)", lambda: [
         _yellow_clay_length("carsington_parts_size3_Y30"),
         *{_sensitivity_row(f"carsington_parts_size{n}_Y30")[1] for n in (3, 2)},
         *(_sensitivity_row(f"carsington_parts_size{n}_Y30")[2] for n in (3, 2))]),
    ("docs/carsington.md", "{} m long (the default), at {} and {} m OD", lambda: [
        _yellow_clay_length("carsington_parts_size3"),
        *(_sensitivity_row(f"carsington_parts_size{n}")[2] for n in (3, 2))]),
    ("docs/carsington.md", "{} m long, it carries {} m OD on both and fails at {} and {} m OD",
     lambda: [_yellow_clay_length("carsington_parts_size3_Y50"),
              *{_sensitivity_row(f"carsington_parts_size{n}_Y50")[1] for n in (3, 2)},
              *(_sensitivity_row(f"carsington_parts_size{n}_Y50")[2] for n in (3, 2))]),
    ("docs/carsington.md", "Between {} and {} m the collapse level falls on average by {} m for "
     "each metre of layer (3 m mesh)", lambda: [
         _yellow_clay_length("carsington_parts_size3_Y30"),
         _yellow_clay_length("carsington_parts_size3"),
         (_sensitivity_row("carsington_parts_size3_Y30")[2]
          - _sensitivity_row("carsington_parts_size3")[2])
         / (_yellow_clay_length("carsington_parts_size3")
            - _yellow_clay_length("carsington_parts_size3_Y30"))]),
    ("docs/carsington.md", "({}, {} and {} m OD for a layer {}, {} and {} m thick on the 3 m mesh",
     lambda: [*(_sensitivity_row(f"carsington_parts_size3{t}")[2]
                for t in ("_T1.0", "", "_T2.0")),
              *(_json(f"docs/summaries/carsington_parts_size3{t}.json")["parameters"][
                  "yellow_clay_thickness"] for t in ("_T1.0", "", "_T2.0"))]),
    ("docs/carsington.md", "node A moves {} to {} mm at 198 m OD and {} to {} mm at 200.5 m OD",
     lambda: [f(_sensitivity_row(f"carsington_parts_size{n}_Y{y}")[k]
                for n in (3, 2) for y in (20, 25))
              for k in (2, 3) for f in (min, max)]),
    ("docs/carsington.md", "its length decides the fill level; its thickness moves it by up to "
     "{} m", lambda: [_thickness_spread()]),
    ("docs/carsington.md", "Over the published thickness the collapse level moves by up to {} m",
     lambda: [_thickness_spread()]),
    ("docs/carsington.md", "A {} m layer puts the collapse within {} m of the observed {} m OD",
     lambda: [_yellow_clay_length("carsington_parts_size3_Y30"),
              max(abs(_sensitivity_row(f"carsington_parts_size{n}_Y30")[2] - OBSERVED_SLIP)
                  for n in (3, 2)), OBSERVED_SLIP]),
    ("docs/carsington.md", "the finer mesh gives the smaller figure in each of the {} pairs of the "
     "table's node A columns", lambda: _finer_smaller_node_a()),
    ("docs/carsington.md", "with the {} m layer node A moves back upstream from 198 to 200.5 m OD "
     "on both meshes", lambda: [_yellow_clay_length("carsington_parts_size3_Y25")] * all(
         _node_a_at(f"carsington_parts_size{n}_Y25", 200.5)
         < _node_a_at(f"carsington_parts_size{n}_Y25", 198.0) for n in (3, 2))),
    ("docs/carsington.md", "the section stands to the design crest with up to {} m of yellow clay "
     "and with none of {} m or more", lambda: [
         _yellow_clay_length(f"carsington_parts_size3{t}") for t in ("_Y25", "_Y30")] * (
         _stands_on_both("_Y20") and _stands_on_both("_Y25")
         and not any(_completed(f"carsington_parts_size{n}{t}") for n in (3, 2)
                     for t in ("_Y30", "", "_Y50")))),
    ("docs/carsington.md", "The coarser meshes overstate it ({} m OD on the 6 m mesh)",
     lambda: [_parts_row(PARTS_MESHES[0])[5]]),
    ("docs/carsington.md", "the 3 m mesh then stops at {} % of the part's weight against {} %",
     lambda: [100.0 * _json(f"docs/summaries/{n}.json")["construction"]["collapsing_lift"][
         "weight_carried"] for n in ("carsington_parts_size3_increment1e-4",
                                     "carsington_parts_size3")]),
    ("docs/carsington.md", "Node A agrees within {} % at 190 m OD on the three meshes",
     lambda: [100.0 * _rel_spread([_continuum_mesh_row(n)[-1] for n in (
         "carsington", "carsington_size3", "carsington_size2")])]),
    ("docs/carsington.md", "| the core's axis at the foundation level | {} | {} | {} | {} |",
     lambda: _node_a("axis_foundation_level")),
    ("docs/carsington.md", "| the core's axis at the top of the boot (default) | {} | {} | {} | "
     "{} |", lambda: _node_a("axis_boot_top")),
    ("docs/carsington.md", "| the core's upstream face at the top of the boot | {} | {} | {} | "
     "{} |", lambda: _node_a("upstream_face_boot_top")),
    ("docs/carsington.md", "| the core's axis at the berm top | {} | {} | {} | {} |",
     lambda: _node_a("axis_berm_top")),
    ("docs/carsington.md", "| {} (default) | {} | {} | {} | lift {} (to {}), {} % | {} | {} | {} | "
     "{} |", lambda: _softening("carsington_softening")),
    ("docs/carsington.md", "(fill carried {}-{} m OD) instead of the last lift",
     lambda: [_json("docs/summaries/carsington_softening_ur0.2.json")["construction"][
         "fill_level_m_od"], _json("docs/summaries/carsington_softening.json")["construction"][
         "fill_level_m_od"]]),
    # the rows of the softening table, each told apart by the row after it
    *(("docs/carsington.md", SOFT_ROW + after, lambda name=name: _softening(name))
      for name, after in (("carsington_softening_size8", "\n| 0.5 (default)"),
                          ("carsington_softening_size5", "\n| 0.5 | 4 |"),
                          ("carsington_softening_size4", "\n| 0.5 | 3 |"),
                          ("carsington_softening_size3", "\n| 0.5 | 2.5 |"),
                          ("carsington_softening_size2.5", "\n| 0.5 | 2 |"),
                          ("carsington_softening_size2", "\n| 0.5 | 1.5 |"),
                          ("carsington_softening_size1.5", "\n| 0.2"),
                          ("carsington_softening_ur0.2", "\n| 1.0"),
                          ("carsington_softening_ur1", "\n\n- **Fill"))),
    ("docs/carsington.md", "on the eight meshes the same lift collapses, at {}-{} % of its weight",
     lambda: [f(100.0 * _json(f"docs/summaries/{n}.json")["construction"]["collapsing_lift"][
         "weight_carried"] for n in SOFT_MESHES) for f in (min, max)]),
    ("docs/carsington.md", "crest drops {}-{} m against about {} m observed ({} % short at "
     "most, within the {} % bar), and moves {} % from the 4 m to the 3 m mesh",
     lambda: _cars_crest_spread()[:6]),
    ("docs/carsington.md", "two and the 2.5 m mesh) and {} % from the 2 m to the 1.5 m mesh",
     lambda: _cars_crest_spread()[6:]),
    ("docs/carsington.md", "from each of the eight meshes to the next it moves by {}, {}, {}, {}, "
     "{}, {} and {} %", lambda: _steps([_soft_disc(n)["crest_drop_m"] for n in SOFT_MESHES])),
    ("docs/carsington.md", "next within the {} % mesh bar in all {} steps.**",
     lambda: (lambda v: [15.0, len(v)] if all(x <= 15.0 for x in v) else [])(
         _steps([_soft_disc(n)["crest_drop_m"] for n in SOFT_MESHES]))),
    ("docs/carsington.md", "The upstream toe advances {}, {}, {}, {}, {}, {}, {} and {} m on the "
     "{}, {}, {}, {}, {}, {}, {} and {} m meshes",
     lambda: [_soft_disc(n)["toe_runout_m"] for n in SOFT_MESHES] + _soft_sizes(SOFT_MESHES)),
    ("docs/carsington.md", "The `crack_at_crest` check\n  (at every record of the run's state) "
     "fails on the {}, {}, {}, {}, {}, {} and {} m meshes, and with u_r\n  {} and {} m, and "
     "passes on the {} m mesh: there a failed interface joined to the crest's\n  top stands "
     "open by {} m at {} s, a crack {} m deep.", lambda: _crest_crack_finest()),
    ("docs/carsington.md", "opens on every mesh; the widest opening of a failed interface at the "
     "crest's top at any record is {}, {}, {}, {}, {}, {}, {} and {} mm on the eight meshes, "
     "within the {}-{} mm of the crack surveyed on the crest before the slide on {} of them",
     lambda: _crest_openings()),
    ("docs/carsington.md", "within the {} % bar on {} of the {} meshes of {} m and finer, but "
     "without\n  a trend: from one of those meshes to the next it moves by {}, {}, {} and {} %, in "
     "{}\n  of those {} steps beyond the {} % mesh bar", lambda: _toe_finer()),
    ("docs/carsington.md", "The shoulder as a whole moves {}, {}, {}, {}, {}, {}, {} and {} m "
     "upstream on average: {} % apart on the three finest meshes",
     lambda: [-_soft_disc(n)["upstream_shoulder_mean_dx_m"] for n in SOFT_MESHES]
     + [100.0 * _rel_spread([_soft_disc(n)["upstream_shoulder_mean_dx_m"]
                             for n in SOFT_MESHES[-3:]])]),
    ("docs/carsington.md", "but {} % apart on the 3 m and 2.5 m meshes",
     lambda: [100.0 * _rel_spread([_soft_disc(n)["upstream_shoulder_mean_dx_m"] for n in (
         "carsington_softening_size3", "carsington_softening_size2.5")])]),
    ("docs/carsington.md", "The node first at the toe moves {}, {}, {}, {}, {}, {}, {} and {} m",
     lambda: [-_soft_disc(n)["upstream_toe_dx_m"] for n in SOFT_MESHES]),
    ("docs/carsington.md", "its fragment stays up to {} m behind the berm's front",
     lambda: [max(_soft_disc(n)["toe_runout_m"] + _soft_disc(n)["upstream_toe_dx_m"]
                  for n in SOFT_MESHES)]),
    ("docs/carsington.md", "With u_r 1 m the toe advances {} m",
     lambda: [_soft_disc("carsington_softening_ur1")["toe_runout_m"]]),
    ("docs/carsington.md", "(the crest drops {} m, the toe advances {} m)",
     lambda: [_soft_disc("carsington_softening_ur0.2")[k] for k in ("crest_drop_m",
                                                                    "toe_runout_m")]),
    ("docs/carsington.md", "| size [m] | 35.94 m | 35.97 m | 36 m | 36.03 m | 36.06 m | toe: "
     "mean, sd | crest drop: mean, sd |\n  |---|---|---|---|---|---|---|---|\n"
     + "".join(f"  | {z} |" + " {}, {} |" * 7 + "\n" for z in SOFT_SAMPLE_SIZES),
     lambda: [v for z in SOFT_SAMPLE_SIZES for v in _soft_sample_row(z)]),
    ("docs/carsington.md", "Every run collapses in lift {} and comes to rest. One run's toe "
     "movement scatters by {}, {}, {} and {} % on the 4, 3, 2.5 and 2 m meshes (largest over "
     "smallest of five runs), but the 2.5 m mesh's five runs ({} to {} m) lie apart from the 3 m "
     "mesh's ({} to {} m) and the 2 m mesh's ({} to {} m). The five runs' means, {}, {}, {} and "
     "{} m, are {}, {} and {} % apart from one mesh to the next (larger over smaller): the 4, 3 "
     "and 2 m meshes' means lie within {} % of each other, inside the {} % mesh bar, and the 2.5 "
     "m mesh's far below them", lambda: _soft_sample_toe()),
    ("docs/carsington.md", "The crest drop is steady on each mesh (one run's scatter at most {} "
     "%); its means, {}, {}, {} and {} m, are {}, {} and {} % apart from one mesh to the next, "
     "within the {} % mesh bar (the step from the 3 m mesh, whose mean is the highest, close to "
     "it), and lie {} "
     "to {} % short of the observed {} m, within the {} % bar. The shoulder's mean upstream "
     "movement (five-run means {}, {}, {} and {} m) agrees within {} % on the 2.5 and 2 m "
     "meshes and is {} % apart from the 3 to the 2.5 m mesh.", lambda: _soft_sample_crest()),
    # --- docs/hybrid.md: mesh objectivity at a glance -----------------------------------------
    ("docs/hybrid.md", "| H2 | collapse load [kPa] | {} | {} | {} (unstructured, {} m) | met "
     "over five quadrilateral meshes ({} %), and on the refined structured mesh with Newton's "
     "retry ({} % below the default one; without it that mesh stops {} % below, where Newton "
     "stalls); not on triangles ({} % below, under settlement control) |",
     lambda: [v[i] for i in (0, 1, 2, 3, 4, 6, 5, 7)] if (v := _glance_h2_collapse()) else []),
    ("docs/hybrid.md", "| H2 | settlement at rest since the handover [m] | {} | {} | {} "
     "(unstructured, {} m) | not met: {} % across the types; on refinement {} % (unstructured), "
     "{} % (structured) |", lambda: _glance_h2("final_settlement_m")),
    ("docs/hybrid.md", "| H2 | heave at rest [m] | {} | {} | {} (unstructured, {} m) | on "
     "refinement ({} % unstructured, {} % structured), not across the types ({} %; {} % at {} "
     "m) |", lambda: _glance_h2("max_heave_beside_footing_m")),
    ("docs/hybrid.md", "| H3 | active thrust, continuum [kN/m] | {} | {} | {} (grid), {} "
     "(unstructured), {} m; {} (grid, {} m) | not met on refinement: {} % over the three "
     "grids, still falling ({} % then {} %, each step within the bar); the mesh types at most {} "
     "% apart at one size; {} % above Rankine's {} on the finest (exact for a smooth base "
     "only: C8) |", lambda: _glance_h3_thrust()),
    ("docs/hybrid.md", "| H3 | wedge at 0.1 H [deg] | {} | {} | {} (grid), {} (unstructured), {} "
     "m; {} (grid, {} m) | met: each within {} deg of 45 + phi/2 = {} deg, the five meshes "
     "within {} deg |", lambda: _glance_h3_wedge()),
    ("docs/hybrid.md", "| H3 | run-out, mean of runs [m] | {} (nine) | {} (nine) | {} (grid), {} "
     "(unstructured), {} m, five each; {} (grid, {} m, five) | within the bar on refinement of "
     "the grid ({} % to {} m, {} % on to {} m; the unstructured mesh's mean moves {} %, "
     "standard error {} %); across the types at {} m ({} %, standard error {} %); not verified "
     "at {} m ({} %) |", lambda: _glance_h3_runout()),
    # --- docs/hybrid.md: H2 -----------------------------------------------------------------
    ("docs/hybrid.md", "B = {} m strip (half model {} m x {} m, {} Q4 / Q2 cells, {} m at the "
     "footing edge), c = {} kPa, phi = {} deg, psi = {}, gamma = {} kN/m3 (assumed), E = {} MPa, "
     "nu = {}.",
     lambda: [*(h2()["parameters"][k] for k in ("footing_width", "width", "depth")),
              h2()["continuum"]["cells"],
              *(h2()["parameters"][k] for k in ("fine", "cohesion", "phi", "psi",
                                                "unit_weight")),
              h2()["parameters"]["E"] / 1000.0, h2()["parameters"]["nu"]]),
    ("docs/hybrid.md", "the soil softens to c_r = {} kPa, phi_r = {} deg over a slip of u_r = {} m",
     lambda: [h2()["parameters"][k] for k in ("residual_cohesion", "residual_phi",
                                              "softening_displacement")]),
    ("docs/hybrid.md", "collapse (the softening soil's peak) at **{} kPa**; the classical "
     "bearing-capacity formulae are limit loads of a perfectly plastic soil and no reference for "
     "it (they are compared, without a bar, with the perfectly plastic footing in C7; "
     "Prandtl's weightless limit load is checked in C6), {} increments, {} Newton "
     "iterations, {} s;",
     lambda: [h2()["continuum"]["collapse_pressure_kPa"]]
     * all(h2()["checks"][f"collapse_vs_{k}"]["reference"] is None
           for k in ("Vesic", "Meyerhof", "Terzaghi"))
     + [h2()["continuum"]["steps"], h2()["continuum"]["newton_iterations"],
        h2()["continuum"]["wall_time_s"]]),
    ("docs/hybrid.md", "with the footing centre {} m down. Handover: every bond may fail "
     "where its strength is exceeded ({} of {} interfaces splittable) and no element is held",
     lambda: [h2()["continuum"]["curve"][-1][0], h2()["handover"]["splittable_interfaces"],
              h2()["handover"]["interfaces"]]
     if h2()["handover"]["frozen_elements"] == 0 else [math.nan]),
    ("docs/hybrid.md", "pressure raised from the collapse load to {} kPa over {} s and held; the "
     "footing reached **{} m** (counted from the handover) at t = {} s (it is a dynamic punch: "
     "{} kPa is {} times the collapse load, alpha = {} 1/s), was unloaded over {} s and came to "
     "rest at t = {} s with {} m of settlement since the handover, {} m in all; the ground "
     "beside the footing rose by up to {} m (the largest rise of the surface); {} interfaces "
     "failed. Energy never above its sources (the energy at the start of each run plus the "
     "work done since: excess {}, peak {} of the supply); elements ({}) "
     "and mass ({} t/m) unchanged. {} steps in {} s.",
     lambda: [h2()["parameters"]["pressure"], h2()["parameters"]["ramp_time"],
              h2()["discrete"]["settlement_at_unloading_m"], h2()["discrete"]["unloaded_at_s"],
              h2()["parameters"]["pressure"],
              h2()["parameters"]["pressure"] / h2()["continuum"]["collapse_pressure_kPa"],
              h2()["parameters"]["mass_damping"], h2()["parameters"]["ramp_time"],
              h2()["discrete"]["time_to_rest_s"], h2()["discrete"]["final_settlement_m"],
              h2()["discrete"]["final_total_settlement_m"],
              h2()["discrete"]["max_heave_beside_footing_m"],
              h2()["discrete"]["interfaces_failed"],
              h2()["checks"]["energy_excess_over_sources"]["computed"],
              h2()["discrete"]["energy_peak_over_supply"], h2()["discrete"]["elements"],
              h2()["discrete"]["mass_t_per_m"], h2()["discrete"]["steps"],
              h2()["discrete"]["wall_time_s"]]),
    ("docs/hybrid.md", "From the start of the unloading to rest the footing went down a "
     "further {} m.",
     lambda: [h2()["discrete"]["final_settlement_m"]
              - h2()["discrete"]["settlement_at_unloading_m"]]),
    ("docs/hybrid.md", "the run reads rest at t = {} s after {} steps, against t = {} s after {} "
     "steps with the dashpots. "
     "The settlement since the handover is {} m there against {} m ({} % apart), the heave {} "
     "against {} m ({} %).",
     lambda: _h2_far_boundary()),
    # H2's mesh sensitivity: rows by the mesh they start with
    ("docs/hybrid.md", "| quads, `fine={}` | {} | {} | {} | {} | {} | {} |\n| quads, `fine=0.12`",
     lambda: _h2_row("h2_fine0.16")),
    ("docs/hybrid.md", "| quads, `fine={}` | {} | {} | {} | {} | {} | {} |\n| quads, `fine=0.08`",
     lambda: _h2_row("h2_fine0.12")),
    ("docs/hybrid.md", "| quads, `fine={}` (default) | {} | {} | {} | {} | {} | {} |",
     lambda: _h2_row("h2")),
    ("docs/hybrid.md", "| quads, `fine={}` | {} | {} | {} | {} | {} | {} |\n| structured",
     lambda: _h2_row("h2_fine0.04")),
    ("docs/hybrid.md", "| structured quads, `fine={}` | {} | {} | {} | {} | {} | {} |",
     lambda: _h2_row("h2_structured")),
    ("docs/hybrid.md", "| structured quads, `fine={}` ({} increments) | {} | {} | {} | {} | {} "
     "| {} |",
     lambda: _h2_row("h2_structured_fine0.04")[:1]
     + [_json("docs/summaries/h2_structured_fine0.04.json")["parameters"]["continuum_steps"]]
     + _h2_row("h2_structured_fine0.04")[1:]),
    ("docs/hybrid.md", "in the case's {} increments its continuum stalls short of the "
     "collapse, before the settlement runs away",
     lambda: [_json("docs/summaries/h2_structured.json")["parameters"]["continuum_steps"]]),
    ("docs/hybrid.md", "in {} increments (`--set continuum_steps={}`, the last row) it "
     "stops at {} kPa with the settlement running away, which the case takes for the "
     "collapse, {} % below the 0.08 m structured mesh and {} % below the default mesh",
     # "Not on the refined structured mesh": beyond the 3 % bar
     lambda: [*[_json("docs/summaries/h2_structured_fine0.04.json")["parameters"][
         "continuum_steps"]] * 2, _collapse_kpa("h2_structured_fine0.04"),
         100.0 * (1.0 - _collapse_kpa("h2_structured_fine0.04") / _collapse_kpa("h2_structured")),
         100.0 * (1.0 - _collapse_kpa("h2_structured_fine0.04") / _collapse_kpa("h2"))]
     if _collapse_kpa("h2_structured") / _collapse_kpa("h2_structured_fine0.04") > 1.03
     else []),
    ("docs/hybrid.md", "refined to 0.04 m it heaves {} % less and settles {} % further than at "
     "0.08 m: each mesh type converges on its own heave, the two {} % apart (the 0.04 m meshes)",
     lambda: [v for v in [
         100.0 * (1.0 - _h2_disc("h2_structured_fine0.04", "max_heave_beside_footing_m")
                  / _h2_disc("h2_structured", "max_heave_beside_footing_m")),
         100.0 * (_h2_disc("h2_structured_fine0.04", "final_settlement_m")
                  / _h2_disc("h2_structured", "final_settlement_m") - 1.0),
         100.0 * _rel_spread([_h2_disc(n, "max_heave_beside_footing_m")
                              for n in ("h2_structured_fine0.04", "h2_fine0.04")])]]
     if (g := 100.0 * (1.0 - _h2_disc("h2_structured_fine0.04", "max_heave_beside_footing_m")
                       / _h2_disc("h2_structured", "max_heave_beside_footing_m"))) > 0.0
     and g <= 10.0 else []),
    ("docs/hybrid.md", "the structured mesh's punch carries a mean pressure of {} kPa ({} % below "
     "its 0.08 m one's) and heaves {} m ({} % apart; "
     "`docs/summaries/h2_punch_structured_fine0.04.json`): on the two structured meshes the "
     "punch's pressure and heave agree within the 10 % bar",
     lambda: _punch_structured_refined()),
    ("docs/hybrid.md", "the heave moves by {} %, within a 10 % bar",
     lambda: [100.0 * abs(_json("docs/summaries/h2_fine0.04.json")["discrete"][
         "max_heave_beside_footing_m"] / h2()["discrete"]["max_heave_beside_footing_m"] - 1.0)]),
    ("docs/hybrid.md", "and by {} % over the 0.12, 0.08 and 0.04 m meshes",
     lambda: [100.0 * _rel_spread([_json(f"docs/summaries/{n}.json")["discrete"][
         "max_heave_beside_footing_m"] for n in ("h2_fine0.12", "h2", "h2_fine0.04")])]),
    ("docs/hybrid.md", "heaves are {} % apart and final settlements {} % apart",
     lambda: [_spread("max_heave_beside_footing_m"), _spread("final_settlement_m")]),
    ("docs/hybrid.md", "how far the footing runs on while the load comes off and after: {} m "
     "more on the default mesh, {} m more on the refined one",
     lambda: [d["final_settlement_m"] - d["settlement_at_unloading_m"] for d in (
         h2()["discrete"], _json("docs/summaries/h2_fine0.04.json")["discrete"])]),
    # H2's displacement-controlled punch: two meshes at two speeds
    ("docs/hybrid.md", "| `fine={}` | {} | {} | {} | {} | {} | {} |\n"
     "| `fine={}` (default) | {} | {} | {} | {} | {} | {} |\n"
     "| `fine={}` | {} | {} | {} | {} | {} | {} |\n"
     "| `fine={}` (default) | {} | {} | {} | {} | {} | {} |\n"
     "| `fine={}` | {} | {} | {} | {} | {} | {} |\n"
     "| structured, `fine={}` | {} | {} | {} | {} | {} | {} |\n"
     "| `fine={}`, u_r = {} m | {} | {} | {} | {} | {} | {} |\n"
     "| `fine={}`, u_r = {} m | {} | {} | {} | {} | {} | {} |",
     lambda: [v for n in ("h2_punch_fine0.12", *PUNCH_RUNS, "h2_punch_structured")
              for v in _punch_row(n)]
     + [v for n in ("h2_punch_ur0.1", "h2_punch_ur0.4")
        for v in [*_punch_row(n)[:1], _punch(n)["parameters"]["softening_displacement"],
                  *_punch_row(n)[1:]]]),
    ("docs/hybrid.md", "with half of it ({} m) the soil heaves {} % more and the mean pressure "
     "is {} % lower; with twice it ({} m) the heave is {} % smaller and the mean pressure {} % "
     "higher (the last two rows; the continuum's collapse load moves by {} and +{} %)",
     lambda: [_punch("h2_punch_ur0.1")["parameters"]["softening_displacement"],
              _ur_change("h2_punch_ur0.1", "max_heave_beside_footing_m"),
              -_ur_change("h2_punch_ur0.1", "mean_bearing_pressure_kpa"),
              _punch("h2_punch_ur0.4")["parameters"]["softening_displacement"],
              -_ur_change("h2_punch_ur0.4", "max_heave_beside_footing_m"),
              _ur_change("h2_punch_ur0.4", "mean_bearing_pressure_kpa"),
              _ur_collapse("h2_punch_ur0.1"), _ur_collapse("h2_punch_ur0.4")]),
    ("docs/hybrid.md", "Over the three unstructured meshes (0.12, 0.08 and 0.04 m) the mean "
     "pressures are {} % apart and the heaves {} %; the structured mesh heaves {} % more than "
     "the default one, and its mean pressure and its pressure over the last fifth are {} and "
     "{} % apart from the default one's (lower)",
     lambda: [100.0 * _rel_spread([_punch(n)["discrete"][k] for n in (
         "h2_punch_fine0.12", "h2_punch", "h2_punch_fine0.04")])
         for k in ("mean_bearing_pressure_kpa", "max_heave_beside_footing_m")]
     + [100.0 * (_punch("h2_punch_structured")["discrete"]["max_heave_beside_footing_m"]
                 / _punch("h2_punch")["discrete"]["max_heave_beside_footing_m"] - 1.0)]
     + [_punch_gap("h2_punch", "h2_punch_structured", k)
        for k in ("mean_bearing_pressure_kpa", "bearing_pressure_last_fifth_kpa")]),
    ("docs/hybrid.md", "at 0.25 m/s the mean pressure moves by {} % and the heave by {} %, "
     "within the 10 % bar (`test_footing_punch_refined`), and the pressure over the last fifth "
     "of the push by {} %; at 0.125 m/s by {}, {} and {} %: the last fifth's pressure is not "
     "verified.",
     lambda: _punch_refinement_gaps()),
    ("docs/hybrid.md", "the rise as the load comes off, {} and {} m on the default mesh and its "
     "refinement at 0.25 m/s "
     "and {} and {} m at 0.125 m/s: not converged",
     lambda: [_punch(n)["discrete"]["settlement_at_unloading_m"]
              - _punch(n)["discrete"]["final_settlement_m"] for n in PUNCH_RUNS]),
    ("docs/hybrid.md", "so their final settlements, {} % apart, are verified only as far",
     lambda: [_punch_gap("h2_punch", "h2_punch_fine0.04", "final_settlement_m")]),
    ("docs/hybrid.md", "All {} punch runs of the table reach rest.",
     lambda: [len(PUNCH_TABLE)] if all(_punch(n)["discrete"]["stop"] == "rest"
                                       for n in PUNCH_TABLE) else []),
    ("docs/hybrid.md", "Halving the speed moves the settlement by {} and {} %, the heave by {} "
     "and {} % and the mean pressure by {} and {} % (default and refined mesh)",
     lambda: [_punch_gap(a, b, k) for k in (
         "final_settlement_m", "max_heave_beside_footing_m", "mean_bearing_pressure_kpa")
         for a, b in (("h2_punch", "h2_punch_v0.125"),
                      ("h2_punch_fine0.04", "h2_punch_v0.125_fine0.04"))]),
    ("docs/hybrid.md", "than the default one and heaves {} % more",
     lambda: [100.0 * (_json("docs/summaries/h2_structured.json")["discrete"][
         "max_heave_beside_footing_m"] / h2()["discrete"]["max_heave_beside_footing_m"] - 1.0)]),
    ("docs/hybrid.md", "The structured mesh settles {} % further than the default one",
     lambda: [100.0 * (_json("docs/summaries/h2_structured.json")["discrete"][
         "final_settlement_m"] / h2()["discrete"]["final_settlement_m"] - 1.0)]),
    ("docs/hybrid.md", "(spread {} % over those five meshes, within the 3 % bar)",
     lambda: [s] if (s := 100.0 * (max(q := [_json(f"docs/summaries/{n}.json")["continuum"][
         "collapse_pressure_kPa"] for n in H2_MESHES]) - min(q)) / min(q)) <= 3.0 else []),
    ("docs/hybrid.md", "| quads, `fine=0.08` (default) | {}, {}, {} | {}, {}, {} | stalls before "
     "the collapse |", lambda: [v for n in ("h2_W4.7952", "h2") for v in _h2_sample(n, 4.8)]),
    ("docs/hybrid.md", "| structured quads, `fine=0.08` | {}, {}, {} | {}, {}, {} | {}, {}, {} |",
     lambda: [v for n in ("h2_structured_W4.7952", "h2_structured", "h2_structured_W4.8048")
              for v in _h2_sample(n, 4.8)]),
    ("docs/hybrid.md", "Between these runs the settlement moves by at most {} % and the heave by "
     "{} % (largest over smallest on each mesh)", _h2_sample_spread),
    # --- docs/hybrid.md: H3 -----------------------------------------------------------------
    ("docs/hybrid.md", "| {} m | {} | {} | {} | {} |\n| 0.5 m (default)",
     lambda: _h3_row("h3_size1.0")),
    ("docs/hybrid.md", "| {} m (default) | {} | {} | {} | {} |", lambda: _h3_row("h3")),
    ("docs/hybrid.md", "| {} m | {} | {} | {} | {} |\n| 0.125 m |",
     lambda: _h3_row("h3_size0.25")),
    ("docs/hybrid.md", "| {} m | {} | {} | {} | {} |\n| unstructured",
     lambda: _h3_row(H3_FINEST)),
    ("docs/hybrid.md", "| unstructured quads, {} m | {} | {} | {} | {} |\n| unstructured quads, "
     "0.25 m |", lambda: _h3_row("h3_unstructured")),
    ("docs/hybrid.md",
     "| unstructured quads, {} m | {} | {} | {} | {} |\n\n- **Wedge: verified.**",
     lambda: _h3_row("h3_unstructured_size0.25")),
    ("docs/hybrid.md", "from 0.5 to 0.25 m the\n  wedge moves by {} deg, and from the "
     "structured to the unstructured 0.5 m mesh by {} deg",
     lambda: [_h3_change("h3", "h3_size0.25")[0], _h3_change("h3", "h3_unstructured")[0]]),
    ("docs/hybrid.md", "From\n  0.5 to 0.25 m it changes by {} %, within a 10 % bar",
     lambda: [_h3_change("h3", "h3_size0.25")[1]] if _h3_change("h3", "h3_size0.25")[1] <= 10.0
     else []),
    ("docs/hybrid.md", "and the means of each grid's runs by {} % (below); from the structured "
     "to the unstructured 0.5 m mesh by {} % (strict xfail",
     lambda: [abs(m[1]), _h3_change("h3", "h3_unstructured")[1]]
     if (m := _h3_refined_means()) else []),
    ("docs/hybrid.md",
     "`test_retaining_wall_collapse_runout_unstructured`): there the deposit ends at {} m with "
     "no element beyond it, the shortest of the unstructured mesh's nine runs, and averaged over "
     "nine runs each the unstructured mesh runs out {} % shorter (below)",
     lambda: [_h3_row("h3_unstructured")[3], a[0]]
     if _h3_change("h3", "h3_unstructured")[1] > 10.0
     and h3_unstructured()["discrete"]["detached_elements"] == 0
     and h3_unstructured()["discrete"]["runout_m"] == min(_h3_runouts("h3_unstructured"))
     and (a := _h3_across()) else []),
    ("docs/hybrid.md", "The 1 m grid (ten elements\n  over the wall's height) runs out {} % "
     "further than the 0.5 m one (one run each; {} % beyond the 0.5 m grid's mean of nine, "
     "below)",
     lambda: [100.0 * (_h3_row("h3_size1.0")[3] / _h3_row("h3")[3] - 1.0),
              pct(_h3_row("h3_size1.0")[3], statistics.mean(_h3_runouts("h3")))]),
    ("docs/hybrid.md", "Thesis wall H = {} m, sand phi = {} deg, c = 0, gamma = {}, E = {} MPa, "
     "nu = {}, psi = phi",
     lambda: [h3()["parameters"]["height"], h3()["parameters"]["phi"],
              h3()["parameters"]["unit_weight"], h3()["parameters"]["E"] / 1000.0,
              h3()["parameters"]["nu"]]),
    ("docs/hybrid.md", "backfill {} m on a 1 m ground layer that runs {} m in front of the wall "
     "(`meshes/wall.py`, {} m structured Q4, {} cells).",
     lambda: [h3()["parameters"]["length"], h3()["parameters"]["front"],
              h3()["parameters"]["size"], h3()["continuum"]["cells"]]),
    ("docs/hybrid.md", "at-rest thrust {} kN/m, active translation {} m: {} kN/m (Rankine {}: "
     "{} %, rough base;",
     lambda: [h3()["continuum"]["at_rest_thrust_kN_per_m"], h3()["parameters"]["translation"],
              h3()["checks"]["active_thrust"]["computed"],
              h3()["checks"]["active_thrust"]["reference"],
              pct(h3()["checks"]["active_thrust"]["computed"],
                  h3()["checks"]["active_thrust"]["reference"])]),
    ("docs/hybrid.md", "{} m toward the backfill: {} kN/m (Rankine {}: {} %)",
     lambda: [h3()["parameters"]["passive_translation"],
              h3()["checks"]["passive_thrust"]["computed"],
              h3()["checks"]["passive_thrust"]["reference"],
              pct(h3()["checks"]["passive_thrust"]["computed"],
                  h3()["checks"]["passive_thrust"]["reference"])]),
    ("docs/hybrid.md", "At rest: **t = {} s**, {} "
     "steps, {} s wall, {} interfaces failed. The sand runs out {} m in front of the wall; the\n"
     "debris surface lies at {} deg.",
     lambda: [h3()["discrete"]["time_s"], h3()["discrete"]["steps"],
              h3()["discrete"]["wall_time_s"], h3()["discrete"]["interfaces_failed"],
              h3()["discrete"]["runout_m"], h3()["discrete"]["final_slope_deg"]]),
    ("docs/hybrid.md", "When the top of the face has moved 0.1 H = {} m (t = {} s):\n"
     "**{} deg** against 45 + phi/2 = {} deg (bar {} deg: met).",
     lambda: [h3()["parameters"]["wedge_at"], _wedge("1", "time_s"),
              h3()["checks"]["wedge_angle"]["computed"],
              h3()["checks"]["wedge_angle"]["reference"],
              h3()["checks"]["wedge_angle"]["bar"] * h3()["checks"]["wedge_angle"]["reference"]]
     if h3()["checks"]["wedge_angle"]["passed"] else [math.nan]),
    ("docs/hybrid.md", "(the intercept falls from {} m to {} m); at rest the scarp runs\n"
     "from the heel at {} deg",
     lambda: [_wedge("0.1", "intercept_m"), _wedge("2", "intercept_m"),
              h3()["discrete"]["moving_zone_back_at_rest"]["angle_deg"]]),
    ("docs/hybrid.md", "| inclination [deg] | {} | {} | {} | {} | {} | {} |",
     lambda: [*(_wedge(m, "angle_deg") for m in ("0.1", "0.2", "0.5", "1", "2")),
              h3()["discrete"]["moving_zone_back_at_rest"]["angle_deg"]]),
    ("docs/hybrid.md", "| base intercept [m] | {} | {} | {} | {} | {} | {} |",
     lambda: [*(_wedge(m, "intercept_m") for m in ("0.1", "0.2", "0.5", "1", "2")),
              h3()["discrete"]["moving_zone_back_at_rest"]["intercept_m"]]),
    # --- docs/hybrid.md: D10 ----------------------------------------------------------------
    ("docs/hybrid.md", "the handover residual is {} % of the face weight",
     lambda: [100.0 * d10()["handover_residual_over_face_weight"]]),
    ("docs/hybrid.md", "({} of {} interfaces: {} tension, {} shear), topples and rests at t = {} s",
     lambda: [d10()[k] for k in ("n_failed", "n_interfaces", "n_failed_tension",
                                 "n_failed_shear", "time")]),
    # --- docs/continuum.md ------------------------------------------------------------------
    ("docs/continuum.md", "(C5 and C6: {} % and {} % above it",
     lambda: [100 * row("C5", "limit_pressure", "error"),
              100 * row("C6", "limit_pressure", "error")]),
    ("docs/continuum.md", "The H2 footing's continuum phase (`make demo`, {} Q2 cells, psi = {}, "
     "pressure raised in {} increments to {} kPa) takes {} converged increments, {} Newton "
     "iterations and {} s of solver time to its collapse at {} kPa",
     lambda: [h2()["continuum"]["cells"], h2()["parameters"]["psi"],
              h2()["parameters"]["continuum_steps"], h2()["parameters"]["pressure"],
              h2()["continuum"]["steps"], h2()["continuum"]["newton_iterations"],
              h2()["continuum"]["wall_time_s"], h2()["continuum"]["collapse_pressure_kPa"]]),
    ("docs/continuum.md", "Bishop & Morgenstern's charts give {}; this project's Bishop search "
     "gives {} on the same section.",
     lambda: [row("C9", "factor_of_safety_H/16", "reference"), row("C9", "bishop_search")]),
    *[("docs/continuum.md", f"| {label} | {{}} ({{}} %) | {{}} ({{}} %) |",
       lambda mesh=mesh: [v for case in ("C9-associated", "C9")
                          for v in (row(case, f"factor_of_safety_{mesh}"),
                                    pct(row(case, f"factor_of_safety_{mesh}"),
                                        row(case, f"factor_of_safety_{mesh}", "reference")))])
      for label, mesh in (("H/16", "H/16"), ("H/24", "H/24"))],
    ("docs/continuum.md", "| H/32 ({} cells) | {} ({} %) | {} ({} %) |",
     lambda: [verify("C9")["stats"]["cells"],
              *[v for case in ("C9-associated", "C9")
                for v in (row(case, "factor_of_safety_H/32"),
                          pct(row(case, "factor_of_safety_H/32"),
                              row(case, "factor_of_safety_H/32", "reference")))]]),
    ("docs/continuum.md", "| spread | {} % | {} % |",
     lambda: [100 * row("C9-associated", "mesh_spread"), 100 * row("C9", "mesh_spread")]),
    ("docs/continuum.md", "The finest mesh runs to its F in {} s (psi = 0) and {} s (psi = phi) "
     "of solver time",
     lambda: [verify("C9")["stats"]["wall_time_s"],
              verify("C9-associated")["stats"]["wall_time_s"]]),
    ("docs/continuum.md", "F = {} / {} / {} on the three meshes against Bishop's {} (the "
     "finest {} % below it)",
     lambda: [*(row("C9-weak", f"factor_of_safety_H/{n}") for n in (16, 24, 32)),
              row("C9-weak", "bishop_search"),
              100 * row("C9-weak", "factor_of_safety_within_5_percent_of_bishop", "error")]),
    ("docs/continuum.md", "the limit pressure against Prandtl's {} kPa",
     lambda: [row("C6", "limit_pressure", "reference")]),
    ("docs/continuum.md", "C5 and C6 limit loads {} % and {} % above Prandtl (P2, {} cells); the "
     "psi = 0 plateau (C6-psi0) {} % below Prandtl",
     lambda: [100 * row("C5", "limit_pressure", "error"),
              100 * row("C6", "limit_pressure", "error"),
              *{verify(c)["stats"]["cells"] for c in ("C5", "C6", "C6-psi0")},
              -pct(row("C6-psi0", "limit_pressure"),
                   row("C6-psi0", "limit_pressure", "reference"))]),
    ("docs/hybrid.md", "| mesh | {} | {} | {} | {} | {} | {} | {} | {} | {} | mean | sd |",
     lambda: list(H3_LENGTHS)),
    *[("docs/hybrid.md", f"| {name} |" + " {} |" * 11, lambda stem=stem: _h3_row_runs(stem))
      for stem, name in (("h3", "structured, 0.5 m (default)"),
                         ("h3_unstructured", "unstructured quads, 0.5 m"))],
    *[("docs/hybrid.md", f"| {name} |" + " {} | - | {} | - | {} | - | {} | - | {} | {} | {} |",
       lambda stem=stem: _h3_row_runs(stem, H3_REFINED_LENGTHS))
      for stem, name in (("h3_size0.25", "structured, 0.25 m"),
                         ("h3_unstructured_size0.25", "unstructured quads, 0.25 m"),
                         (H3_FINEST, "structured, 0.125 m"))],
    ("docs/hybrid.md", "- **Refined once more, the grid's mean run-out moves by {} %.** On the "
     "grid of 0.125 m (eighty elements over the wall's height) the five runs (the same backfill "
     "lengths) average {} m, {} % from the 0.25 m grid's five (standard error {} %: less than "
     "one standard error from no change) and {} % from the 0.5 m grid's nine: on three grids "
     "the mean run-out stays within the 10 % bar. "
     "One run's run-out scatters by {} % (largest over smallest of the five); the wedge at "
     "0.1 H lies between {} and {} deg.", lambda: _h3_finest()),
    ("docs/hybrid.md", "The active thrust in the continuum, {} kN/m on the 0.125 m grid, falls by "
     "{} % from the 0.25 m grid's, after {} % from the 0.5 m one: each step within the 3 % bar "
     "of a limit load, but {} % over the three grids and still falling, so the thrust is not "
     "shown converged; on the finest grid it lies {} % above Rankine's {} kN/m (exact for a "
     "smooth base only: C8).", lambda: _h3_finest_thrust()),
    ("docs/hybrid.md", "One run's run-out scatters by {} % on the grid and {} % on the "
     "unstructured mesh (largest over smallest of nine runs), its wedge at 0.1 H by {} and {} "
     "deg: a single pair of runs can land on either side of the 10 % bar",
     lambda: _h3_scatter()
     if min(p := [100.0 * (1.0 - u / g) for g, u in zip(_h3_runouts("h3"),
                                                        _h3_runouts("h3_unstructured"))])
     <= 10.0 < max(p) else []),
    ("docs/hybrid.md", "Averaged over the nine runs, the unstructured mesh runs out {} % shorter "
     "than the grid ({} against {} m); the standard error of that shortfall, from the runs' "
     "standard deviations, is {} %. The shortfall is unlikely to be chance ({} standard errors "
     "from none), and its estimate lies beyond the 10 % bar, by less than one standard error "
     "({}): **the run-out is not verified across mesh types**, and nine runs on each cannot "
     "tell whether the mesh type alone moves it by more than the bar",
     lambda: a if (a := _h3_across()) and a[5] < 1.0 else []),
    ("docs/hybrid.md", "On refinement the 0.25 m grid's five runs average {} m, {} % from the "
     "0.5 m grid's nine (standard error {} %): within the bar. The unstructured mesh's five runs "
     "at 0.25 m average {} m, {} % beyond its nine at 0.5 m (standard error {} %: within the bar "
     "by about half a standard error only; one run, at 20 m, moves by {} %); their standard "
     "deviation is {} m against {} m at 0.5 m.",
     lambda: [m[0], abs(m[1]), m[2], *m[3:]] if (m := _h3_refined_means()) and m[4] > 0.0
     and 0.3 < (10.0 - m[4]) / m[5] < 0.7 else []),
    ("docs/hybrid.md", "The unstructured 0.25 m mesh's five runs average {} % short of the 0.25 m "
     "grid's five ({} against {} m; standard error {} %): within the 10 % bar, by {} standard "
     "errors, and {} standard errors from none, so five runs on each do not tell the two types "
     "apart. One pair of runs can still miss the bar: at 20 m the unstructured mesh runs out {} "
     "% short of the grid ({} against {} m).", lambda: _h3_refined_across()),
    ("docs/hybrid.md", "In the continuum the active thrust is {} kN/m on the unstructured 0.5 m "
     "mesh (the grid's: {}), and {} and {} kN/m on the 0.25 m grid and unstructured mesh.",
     _h3_thrusts),
    ("docs/hybrid.md", "0.5 m mesh by {} deg\n  (`test_retaining_wall_collapse_wedge_meshes`), "
     "both within one run's scatter",
     lambda: [d] if (d := _h3_change("h3", "h3_unstructured")[0]) <= _h3_scatter()[3]
     and _h3_change("h3", "h3_size0.25")[0] <= _h3_scatter()[2] else []),
    # --- docs/hybrid.md: R1 -----------------------------------------------------------------
    ("docs/hybrid.md", "aluminium bars, L0 = {} m (H0 = {} m at a = {}), phi = {} deg, c = 0, "
     "density {} t/m3, E = {} kPa, nu = {}",
     lambda: [r1("a0.5")["parameters"][k] for k in ("length",)]
     + [r1("a0.5")["parameters"]["length"] * r1("a0.5")["parameters"]["aspect"],
        r1("a0.5")["parameters"]["aspect"]]
     + [r1("a0.5")["parameters"][k] for k in ("phi", "density", "E", "nu")]),
    ("docs/hybrid.md", "unstructured triangles of size L0 / {} (random",
     lambda: [r1("a0.5")["parameters"]["nx"]]),
    ("docs/hybrid.md", "normal contact damping ratio zeta = {} (restitution {}:",
     lambda: [z := r1("a0.5")["parameters"]["contact_damping"], _restitution(z)]),
    ("docs/hybrid.md", "`make docs`), grains of L0 / {}:", lambda: [r1("a1")["parameters"]["nx"]]),
    ("docs/hybrid.md", "| {} | {} | - | {} | {} | {} | {} | {} | {} |", lambda: _r1_row("a0.5")),
    ("docs/hybrid.md", "| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n| 2 |",
     lambda: _r1_row("a1")),
    ("docs/hybrid.md", "| {} | {} | {} | - | {} | {} | {} | {} | {} |", lambda: _r1_row("a2")),
    ("docs/hybrid.md", "(phi_c = {} deg for a bulk {} deg)",
     lambda: [r1("a1")["grains"]["contact_phi_deg"], r1("a1")["grains"]["bulk_phi_deg"]]),
    *[("docs/hybrid.md", f"| a = {a} | {{}}, {{}} | {{}}, {{}} | {{}}, {{}} | "
       + ("-" if a == "0.5" else "{}") + ", {} |",
       lambda a=a: [v for run in _r1_packings(a) for v in (
           r1(run)["deposit"]["normalised_runout"], r1(run)["deposit"]["height_over_H0"])]
       + [v for v in (r1(f"a{a}")["deposit"]["references"]["rods2015_runout"],
                      r1(f"a{a}")["deposit"]["references"]["rods2015_height"])
          if v is not None])
      for a in ("0.5", "1", "2")],
    ("docs/hybrid.md", "The run-out of one run scatters by {} %, {} % and {} % (largest over "
     "smallest of the three packings) at a = 0.5, 1 and 2: up to as much as the bar",
     lambda: s if 12.0 <= max(s := [_r1_scatter(a) for a in ("0.5", "1", "2")]) <= 16.0
     else []),
    ("docs/hybrid.md", "final height at every aspect ratio in every packing** (at most {} % from "
     "the rods)",
     lambda: [g] if (g := max(abs(_r1_height_gap(run)) for a in ("0.5", "1", "2")
                              for run in _r1_packings(a))) <= 15.0 else []),
    ("docs/hybrid.md", "at a = 1 all three packings run out within 15 % of the rods, {} to {} % "
     "further (their mean {} % further); at a = 2 all three run {} to {} % further (their "
     "mean {} %)",
     lambda: [-max(_r1_gap(run) for run in _r1_packings("1")),
              -min(_r1_gap(run) for run in _r1_packings("1")),
              -sum(_r1_gap(run) for run in _r1_packings("1")) / 3.0,
              -max(_r1_gap(run) for run in _r1_packings("2")),
              -min(_r1_gap(run) for run in _r1_packings("2")),
              -sum(_r1_gap(run) for run in _r1_packings("2")) / 3.0]
     if all(-15.0 <= _r1_gap(run) < 0.0 for run in _r1_packings("1"))
     and all(_r1_gap(run) < -15.0 for run in _r1_packings("2")) else []),
    ("docs/hybrid.md", "ends {} m from the back wall, and the computed deposit {} m from it "
     "({} % further; (L_inf - L0) / L0 {} % beyond the measured one)",
     lambda: [x := ref.bui2008_final_surface()[-1][0], y := r1("a0.5")["deposit"]["runout_m"],
              100.0 * (y / x - 1.0),
              100.0 * (r1("a0.5")["deposit"]["normalised_runout"] / b - 1.0)]
     if (b := _bui_runout()) is not None else []),
    *[("docs/hybrid.md", f"| {words} | {{}}, {{}} | {{}}, {{}} | {{}}, {{}} |",
       lambda tail=tail: [r1(f"a{a}{tail}")["deposit"][k] for a in ("0.5", "1", "2")
                          for k in ("normalised_runout", "height_over_H0")])
      for words, tail in (("flat (the case's)", ""), ("rough", "_rough"))],
    ("docs/hybrid.md", "| the rods | -, {} | {}, {} | {}, {} |",
     lambda: [r1("a0.5")["deposit"]["references"]["rods2015_height"],
              *[r1(f"a{a}")["deposit"]["references"][k] for a in ("1", "2")
                for k in ("rods2015_runout", "rods2015_height")]]),
    ("docs/hybrid.md", "The rough floor shortens the run-out (L_inf - L0) / L0 by {}, {} and {} % "
     "at a = 0.5, 1 and 2", _r1_floor),
    ("docs/hybrid.md", "On these grains (L0 / {}) the rods lie between the two floors: at a = 1 "
     "and 2 the rough floor runs {} and {} % short of them and the flat one {} and {} % beyond",
     lambda: [r1("a1")["parameters"]["nx"], _r1_gap("a1_rough"), _r1_gap("a2_rough"),
              -_r1_gap("a1"), -_r1_gap("a2")]),
    ("docs/hybrid.md", "ends between the two floors too: {} m from the back wall, against {} m "
     "on the rough floor and {} m on the flat one ((L_inf - L0) / L0 {} % short of the "
     "measured one and {} % beyond it)",
     lambda: [ref.bui2008_final_surface()[-1][0],
              r1("a0.5_rough")["deposit"]["runout_m"], r1("a0.5")["deposit"]["runout_m"],
              100.0 * (1.0 - r1("a0.5_rough")["deposit"]["normalised_runout"] / b),
              100.0 * (r1("a0.5")["deposit"]["normalised_runout"] / b - 1.0)]
     if (b := _bui_runout()) is not None else []),
    ("docs/hybrid.md", "(the flat floor's over the rough one's: {} and {} % at a = 1 and 2, "
     "against {} and {} % between 2 deg less and 2 deg more than the calibrated angle, above)",
     lambda: [100.0 * _rel_spread([r1(f"a{a}{t}")["deposit"]["normalised_runout"]
                                   for t in ("", "_rough")]) for a in ("1", "2")]
     + [100.0 * _rel_spread([r1(f"a{a}_phic{c}")["deposit"]["normalised_runout"]
                             for c in (9.1, 13.1)]) for a in ("1", "2")]),
    ("docs/hybrid.md", "the column keeps its area and within {} % its number of grains",
     lambda: [max(100.0 * abs(1.0 - r1(f"a{a}_rough")["discrete"]["column_elements"]
                              / r1(f"a{a}")["discrete"]["column_elements"])
                  for a in ("0.5", "1", "2"))]),
    ("docs/hybrid.md", "less than the run-out: on the rough floor it is within {} % of the "
     "rods' at a = 1 and 2",
     lambda: [g] if (g := max(abs(_r1_height_gap(f"a{a}_rough")) for a in ("1", "2")))
     <= 5.0 else []),
    ("docs/hybrid.md", "L_inf grows by {} and {} % from L0 / 10 to L0 / 20 and on to L0 / 30 at "
     "a = 0.5, and by {} and {} % at a = 1, against {} and {} %, {} and {} % on the flat floor "
     "(above)", lambda: [v for g in _r1_rough_grain_size().values() for a in ("0.5", "1")
                        for v in g[a][:2]]),
    ("docs/hybrid.md", "(from L0 / 10 to L0 / 30, {} against {} % at\na = 0.5 and {} against {} % "
     "at a = 1), not enough for the 10 % bar",
     lambda: [g[floor][a][2] for a in ("0.5", "1") for floor in ("rough", "flat")]
     if (g := _r1_rough_grain_size()) else []),
    ("docs/hybrid.md", "barely moves at a = 0.5 ((L_inf - L0) / L0 {}: its stacked squares "
     "stand without lateral support) and at a = 1 and 2 runs out less far than the triangles "
     "((L_inf - L0) / L0 {} and {}, H_inf / H0 {} and {})",
     lambda: [r1("a0.5_squares")["deposit"]["normalised_runout"],
              *[r1(f"a{a}_squares")["deposit"]["normalised_runout"] for a in ("1", "2")],
              *[r1(f"a{a}_squares")["deposit"]["height_over_H0"] for a in ("1", "2")]]
     if r1("a0.5_squares")["deposit"]["normalised_runout"] < 0.05
     and all(r1(f"a{a}_squares")["deposit"]["normalised_runout"]
             < r1(f"a{a}")["deposit"]["normalised_runout"] for a in ("1", "2"))
     and all((r1(f"a{a}_squares")["parameters"]["cells"], r1(f"a{a}_squares")["parameters"][
         "structured"]) == ("quadrilateral", True) for a in ("0.5", "1", "2")) else []),
    ("docs/hybrid.md", "the perfectly plastic soil stalls\n  the same way on the refined "
     "triangles, at {} kPa",
     lambda: [q] if (q := _stopped_at("h2_load_triangle_fine0.04_perfect", "load factor",
                                      RAN_AWAY_NOT)) == q else []),
    ("docs/hybrid.md", "The case's floor is a smooth plane on which a grain slides at the "
     "contact angle\n({} deg)", lambda: [r1("a1")["grains"]["contact_phi_deg"]]),
    *[("docs/hybrid.md", f"| {a} | {{}}, {{}} | {{}}, {{}} | {{}}, {{}} |",
       lambda a=a: [v for run in (f"a{a}_nx10", f"a{a}", f"a{a}_nx30")
                    for v in (r1(run)["deposit"]["normalised_runout"],
                              r1(run)["deposit"]["height_over_H0"])])
      for a in ("0.5", "1", "2")],
    ("docs/hybrid.md", "| 0.5 | {}, {} | {}, {}; {}, {}; {}, {} | {}, {} | {}, {} |",
     lambda: _r1_fine_row("0.5", ("30", "40-", "40", "40+", "50", "60"))),
    ("docs/hybrid.md", "| 1 | {}, {} | {}, {}; {}, {}; {}, {} | - | {}, {}; {}, {}; {}, {} |",
     lambda: _r1_fine_row("1", ("30", "40-", "40", "40+", "60-", "60", "60+"))),
    ("docs/hybrid.md", "the rough floor's run-out grows on: L_inf is {} and {} m at L0 / 40 and 60 "
     "at a = 0.5 ({} and {} % beyond the size before), {} and {} m at a = 1 ({} and {} %); its "
     "teeth are half a grain high",
     lambda: g if (g := _r1_rough_growth())  # the case's teeth: half a grain high
     and "roughness=0.5 * size" in (CASES / "granular_collapse.py").read_text() else []),
    ("docs/hybrid.md", "On grains of L0 / 60 at a = 0.5 the rough floor's deposit ends {} % short "
     "of Bui et al.'s measured one ({} against {} m), within the flat floor's packing scatter "
     "at L0 / 40 ({} %) and still growing, the flat floor's {} % beyond it ({} m)",
     lambda: [*v[:3], c[4], *v[3:]] if (v := _r1_rough_vs_bui()) and (c := _r1_fine_converged())
     and v[0] < c[4] and _r1_rough_growth() else []),
    ("docs/hybrid.md", "at a = 1 the rough floor's (L_inf - L0) / L0 on grains of L0 / 40 is {}, "
     "{} % short of the rods' {}, the flat floor's {} to {} on the same grains (three packings) "
     "{} to {} % beyond, and on grains of L0 / 60 {} on the rough floor ({} % short) and {} to {} "
     "on the flat one (three packings, {} to {} % beyond). So on the grains where the flat "
     "floor's run-out stops growing the rods at a = 1 still lie between the two floors",
     _r1_rough_vs_rods),
    ("docs/hybrid.md", "and at a = 0.5 the rough floor ends within {} % of the measured deposit "
     "where the flat one overshoots it by a third",
     lambda: [v[0]] if (v := _r1_rough_vs_bui()) else []),
    ("docs/hybrid.md", "These grains (L0 / {}) are too coarse for a converged run-out: on finer "
     "ones it runs further still, beyond the bar at a = 0.5 (the deposit's end against Bui et "
     "al.'s) and 1 too",
     lambda: [r1("a1")["parameters"]["nx"]] if _r1_fine_converged() and _r1_fine_beyond()
     and all(_r1_fine_runout(a, "60") > r1(f"a{a}")["deposit"]["runout_m"] for a in ("0.5", "1"))
     else []),
    ("docs/hybrid.md", "| 2 | {}, {} | -; {}, {}; - | - | - |",
     lambda: _r1_fine_row("2", ("30", "40"))),
    ("docs/hybrid.md", "At a = 2 (one packing on each grain size) L_inf moves by {} % from L0 / 30 "
     "to L0 / 40, and on grains of L0 / 40 (L_inf - L0) / L0 is {}, {} % beyond the rods' {}, the "
     "final height within {} % of theirs",
     lambda: [pct(_r1_fine_runout("2", "40"), _r1_fine_runout("2", "30")),
              d["normalised_runout"], pct(d["normalised_runout"], r["rods2015_runout"]),
              r["rods2015_runout"], abs(pct(d["height_over_H0"], r["rods2015_height"]))]
     if (d := _r1_fine_deposit("2", "40")) and (r := d["references"])
     and 0.0 < pct(_r1_fine_runout("2", "40"), _r1_fine_runout("2", "30")) else []),
    ("docs/hybrid.md", "At a = 0.5 and 1 the run-out stops growing beyond L0 / 40, within one "
     "packing's scatter: the three packings at L0 / 40 scatter by {} and {} % (largest over "
     "smallest); at a = 0.5 the runs on finer grains end within their range (the L0 / 40 "
     "packings' mean L_inf, {} m, is {} % from the run at L0 / 60), and at a = 1 the three "
     "packings at L0 / 60 average {} m, {} % beyond the three at L0 / 40 ({} m), and scatter "
     "by {} %. From L0 / 30 to L0 / 60 L_inf moves by {} % at a = 0.5 and by {} to {} % at "
     "a = 1 (three packings), within the 10 % bar (from L0 / 10 to L0 / 20 by {} and {} %)",
     lambda: [c[4], c[5], c[6], c[8], *p, c[0], min(m), max(m), c[2], c[3]]
     if (c := _r1_fine_converged()) and (p := _r1_fine_packings()) and p[1] > 0.0
     and (m := [pct(_r1_fine_runout("1", k), _r1_fine_runout("1", "30"))
                for k in ("60-", "60", "60+")]) and min(m) > 0.0 else []),
    ("docs/hybrid.md", "The final height falls from L0 / 40 to L0 / 60: at L0 / 60 it is lower "
     "than in every packing at L0 / 40 at both aspect ratios; at a = 1, where it did not fall "
     "from L0 / 30 to L0 / 40, the three packings' mean falls by {} % ({} to {}), every packing "
     "at L0 / 60 ({} to {}) below every one at L0 / 40 ({} to {}). The step is within the 10 "
     "% bar, and as large as the L0 / 60 packings' own scatter in height ({} %), but it is "
     "one step with all three packings on the same side, so the final height is not shown "
     "converged.",
     _r1_fine_height_trend),
    ("docs/hybrid.md", "The run-out it stops at lies **beyond the experiments**: at L0 / 60 "
     "(L_inf - L0) / L0 is {} at a = 0.5, against {} from Bui et al.'s measured surface (L_inf {} "
     "against {} m, {} % further), and {} to {} at a = 1 (three packings), {} to {} % beyond the "
     "rods' {} (the three packings at L0 / 40: {} to {} % beyond)", _r1_fine_beyond),
    ("docs/hybrid.md", "The final height at a = 1 is within 15 % of the rods' ({} to {} against "
     "{}); at a = 0.5 it is {} at L0 / 60 (the rods: {})", _r1_fine_heights),
    ("docs/hybrid.md", "at a = 1 the table's grains of L0 / 20 came within it ({} % beyond the "
     "rods on average over three packings, above)",
     lambda: [-statistics.mean(_r1_gap(run) for run in _r1_packings("1"))]
     if all(-15.0 <= _r1_gap(run) < 0.0 for run in _r1_packings("1")) and _r1_fine_beyond()
     else []),
    ("docs/hybrid.md", "L_inf grows by {} %, {} % and {} % from L0 / 10 to L0 / 20 at a = 0.5, "
     "1 and 2",
     lambda: [100.0 * (r1(f"a{a}")["deposit"]["runout_m"] / r1(f"a{a}_nx10")["deposit"][
         "runout_m"] - 1.0) for a in ("0.5", "1", "2")]),
    ("docs/hybrid.md", "(L_inf by {} %, {} % and {} % from L0 / 20 to L0 / 30 at a = 0.5, 1 "
     "and 2)",
     lambda: [100.0 * (r1(f"a{a}_nx30")["deposit"]["runout_m"] / r1(f"a{a}")["deposit"][
         "runout_m"] - 1.0) for a in ("0.5", "1", "2")]),
    ("docs/hybrid.md", "Three more packings ({}, {} and {} grains across; "
     "`python -m hybrid.discrete.biaxial --across {} {} {}`, kept apart in `CALIBRATION_CHECK`)",
     lambda: [*bx.CHECK_PACKINGS] * 2),
    ("docs/hybrid.md", "scatter more widely still (the seven span up to {} deg of bulk angle "
     "at one contact angle): with them the mean curve moves by at most {} deg and the contact "
     "angle for 19.8 deg from {} to {} deg, a shift far inside the curve's uncertainty",
     _calibration_check),
    ("docs/hybrid.md", "the default quadrilaterals settle {} m since the handover and heave {} m, "
     "{} and {} % from the load-controlled run's; the triangles settle {} m, {} % "
     "less than "
     "the quadrilaterals, and heave {} m, {} % less ({} failed interfaces against {})",
     _h2_rest_figures),
    ("docs/hybrid.md", "| default quads 0.08 m | load, {} | {} | {} | {} |",
     lambda: [_h2_hold_steps("default"), h2()["continuum"]["collapse_pressure_kPa"],
              (c := _h2_hold("default"))["collapse_pressure_kPa"], c["held_increments"]]),
    ("docs/hybrid.md", "| quads 0.08 m, 0.1 % wider | load, {} | stalls before the collapse | "
     "{} | {} |", lambda: [_h2_hold_steps("W4.8048"),
                           (c := _h2_hold("W4.8048"))["collapse_pressure_kPa"],
                           c["held_increments"]] if _h2_load_stopped("W4.8048") else []),
    ("docs/hybrid.md", "| structured quads 0.04 m | load, {} | {} | {} | {} |",
     lambda: [(s := _json("docs/summaries/h2_structured_fine0.04.json"))["parameters"][
         "continuum_steps"], s["continuum"]["collapse_pressure_kPa"],
         (c := _h2_hold("structured_fine0.04"))["collapse_pressure_kPa"], c["held_increments"]]),
    ("docs/hybrid.md", "| refined quads 0.04 m | load, {} | {} | stops at {}, the settlement not "
     "running away | - |",
     lambda: [24, _json("docs/summaries/h2_fine0.04.json")["continuum"]["collapse_pressure_kPa"],
              _stopped_at("h2_hold_fine0.04", "load factor", RAN_AWAY_NOT)]
     if _h2_hold_fine_stop() else []),
    ("docs/hybrid.md", "| triangles, 0.08 m | load, {} | stalls at {} | stalls at {} | - |",
     lambda: [24, _stopped_at("h2_load_triangle", "load factor", RAN_AWAY_NOT),
              _stopped_at("h2_hold_triangle", "load factor", RAN_AWAY_NOT)]),
    ("docs/hybrid.md", "| structured quads, 0.08 m | settlement, {} | {} | {} | {} |",
     lambda: [_h2_hold_steps("settlement_structured"), _h2_settlement("structured"),
              (c := _h2_hold("settlement_structured"))["collapse_pressure_kPa"],
              c["held_increments"]]),
    ("docs/hybrid.md", "| triangles, 0.08 m | settlement, {} | {} | stalls at {} | - |",
     lambda: [100, _h2_settlement("triangle_steps100"),
              _stopped_at("h2_hold_settlement_triangle_steps100", "largest value",
                          "Newton stalled")]),
    ("docs/hybrid.md", "and the ramp collapses at {} kPa, {} % below the 0.08 m structured mesh "
     "and {} % below the default mesh, within the 3 % bar", _h2_hold_refined),
    ("docs/hybrid.md", "The mesh 0.1 % wider, whose load ramp stalls, collapses at {} kPa, {} % "
     "from the default mesh, as under settlement control",
     _h2_hold_wider),
    ("docs/hybrid.md", "an increment whose settlement did not run away ({} times the first "
     "increment's rate, below the collapse test's 10)", _h2_hold_fine_stop),
    ("docs/hybrid.md", "starts from the plain ramp's stop, {} % below the collapse.",
     lambda: [100.0 * (1.0 - _json("docs/summaries/h2_structured_fine0.04.json")["continuum"][
         "collapse_pressure_kPa"] / _h2_hold("structured_fine0.04")["collapse_pressure_kPa"])]),
    ("docs/hybrid.md", "| quads 0.08 m (default) | {} | {} | {} |",
     lambda: [24, _h2_settlement("default"), h2()["continuum"]["collapse_pressure_kPa"]]),
    ("docs/hybrid.md", "| quads 0.08 m, half-width 4.8048 m | {} | {} | stalls before the "
     "collapse |", lambda: [24, _h2_settlement("W4.8048")]
     if _h2_load_stopped("W4.8048") else []),
    *[("docs/hybrid.md", f"| {label} | {{}} | {{}} | {{}} |",
       lambda n=n, m=m: [24, _h2_settlement(n),
                         _json(f"docs/summaries/{m}.json")["continuum"]["collapse_pressure_kPa"]])
      for label, n, m in (("structured quads 0.08 m", "structured", "h2_structured"),
                          ("quads 0.04 m", "fine0.04", "h2_fine0.04"))],
    ("docs/hybrid.md", "| structured quads 0.04 m | {} | stalls before the peak | stalls (in {} "
     "increments: {}) |",
     lambda: [24, (s := _json("docs/summaries/h2_structured_fine0.04.json"))["parameters"][
         "continuum_steps"], s["continuum"]["collapse_pressure_kPa"]]
     if _h2_settlement_stopped("structured_fine0.04") else []),
    ("docs/hybrid.md", "| triangles 0.08 m | {} | stalls before the peak | stalls |",
     lambda: [24] if _h2_settlement_stopped("triangle") and _h2_load_stopped("triangle")
     else []),
    ("docs/hybrid.md", "| triangles 0.08 m | {} | {} | |",
     lambda: [100, _h2_settlement("triangle_steps100")]),
    ("docs/hybrid.md", "The four quadrilateral meshes that reach the peak agree within {} %, "
     "within the 3 % bar", lambda: _h2_settlement_agreement()[:1]),
    ("docs/hybrid.md", "each within {} % of its own load-controlled collapse; the mesh {} % "
     "wider, whose load ramp stalls, collapses within {} % of the default one",
     lambda: [a[1], 100.0 * (4.8048 / h2()["parameters"]["width"] - 1.0), a[2]]
     if (a := _h2_settlement_agreement()) else []),
    ("docs/hybrid.md", "outside the bar (strict xfail "
     "`test_footing_failure_collapse_load_triangles`), where without softening the two cell "
     "shapes agree within {} % (above)",
     lambda: _h2_perfect()[2:]),
    ("docs/hybrid.md", "in {} ({} mm) it passes the peak at {} kPa, {} % below the default "
     "quadrilaterals under the same control: outside the bar",
     lambda: [(p := _json("docs/summaries/h2_settlement_triangle_steps100.json")["parameters"])[
         "continuum_steps"], 1e3 * p["continuum_settlement"] / p["continuum_steps"],
         *_h2_triangle_gap()] if _h2_triangle_gap() else []),
    ("docs/hybrid.md", "Under settlement control (below) the triangles pass the peak, {} % below "
     "the quadrilaterals", lambda: _h2_triangle_gap()[1:]),
    ("docs/hybrid.md", "collapses on the triangles at {} kPa and on the quadrilaterals at {} kPa: "
     "on the default size and without softening the cell shape moves the limit load by {} %",
     _h2_perfect),
    ("docs/hybrid.md", "| none: zeta = {}, E = {} kPa, phi_c = {} deg | {}, {} | {}, {} |",
     lambda: [r1("a1")["parameters"]["contact_damping"], r1("a1")["parameters"]["E"],
              r1("a1")["grains"]["contact_phi_deg"]]
     + [r1(f"a{a}")["deposit"][k] for a in ("1", "2")
        for k in ("normalised_runout", "height_over_H0")]),
    *[("docs/hybrid.md", f"| contact damping zeta = {z} (restitution {{}}) | {{}}, {{}} | "
       "{}, {} |", lambda z=z: [_restitution(z), *_r1_variant(f"zeta{z}", "contact_damping", z)])
      for z in (0.1, 0.6)],
    ("docs/hybrid.md", "| grains ten times stiffer, E = {} kPa | {}, {} | {}, {} |",
     lambda: [e := 10.0 * r1("a1")["parameters"]["E"], *_r1_variant("E8400", "E", e)]),
    *[("docs/hybrid.md", f"| contact angle phi_c = {c} deg (the calibrated one {words} deg) | "
       "{}, {} | {}, {} |", lambda c=c, d=d: _r1_variant(f"phic{c}", "contact_phi", c)
       if abs(c - r1("a1")["grains"]["contact_phi_deg"] - d) < 0.05 else [])
      for c, words, d in ((9.1, "less 2", -2.0), (12.1, "and 1", 1.0), (13.1, "and 2", 2.0))],
    ("docs/hybrid.md", "change the run-out by up to {} % at a = 1 and {} % at a = 2 from the "
     "case's run, against one packing's scatter of {} and {} % (above): at a = 1 by more "
     "than that scatter, at a = 2 by about as much, so there one packing per run cannot tell "
     "their effect from it", _r1_damping_moves),
    ("docs/hybrid.md", "At a = 2 the most damped contacts (zeta = 0.6) and the stiffer grains "
     "bring this packing's run-out within 15 % of the rods ({} and {} % beyond), the least "
     "damped contacts do not ({} % beyond)",
     lambda: [-_r1_gap("a2_zeta0.6"), -_r1_gap("a2_E8400"), -_r1_gap("a2_zeta0.1")]
     if all(0.0 <= -_r1_gap(f"a2_{v}") <= 15.0 for v in ("zeta0.6", "E8400"))
     and -_r1_gap("a2_zeta0.1") > 15.0 else []),
    ("docs/hybrid.md", "The contact angle moves the run-out most at a = 1: 2 deg less than the "
     "calibrated angle by {} % ({} % beyond the rods), 2 deg more by {} % ({} % short of the "
     "rods); at a = 2 by {} and {} % ({} and {} % beyond the rods); at a = 2 the most damped "
     "contacts move it as much ({} %). The final height is lowest at {} deg less than the "
     "calibrated angle and highest at {} deg more, at both aspect ratios",
     lambda: [*m, 2, 2] if (m := _r1_angle_moves()) and _r1_heights_ends() else []),
    ("docs/hybrid.md", "this packing's run-out and final height within 15 % of the rods at both "
     "aspect ratios (the largest gap {} %)",
     lambda: [g] if (g := max(max(abs(_r1_gap(f"a{a}_phic12.1")),
                                  abs(_r1_height_gap(f"a{a}_phic12.1"))) for a in ("1", "2")))
     <= 15.0 else []),
    ("docs/hybrid.md", "calibrated angle (its uncertainty either side) differ by {} % and {} % "
     "in run-out and by {} % and {} % in final height at a = 1 and 2 (the larger over the "
     "smaller)",
     _r1_angle_spans),
    ("docs/hybrid.md", "more lifts the final height at a = 1 to {} % above the rods'",
     lambda: [g] if (g := _r1_height_gap("a1_phic13.1")) > 15.0 else []),
    ("docs/hybrid.md", "so its gap ({} to {} % over the three packings, above)",
     lambda: [-max(_r1_gap(run) for run in _r1_packings("2")),
              -min(_r1_gap(run) for run in _r1_packings("2"))]
     if all(_r1_gap(run) < -15.0 for run in _r1_packings("2")) else []),
    ("docs/hybrid.md", "whose run-out scatters by {} and {} % at a = 1 and 2: above",
     lambda: [_r1_scatter(a) for a in ("1", "2")]),
    ("docs/hybrid.md", "| the rods | {}, {} | {}, {} |",
     lambda: [r1(f"a{a}")["deposit"]["references"][k] for a in ("1", "2")
              for k in ("rods2015_runout", "rods2015_height")]),
    # --- docs/carsington.md: one run is one sample ------------------------------------
    ("docs/carsington.md", "| 6 | {}, {} | {}, {} | {}, {} |\n  | 4 | {}, {} | {}, {} | {}, {} "
     "|\n  | 3 | {}, {} | {}, {} | {}, {} |",
     lambda: [v for z in ("", "_size4", "_size3") for d in _cars_samples(z)
              for v in (d["toe_runout_m"], d["crest_drop_m"])]),
    ("docs/carsington.md", "One run's toe movement scatters by at least {}, {} and {} % on the 6, "
     "4 and 3 m meshes (largest over smallest of three runs), its crest drop by {}, {} and {} %. "
     "The three runs' mean toe movements on the 4 and 3 m meshes ({} and {} m) are {} % apart, "
     "more than either mesh's scatter", _cars_sample_spreads),
    ("docs/carsington.md", "and a crack from the crest opens during the slide ({} m deep, {} m "
     "open at the crest's top at most)",
     lambda: [(d := _soft_disc("carsington_discrete_softening"))[
         "crest_crack_during_slide_deepest_m"], d["crest_crack_during_slide_surface_opening_m"]]
     if _json("docs/summaries/carsington_discrete_softening.json")["checks"]["crack_at_crest"][
         "passed"] else []),
    ("docs/carsington.md", "on the 3 m mesh one of the three advances {} m, within 30 % of the "
     "observed {} m",
     lambda: [t, 12.0] if [abs(d["toe_runout_m"] / 12.0 - 1.0) <= 0.3
                           for d in _cars_samples("_size3")].count(True) == 1
     and (t := max(d["toe_runout_m"] for d in _cars_samples("_size3"))) else []),
    ("docs/carsington.md", "the three runs' means on the 4 and 3 m meshes ({} and {} m) are {} % "
     "apart, within 30 % of the observed {} m. None of the nine runs opens a crack 0.1 m wide "
     "from the crest during the slide",
     lambda: [a, b, 100.0 * abs(a / b - 1.0), 10.0]
     if min(a := sum(d["crest_drop_m"] for d in _cars_samples("_size4")) / 3.0,
            b := sum(d["crest_drop_m"] for d in _cars_samples("_size3")) / 3.0) >= 7.0
     and not any(d["crest_crack_during_slide_seen"] for z in ("", "_size4", "_size3")
                 for d in _cars_samples(z)) else []),
]


def _cars_discrete(name: str) -> list[float]:
    """Toe movement, crest drop, failed interfaces and rest time of a Carsington run."""
    d = _json(f"docs/summaries/{name}.json")["discrete"]
    return [d["toe_runout_m"], d["crest_drop_m"], d["interfaces_failed"], d["time_s"]]


def _default_onset() -> list[float]:
    """Where failure begins in the default run: the first check's time and its bonds (all,
    beside the yellow clay, at the crest's top, elsewhere); the crest's failed bonds; the
    run's failed bonds by mode. The words: the yellow clay's bonds at the first check fail
    in shear, the crest's top fails at it too, all in tension, and the run's bonds fail in
    tension, shear or as distorted fragments only."""
    d = carsington()["discrete"]
    first, onset, modes = d["first_failures"], d["failure_onset"], d["interfaces_failed_by_mode"]
    assert math.isclose(first["time_s"], 10 * d["dt_s"], rel_tol=1e-9)  # the run's first check
    assert first["interfaces"] == first["yellow_clay"] + first["crest_top"] + first["elsewhere"]
    assert onset["yellow_clay"]["first_failure_s"] == first["time_s"]
    assert onset["yellow_clay"]["first_failure_modes"] == {"shear": first["yellow_clay"]}
    assert onset["crest_top"]["first_failure_s"] == first["time_s"]
    assert onset["crest_top"]["first_failure_modes"] == {"tension": first["crest_top"]}
    crest = onset["crest_top"]["failed_by_mode"]
    assert set(crest) == {"tension"}
    assert d["interfaces_failed"] == modes["tension"] + modes["shear"] + modes["distorted"]
    return [first["time_s"], first["interfaces"], first["yellow_clay"], first["crest_top"],
            first["elsewhere"], crest["tension"], d["interfaces_failed"], modes["tension"],
            modes["shear"], modes["distorted"]]


def _default_onset_core() -> float:
    """When the core's first bond fails in the default run [s]. The words: the boot's and the
    upstream shoulder's fail at the first check, the core's later."""
    onset = carsington()["discrete"]["failure_onset"]
    first = onset["anywhere"]["first_failure_s"]
    assert onset["boot"]["first_failure_s"] == first
    assert onset["upstream_shoulder"]["first_failure_s"] == first
    assert onset["core"]["first_failure_s"] > first
    return onset["core"]["first_failure_s"]


def _core_face(name: str) -> dict[str, float]:
    """How much of the core's boundary with Zone I upstream of the axis slipped in a run."""
    return _json(f"docs/summaries/{name}.json")["discrete"]["slip_along_core_upstream_face"]


def _core_face_pct(name: str) -> float:
    """The share of that boundary's length that slipped [%]."""
    face = _core_face(name)
    return 100.0 * face["slipped_length_m"] / face["length_m"]


def _core_face_softening() -> list[float]:
    """That boundary's length on the softening meshes [m] (one figure: they agree within
    0.5 m), the share slipped on each [%], the least and largest largest slip [m]; the
    default's share [%], length [m] and largest slip [m]; the discrete softening run's share
    [%]. The words: at least 70 % slips on every softening mesh."""
    faces = [_core_face(n) for n in SOFT_MESHES]
    length = [f["length_m"] for f in faces]
    assert max(length) - min(length) < 0.5
    pct = [_core_face_pct(n) for n in SOFT_MESHES]
    assert min(pct) >= 70.0
    most = [f["max_slip_m"] for f in faces]
    default = _core_face("carsington")
    return [statistics.mean(length), *pct, min(most), max(most), _core_face_pct("carsington"),
            default["length_m"], default["max_slip_m"],
            _core_face_pct("carsington_discrete_softening")]


def _cars_discrete_runs() -> list[dict[str, Any]]:
    """Every committed Carsington run with a discrete phase."""
    runs = [json.loads(p.read_text())
            for p in sorted((ROOT / "docs" / "summaries").glob("carsington*.json"))]
    return [r for r in runs if "discrete" in r]


def _onset_everywhere() -> list[float]:
    """The runs with a discrete phase, in how many every failed bond at the crest's top fails
    in tension, in how many the crest's top fails at the first check, the latest it fails
    after it [s], the fewest and most bonds the first check fails elsewhere, in how many
    runs the core's fail at it. The words: in every run the first check that fails a bond is
    the run's first (10 steps in), the yellow clay's bonds fail at it, the crest's first
    failed bonds fail in tension (its others in tension or as softened), bonds elsewhere fail
    at it; in the design-height runs with softening most of its bonds fail as softened."""
    runs = _cars_discrete_runs()
    lag, elsewhere, all_tension, core = [], [], 0, 0
    for r in runs:
        d = r["discrete"]
        onset, first = d["failure_onset"], d["first_failures"]
        assert math.isclose(first["time_s"], 10 * d["dt_s"], rel_tol=1e-9)
        assert onset["yellow_clay"]["first_failure_s"] == first["time_s"]
        assert set(onset["crest_top"]["first_failure_modes"]) == {"tension"}
        modes = set(onset["crest_top"]["failed_by_mode"])
        assert modes <= {"tension", "softened"}
        all_tension += modes == {"tension"}
        lag.append(onset["crest_top"]["first_failure_s"] - first["time_s"])
        elsewhere.append(first["elsewhere"])
        core += onset["core"]["first_failure_s"] == first["time_s"]
        if r["parameters"]["discrete_softening"] and d["start"] == "end of construction " \
                "(design height)":
            softened = onset["anywhere"]["first_failure_modes"].get("softened", 0)
            assert 2 * softened > first["interfaces"], r["out"]
    assert min(elsewhere) > 0
    return [len(runs), all_tension, sum(x == 0.0 for x in lag), max(lag), min(elsewhere),
            max(elsewhere), core]


# the softening analysis (u_r 0.5 m) on the 8, 6, 5, 4, 3, 2.5, 2 and 1.5 m meshes
SOFT_MESHES = ("carsington_softening_size8", "carsington_softening",
               "carsington_softening_size5", "carsington_softening_size4",
               "carsington_softening_size3", "carsington_softening_size2.5",
               "carsington_softening_size2", "carsington_softening_size1.5")


# the most a Carsington post-failure movement may change from one mesh to the next [%]
MESH_BAR = 100.0 * MESH_CHANGE


# the design-height analysis with softening in the discrete phase on the 6, 4, 3 and 2 m meshes
DESIGN_HEIGHT_MESHES = ("carsington_design_height_softening",
                        "carsington_design_height_softening_size4",
                        "carsington_design_height_softening_size3",
                        "carsington_design_height_softening_size2")


# from the design height with the yellow clay 25 m long and the fill above 194 m OD in 0.5 m
# parts: the thesis's discrete phase on the 3 m mesh, then softening on the 4, 3 and 2 m meshes
DESIGN_HEIGHT_PARTS = ("carsington_design_height_parts",
                       "carsington_design_height_parts_softening_size4",
                       "carsington_design_height_parts_softening_size3",
                       "carsington_design_height_parts_softening_size2")


def _design_height_parts(name: str) -> dict[str, Any]:
    """A design-height run of the 25 m section in parts: its summary, checked to be the run
    its name labels (mesh size, yellow clay, parts, softening in the discrete phase only) and
    to have carried the fill to the crest; a ValueError otherwise."""
    d = _json(f"docs/summaries/{name}.json")
    p = d["parameters"]
    tail = name.removeprefix("carsington_design_height_parts")
    size, _, length = tail.removeprefix("_softening").removeprefix("_size").partition("_Y")
    label = (float(size or 3.0), float(length or 25.0), 194.0, 0.5, tail.startswith("_softening"),
             False)
    if (p["size"], p["yellow_clay_length"], p["parts_above"], p["part_height"],
            p["discrete_softening"], p["softening"]) != label or not d["construction"][
            "completed"] or d["discrete"]["start"] != "end of construction (design height)":
        raise ValueError(f"{name}: not the run its label says")
    if not length and size in ("3", "2"):  # the words: the Sensitivity table's 25 m run
        base = _json(f"docs/summaries/carsington_parts_size{size}_Y25.json")
        changed = {k for k in p if p[k] != base["parameters"][k]}
        if changed - {"discrete_softening", "discrete_time"} or d["core_displacement_mm"] != \
                base["core_displacement_mm"]:
            raise ValueError(f"{name}: its continuum stage is not carsington_parts_size{size}_Y25")
    return d


def _design_height_parts_row(name: str) -> list[float]:
    """Cells, toe, crest drop, the crest crack's first time [s] and depth [m], the widest
    opening at the crest's top [m] and failed interfaces of a design-height run in parts; a
    ValueError unless its crack check passed (the table gives a time for every run)."""
    d = _design_height_parts(name)
    disc = d["discrete"]
    if not d["checks"]["crack_at_crest"]["passed"]:
        raise ValueError(f"{name}: no crack open 0.1 m from the crest")
    if disc["crest_crack_during_slide_deepest_time_s"] != disc[
            "crest_crack_during_slide_first_time_s"]:  # the words: that crack's depth
        raise ValueError(f"{name}: the deepest crack is not the first")
    onset = disc["failure_onset"]
    if not (onset["crest_top"]["first_failure_s"] > onset["yellow_clay"]["first_failure_s"]
            == disc["first_failures"]["time_s"]) or set(
            onset["crest_top"]["first_failure_modes"]) != {"tension"}:
        raise ValueError(f"{name}: not the yellow clay first and the crest later, in tension")
    return [d["mesh"]["cells"], disc["toe_runout_m"], disc["crest_drop_m"],
            disc["crest_crack_during_slide_first_time_s"],
            disc["crest_crack_during_slide_deepest_m"],
            disc["crest_crack_during_slide_surface_opening_m"], disc["interfaces_failed"]]


def _design_height_cracks() -> list[float]:
    """The crest crack in the design-height runs in parts: the range of its first time [s]
    and of its depth [m]; the yellow clay of the whole-lift design-height runs [m]; the same
    25 m section in whole lifts (3 m mesh, softening): its yellow clay [m], widest opening at
    the crest's top, toe and crest drop [m]; the part height and the whole top lift's
    thickness [m]; the range of the widest opening at the crest's top [m] and the surveyed
    crack [mm]. The words: the crack found in every run in parts (the row helper), one
    interface deep, within the last part, and in none of the (ten) design-height runs with
    30 m of yellow clay in whole lifts nor in the 25 m section in whole lifts; its widest
    opening wider than the surveyed crack's."""
    runs = [_design_height_parts(n)["discrete"] for n in DESIGN_HEIGHT_PARTS]
    for n in DESIGN_HEIGHT_PARTS:
        _design_height_parts_row(n)
    whole = [r for r in _cars_discrete_runs()
             if round(r["parameters"]["yellow_clay_length"]) == 30 and r["discrete"]["start"]
             == "end of construction (design height)"]
    if len(whole) != 10 or any(r["checks"]["crack_at_crest"]["passed"]
                              or r["parameters"]["parts_above"] is not None for r in whole):
        raise ValueError("a design-height run with 30 m of yellow clay found the crack")
    top_lift = {r["mesh"]["lift_tops_m_OD"][-1] - r["mesh"]["lift_tops_m_OD"][-2] for r in whole}
    parts = {_design_height_parts(n)["parameters"]["part_height"] for n in DESIGN_HEIGHT_PARTS}
    if len(top_lift) != 1 or len(parts) != 1:
        raise ValueError("not one top lift, not one part height")
    if any(d["crest_crack_during_slide_deepest_interfaces"] != 1 for d in runs):
        raise ValueError("a crack of more than one interface")
    first, depth, widest = ([d[k] for d in runs] for k in (
        "crest_crack_during_slide_first_time_s", "crest_crack_during_slide_deepest_m",
        "crest_crack_during_slide_surface_opening_m"))
    surveyed = ref.CARSINGTON_CREST_CRACK_MM
    if min(widest) <= surveyed[1] / 1000.0:
        raise ValueError("an opening no wider than the surveyed crack")
    if max(depth) >= min(parts):  # the words: within the last part placed
        raise ValueError("a crack deeper than a part")
    whole = []
    for size in (3.0, 2.0):
        same = _json(f"docs/summaries/carsington_design_height_Y25_softening_size{size:g}.json")
        p = same["parameters"]
        if (p["size"], p["yellow_clay_length"], p["parts_above"], p["discrete_softening"]) != (
                size, 25.0, None, True) or not same["construction"]["completed"] or same[
                "checks"]["crack_at_crest"]["passed"] or same["mesh"]["lift_tops_m_OD"][-2:] != [
                198.0, 200.5]:
            raise ValueError("not the 25 m section in whole lifts without a crack")
        whole += [same["discrete"][k] for k in ("crest_crack_during_slide_surface_opening_m",
                                                "toe_runout_m", "crest_drop_m")]
    return [min(first), max(first), min(depth), max(depth),
            _yellow_clay_length("carsington_design_height"), p["yellow_clay_length"], *whole,
            *parts, *top_lift, min(widest), max(widest), *surveyed]


def _parts_samples(size: str) -> list[dict[str, Any]]:
    """The design-height softening runs in parts on one mesh (``size`` "4", "3" or "2") with
    the yellow clay 24.97, 25 and 25.03 m long: their discrete summaries; a ValueError unless
    each crack check passed (the words: found in all nine)."""
    names = [f"carsington_design_height_parts_softening_size{size}{tail}"
             for tail in ("_Y24.97", "", "_Y25.03")]
    for n in names:
        _design_height_parts_row(n)
    return [_design_height_parts(n)["discrete"] for n in names]


def _parts_sample_spreads() -> list[float]:
    """The widest opening at the crest's top over the nine runs [m]; the crest drop's scatter
    on the 4, 3 and 2 m meshes [%], its three-run means [m] and their steps [%]."""
    runs = {z: _parts_samples(z) for z in ("4", "3", "2")}
    widest = [d["crest_crack_during_slide_surface_opening_m"] for v in runs.values() for d in v]
    crest = [[d["crest_drop_m"] for d in v] for v in runs.values()]
    means = [sum(c) / 3.0 for c in crest]
    return [min(widest), max(widest), *(100.0 * _rel_spread(c) for c in crest), *means,
            *_steps(means)]


def _parts_sample_means() -> list[float]:
    """The crest drop's three-run means: their steps [%], the mesh bar [%], the least and
    largest mean over the observed drop [%], the observed drop [m] and the bar [%]; then the
    toe's range on the 4 m mesh [m]. The words: both steps within the mesh bar,
    only the 3 m mesh's mean within the bar, the second step within the mesh bar by less
    than one run's scatter, and on the 2 m mesh a run whose toe moves less than a metre
    beside one whose moves more (the front pushed out or not)."""
    runs = [_parts_samples(z) for z in ("4", "3", "2")]
    means = [sum(d["crest_drop_m"] for d in v) / 3.0 for v in runs]
    bar = carsington()["checks"]["crest_drop"]["bar"]
    observed = ref.CARSINGTON_POST_FAILURE["crest_drop"][0]
    mesh_bar = MESH_BAR
    toe = [[d["toe_runout_m"] for d in v] for v in runs]
    scatter = [100.0 * _rel_spread([d["crest_drop_m"] for d in v]) for v in runs]
    if (max(_steps(means)) > mesh_bar or mesh_bar - _steps(means)[1] >= min(scatter[1:])
            or [abs(m / observed - 1.0) <= bar for m in means] != [False, True, False]
            or min(toe[2]) >= 1.0 or max(toe[2]) <= 1.0):
        return []
    return [*_steps(means), mesh_bar, 100.0 * min(means) / observed,
            100.0 * max(means) / observed, observed, 100.0 * bar,
            min(toe[0]), max(toe[0])]


def _parts_toe_ranges() -> list[float]:
    """The toe's range [m] on the 3 and 2 m meshes in the design-height runs in parts; [] unless
    on the 3 m mesh every run's front is pushed out (at least a metre) and on the 2 m mesh one
    run's is and another's is not (the words)."""
    toe = [d["toe_runout_m"] for d in _parts_samples("3")]
    fine = [d["toe_runout_m"] for d in _parts_samples("2")]
    if min(toe) < 1.0 or not min(fine) < 1.0 <= max(fine):
        return []
    return [min(toe), max(toe), min(fine), max(fine)]


def _design_height_starts() -> list[float]:
    """The yellow clay [m] of the design-height runs in whole lifts (on the 6, 4 and 3 m
    meshes carrying the fill to the crest, on the 2 m mesh not) and in parts (to the crest on
    the 4, 3 and 2 m meshes)."""
    whole = [_json(f"docs/summaries/{n}.json") for n in DESIGN_HEIGHT_MESHES]
    parts = [_design_height_parts(n) for n in DESIGN_HEIGHT_PARTS[1:]]
    if [r["parameters"]["size"] for r in whole] != [6.0, 4.0, 3.0, 2.0] or [
            r["construction"]["completed"] for r in whole] != [True, True, True, False] or [
            r["parameters"]["size"] for r in parts] != [4.0, 3.0, 2.0]:
        return []
    return [whole[0]["parameters"]["yellow_clay_length"], parts[0]["parameters"][
        "yellow_clay_length"]]


def _design_height_parts_movements() -> list[float]:
    """The design-height runs in parts: the crest drop without softening [m]; with softening
    the crest drops [m], the bar [%], the observed crest drop [m], the steps from mesh to mesh
    [%], the mesh bar [%], the toe movements [m] and the shoulder's mean movements [m]. The
    words: only the 3 m mesh's crest drop within the bar, the second step beyond the mesh
    bar, every toe short of the observed one by more than the bar and a toe step beyond the
    mesh bar; the node first at the toe on the 2 m mesh not moving."""
    plain, *soft = (_design_height_parts(n)["discrete"] for n in DESIGN_HEIGHT_PARTS)
    bar = carsington()["checks"]["crest_drop"]["bar"]
    crest_at, toe_at = (ref.CARSINGTON_POST_FAILURE[k][0]
                        for k in ("crest_drop", "upstream_toe_movement"))
    crest = [d["crest_drop_m"] for d in soft]
    toe = [d["toe_runout_m"] for d in soft]
    steps = _steps(crest)
    mesh_bar = MESH_BAR
    if ([abs(c / crest_at - 1.0) <= bar for c in crest] != [False, True, False]
            or [s > mesh_bar for s in steps] != [False, True]
            or not all(t < (1.0 - bar) * toe_at for t in toe)
            or not any(abs(b - a) > mesh_bar / 100.0 * max(a, b) for a, b in zip(toe, toe[1:]))
            or soft[2]["upstream_toe_dx_m"] != 0.0):
        return []
    return [plain["crest_drop_m"], *crest, 100.0 * bar, crest_at, *steps, mesh_bar, *toe,
            *(-d["upstream_shoulder_mean_dx_m"] for d in soft)]


def _design_height_row(name: str) -> list[float]:
    """Cells, fill level, toe, crest drop and failed interfaces of a design-height run; the
    crack column is checked here against the run's crack_at_crest check."""
    d = _json(f"docs/summaries/{name}.json")
    found = d["checks"]["crack_at_crest"]["passed"]
    assert not found, name  # "no" on every mesh
    disc = d["discrete"]
    return [d["mesh"]["cells"], d["construction"]["fill_level_m_od"], disc["toe_runout_m"],
            disc["crest_drop_m"], disc["interfaces_failed"]]


def _collapse_of(name: str) -> list[float]:
    """Collapsing lift, its top, the weight carried [%] and the fill level carried of a run."""
    c = _json(f"docs/summaries/{name}.json")["construction"]
    lift = c["collapsing_lift"]
    return [lift["lift"], lift["top_m_OD"], 100.0 * lift["weight_carried"], c["fill_level_m_od"]]


def _continuum_mesh_row(name: str) -> list[float]:
    """Cells, fill level carried, collapsing lift (number, top, weight [%]), the level at that
    weight and node A at 190 m OD [mm] of a Carsington run (Table 6.3)."""
    d = _json(f"docs/summaries/{name}.json")
    c = d["construction"]
    lift = c["collapsing_lift"]
    node_a = dict((level, ux) for level, ux in d["core_displacement_mm"]["by_fill_level"])
    return [d["mesh"]["cells"], c["fill_level_m_od"], lift["lift"], lift["top_m_OD"],
            100.0 * lift["weight_carried"], c["stages"][-1]["fill_level_m_OD"], node_a[190.0]]


PARTS_MESHES = ("carsington_parts_size6", "carsington_parts_size4.5", "carsington_parts_size3",
                "carsington_parts_size2")


def _parts_row(name: str) -> list[float]:
    """Size, cells, fill level carried, the collapsing part's top, its weight carried [%], the
    level at that weight, the run-away ratio and node A at 190 m OD [mm] (fill in parts)."""
    d = _json(f"docs/summaries/{name}.json")
    c, node_a = d["construction"], dict(map(tuple, d["core_displacement_mm"]["by_fill_level"]))
    lift = c["collapsing_lift"]
    return [d["parameters"]["size"], d["mesh"]["cells"], c["fill_level_m_od"], lift["top_m_OD"],
            100.0 * lift["weight_carried"], c["stages"][-1]["fill_level_m_OD"],
            lift["runaway_ratio"], node_a[190.0]]


def _yellow_clay_length(name: str) -> float:
    return _json(f"docs/summaries/{name}.json")["parameters"]["yellow_clay_length"]


def _completed(name: str) -> bool:
    """The Carsington run ``name`` placed every lift (or part) to the crest."""
    return _json(f"docs/summaries/{name}.json")["construction"]["completed"]


def _stands_on_both(tail: str) -> bool:
    """The sensitivity run ``tail`` placed every part on the 3 and the 2 m mesh."""
    return all(_completed(f"carsington_parts_size{n}{tail}") for n in (3, 2))


#: the fill level at which Carsington slipped [m OD] (Skempton & Vaughan 1993)
OBSERVED_SLIP = 199.5


def _node_a_by_level(name: str) -> dict[float, float]:
    """Node A's horizontal displacement [mm] of a Carsington run at each fill level [m OD]."""
    return dict(map(tuple, _json(f"docs/summaries/{name}.json")["core_displacement_mm"][
        "by_fill_level"]))


def _node_a_at(name: str, level: float) -> float:
    return _node_a_by_level(name)[level]


def _thickness_spread() -> float:
    """The collapse levels' spread [m] over the yellow clay 1.0, 1.5 and 2.0 m thick (3 m mesh)."""
    levels = [_sensitivity_row(f"carsington_parts_size3{t}")[2] for t in ("_T1.0", "", "_T2.0")]
    return max(levels) - min(levels)


def _finer_smaller_node_a() -> list[int]:
    """The number of (3 m, 2 m) pairs of node A figures in the sensitivity table, if the 2 m
    mesh's is the smaller in every pair (else nothing: the claim fails)."""
    pairs = [(_node_a_at(f"carsington_parts_size3{t}", z), _node_a_at(
        f"carsington_parts_size2{t}", z)) for t in ("_Y20", "_Y25", "_Y30") for z in (198.0, 200.5)
        if all(z in _node_a_by_level(f"carsington_parts_size{n}{t}") for n in (3, 2))]
    return [len(pairs)] * all(fine < coarse for coarse, fine in pairs)


def _sensitivity_row(name: str, change: dict[str, float] | None = None) -> list[float]:
    """Cells, fill level carried, the level at the weight carried in the collapsing part (if one
    collapsed) and node A at 198 and 200.5 m OD [mm] (where the fill reached them). With
    ``change``: first checked to be the run of the same size (``carsington_parts_size<n>``)
    with these parameters changed and no other."""
    d = _json(f"docs/summaries/{name}.json")
    if change is not None:
        base = _json(f"docs/summaries/carsington_parts_size{d['parameters']['size']:g}.json")
        differ = {k: v for k, v in d["parameters"].items() if base["parameters"].get(k) != v
                  and k != "progress"}
        if differ != change:
            raise ValueError(f"{name}: parameters {differ} changed, the table says {change}")
    c, node_a = d["construction"], _node_a_by_level(name)
    collapse = [c["stages"][-1]["fill_level_m_OD"]] if c["collapsing_lift"] else []
    return [d["mesh"]["cells"], c["fill_level_m_od"], *collapse,
            *(node_a[z] for z in (198.0, 200.5) if z in node_a)]


def _part_growth(name: str, top: float) -> float:
    """Growth of the largest displacement [m] in the part topped at ``top`` [m OD]."""
    stages = _json(f"docs/summaries/{name}.json")["construction"]["stages"]
    largest = {st["top_m_OD"]: st["max_displacement_m"] for st in stages}
    below = max(z for z in largest if z < top)
    return largest[top] - largest[below]


def _soft_sizes(names: tuple[str, ...] | list[str]) -> list[float]:
    return [_json(f"docs/summaries/{n}.json")["parameters"]["size"] for n in names]


def _steps(values: list[float]) -> list[float]:
    """The change from each value to the next: larger over smaller minus one [%]."""
    return [100.0 * (max(a, b) / min(a, b) - 1.0) for a, b in zip(values, values[1:])]


def _design_height_finer() -> list[float]:
    """The design-height softening runs on the 4, 3 and 2 m meshes: toe movements [m], the
    bar [%] and observed toe [m] (the 4 and 2 m within it, the 3 m not), the 4 to 3 m step
    [%], the bar and observed crest drop [m] and the crest drops (all within it) [m]. The
    section is not the published one (30 m of yellow clay), so the runs' checks set no
    reference: the default run's bar on the observed movements is used."""
    runs = [_soft_disc(n) for n in DESIGN_HEIGHT_MESHES[1:]]
    bar = carsington()["checks"]["crest_drop"]["bar"]
    toe_at, crest_at = (ref.CARSINGTON_POST_FAILURE[k][0]
                        for k in ("upstream_toe_movement", "crest_drop"))
    toe = [d["toe_runout_m"] for d in runs]
    crest = [d["crest_drop_m"] for d in runs]
    if [abs(t / toe_at - 1.0) <= bar for t in toe] != [True, False, True] or not all(
            abs(c / crest_at - 1.0) <= bar for c in crest):
        return []
    return [*toe, 100.0 * bar, toe_at, 100.0 * _rel_spread(toe[:2]), 100.0 * bar, crest_at,
            *crest]


def _toe_finer() -> list[float]:
    """The toe against the observed slide on the meshes of 4 m and finer: the bar [%], how
    many meet it, how many meshes, the coarsest [m], the change from each to the next [%],
    how many changes exceed the 15 % mesh bar, how many changes, that bar [%]."""
    names = [n for n in SOFT_MESHES if _soft_sizes([n])[0] <= 4.0]
    checks = [_json(f"docs/summaries/{n}.json")["checks"]["upstream_toe_movement"]
              for n in names]
    steps = _steps([_soft_disc(n)["toe_runout_m"] for n in names])
    if not steps[0] <= 15.0 < steps[1]:  # "the 4 and 3 m meshes agree, the 2.5 m one does not"
        return []
    return [100.0 * checks[0]["bar"], sum(c["passed"] for c in checks), len(names),
            _soft_sizes(names)[0], *steps, sum(v > 15.0 for v in steps), len(steps), 15.0]


def _soft_samples(size: str) -> list[dict[str, Any]]:
    """The softening analysis's five runs on the ``size`` m mesh: their summaries, checked to
    differ from the table's run in the yellow clay's length alone, to collapse in the same
    lift as it and to have come to rest; a ValueError otherwise."""
    base = _json(f"docs/summaries/carsington_softening_size{size}.json")
    runs = [base if y == 36.0 else _json(f"docs/summaries/carsington_softening_size{size}_Y{y}"
                                         ".json") for y in SOFT_SAMPLE_LENGTHS]
    for y, r in zip(SOFT_SAMPLE_LENGTHS, runs, strict=True):
        changed = {k for k, v in r["parameters"].items() if base["parameters"][k] != v}
        if (changed - {"yellow_clay_length"} or r["parameters"]["yellow_clay_length"] != y
                or r["construction"]["collapsing_lift"]["lift"]
                != base["construction"]["collapsing_lift"]["lift"]
                or r["discrete"]["stop"] != "rest"):
            raise ValueError(f"carsington_softening_size{size}_Y{y}: not the table's run with "
                             "another yellow-clay length")
    return runs


def _soft_sample_values(size: str, key: str) -> list[float]:
    return [r["discrete"][key] for r in _soft_samples(size)]


def _soft_sample_row(size: str) -> list[float]:
    """A row of the five-run table: toe movement and crest drop of each run [m], then the
    mean and standard deviation of each."""
    toe, crest = (_soft_sample_values(size, k) for k in ("toe_runout_m", "crest_drop_m"))
    return [*(v for pair in zip(toe, crest, strict=True) for v in pair), statistics.mean(toe),
            statistics.stdev(toe), statistics.mean(crest), statistics.stdev(crest)]


def _soft_sample_toe() -> list[float]:
    """The lift every run collapses in; the toe's scatter on each mesh [%]; the ranges of the
    2.5, 3 and 2 m meshes' toes [m]; the means [m] and their steps [%]; the 4, 3 and 2 m
    meshes' means' spread [%] and the mesh bar [%]. [] unless the 2.5 m mesh's range lies
    below both others (the words: apart from them), those three means lie within the mesh bar
    of each other and the 2.5 m mesh's mean beyond it from each (not converged)."""
    lifts = {r["construction"]["collapsing_lift"]["lift"] for z in SOFT_SAMPLE_SIZES
             for r in _soft_samples(z)}
    toe = {z: _soft_sample_values(z, "toe_runout_m") for z in SOFT_SAMPLE_SIZES}
    means = [statistics.mean(toe[z]) for z in SOFT_SAMPLE_SIZES]
    others = [statistics.mean(toe[z]) for z in ("4", "3", "2")]
    low = statistics.mean(toe["2.5"])
    if (len(lifts) != 1 or max(toe["2.5"]) >= min(min(toe["3"]), min(toe["2"]))
            or 100.0 * _rel_spread(others) > MESH_BAR
            or 100.0 * (min(others) / low - 1.0) <= MESH_BAR):
        return []
    return [lifts.pop(), *(100.0 * _rel_spread(toe[z]) for z in SOFT_SAMPLE_SIZES),
            min(toe["2.5"]), max(toe["2.5"]), min(toe["3"]), max(toe["3"]), min(toe["2"]),
            max(toe["2"]), *means, *_steps(means), 100.0 * _rel_spread(others), MESH_BAR]


def _soft_sample_crest() -> list[float]:
    """The crest drop's largest one-run scatter [%], its means [m] and their steps [%], the
    mesh bar [%], the least and largest shortfall of a mean from the observed drop [%], the
    observed drop [m] and the case's bar [%]; the shoulder's five-run means [m], their
    change on the two finest meshes and from the 3 to the 2.5 m mesh [%]. [] unless (the
    words) one run scatters by at most 10 %, every step is within the mesh bar, the largest
    the 3 m mesh's (the highest mean), every mean within the bar short of the observed drop,
    and the shoulder's means within the mesh bar on the two finest meshes, beyond it from the
    3 to the 2.5 m mesh."""
    crest = [_soft_sample_values(z, "crest_drop_m") for z in SOFT_SAMPLE_SIZES]
    means = [statistics.mean(c) for c in crest]
    observed = ref.CARSINGTON_POST_FAILURE["crest_drop"][0]
    bar = 100.0 * carsington()["checks"]["crest_drop"]["bar"]
    short = [100.0 * (1.0 - m / observed) for m in means]
    shoulder = [-statistics.mean(_soft_sample_values(z, "upstream_shoulder_mean_dx_m"))
                for z in SOFT_SAMPLE_SIZES]
    steps, scatter = _steps(means), max(100.0 * _rel_spread(c) for c in crest)
    if (max(steps) > MESH_BAR or not 0.0 < min(short) <= max(short) <= bar
            or scatter > 10.0 or max(means) != means[1] or max(steps) != steps[1]
            or _steps(shoulder)[2] > MESH_BAR or _steps(shoulder)[1] <= MESH_BAR):
        return []
    return [scatter, *means, *steps, MESH_BAR,
            min(short), max(short), observed, bar, *shoulder, _steps(shoulder)[2],
            _steps(shoulder)[1]]


def _crest_openings() -> list[float]:
    """The widest opening at the crest's top on the eight softening meshes [mm], the surveyed
    crack's range [mm] and how many lie in it; [] unless one opens on every mesh."""
    w = [1000.0 * _soft_disc(n)["crest_crack_during_slide_surface_opening_m"]
         for n in SOFT_MESHES]
    low, high = ref.CARSINGTON_CREST_CRACK_MM
    return [*w, low, high, sum(low <= v <= high for v in w)] if min(w) > 0.0 else []


def _crest_crack_finest() -> list[float]:
    """The softening meshes (then the u_r runs) whose crest-crack check failed, the one mesh
    where it passed, and its crack: the largest opening at its deepest [m], when [s], how
    deep [m]; [] unless only the finest mesh passed (the words)."""
    passed = [_json(f"docs/summaries/{n}.json")["checks"]["crack_at_crest"]["passed"]
              for n in SOFT_MESHES]
    others = [_json(f"docs/summaries/carsington_softening_{u}.json") for u in ("ur0.2", "ur1")]
    if passed != [False] * 7 + [True] or any(o["checks"]["crack_at_crest"]["passed"]
                                            for o in others):
        return []
    d = _soft_disc(SOFT_MESHES[-1])
    return [*_soft_sizes(SOFT_MESHES[:-1]),
            *(o["parameters"]["softening_displacement"] for o in others),
            _soft_sizes(SOFT_MESHES[-1:])[0], d["crest_crack_during_slide_deepest_max_opening_m"],
            d["crest_crack_during_slide_deepest_time_s"], d["crest_crack_during_slide_deepest_m"]]


def _soft_disc(name: str) -> dict[str, Any]:
    return _json(f"docs/summaries/{name}.json")["discrete"]


def _rel_spread(values: list[float]) -> float:
    """max / min - 1 of same-signed values [-]."""
    return max(values) / min(values) - 1.0 if values[0] > 0 else min(values) / max(values) - 1.0


def _cars_crest_spread() -> list[float]:
    """The softening analysis's crest drop on the eight meshes: its range, the observed value,
    the largest shortfall [%] (within the case's bar, which every run reports), the bar [%]
    and the change from the 4 m to the 3 m mesh and from the 2 m to the 1.5 m mesh [%]."""
    crest = [_soft_disc(n)["crest_drop_m"] for n in SOFT_MESHES]
    at = dict(zip(_soft_sizes(SOFT_MESHES), crest, strict=True))
    checks = [_json(f"docs/summaries/{n}.json")["checks"]["crest_drop"] for n in SOFT_MESHES]
    observed = ref.CARSINGTON_POST_FAILURE["crest_drop"][0]
    if not all(c["passed"] for c in checks):
        return [math.nan]
    return [min(crest), max(crest), observed, 100.0 * (1.0 - min(crest) / observed),
            100.0 * checks[0]["bar"], 100.0 * abs(at[3.0] / at[4.0] - 1.0),
            100.0 * abs(at[1.5] / at[2.0] - 1.0)]


def _cars_observed(name: str) -> list[float]:
    """The default run's movement ``name`` and the bar [%] it misses."""
    check = carsington()["checks"][name]
    return [check["computed"], 100.0 * check["bar"]] if check["passed"] is False else [math.nan]


def _softening(name: str) -> list[float]:
    """A row of docs/carsington.md's softening table from its summary."""
    d = _json(f"docs/summaries/{name}.json")
    collapse, disc = d["construction"]["collapsing_lift"], d["discrete"]
    return [d["parameters"]["softening_displacement"], d["parameters"]["size"], d["mesh"]["cells"],
            d["construction"]["fill_level_m_od"], collapse["lift"], collapse["top_m_OD"],
            100.0 * collapse["weight_carried"], disc["toe_runout_m"], disc["crest_drop_m"],
            disc["interfaces_failed"], disc["time_s"]]


H2_MESHES = ("h2_fine0.16", "h2_fine0.12", "h2", "h2_fine0.04", "h2_structured")


def _h2_row(name: str) -> list[float]:
    """A row of docs/hybrid.md's H2 mesh table from its summary (discrete columns if run)."""
    d = _json(f"docs/summaries/{name}.json")
    row = [d["parameters"]["fine"], d["continuum"]["cells"],
           d["continuum"]["collapse_pressure_kPa"]]
    if "discrete" in d:
        disc = d["discrete"]
        row += [disc["final_settlement_m"], disc["final_total_settlement_m"],
                disc["max_heave_beside_footing_m"], disc["interfaces_failed"]]
    return row


def _collapse_kpa(name: str) -> float:
    """An H2 run's continuum collapse load [kPa]."""
    return _json(f"docs/summaries/{name}.json")["continuum"]["collapse_pressure_kPa"]


def _h2_disc(name: str, key: str) -> float:
    """An H2 run's discrete measure ``key``, from a run that reached rest."""
    d = _json(f"docs/summaries/{name}.json")["discrete"]
    assert d["stop"] == "rest", name
    return d[key]


def _punch(name: str) -> dict[str, Any]:
    """A displacement-controlled H2 run's summary, checked to be one (control = punch)."""
    d = _json(f"docs/summaries/{name}.json")
    assert d["discrete"]["control"] == "punch", name
    return d


PUNCH_RUNS = ("h2_punch", "h2_punch_fine0.04", "h2_punch_v0.125", "h2_punch_v0.125_fine0.04")
# the runs of docs/hybrid.md's punch table
PUNCH_TABLE = ("h2_punch_fine0.12", *PUNCH_RUNS, "h2_punch_structured", "h2_punch_ur0.1",
               "h2_punch_ur0.4")


def _punch_row(name: str) -> list[float]:
    """A row of the H2 punch table: mesh, speed, pressures, settlement, heave, failures."""
    d = _punch(name)
    disc = d["discrete"]
    return [d["parameters"]["fine"], d["parameters"]["punch_speed"],
            disc["mean_bearing_pressure_kpa"], disc["bearing_pressure_last_fifth_kpa"],
            disc["final_settlement_m"], disc["max_heave_beside_footing_m"],
            disc["interfaces_failed"]]


def _ur_change(name: str, key: str) -> float:
    """Change [%] of a punch run's ``key`` with another u_r from the default punch (u_r 0.2 m)."""
    assert _punch("h2_punch")["parameters"]["softening_displacement"] == 0.2
    return 100.0 * (_punch(name)["discrete"][key] / _punch("h2_punch")["discrete"][key] - 1.0)


def _ur_collapse(name: str) -> float:
    """The continuum collapse load's change [%] of a punch run with another u_r."""
    return 100.0 * (_punch(name)["continuum"]["collapse_pressure_kPa"]
                    / _punch("h2_punch")["continuum"]["collapse_pressure_kPa"] - 1.0)


def _punch_gap(a: str, b: str, key: str) -> float:
    """How far apart [%] two punch runs' ``key`` are (larger over smaller minus one)."""
    return 100.0 * _rel_spread([_punch(n)["discrete"][key] for n in (a, b)])


def _punch_structured_refined() -> list[float]:
    """The structured mesh's punch refined to 0.04 m, at rest: its mean pressure [kPa] and
    how far below the 0.08 m one's [%], its heave [m] and its distance from the 0.08 m one's
    [%]; [] unless both distances are within the 10 % bar (the words)."""
    fine, coarse = "h2_punch_structured_fine0.04", "h2_punch_structured"
    p = [_punch(n)["discrete"]["mean_bearing_pressure_kpa"] for n in (fine, coarse)]
    out = [p[0], 100.0 * (1.0 - p[0] / p[1]), _h2_disc(fine, "max_heave_beside_footing_m"),
           _punch_gap(coarse, fine, "max_heave_beside_footing_m")]
    return out if max(out[1], out[3]) <= 10.0 else []


def _punch_refinement_gaps() -> list[float]:
    """Mean pressure, heave and last fifth's pressure: how far apart [%] on the default mesh
    and its refinement at 0.25 m/s, then at 0.125 m/s; [] unless the first two are within the
    10 % bar at 0.25 m/s and the last fifth's pressure is outside it at 0.125 m/s (the
    words)."""
    g = [_punch_gap(a, b, k) for a, b in (("h2_punch", "h2_punch_fine0.04"),
                                          ("h2_punch_v0.125", "h2_punch_v0.125_fine0.04"))
         for k in ("mean_bearing_pressure_kpa", "max_heave_beside_footing_m",
                   "bearing_pressure_last_fifth_kpa")]
    return g if max(g[0], g[1]) <= 10.0 < g[5] else []


def _spread(key: str) -> float:
    """Largest over smallest minus one [%] of an H2 discrete measure over the unstructured
    meshes whose discrete run reached rest."""
    runs = [_json(f"docs/summaries/{n}.json") for n in H2_MESHES if n != "h2_structured"]
    v = [d["discrete"][key] for d in runs if d.get("discrete", {}).get("stop") == "rest"]
    return 100.0 * (max(v) / min(v) - 1.0)


def _h3_row(name: str) -> list[float]:
    """A row of docs/hybrid.md's H3 mesh table from its summary."""
    d = _json(f"docs/summaries/{name}.json")
    disc = d["discrete"]
    return [d["parameters"]["size"], disc["elements"], disc["wedge_angle_deg"], disc["runout_m"],
            -disc["farthest_element_x_m"]]


# H3's four meshes of the glance table: the 0.5 m grid and unstructured mesh, then both at 0.25 m
H3_GLANCE = ("h3", "h3_unstructured", "h3_size0.25", "h3_unstructured_size0.25")


def _glance_h2_collapse() -> list[float]:
    """The structured, default and refined meshes' collapse loads [kPa], the refined size [m],
    the spread over the mesh table's meshes but the refined structured one [%], how far below
    the default that one stops [%] and collapses with Newton's retry [%], the triangles' gap
    under settlement control [%]; [] unless the spread is within the 3 % bar and the plain stop
    and the triangles beyond it (the words)."""
    spread = 100.0 * _rel_spread([_collapse_kpa(n) for n in H2_MESHES])
    stop = 100.0 * (1.0 - _collapse_kpa("h2_structured_fine0.04") / _collapse_kpa("h2"))
    hold, triangles = _h2_hold_refined(), _h2_triangle_gap()
    if spread > 3.0 or stop <= 3.0 or not hold or not triangles:
        return []
    return [_collapse_kpa("h2_structured"), _collapse_kpa("h2"), _collapse_kpa("h2_fine0.04"),
            _json("docs/summaries/h2_fine0.04.json")["parameters"]["fine"], spread, stop, hold[2],
            triangles[1]]


def _glance_h2(key: str) -> list[float]:
    """An H2 measure at rest on the structured, default and refined unstructured meshes, the
    refined size [m], then the changes [%] the words give: for the settlement, from the default
    to the structured mesh, on refinement of the unstructured and of the structured mesh; for
    the heave, on those refinements, then across the types at 0.08 and at 0.04 m (and that
    size). [] unless only the heave's refinements pass the 10 % bar (the words)."""
    v = [_h2_disc(n, key) for n in ("h2_structured", "h2", "h2_fine0.04")]
    fine = _json("docs/summaries/h2_fine0.04.json")["parameters"]["fine"]
    across = [100.0 * _rel_spread(v[:2]), 100.0 * _rel_spread(
        [_h2_disc(n, key) for n in ("h2_structured_fine0.04", "h2_fine0.04")])]
    refined = [100.0 * _rel_spread(v[1:]), 100.0 * _rel_spread(
        [_h2_disc(n, key) for n in ("h2_structured", "h2_structured_fine0.04")])]
    if key == "max_heave_beside_footing_m":
        if max(refined) > 10.0 or min(across) <= 10.0:
            return []
        return [*v, fine, *refined, *across, fine]
    if across[0] <= 10.0 or refined[0] <= 10.0 or refined[1] > 10.0:
        return []
    return [*v, fine, across[0], *refined]


def _glance_h3_thrust() -> list[float]:
    """H3's active thrust on its four meshes [kN/m], the refined size [m], the 0.125 m grid's
    thrust and size, the spread over the three grids [%], the grid's fall on each refinement
    [%], the larger of the two mesh types' differences at one size [%], the finest grid's
    excess over Rankine's [%] and Rankine's thrust [kN/m]; [] unless the types are within the
    3 % bar and the three grids as ``_h3_finest_thrust`` asks (the words: not met, still
    falling)."""
    t = [_h3_thrust(n) for n in H3_GLANCE]
    sizes = [_json(f"docs/summaries/{n}.json")["parameters"]["size"]
             for n in ("h3_unstructured_size0.25", H3_FINEST)]
    types = 100.0 * max(_rel_spread(t[:2]), _rel_spread(t[2:]))
    if types > 3.0 or not (g := _h3_finest_thrust()):
        return []
    finest, fall_fine, fall_mid, spread, excess, rankine = g
    return [*t, sizes[0], finest, sizes[1], spread, fall_mid, fall_fine, types, excess, rankine]


def _glance_h3_wedge() -> list[float]:
    """H3's wedge at 0.1 H on its four meshes and the 0.125 m grid [deg] (the sizes [m]
    between), the bar [deg], the Rankine angle [deg] and the five's range [deg]; [] unless each
    passed its check (within the bar of 45 + phi/2)."""
    runs = [_json(f"docs/summaries/{n}.json") for n in (*H3_GLANCE, H3_FINEST)]
    checks = [r["checks"]["wedge_angle"] for r in runs]
    w = [r["discrete"]["wedge_angle_deg"] for r in runs]
    bars = [c["bar"] * c["reference"] for c in checks]  # the check's bar is relative
    if not all(c["passed"] and abs(c["computed"] - c["reference"]) <= b
               for c, b in zip(checks, bars, strict=True)):
        return []
    return [*w[:4], runs[2]["parameters"]["size"], w[4], runs[4]["parameters"]["size"], bars[0],
            checks[0]["reference"], max(w) - min(w)]


def _glance_h3_runout() -> list[float]:
    """H3's mean run-outs [m] on the 0.5 m grid and unstructured mesh (nine runs each) and on
    the 0.25 m ones (five each), the refined size [m], the 0.125 m grid's (five) and its size;
    the grid's change on each refinement [%] (the sizes [m] after each), the unstructured
    mesh's and its standard error [%]; the shortfall across the types at 0.25 m and its
    standard error [%]; at 0.5 m [%] (the sizes [m] between)."""
    means = [statistics.mean(_h3_runouts("h3")), statistics.mean(_h3_runouts("h3_unstructured")),
             *(statistics.mean(_h3_runouts(n, H3_REFINED_LENGTHS)) for n in H3_GLANCE[2:])]
    refined, across, finest = _h3_refined_means(), _h3_refined_across(), _h3_finest()
    coarse = _h3_across()
    if not (refined and across and coarse and finest):
        return []
    fine, default, smallest = (_json(f"docs/summaries/{n}.json")["parameters"]["size"]
                               for n in ("h3_size0.25", "h3", H3_FINEST))
    return [*means, fine, finest[1], smallest, abs(refined[1]), fine, abs(finest[2]), smallest,
            abs(refined[4]), refined[5], fine, across[0], across[3], default, coarse[0]]


def _h3_finest() -> list[float]:
    """The 0.125 m grid (five runs): the |change| of its mean run-out from the 0.25 m grid's
    five [%], its mean [m], that change again [%] and its standard error [%], the |change| from
    the 0.5 m grid's nine [%]; one run's scatter [%] (largest over smallest); its wedges at
    0.1 H, least and largest [deg]. [] unless the three grids' means lie within the 10 % bar
    of each other and the last change is less than its standard error (the words)."""
    runs = _h3_runs(H3_FINEST, H3_REFINED_LENGTHS)
    fine = [d["runout_m"] for d in runs]
    mid = _h3_runouts("h3_size0.25", H3_REFINED_LENGTHS)
    mean, change, se = _h3_mean_change(mid, fine)
    coarse = _h3_runouts("h3")
    means = [statistics.mean(coarse), statistics.mean(mid), mean]
    from_coarse = pct(mean, means[0])
    wedges = [d["wedge_angle_deg"] for d in runs]
    if not (100.0 * _rel_spread(means) <= 10.0 and abs(change) < se):
        return []
    return [abs(change), mean, abs(change), se, abs(from_coarse), 100.0 * _rel_spread(fine),
            min(wedges), max(wedges)]


def _h3_finest_thrust() -> list[float]:
    """The 0.125 m grid's active thrust [kN/m], its fall from the 0.25 m grid's and that one's
    from the 0.5 m grid's [%], the spread over the three grids [%], the finest's excess over
    Rankine's [%] and Rankine's thrust [kN/m]; [] unless each step falls within the 3 % bar,
    the spread lies beyond it and the finest lies above Rankine's (the words)."""
    grids = [_h3_thrust(n) for n in ("h3", "h3_size0.25", H3_FINEST)]
    falls = [-pct(grids[2], grids[1]), -pct(grids[1], grids[0])]
    spread = 100.0 * _rel_spread(grids)
    rankine = h3()["checks"]["active_thrust"]["reference"]
    if not (0.0 < min(falls) and max(falls) <= 3.0 < spread and grids[2] > rankine):
        return []
    return [grids[2], *falls, spread, pct(grids[2], rankine), rankine]


def _h3_change(coarse: str, fine: str) -> list[float]:
    """|change of the wedge| [deg] and |change of the run-out| [%] from ``coarse`` to ``fine``."""
    a, b = (_json(f"docs/summaries/{n}.json")["discrete"] for n in (coarse, fine))
    return [abs(a["wedge_angle_deg"] - b["wedge_angle_deg"]),
            100.0 * abs(b["runout_m"] / a["runout_m"] - 1.0)]


def _flat(text: str) -> str:
    return re.sub(r"\s+", " ", text)


def _quoted(text: str) -> tuple[float, float]:
    """A quoted number and half a unit of its last digit."""
    mantissa = text.replace(" ", "").split("e")[0]
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    exponent = int(text.split("e")[1]) if "e" in text else 0
    return float(text.replace(" ", "")), 0.5 * 10.0 ** (exponent - decimals)


@pytest.mark.parametrize("quote", QUOTES, ids=[f"{q[0]}:{q[1][:40]}" for q in QUOTES])
def test_quoted_figure_matches_its_results_file(quote):
    doc, passage, values = quote
    text = _flat((ROOT / doc).read_text())
    pattern = NUMBER.join(re.escape(_flat(part)) for part in passage.split("{}"))
    found = re.findall(pattern, text)
    assert len(found) == 1, f"{doc}: the passage {passage!r} occurs {len(found)} times"
    quoted = found[0] if isinstance(found[0], tuple) else (found[0],)
    expected = values()
    assert len(quoted) == len(expected), (doc, passage, quoted, expected)
    wrong = []
    for text_number, value in zip(quoted, expected, strict=True):
        number, half = _quoted(text_number)
        if not abs(number - float(value)) <= half * (1 + 1e-9):
            wrong.append(f"quoted {text_number}, file {value:.6g}")
    assert not wrong, f"{doc}: {passage!r}: " + "; ".join(wrong)


def test_docs_point_inside_the_repository():
    """No path outside the repository (../, absolute) and no issue numbers in the user docs."""
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        text = path.read_text()
        for bad in (r"\.\./", r"(?<![\w.])/(?:work|tmp|home|root)/", r"\bissues?\s*#?\d+",
                    r"(?<![\w&])#\d+\b"):
            assert not re.search(bad, text), f"{path.name}: {re.search(bad, text).group(0)!r}"


# checks every committed Carsington run keeps (make docs lets a run with a failed check through,
# since the comparisons with the thesis and the observed slide are results the docs report)
CARSINGTON_KEPT = ("energy_excess_over_sources", "elements_conserved", "mass_conserved",
                   "rest_kinetic_ratio", "rest_drift_ratio", "slip_surface_through_yellow_clay",
                   "shoulder_moves_upstream", "failure_begins_at_crest_or_in_yellow_clay",
                   "crest_cracks_in_tension")


# the committed Carsington runs that leave elements detached beyond the embankment's front (the
# toe's advance does not count them), as docs/carsington.md reports them
TOE_DETACHED: dict[str, int] = {}


@pytest.mark.parametrize("path", sorted((ROOT / "docs" / "summaries").glob("carsington*.json")),
                         ids=lambda p: p.stem)
def test_committed_carsington_runs_keep_their_bars(path):
    """Every committed Carsington run with a discrete phase came to rest with bounded energy,
    its elements and mass kept, sliding on the yellow clay with the shoulder upstream, its
    failure beginning at the crest's top or in the yellow clay, the crest cracking in tension; its
    construction checks (equilibrium of the lifts, no stress in fill not yet placed) passed."""
    summary = json.loads(path.read_text())
    checks = summary["checks"]
    for name in ("max_stress_in_unplaced_lifts", "far_field_sigma_v", "far_field_sigma_h"):
        assert checks[name]["passed"], name
    if "discrete" in summary:
        assert summary["discrete"]["stop"] == "rest"
        # the toe's advance is the front of the whole embankment, one continuous mass (where
        # elements lie detached beyond it, docs/carsington.md says how many: TOE_DETACHED)
        assert summary["discrete"]["toe_detached_elements"] == TOE_DETACHED.get(path.stem, 0)
        for name in CARSINGTON_KEPT:
            assert checks[name]["passed"], name


def _formatted(value: float, quoted: str) -> str:
    """``value`` written as ``quoted`` was: its decimals, sign, exponent and thousands spaces."""
    mantissa, _, exponent = quoted.replace(" ", "").partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    sign = "+" if quoted.startswith("+") and value >= 0 else ""
    integer = mantissa.lstrip("+-").split(".")[0]
    if exponent:
        text = f"{value / 10.0 ** int(exponent):.{decimals}f}e{exponent}"
        return sign + text
    text = f"{value:,.{decimals}f}"
    if float(text.replace(",", "")) == 0.0:
        text = text.lstrip("-")  # no "-0.00"
    grouped = " " in quoted or len(integer) < 4  # the docs group digits in threes from 1 000
    return sign + (text.replace(",", " ") if grouped else text.replace(",", ""))


def _spaced(part: str) -> str:
    """A regular expression of ``part`` in which any run of whitespace matches any other."""
    return "".join(r"\s+" if chunk.isspace() else re.escape(chunk)
                   for chunk in re.split(r"(\s+)", part) if chunk)


def refresh(dry_run: bool = False) -> list[str]:
    """Rewrite every number the docs quote (``QUOTES``) that its results file no longer gives.

    A number still right to the rounding it is quoted with is left; another is written as it
    is quoted now (decimals, sign, thousands spaces). Returns what changed, and each quote
    whose passage is not found once or whose values cannot be had (its words to be mended by
    hand). Words around the numbers (a "yes", a "not met") are not touched: read the changes.
    """
    notes = []
    for doc, passage, values in QUOTES:
        path = ROOT / doc
        text = path.read_text()
        found = list(re.finditer(NUMBER.join(_spaced(part) for part in passage.split("{}")),
                                 text))
        if len(found) != 1:
            notes.append(f"{doc}: {len(found)} matches for {passage[:60]!r}")
            continue
        match = found[0]
        try:
            new = values()
        except Exception as words:  # a word the quote pins no longer holds, or its data
            notes.append(f"{doc}: {type(words).__name__} {words} in {passage[:60]!r}")
            continue
        if len(new) != len(match.groups()) or any(not math.isfinite(v) for v in new):
            notes.append(f"{doc}: values {new} do not fit {passage[:60]!r}")
            continue
        for k in range(len(new), 0, -1):  # from the end: earlier spans keep their places
            old = match.group(k)
            number, half = _quoted(old)
            if abs(number - float(new[k - 1])) <= half * (1 + 1e-9):
                continue  # still right to the rounding it is quoted with (the test's rule)
            written = _formatted(float(new[k - 1]), old)
            if written != old:
                notes.append(f"{doc}: {old} -> {written} in {passage[:50]!r}")
                text = text[:match.start(k)] + written + text[match.end(k):]
        if not dry_run and text != path.read_text():
            path.write_text(text)
    return notes


@pytest.mark.parametrize(("value", "quoted", "written"), [
    (1066.9, "1 067", "1 067"), (1048.2, "1 067", "1 048"), (998.4, "1 002", "998"),
    (1234.4, "998", "1 234"), (12345.0, "1 234", "12 345"), (2026.0, "2025", "2026"),
    (0.52461, "0.525", "0.525"), (-5.34, "-5.1", "-5.3"), (6.61, "+6.6", "+6.6"),
    (-0.4, "+6.6", "-0.4"), (0.000123, "1.5e-4", "1.2e-4"), (-0.001, "0.05", "0.00")])
def test_a_refreshed_figure_is_written_as_it_was_quoted(value, quoted, written):
    """``refresh`` writes a new value with the decimals, sign, exponent and thousands spaces of
    the quote it replaces (the docs group digits in threes from 1 000), and what it writes
    reads back as the value to the quote's rounding."""
    assert _formatted(value, quoted) == written
    number, half = _quoted(written)
    assert abs(number - value) <= half * (1 + 1e-9)


def test_refresh_finds_every_quote_and_leaves_current_docs_alone():
    """``refresh`` (run by ``make docs`` after the runs) finds each quoted passage once, gets
    its values and, the committed docs being current, would change nothing."""
    assert refresh(dry_run=True) == []


if __name__ == "__main__":  # python tests/test_docs_numbers.py [--dry-run]: after `make docs`
    import sys

    print("\n".join(refresh(dry_run="--dry-run" in sys.argv)) or "every quoted figure is current")
