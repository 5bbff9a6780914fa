"""How a result says it was made (``results.provenance``): the command as a user calls it again."""

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
