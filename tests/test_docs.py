"""The front door and the docs (issue 29 item 1): a README a newcomer reads in five minutes — at
most 150 lines, the two commands on its first screen, the rooms table and the command list —,
every link in README.md and docs/*.md leading to a file (and heading) that exists, and the
studies' findings as their commands generated them: each file in docs/findings/ starts with the
line naming its command and commit, and the README's table is the one tools/readme_findings.py
makes from the main job's report."""

import importlib.util
import re
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
MAX_README_LINES = 150
FIRST_SCREEN_LINES = 40  # a terminal or a browser window, with the title and one paragraph
# The two commands that do all the set-up on a fresh machine; .ci/run runs the second.
MAIN_JOB = "bash tools/setup.sh && .venv/bin/drake-car-paper --out results/paper"
TESTS = "bash tools/setup.sh && .venv/bin/python -m pytest"
ROOMS = ("data", "law", "systems", "model", "scene", "sim", "results", "sweep", "study",
         "commands")  # tests/test_layout.py's order
MADE_BY = re.compile(r"Made by `drake-car-[a-z-]+ [^`]*` at commit [0-9a-f]{7,40}\b")


def readme_lines():
    return README.read_text().splitlines()


def section(lines, heading):
    """The lines of the README's section ``## heading`` (up to the next ``## ``)."""
    start = lines.index(f"## {heading}")
    end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("## ")),
               len(lines))
    return lines[start + 1:end]


def test_the_readme_is_short():
    n = len(readme_lines())
    assert n <= MAX_README_LINES, f"README.md has {n} lines (at most {MAX_README_LINES}: the " \
        "rest belongs in docs/)"


def test_the_two_commands_are_on_the_first_screen():
    first = "\n".join(readme_lines()[:FIRST_SCREEN_LINES])
    for command in (MAIN_JOB, TESTS):
        assert command in first, f"README.md's first {FIRST_SCREEN_LINES} lines lack {command!r}"
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    assert "drake-car-paper" in scripts, "the main job's console script is not installed"


def test_ci_runs_the_readme_test_command():
    """.ci/run sets up with tools/setup.sh and runs `.venv/bin/python -m pytest` with no
    arguments on .venv: the README's second command."""
    ci = (ROOT / ".ci" / "run").read_text()
    assert "bash tools/setup.sh" in ci
    assert '"$venv/bin/python" -m pytest "$@"' in ci
    runs = re.findall(r"^\s*run_tests (\"[^\"]*\") (\S+)(.*)$", ci, flags=re.M)
    assert any(venv == ".venv" and not rest.strip() for _, venv, rest in runs), runs


def test_the_rooms_table_names_every_room_in_order():
    rows = [line for line in section(readme_lines(), "Where things are: rooms")
            if line.startswith("| `drake_car/")]
    named = [re.match(r"\| `drake_car/(\w+)/` \|", row) for row in rows]
    rooms = [m[1] for m in named if m]
    assert tuple(rooms) == ROOMS, rooms


def test_the_command_list_has_every_console_script():
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    listed = [m[1] for line in section(readme_lines(), "Commands")
              if (m := re.match(r"- `(drake-car-[a-z-]+)`: \S", line))]
    assert sorted(listed) == sorted(scripts), set(listed) ^ set(scripts)
    assert len(listed) == len(set(listed)), listed


def slug(heading):
    """GitHub's anchor for a Markdown heading."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def anchors(path):
    return {slug(m[1]) for m in re.finditer(r"^#+ (.+)$", path.read_text(), flags=re.M)}


def links(path):
    """(target, anchor) of every relative Markdown link in ``path`` (code spans left out)."""
    text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)
    text = re.sub(r"`[^`\n]*`", "", text)
    for m in re.finditer(r"\]\(([^)\s]+)\)", text):
        target = m[1]
        if re.match(r"[a-z]+:", target):  # https:, mailto:
            continue
        file, _, anchor = target.partition("#")
        yield file, anchor


@pytest.mark.parametrize("path", [README, *sorted(DOCS.glob("*.md"))],
                         ids=lambda p: str(p.relative_to(ROOT)))
def test_every_link_resolves(path):
    for file, anchor in links(path):
        target = (path.parent / file).resolve() if file else path
        assert target.exists(), f"{path.relative_to(ROOT)}: link to {file}: no such file"
        if anchor:
            assert target.is_file() and anchor in anchors(target), \
                f"{path.relative_to(ROOT)}: link to {file}#{anchor}: no such heading"


def test_the_readme_links_every_docs_page():
    readme = README.read_text()
    for page in sorted(DOCS.glob("*.md")):
        assert f"(docs/{page.name})" in readme, f"README.md does not link docs/{page.name}"


FINDINGS = sorted((DOCS / "findings").glob("*")) if (DOCS / "findings").is_dir() else []


def test_findings_exist():
    assert {p.name for p in FINDINGS} >= {"paper.md"}, "run tools/findings.sh"


@pytest.mark.parametrize("path", FINDINGS, ids=lambda p: p.name)
def test_every_finding_names_its_command_and_commit(path):
    first = path.read_text().split("\n", 1)[0]
    assert MADE_BY.match(first), f"docs/findings/{path.name}: first line {first[:120]!r} does " \
        "not name the command and commit that made it (tools/findings.sh writes it)"


@pytest.mark.parametrize("study", ["paper", "paper_bmw"])
def test_the_readme_findings_table_is_the_main_jobs_report(study):
    """The README's tables (the Escort's, the BMW's) are their reports' claims, as
    tools/readme_findings.py makes them."""
    spec = importlib.util.spec_from_file_location(
        "readme_findings", ROOT / "tools" / "readme_findings.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    link = f"docs/findings/{study}.md"
    report = (ROOT / link).read_text()
    readme = README.read_text()
    block = readme.split(f"<!-- findings:{study} -->", 1)[1].split(
        f"<!-- /findings:{study} -->", 1)[0]
    assert block.strip().splitlines() == module.findings_table(report, link=link), \
        f"README.md's findings table differs from {link}'s claims: run " \
        f"python tools/readme_findings.py {link} README.md findings:{study}"
