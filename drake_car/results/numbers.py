"""Numbers as the reports print them, one wording for every report."""


def signed(value, digits=0):
    """``value`` with its sign, rounded to ``digits`` decimals; what rounds to zero is printed
    without one ("0.000", never "-0.000" or "+0.000", which read as a change)."""
    shown = f"{round(value, digits) + 0.0:+.{digits}f}"
    return shown[1:] if float(shown) == 0 else shown
