"""The shipped cases need no expert knob of the discrete phase to run.

``RunOptions.plastic_strain_cap`` (a Gauss point turns elastic beyond a plastic strain) and
``RunOptions.split_plastic_strain`` (bonds fail beyond a plastic strain) stay for experts; a
shipped case relies instead on its materials: bonds fail by the strength criteria and where
the material has softened to residual, a failed bond carries the residual strength as a
contact (``hybrid.materials.Contact``), and an element distorted as far as an element can
follow the flow parts from its neighbours (``ties.DISTORTION_LIMIT``). The cases
that still set a knob are named here and in the docs with what they measure without it; the
list may only shrink.
"""

import ast
from pathlib import Path

CASES = Path(__file__).resolve().parent.parent / "cases"
EXPERT_OPTIONS = ("plastic_strain_cap", "split_plastic_strain")
# every shipped case runs without them; a case added here needs its reason in the docs
STILL_SET: set[str] = set()


def _uses(path: Path) -> set[str]:
    """The expert options a case script names in its code: keywords, fields, attributes, keys.

    (A docstring naming one is a constant too, but only a whole-string match counts.)
    """
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.keyword) and node.arg in EXPERT_OPTIONS:
            names.add(node.arg)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) \
                and node.target.id in EXPERT_OPTIONS:
            names.add(node.target.id)
        elif isinstance(node, ast.Attribute) and node.attr in EXPERT_OPTIONS:
            names.add(node.attr)
        elif isinstance(node, ast.Constant) and node.value in EXPERT_OPTIONS:
            names.add(node.value)  # a key of an options dict
    return names


def test_shipped_cases_set_no_expert_knob():
    scripts = sorted(CASES.glob("*.py"))
    assert len(scripts) >= 10
    knobbed = {p.stem for p in scripts if _uses(p)}
    assert knobbed == STILL_SET, (
        f"cases setting {EXPERT_OPTIONS}: {sorted(knobbed)}; expected only {sorted(STILL_SET)}")
