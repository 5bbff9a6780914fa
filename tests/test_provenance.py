"""How a result says it was made (``results.provenance``): the command as a user calls it again."""

import shlex
import sys
from pathlib import Path

import drake_car
from drake_car.results.provenance import _program, provenance


def test_a_job_run_as_a_module_names_the_module_not_its_file():
    # `python -m drake_car.commands.design` has sys.argv[0] = .../drake_car/commands/design.py:
    # "design.py" read as experiments/design.py (docs/findings/design.md said so).
    package = Path(drake_car.__file__).resolve().parent
    assert _program(str(package / "commands" / "design.py")) == \
        "python -m drake_car.commands.design"
    assert _program("/somewhere/.venv/bin/drake-car-design") == "drake-car-design"
    assert _program("experiments/design.py") == "python experiments/design.py"
    assert _program("/elsewhere/drake_car/commands/design.py") == \
        "python /elsewhere/drake_car/commands/design.py", \
        "another copy of the package is not the one running"


def test_provenance_records_the_command_and_the_code():
    info = provenance(extra_value=1)
    assert info["command"] and info["extra_value"] == 1
    assert set(info) >= {"git_commit", "dirty", "drake", "python", "created_utc"}


def test_the_command_is_quoted_as_a_shell_reads_it(monkeypatch):
    # The recorded command is pasted into a shell to rerun: a --scene_text with a space or a
    # brace must come back as one argument (it was joined unquoted).
    argv = ["/x/.venv/bin/drake-car-paper", "--out", "my results", "--scene_text",
            "{car_file: my car.yaml, tyres: !MagicFormula {tir_file: t.tir}}"]
    monkeypatch.setattr(sys, "argv", argv)
    command = provenance()["command"]
    assert command.startswith("drake-car-paper ")
    assert shlex.split(command)[1:] == argv[1:]
