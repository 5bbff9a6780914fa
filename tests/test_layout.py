"""The package's layout as rooms (README, "Where things are"): each room imports only itself and
the rooms before it (data ← law ← systems ← model ← scene ← sim ← results ← sweep ← study ←
commands; the package's ``__init__``, the front door, may import any room); every module is in
a room, so every module is counted where it sits; rooms with more than one concept hold them as
sub-rooms (folders), which the README names; no import cycles; no module over 400 lines, in the
package, ``experiments/`` and ``benchmarks/``; no two modules of one name where the name says
nothing of its room (a command is named by its job); nothing in the package imports a script;
one name per job (module, console script, experiment script); the shared options declared in
one place."""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "drake_car"
ROOMS = ("data", "law", "systems", "model", "scene", "sim", "results", "sweep", "study",
         "commands", "front door")
MAX_LINES = 400


def modules():
    """module name -> path, for every module of the package."""
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        if any(part in ("urdf", "scenes") for part in path.relative_to(PACKAGE).parts):
            continue
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found[".".join(parts)] = path
    return found


def room(module):
    """A module's room: its first folder under the package; the package's ``__init__`` is the
    front door, above every room. A module outside the rooms has none (a test fails)."""
    parts = module.split(".")
    if len(parts) == 1:
        return "front door"
    return parts[1] if parts[1] in ROOMS else None


@pytest.mark.parametrize("module", sorted(modules()))
def test_every_module_is_in_a_room(module):
    assert room(module) is not None, f"{module} is in no room of {ROOMS[:-1]}"
    assert not module.endswith("__main__"), f"{module}: a command belongs in drake_car/commands/"


def imports(path, module):
    """The package's modules that ``path`` imports (resolved to existing modules)."""
    known = modules()
    tree = ast.parse(path.read_text())
    found = set()
    for node in ast.walk(tree):
        names = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                package = module.split(".")[: -node.level if path.name != "__init__.py" else
                                            len(module.split(".")) - node.level + 1]
                base = ".".join(package + ([base] if base else []))
            names = [base] + [f"{base}.{a.name}" for a in node.names]
        for name in names:
            while name and name not in known:
                name = name.rpartition(".")[0]
            if name.startswith("drake_car") and name != "drake_car":
                found.add(name)
    found.discard(module)
    return found


GRAPH = {m: imports(p, m) for m, p in modules().items()}


@pytest.mark.parametrize("module", sorted(GRAPH))
def test_rooms_import_only_rooms_before_them(module):
    if room(module) is None:
        pytest.fail(f"{module} is in no room")
    mine = ROOMS.index(room(module))
    for target in GRAPH[module]:
        assert ROOMS.index(room(target)) <= mine, (
            f"{module} ({room(module)}) imports {target} ({room(target)})")


def test_no_import_cycles():
    visiting, done = set(), set()

    def visit(module, path):
        if module in done:
            return
        assert module not in visiting, "import cycle: " + " -> ".join(path + [module])
        visiting.add(module)
        for target in GRAPH[module]:
            visit(target, path + [module])
        visiting.discard(module)
        done.add(module)

    for module in GRAPH:
        visit(module, [])


SCRIPTS = sorted(p for folder in ("experiments", "benchmarks") for p in (ROOT / folder).glob("*.py"))
# Sub-rooms: each room's folders, as the README's table names them.
SUB_ROOMS = {
    "law": {"friction", "tyre", "road", "numerics", "comfort"},
    "study": {"paper", "design", "handling", "rig", "ride", "car"},
}
# Names that say a module's role inside its sub-room (each sub-room may have its own).
ROLE_NAMES = {"__init__", "__main__", "compiled", "figures", "report", "measures", "tables",
              "analysis"}


@pytest.mark.parametrize("path", [*modules().values(), *SCRIPTS],
                         ids=lambda p: str(p.relative_to(ROOT)))
def test_modules_and_scripts_are_small(path):
    lines = len(path.read_text().splitlines())
    assert lines <= MAX_LINES, f"{path.relative_to(ROOT)}: {lines} lines"


def test_sub_rooms_are_the_ones_named():
    for room_name, expected in SUB_ROOMS.items():
        found = {p.name for p in (PACKAGE / room_name).iterdir()
                 if p.is_dir() and (p / "__init__.py").is_file()}
        assert found == expected, (room_name, found)
        loose = sorted(p.name for p in (PACKAGE / room_name).glob("*.py")
                       if p.name != "__init__.py")
        assert len(loose) <= 2, f"{room_name}/ holds loose modules {loose}: put them in a sub-room"


def test_no_two_modules_share_a_name_that_says_nothing_of_its_room():
    names = {}
    for module, path in modules().items():
        if path.name != "__init__.py" and room(module) != "commands":  # a command: its job
            names.setdefault(module.rsplit(".", 1)[-1], []).append(module)
    shared = {n: ms for n, ms in names.items() if len(ms) > 1 and n not in ROLE_NAMES}
    assert not shared, shared


def test_the_package_imports_no_script():
    for module, path in modules().items():
        text = path.read_text()
        for script in ("experiments", "benchmarks", "tests"):
            assert f"import {script}" not in text and f"from {script}" not in text, module


def test_the_law_and_its_tests_know_no_simulation():
    """Law modules import nothing but law (and data); their tests nothing from later rooms."""
    for module, targets in GRAPH.items():
        if room(module) == "law":
            assert {room(t) for t in targets} <= {"law", "data"}, module
    tests = Path(__file__).parent
    for name in ("test_friction_law.py", "test_magic_formula.py", "test_akima.py"):
        tree = ast.parse((tests / name).read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("drake_car"):
                assert room(node.module) in ("law", "data"), (name, node.module)


COMMANDS = PACKAGE / "commands"
JOBS = sorted(p.stem for p in COMMANDS.glob("*.py") if p.stem not in ("__init__", "cli"))
# The options every command takes from ``commands.cli.parser`` (none declares them itself).
SHARED_OPTIONS = {"--out", "--scene", "--scene_text", "--workers", "--scheduler", "--quiet",
                  "--verbose"}


def _added_options(path):
    """The option strings ``path`` declares with ``add_argument``."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
                and node.func.attr == "add_argument"):
            found |= {a.value for a in node.args if isinstance(a, ast.Constant)
                      and isinstance(a.value, str) and a.value.startswith("--")}
    return found


@pytest.mark.parametrize("job", JOBS)
def test_one_name_per_job(job):
    """A job's module drake_car/commands/JOB.py, its console script drake-car-JOB (underscores as
    hyphens) and experiments/JOB.py, a thin call of the command, share one name; the usage line
    shows the console script."""
    import tomllib
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    script = "drake-car-" + job.replace("_", "-")
    assert scripts.get(script) == f"drake_car.commands.{job}:console", (script, scripts)
    text = (COMMANDS / f"{job}.py").read_text()
    assert "def console(" in text and f'name="{job}"' in text, job
    experiment = ROOT / "experiments" / f"{job}.py"
    assert experiment.is_file(), f"experiments/{job}.py is missing"
    imported = {node.module for node in ast.walk(ast.parse(experiment.read_text()))
                if isinstance(node, ast.ImportFrom)}
    assert imported == {f"drake_car.commands.{job}"}, (experiment, imported)
    assert len(experiment.read_text().splitlines()) <= 15, experiment


def test_every_console_script_is_a_job():
    import tomllib
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    assert sorted(target.split(":")[0].rsplit(".", 1)[1] for target in scripts.values()) == JOBS
    assert sorted(p.stem for p in (ROOT / "experiments").glob("*.py")) == JOBS


@pytest.mark.parametrize("path", [COMMANDS / f"{job}.py" for job in JOBS]
                         + sorted((ROOT / "benchmarks").glob("*.py")),
                         ids=lambda p: str(p.relative_to(ROOT)))
def test_no_command_declares_a_shared_option_itself(path):
    """--out, --scene, --scene_text, --workers, --scheduler, --quiet, --verbose come from
    ``commands.cli.parser``, for the commands and the benchmarks alike."""
    declared = _added_options(path) & SHARED_OPTIONS
    assert not declared, f"{path.relative_to(ROOT)} declares {sorted(declared)} itself"
    assert "argparse.ArgumentParser(" not in path.read_text(), (
        f"{path.relative_to(ROOT)}: build the parser with drake_car.commands.cli.parser")
