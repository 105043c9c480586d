"""The README's code examples run as written (with the public API only)."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _examples() -> list[str]:
    text = (ROOT / "README.md").read_text()
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


@pytest.mark.parametrize("index", range(len(_examples())))
def test_readme_example_runs(index, tmp_path):
    """Each example runs in a fresh interpreter (from an empty folder; mesh scripts found in
    the repository) and writes what it says it writes."""
    code = _examples()[index].replace('"meshes/', f'"{ROOT}/meshes/')
    script = tmp_path / "example.py"
    script.write_text(code)
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                          text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    written = [p for p in (tmp_path / "results").rglob("*") if p.is_file()]
    assert written, "the example wrote no results"
