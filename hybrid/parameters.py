"""Validated case parameters: the rules sit on the fields, one check serves every case.

A case's ``Parameters`` derives from :class:`CaseParameters` and declares its limits with
:func:`param` where the default is given::

    @dataclass
    class Parameters(CaseParameters):
        element_size: float = param(0.25, gt=0)  # Q4 element size [m]
        cells: str = param("quadrilateral", choices=("quadrilateral", "triangle"))

Every field is checked when the record is made (``main(**overrides)``, ``--set``): a number
must be a finite number of its annotated type (``True`` is not a number), an ``int`` a whole
number, a ``bool`` True or False, and the declared bounds and choices must hold (None passes
where the annotation allows it). A bad value is a :class:`ParameterError` naming the
parameter, the value and the rule.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections.abc import Sequence
from typing import Any

#: the cell shapes of the meshes
CELLS = ("triangle", "quadrilateral")

__all__ = ["CELLS", "CaseParameters", "ParameterError", "check_field", "field_kind", "param"]


class ParameterError(ValueError):
    """A case parameter is out of its range or of the wrong type."""


def param(default: Any, *, gt: float | None = None, ge: float | None = None,
          lt: float | None = None, le: float | None = None,
          choices: Sequence[Any] | None = None) -> Any:
    """A dataclass field with ``default`` and its limits: > gt, >= ge, < lt, <= le, in choices."""
    rules = {k: v for k, v in (("gt", gt), ("ge", ge), ("lt", lt), ("le", le),
                               ("choices", None if choices is None else tuple(choices)))
             if v is not None}
    return dataclasses.field(default=default, metadata={"rules": rules})


def field_kind(field: dataclasses.Field) -> tuple[str, bool]:
    """(the annotated type's name, whether None is allowed) of a field."""
    text = field.type if isinstance(field.type, str) else getattr(field.type, "__name__", "")
    options = [k.strip() for k in str(text).split("|")]
    return next((k for k in options if k != "None"), "str"), "None" in options


def _rule_text(rules: dict[str, Any]) -> str:
    words = {"gt": ">", "ge": ">=", "lt": "<", "le": "<="}
    parts = [f"{words[k]} {v:g}" for k, v in rules.items() if k in words]
    if "choices" in rules:
        parts.append("one of " + ", ".join(repr(c) for c in rules["choices"]))
    return " and ".join(parts)


def check_field(field: dataclasses.Field, value: Any) -> None:
    """Raise :class:`ParameterError` unless ``value`` is valid for ``field``."""
    kind, optional = field_kind(field)
    rules = field.metadata.get("rules", {})

    def bad(rule: str) -> ParameterError:
        return ParameterError(f"case parameter {field.name} = {value!r}: must be {rule} "
                              f"(--set {field.name}=VALUE)")

    if value is None:
        if optional:
            return
        raise bad(f"a {kind}")
    if kind in ("float", "int"):
        number = isinstance(value, int | float) and not isinstance(value, bool)
        if not number or not math.isfinite(value):
            raise bad(f"a finite {'number' if kind == 'float' else 'whole number'}")
        if kind == "int" and not isinstance(value, numbers.Integral):
            raise bad("a whole number (an int, not 2.0)")
        if not (value > rules.get("gt", -math.inf) and value >= rules.get("ge", -math.inf)
                and value < rules.get("lt", math.inf) and value <= rules.get("le", math.inf)):
            raise bad(_rule_text(rules))
    elif kind == "bool" and not isinstance(value, bool):
        raise bad("True or False")
    elif kind == "str" and not isinstance(value, str):
        raise bad("a text")
    if "choices" in rules and value not in rules["choices"]:
        raise bad(_rule_text({"choices": rules["choices"]}))


@dataclasses.dataclass
class CaseParameters:
    """Base of a case's ``Parameters``: every field is checked when the record is made."""

    def __post_init__(self) -> None:
        """Check every field (type, finiteness, the limits given with :func:`param`)."""
        for field in dataclasses.fields(self):
            check_field(field, getattr(self, field.name))

    def pick(self, names: Sequence[str]) -> dict[str, Any]:
        """The values of the fields ``names``, by name.

        E.g. the dimensions a mesh builder takes as keywords.
        """
        return {name: getattr(self, name) for name in names}
