"""The command line's self-description: --version, --list with units; the one box order."""

import subprocess

import pytest
from conftest import CASES, PYTHON, ROOT

import hybrid
from hybrid.case import describe, load_case, parameter_notes
from hybrid.io import check_box


def _hybrid(*args):
    return subprocess.run([PYTHON, "-m", "hybrid", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)


def test_version():
    result = _hybrid("--version")
    assert result.returncode == 0 and result.stdout.strip() == f"hybrid {hybrid.__version__}"


def test_list_shows_units_and_meaning_of_every_case_parameter():
    """`--list` prints each parameter with its default and the unit and meaning written on its
    line in the case script; every parameter of every case has one."""
    result = _hybrid("run", str(CASES / "footing_failure.py"), "--list")
    assert result.returncode == 0, result.stderr
    lines = {line.split()[0]: line for line in result.stdout.splitlines()}
    assert lines["cohesion"].split() == ["cohesion", "=", "69.0", "c", "[kPa]"]
    assert "[kPa]" in lines["pressure"] and "footing pressure" in lines["pressure"]
    for script in sorted(CASES.glob("*.py")):
        parameters = load_case(script).Parameters
        bare = [name for name, note in parameter_notes(parameters).items() if not note]
        assert not bare, f"{script.name}: parameters without a unit / meaning comment: {bare}"
        assert len(describe(parameters).splitlines()) == len(parameter_notes(parameters))


def test_box_order_is_xmin_ymin_xmax_ymax():
    """Every box (figure windows, contact bounds) is (xmin, ymin, xmax, ymax); the axis-limits
    order (xmin, xmax, ymin, ymax) is refused where it shows, with the order in the message."""
    assert check_box((0, -1.8, 3, 0.6)) == (0.0, -1.8, 3.0, 0.6)
    with pytest.raises(ValueError, match=r"\(xmin, ymin, xmax, ymax\)"):
        check_box((0.0, 3.0, -1.8, 0.6))  # the footing's window in the axis-limits order
    with pytest.raises(ValueError, match="four numbers"):
        check_box((0.0, 3.0, 1.0))


def test_progress_is_quiet_unless_enabled_and_falls_back_to_lines(capsys, monkeypatch):
    """The library shows no progress by default; enabled, without tqdm, a stage prints a
    line with its desc, how far it is and the facts given."""
    import sys

    from hybrid import progress

    bar = progress.progress("load", 1800.0, "kPa")
    bar.update(900.0, factor=900.0)
    bar.close()
    assert capsys.readouterr().err == ""
    monkeypatch.setitem(sys.modules, "tqdm", None)  # import tqdm fails
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    progress.enable()
    try:
        bar = progress.Progress("load", 1800.0, "kPa", every=0.0)
        bar.update(900.0, factor=900.0)
        bar.close()
    finally:
        progress.enable(False)
    err = capsys.readouterr().err
    assert err.startswith("load: 900 / 1800 kPa factor 900") and err.count("\n") == 1


def test_a_wrapped_parameter_comment_is_read_whole(tmp_path):
    """A field's comment continued on a comment-only line indented past "# " (as a wrapped
    comment is) belongs to that field; a section comment after it does not."""
    script = tmp_path / "wrapped.py"
    script.write_text(
        "import dataclasses\n\n\n@dataclasses.dataclass\nclass Parameters:\n"
        "    size: float = 6.0  # element size [m] (6: ~1 000 cells; 12:\n"
        "    #                    coarse)\n"
        "    # --- materials\n"
        "    E: float = 1.0  # [kPa]\n\n\ndef main():\n    pass\n")
    notes = parameter_notes(load_case(script).Parameters)
    assert notes == {"size": "element size [m] (6: ~1 000 cells; 12: coarse)", "E": "[kPa]"}


def test_inherited_parameter_comments_are_read_from_the_base(tmp_path):
    """A field inherited from a base record (e.g. a published table) has its note from the
    base's source; a field the derived class redeclares has its own note."""
    script = tmp_path / "derived.py"
    script.write_text(
        "import dataclasses\n\n\n@dataclasses.dataclass\nclass Table:\n"
        "    E: float = 1.0  # [kPa] (Table 1)\n"
        "    nu: float = 0.3  # [-] (Table 1)\n\n\n"
        "@dataclasses.dataclass\nclass Parameters(Table):\n"
        "    nu: float = 0.25  # [-] (assumed)\n"
        "    size: float = 6.0  # element size [m]\n\n\ndef main():\n    pass\n")
    notes = parameter_notes(load_case(script).Parameters)
    assert notes == {"E": "[kPa] (Table 1)", "nu": "[-] (assumed)", "size": "element size [m]"}


def test_a_case_named_without_its_path(tmp_path):
    """``hybrid run carsington`` finds cases/carsington.py, from any folder; a wrong name
    says how to name a case."""
    for cwd in (ROOT, tmp_path):
        listed = subprocess.run([PYTHON, "-m", "hybrid", "run", "carsington", "--list"],
                                cwd=cwd, capture_output=True, text=True, timeout=120)
        assert listed.returncode == 0, listed.stderr
        assert "core_cu" in listed.stdout
    wrong = _hybrid("run", "no_such_case", "--list")
    assert wrong.returncode == 2
    assert "give its path (cases/<name>.py)" in wrong.stderr
