"""Figures of the paper's study (Figs. 13-16) and one for each claim that the paper's figures do
not show, from run histories. Every figure marks the phases I-IV; places a and b are drawn as
the windows the report averages over (shaded bands, with the averaged values); legends and
notes sit outside the axes (``_save`` refuses a legend over data)."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import FuncFormatter, MultipleLocator  # noqa: E402

from drake_car.study.paper.claims import (  # noqa: E402
    CASES, DISPLACEMENT_THRESHOLD_M, SYMMETRY_TOLERANCE, count_reaching, numbers_text,
    phase_one_return, place_values, run_of, set_roles)

# The paper's three sets in its colours' order; more sets take matplotlib's next colours.
_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown",
            "tab:pink", "tab:gray", "tab:olive", "tab:cyan")


def set_colour(number):
    return _COLOURS[(number - 1) % len(_COLOURS)]


def _numbers(study):
    return set_roles(r.friction for r in study.values()).numbers
CASE_LINE = {"a": "-", "b": "--"}
PLACE_COLOUR = {"a": "tab:purple", "b": "tab:brown"}
DPI = 110
OUTSIDE = dict(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=8)
CAPTION_16 = (
    "The static phase's friction coefficient (eq. 1): μ = -(1 - β) μ1 sgn(Δ) - β μs sgn(v).\n"
    "β: the weight of its velocity part, from the rod's speed v in the cylinder: 0 at rest, "
    "rising to 1 at |v| = Δv; 1 while the rod slides (kinetic phase, |v| > Δv).\n"
    "μ1: its creep part, from the creep Δ (the rod's pre-sliding displacement while it "
    "sticks): 0 at Δ = 0, rising to μs at |Δ| = Δmax;\n0 while sliding, restarting from 0 "
    "when the rod sticks again. μ1 reaching μs (dashed line): the creep saturated while "
    "sticking; the paper counts two such times.")
FIGURES = {
    "fig13.png": "Fig. 13: the steering rack's displacement in both cases",
    "fig14_a.png": "Fig. 14a: Δd of the left strut, case a, every set, places a and b shaded "
                   "(claim 2)",
    "fig14_b.png": "Fig. 14b: Δd of the right strut, case a (claim 2)",
    "fig15_a.png": "Fig. 15a: Δd of the left strut, case b (claim 2)",
    "fig15_b.png": "Fig. 15b: Δd of the right strut, case b (claim 2)",
    "fig16.png": "Fig. 16: β and μ1 of both struts, case a, the dry set nearest the paper's "
                 "μs = 0.2, μs marked (claim 6)",
    "claim1_return.png": "claim 1: the rods as the acceleration ends, until the lane change",
    "load_split.png": "claim 3: change of the left-right rod difference and of the front "
                      "load split from place a to b, per run",
    "symmetry.png": "claim 4: case a against the mirrored case b, per set",
    "rod_rotation.png": "claim 5: the rods' rotation in their cylinders, with the 3° bound",
}


def place_windows(history, timeline):
    """(start, end) s of places a and b: the windows ``paper.place_values`` averages over."""
    t3, end = timeline.boundaries()[1], float(history["t"][-1])
    return {"a": (t3 - 0.3, t3), "b": (end - 0.5, end)}


def legend_overlaps(fig):
    """(legend, axes) index pairs where a legend covers an axes' plotting area."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
    return [(i, j) for i, legend in enumerate(legends)
            for j, ax in enumerate(fig.axes)
            if legend.get_window_extent(renderer).overlaps(ax.get_window_extent(renderer))]


def _save(fig, path):
    covered = legend_overlaps(fig)
    if covered:
        raise ValueError(f"{path}: a legend covers data (legend, axes) {covered}")
    fig.savefig(path, dpi=DPI, bbox_inches="tight")
    plt.close(fig)


def _phases(ax, timeline, label=True):
    """Phase boundaries (dotted) and names above the axes, within its x range."""
    t2, t3, t4, end = timeline.boundaries()
    lo, hi = ax.get_xlim()
    for x in (t2, t3, t4):
        if lo < x < hi:
            ax.axvline(x, color="k", lw=0.6, ls=":")
    if not label:
        return
    for name, (a, b) in zip(("I", "II", "III", "IV"), ((0, t2), (t2, t3), (t3, t4), (t4, end))):
        a, b = max(a, lo), min(b, hi)
        if b > a:
            ax.text(0.5 * (a + b), 1.01, name, transform=ax.get_xaxis_transform(),
                    ha="center", va="bottom", fontsize=9)


def _places(ax, history, timeline):
    """Places a and b as shaded bands, named above the axes."""
    for place, (a, b) in place_windows(history, timeline).items():
        ax.axvspan(a, b, color=PLACE_COLOUR[place], alpha=0.12, lw=0)
        ax.text(0.5 * (a + b), 1.01, place, transform=ax.get_xaxis_transform(), ha="center",
                va="bottom", fontsize=10, fontweight="bold", color=PLACE_COLOUR[place])


def _right_label(ax, y, text, **style):
    """A horizontal line at ``y`` named outside the axes, on its right."""
    ax.axhline(y, **({"color": "k", "lw": 0.8, "ls": "--"} | style))
    ax.text(1.005, y, text, transform=ax.get_yaxis_transform(), va="center", fontsize=8)


def fig13(study, timeline, path):
    fig, ax = plt.subplots(figsize=(9, 3.8))
    for case in CASES:
        h = run_of(study, case, _numbers(study)[0]).columns
        ax.plot(h["t"], 1e3 * h["rack_m"], CASE_LINE[case], label=f"case {case}")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("rack displacement [mm] (left +)")
    ax.grid(alpha=0.3)
    ax.legend(**OUTSIDE)
    _phases(ax, timeline)
    ax.set_title("Fig. 13: steering rack (Akima spline through the lane change's knots)", pad=18)
    _save(fig, path)


def fig_dd(study, timeline, case, side, path, title):
    """Δd of one strut in one case for every set; places a and b shaded, each set's
    average over them drawn across the band and listed beside the plot."""
    fig, ax = plt.subplots(figsize=(10, 4.4))
    rows = []
    for number in _numbers(study):
        run = run_of(study, case, number)
        h, colour = run.columns, set_colour(number)
        ax.plot(h["t"], 1e3 * h[f"dd_{side}_m"], color=colour, lw=1.2, label=run.friction.label)
        values = place_values(h, timeline, f"dd_{side}_m")
        for (a, b), value in zip(place_windows(h, timeline).values(), values):
            ax.plot([a, b], [1e3 * value] * 2, color=colour, lw=3.5, solid_capstyle="butt")
        rows.append(f"set {number}  {1e3 * values[0]:8.3f} {1e3 * values[1]:8.3f} "
                    f"{1e3 * (values[1] - values[0]):+8.3f}")
    _places(ax, run.columns, timeline)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("Δd from static equilibrium [mm] (rod in +)")
    ax.grid(alpha=0.3)
    ax.legend(title="friction set", **OUTSIDE)
    ax.text(1.01, 0.55, "averages over the places [mm]\n"
            "            a        b      b-a\n" + "\n".join(rows),
            transform=ax.transAxes, va="top", ha="left", family="monospace", fontsize=7.5)
    _phases(ax, timeline)
    ax.set_title(title, pad=18)
    _save(fig, path)


def fig16(study, timeline, path):
    """β and μ1 of both struts (case a, the dry set nearest the paper's μs = 0.2: its set 2),
    μs marked, phases on every panel, the terms defined below; False (nothing written) when
    no set is dry."""
    number = set_roles(r.friction for r in study.values()).fig16
    if number is None:
        return False
    run = run_of(study, "a", number)
    h, mu_s = run.columns, run.friction.mu_s
    fig, axes = plt.subplots(2, 2, figsize=(13, 6.2), sharex=True)
    for col, side in enumerate(("left", "right")):
        beta, mu1 = axes[0, col], axes[1, col]
        beta.plot(h["t"], h[f"beta_{side}"], color="tab:purple", lw=0.9)
        mu1.plot(h["t"], h[f"mu1_{side}"], color="tab:orange", lw=0.9)
        _right_label(mu1, mu_s, f"μs = {mu_s:g}")
        mu1.set_ylim(-0.05 * mu_s, 1.15 * mu_s if mu_s > 0 else 1.0)
        beta.set_ylim(-0.05, 1.1)
        peak = float(np.max(h[f"mu1_{side}"])) / mu_s if mu_s > 0 else 0.0
        beta.set_title(f"{side} strut: μ1 reaches μs {count_reaching(h[f'mu1_{side}'], mu_s)} "
                       f"times (largest μ1/μs {peak:.2f})", pad=18, fontsize=10)
        beta.set_ylabel("β")
        mu1.set_ylabel("μ1")
        mu1.set_xlabel("t [s]")
        for ax in (beta, mu1):
            ax.grid(alpha=0.3)
            _phases(ax, timeline)
    fig.suptitle(f"Fig. 16: β and μ1, case a, set {run.friction.label}")
    fig.subplots_adjust(wspace=0.28, hspace=0.3)
    fig.text(0.06, -0.02, CAPTION_16, fontsize=9, va="top", ha="left")
    _save(fig, path)
    return True


def claim1_return(study, timeline, path):
    """The rods from before the acceleration ends to the lane change: the window claim 1 is
    judged on shaded, each run's movement in it listed."""
    t2, t3, _, end = timeline.boundaries()
    window = (t2 - 0.3, t3)
    fig, axes = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    rows = []
    for number in _numbers(study):
        for case in CASES:
            run = run_of(study, case, number)
            h = run.columns
            moved = [phase_one_return(h, timeline, s) for s in ("left", "right")]
            rows.append(f"{run.name}  {1e3 * moved[0]:7.3f} {1e3 * moved[1]:7.3f}")
            for ax, side in zip(axes, ("left", "right")):
                ax.plot(h["t"], 1e3 * h[f"dd_{side}_m"], CASE_LINE[case],
                        color=set_colour(number), lw=1.1, label=f"{run.name} (set {number})")
    for ax, side in zip(axes, ("left", "right")):
        ax.set_xlim(max(0.0, window[0] - 1.0), min(end, window[1] + 0.5))
        ax.axvspan(*window, color="tab:red", alpha=0.08, lw=0)
        ax.set_ylabel(f"Δd {side} [mm]")
        ax.grid(alpha=0.3)
        _phases(ax, timeline)
    axes[0].legend(**OUTSIDE)
    axes[1].set_xlabel("t [s] (shaded: the window claim 1 is judged on)")
    roles = set_roles(r.friction for r in study.values())
    judged = ("" if roles.high is None else
              f"\n\nclaim 1: set {roles.high} ≤ {1e3 * DISPLACEMENT_THRESHOLD_M:g} mm"
              + (f",\n{numbers_text(roles.others)} > {1e3 * DISPLACEMENT_THRESHOLD_M:g} mm"
                 if roles.others else ""))
    axes[1].text(1.01, 1.0, "movement in the window\n(max - min) [mm]\n"
                 "      left    right\n" + "\n".join(rows) + judged,
                 transform=axes[1].transAxes, va="top", family="monospace", fontsize=7.5)
    axes[0].set_title("Claim 1: do the rods return when the acceleration ends?", pad=18)
    _save(fig, path)


def _split_changes(h, timeline, corner):
    left, right = (place_values(h, timeline, f"dd_{s}_m") for s in ("left", "right"))
    fl, fr = place_values(h, timeline, "Fz_fl_N"), place_values(h, timeline, "Fz_fr_N")
    rods = (left[1] - right[1]) - (left[0] - right[0])
    load = (fl[1] - fr[1]) - (fl[0] - fr[0])
    return 1e3 * rods, load, 100 * load / corner


def load_split(study, timeline, path, outcomes=None):
    """Claim 3 per run: the change from place a to b of Δd_left - Δd_right (with the
    "practically zero" band) and of the front split Fz_fl - Fz_fr in % of the corner load (a
    scale on which 1 % is plain). With ``outcomes`` (``outcomes.csv``'s rows) the bars are each
    run's value at the finest step it tried, with its converged error (or, not converged, the
    span of its last steps, or its windows' error where resolved locally; the solver's added)
    as an error bar and its values at every step as markers; without,
    the runs' values at their own step."""
    names = sorted(study)
    h1 = run_of(study, "a", _numbers(study)[0]).columns
    corner = 0.5 * (float(h1["Fz_fl_N"][0]) + float(h1["Fz_fr_N"][0]))
    values = np.array([_split_changes(study[n].columns, timeline, corner) for n in names])
    if outcomes is not None:
        for k, n in enumerate(names):
            values[k, 0] = 1e3 * outcomes[(n, "lr_change_m")]["value"]
            values[k, 2] = 100 * outcomes[(n, "split_change")]["value"]
            values[k, 1] = values[k, 2] * corner / 100
    fig, (rods, load) = plt.subplots(2, 1, figsize=(9, 6.4), sharex=True)
    x = np.arange(len(names))
    colours = [set_colour(study[n].friction.number) for n in names]
    hatches = ["" if study[n].case == "a" else "//" for n in names]
    for ax, column in ((rods, 0), (load, 2)):
        for k in range(len(names)):
            ax.bar(x[k], values[k, column], 0.6, color=colours[k], hatch=hatches[k],
                   edgecolor="k", lw=0.5)
        ax.axhline(0, color="k", lw=0.8)
        ax.grid(alpha=0.3, axis="y")
    t = DISPLACEMENT_THRESHOLD_M * 1e3
    rods.axhspan(-t, t, color="tab:green", alpha=0.15, lw=0)
    # Linear within the "practically zero" band, logarithmic beyond: 0.05 mm and 10 mm alike.
    rods.set_yscale("symlog", linthresh=t, linscale=0.6)
    top = max(10 * t, 1.5 * float(np.max(np.abs(values[:, 0]))))
    rods.set_ylim(-top, top)
    rods.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    rods.set_ylabel("change of Δd_left - Δd_right\nfrom a to b [mm] (log beyond ±" f"{t:g})")
    tried = [100 * abs(v) for n in names for v in outcomes[(n, "split_change")]["values"]] \
        if outcomes is not None else []
    span = max(2.0, 1.25 * float(np.max(np.abs(values[:, 2]))), 1.1 * max(tried, default=0))
    load.set_ylim(-span, span)
    load.yaxis.set_major_locator(MultipleLocator(0.5 if span <= 4 else 1.0))
    for y in (-1, 1):
        load.axhline(y, color="k", lw=0.6, ls="--")
    for k in range(len(names)):
        v = values[k, 2]
        newtons = round(float(values[k, 1]))
        load.text(x[k] + 0.32, v, f"{newtons:+d} N" if newtons else "0 N",
                  ha="left", va="center", fontsize=8)
    load.set_ylabel("change of Fz_fl - Fz_fr from a to b\n[% of the corner load]")
    load.set_xticks(x, names)
    load.set_xlabel("run (case_set; hatched: case b)")
    handles = [plt.Rectangle((0, 0), 1, 1, color=set_colour(k)) for k in _numbers(study)]
    labels = [run_of(study, "a", k).friction.label for k in _numbers(study)]
    handles.append(plt.Rectangle((0, 0), 1, 1, color="tab:green", alpha=0.15))
    labels.append(f"practically zero (±{t:g} mm)")
    handles.append(plt.Line2D([], [], color="k", lw=0.6, ls="--"))
    labels.append("±1 % of the corner load")
    if outcomes is not None:
        for ax, outcome, scale in ((rods, "lr_change_m", 1e3), (load, "split_change", 100)):
            for k, n in enumerate(names):
                row = outcomes[(n, outcome)]
                if row["error"] is not None:  # the whole budget: the step's and the solver's
                    budget = row["error"] + (row.get("solver_error") or 0.0)
                    ax.errorbar(x[k], scale * row["value"], yerr=scale * budget,
                                color="k" if row["converged"] else "tab:red", capsize=4,
                                lw=1.2)
                ax.plot([x[k]] * len(row["values"]), scale * np.asarray(row["values"]), "kx",
                        ms=5, alpha=0.7)
        handles += [plt.Line2D([], [], color="k", marker="x", ls=""),
                    plt.Line2D([], [], color="k", lw=1.2),
                    plt.Line2D([], [], color="tab:red", lw=1.2)]
        labels += ["each step tried (outcomes.csv)", "converged: ± its error",
                   "not converged: ± the span of its last steps\n(resolved locally: of "
                   "its windows)"]
    rods.legend(handles, labels, title="friction set (bars: steady,\nwindow averages)",
                **OUTSIDE)
    rods.set_title("Claim 3: lasting left-right change from place a to place b", pad=10)
    _save(fig, path)


def symmetry(study, timeline, path):
    """Claim 4: |Δd(case a, side) - Δd(case b, other side)| per set, against 1 % of the
    largest |Δd|."""
    fig, ax = plt.subplots(figsize=(10, 4))
    peak = 0.0
    for number in _numbers(study):
        a, b = run_of(study, "a", number).columns, run_of(study, "b", number).columns
        for side, other, line in (("left", "right", "-"), ("right", "left", ":")):
            ax.plot(a["t"], 1e3 * np.abs(a[f"dd_{side}_m"] - b[f"dd_{other}_m"]), line,
                    color=set_colour(number), lw=1,
                    label=f"set {number}: a {side} vs b {other}")
            peak = max(peak, float(np.max(np.abs(a[f"dd_{side}_m"]))))
    ax.axhline(1e3 * SYMMETRY_TOLERANCE * peak, color="tab:red", lw=1, ls="--",
               label=f"{100 * SYMMETRY_TOLERANCE:g} % of the largest |Δd| "
                     f"({1e3 * SYMMETRY_TOLERANCE * peak:.2f} mm): \"almost identical\"")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("|Δd(a, side) - Δd(b, other side)| [mm]")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(**OUTSIDE)
    _phases(ax, timeline)
    ax.set_title("Claim 4: case a against the mirrored case b (Fig. 14a vs 15b, 14b vs 15a)",
                 pad=18)
    _save(fig, path)


def rod_rotation(study, timeline, path):
    """Claim 5: each rod's rotation in its cylinder, both struts, every run; ±3° marked."""
    fig, axes = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    worst = (0.0, None, None, None)
    for number in _numbers(study):
        for case in CASES:
            run = run_of(study, case, number)
            h = run.columns
            for ax, side in zip(axes, ("left", "right")):
                deg = np.degrees(h[f"rot_{side}_rad"])
                ax.plot(h["t"], deg, CASE_LINE[case], color=set_colour(number), lw=1,
                        label=f"{run.name} (set {number})")
                k = int(np.argmax(np.abs(deg)))
                if abs(deg[k]) > abs(worst[0]):
                    worst = (float(deg[k]), float(h["t"][k]), ax, run.name)
    for ax, side in zip(axes, ("left", "right")):
        for y in (-3.0, 3.0):
            ax.axhline(y, color="tab:red", lw=1, ls="--")
        ax.set_ylabel(f"rotation, {side} rod [°]")
        ax.grid(alpha=0.3)
        _phases(ax, timeline)
    value, t, ax, name = worst
    handles, labels = axes[0].get_legend_handles_labels()
    if ax is not None:
        ax.plot([t], [value], "o", mfc="none", mec="k", ms=10)
        handles.append(plt.Line2D([], [], marker="o", mfc="none", mec="k", ls="", ms=10))
        labels.append(f"largest |rotation|: {abs(value):.2f}° ({name})")
    handles.append(plt.Line2D([], [], color="tab:red", lw=1, ls="--"))
    labels.append("±3°: the paper's bound")
    axes[0].legend(handles, labels, **OUTSIDE)
    lim = max(3.6, 1.15 * abs(value))
    for ax in axes:
        ax.set_ylim(-lim, lim)
    axes[1].set_xlabel("t [s]")
    axes[0].set_title("Claim 5: the rod's rotation in the cylinder (the paper: below 3°)", pad=18)
    _save(fig, path)


def all_figures(study, timeline, out, outcomes=None):
    """Writes every figure into ``out``; returns file -> what it shows. ``outcomes``: the rows
    of ``outcomes.csv`` (the deciding numbers per run, refined), or None."""
    fig13(study, timeline, out / "fig13.png")
    for fig, case, side, name in (("14", "a", "left", "a"), ("14", "a", "right", "b"),
                                  ("15", "b", "left", "a"), ("15", "b", "right", "b")):
        start = "left" if case == "a" else "right"
        fig_dd(study, timeline, case, side, out / f"fig{fig}_{name}.png",
               f"Fig. {fig}{name}: lane change starting {start} (case {case}), {side} strut")
    written = dict(FIGURES)
    if not fig16(study, timeline, out / "fig16.png"):
        del written["fig16.png"]
    claim1_return(study, timeline, out / "claim1_return.png")
    load_split(study, timeline, out / "load_split.png", outcomes)
    symmetry(study, timeline, out / "symmetry.png")
    rod_rotation(study, timeline, out / "rod_rotation.png")
    return written

