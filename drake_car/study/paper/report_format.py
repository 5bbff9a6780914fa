"""How the paper study's report writes its numbers: quantities in the reader's units, a
deciding number's threshold and numerical error, how far a verdict is from flipping, table rows
and figure links (pure formatting, no study logic)."""

import math

from drake_car.study.paper.local_route import local_error

SYMBOLS = {"<=": "≤", "<": "<", ">": ">", ">=": "≥", "==": "="}
# The figures that show each claim (files of drake_car.study.paper.figures.all_figures).
CLAIM_FIGURES = {1: ("claim1_return.png", "fig14_a.png", "fig14_b.png"),
                 2: ("fig14_a.png", "fig14_b.png", "fig15_a.png", "fig15_b.png"),
                 3: ("load_split.png",),
                 4: ("symmetry.png", "fig14_a.png", "fig15_b.png"),
                 5: ("rod_rotation.png",),
                 6: ("fig16.png",)}


def quantity(value, unit, error=False):
    """``value`` (SI) as the report writes it: mm, deg, N, N m, %, a ratio or a count."""
    if value is None:
        return "-"
    if unit == "count":
        return f"{value:.0f}"
    scale, suffix, digits = {"m": (1e3, " mm", 3), "rad": (180 / math.pi, "°", 2),
                             "N": (1.0, " N", 0), "N m": (1.0, " N m", 2),
                             "fraction": (100.0, " %", 2),
                             "ratio": (1.0, "", 3)}[unit]
    digits += 1 if error and unit in ("rad", "fraction") else 0
    shown = f"{scale * value:.{digits}f}"
    if error and value > 0 and float(shown) == 0:
        return f"< {10.0 ** -digits:g}{suffix}"
    return shown + suffix


def threshold_text(m):
    return f"{SYMBOLS[m['relation']]} {quantity(m['threshold'], m['unit'])}"


def error_text(row):
    """A measure's numerical error as the report writes it: "±e" where converged, "not
    converged" with the values at each step where not; a locally resolved run's its windows'."""
    if row.get("route") == "local":
        return local_error(row, quantity(row["error"] or 0.0, row["unit"], error=True))
    if row["error"] is None:
        return "not estimated (--no_verify: one step only)"
    if not row["converged"]:
        return "not converged: " + by_step(row)
    if row["unit"] == "count":
        return "converged (the same count at the last steps)"
    text = quantity(row["error"], row["unit"], error=True)
    return (text if text.startswith("<") else "±" + text) + \
        f" (converged at {1e3 * min(row['steps_s']):g} ms)"


def by_step(row):
    return ", ".join(f"{quantity(v, row['unit'])} at {1e3 * h:g} ms"
                     for h, v in zip(row["steps_s"], row["values"]))


def flip(row):
    """How far the verdict of one measure is from flipping, in units of its error."""
    if row["margin"] is None or row["error"] is None:
        return "-"
    if not row["converged"]:
        if row["unit"] == "count" or not row.get("decided"):
            return "**not converged**"
        n = row["margin"] / row["error"]
        n = f"{n:.0f}" if n >= 10 else f"{n:.1f}"
        if row.get("route") == "local":
            return (f"{n} × its error (the windows' summed error, above its tolerance: "
                    "not converged)")
        return (f"{n} × its spread (not converged at first order: the spread of its last "
                "three steps)")
    if row["unit"] == "count":
        return "exact (a converged count)"
    if row["error"] == 0:
        return "no change between the last steps"
    n = row["margin"] / row["error"]
    if n <= 1:  # the error is larger than the margin: the verdict is not decided
        return f"**{n:.2g} × the error** (within it)"
    return f"{n:.0f} × the error"


def verdict_text(c, s):
    """yes / **no**, not applicable (the study's sets cannot decide it), or undecided at the
    finest step tried."""
    if c["reproduced"] is None:
        return f"not applicable ({c.get('why', 'no measure')})"
    word = "yes" if c["reproduced"] else "**no**"
    if c.get("decided") is False:
        r = s.get("refinement") or {}
        return (f"undecided at the finest step tried ({1e3 * r.get('finest_step_s', 0):g} ms, "
                f"{r.get('wall_s', 0):.0f} s of wall); at it: {word.strip('*')}")
    return word


def span(interval):
    return f"{interval[0]:.3g} s to {interval[1]:.3g} s"


def table_row(*cells):
    """A Markdown table row; a "|" inside a cell (|Δd|) is escaped."""
    return "| " + " | ".join(str(c).replace("|", "\\|") for c in cells) + " |"


def links(i, figures):
    shown = [f for f in CLAIM_FIGURES[i] if f in figures]
    return ", ".join(f"[{f}]({f})" for f in shown) or "-"
