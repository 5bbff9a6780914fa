"""The README's "what the main job finds" table, made from the main job's report (never typed):

    python tools/readme_findings.py docs/findings/paper.md README.md [MARKER]

reads the report's two tables ("The paper's claims": each claim and its verdict; "Every number
behind a verdict": each deciding number with its threshold and numerical error) and writes,
between README.md's markers ``<!-- findings:paper -->`` and ``<!-- /findings:paper -->``, one
row per claim: the claim, the verdict, the numbers that decide it with their errors, and a
first line naming the report's command and commit (the report's own first line). With MARKER, between
``<!-- MARKER -->`` and ``<!-- /MARKER -->`` (the second shipped car's: ``findings:paper_bmw``).
Run by tools/findings.sh after it copies the report."""

import re
import sys
from pathlib import Path

MARKER = "findings:paper"
BEGIN, END = f"<!-- {MARKER} -->", f"<!-- /{MARKER} -->"


def cells(line):
    """A Markdown table row's cells (``\\|`` inside a cell is kept)."""
    parts = re.split(r"(?<!\\)\|", line.strip())
    return [p.strip() for p in parts[1:-1]]


def table(text, heading):
    """The rows (as cell lists) of the first table after ``heading``, header and rule left out."""
    after = text.split(heading, 1)[1]
    rows = []
    for line in after.splitlines():
        if line.startswith("|"):
            rows.append(cells(line))
        elif rows:
            break
    return rows[2:]


def short_verdict(text):
    """``yes``, ``no``, or ``undecided (at 0.0625 ms: yes)`` from the report's verdict cell."""
    text = text.replace("*", "")
    found = re.match(r"undecided at the finest step tried \(([^,]+),.*at it: (\w+)", text)
    return f"undecided (at {found[1]}: {found[2]})" if found else text


def findings_table(report, link="docs/findings/paper.md"):
    """The README's lines for ``report`` (the text of docs/findings/paper.md)."""
    first = report.splitlines()[0]
    found = re.match(r"Made by (`[^`]+`) at commit ([^(]+?) \(([^,]+),", first)
    if not found:
        raise SystemExit(f"the report's first line names no command and commit: {first!r}")
    claims = table(report, "## The paper's claims")
    numbers = table(report, "## Every number behind a verdict")
    lines = [f"Made by {found[1]} at commit {found[2]} ({found[3]}; its report: "
             f"[{link}]({link})):", "",
             "| # | the paper's claim | verdict | the numbers that decide it (threshold), their numerical error |",
             "|---|---|---|---|"]
    for number, claim, verdict, *_ in claims:
        deciding = [f"{n[1]}: **{n[3]}** ({n[2]}), error {n[4]}"
                    for n in numbers if n[0] == number and n[-1] == "yes"]
        lines.append(f"| {number} | {claim} | {short_verdict(verdict)} | "
                     f"{'; '.join(deciding)} |")
    return lines


def main(report_path, readme_path, marker=MARKER):
    begin, end = f"<!-- {marker} -->", f"<!-- /{marker} -->"
    report = Path(report_path).read_text()
    readme = Path(readme_path).read_text()
    if begin not in readme or end not in readme:
        raise SystemExit(f"{readme_path}: no {begin} ... {end} markers")
    head, rest = readme.split(begin, 1)
    _, tail = rest.split(end, 1)
    Path(readme_path).write_text(
        head + begin + "\n" + "\n".join(findings_table(report, link=str(report_path))) + "\n" + end + tail)


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        raise SystemExit(__doc__)
    main(*sys.argv[1:])
