"""The package's layout as rooms (README, "Where things are"): each room imports only itself and the rooms
before it (data ← law ← systems ← model ← scene ← sim ← study ← the commands at the top of the
package); no import cycles; no module over 400 lines; nothing in the package imports a script."""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "drake_car"
ROOMS = ("data", "law", "systems", "model", "scene", "sim", "study", "commands")
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
    parts = module.split(".")
    if len(parts) == 1:
        return "commands"
    return parts[1] if parts[1] in ROOMS else "commands"


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


@pytest.mark.parametrize("module", sorted(GRAPH))
def test_modules_are_small(module):
    lines = len(modules()[module].read_text().splitlines())
    assert lines <= MAX_LINES, f"{module}: {lines} lines"


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
