"""Import a Python script by its path.

The case scripts in ``cases/`` and the gmsh scripts in ``meshes/`` are files, not modules of
a package.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

__all__ = ["import_script"]


def import_script(path: str | Path, prefix: str) -> ModuleType:
    """Execute the script at ``path`` as the module ``{prefix}_{stem}`` and return it.

    The module is registered in ``sys.modules``, as dataclasses and pickling need.
    """
    path = Path(path)
    spec = importlib.util.spec_from_file_location(f"{prefix}_{path.stem}", path)
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot import '{path}'")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module
