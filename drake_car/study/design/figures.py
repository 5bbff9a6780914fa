"""Figures of the design study: heat maps of 2-D slices with the study's car's point (its
values: the user's car, or the paper's) and the threshold's boundary, the one-factor lines, the
Sobol indices with their confidence intervals, the Monte-Carlo distributions with each
mitigation's. ``prefix`` heads every title (the smoke test's "not findings")."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def heat_map(xs, ys, values, *, x_label, y_label, paper, threshold, title, path,
             value_label="lasting front load split change [% of corner load]", noise=None,
             unconverged=None, star_label="the paper's car", prefix="", missing=None):
    """``values[j][i]`` at (xs[i], ys[j]), in %; the contour |value| = threshold (%) drawn;
    cells whose |value| is within their error ``noise`` (a number, or one per cell, in the
    values' unit) of the threshold marked x: the boundary there is not resolved; cells
    ``unconverged`` (booleans per cell) framed by a square: not converged at the finest step
    tried. A cell without a value (NaN) is written "n/m" (not measured), ``missing`` saying
    why under the title; no boundary is drawn through the map unless every cell has one."""
    z = np.asarray(values, dtype=float)
    measured = np.isfinite(z)
    fig, ax = plt.subplots(figsize=(6.4, 5.0))
    size = np.abs(z[measured])
    limit = max(float(size.max()) if size.size else 0.0, threshold * 1.5, 1e-9)
    mesh = ax.pcolormesh(xs, ys, z, shading="nearest", cmap="RdBu_r", vmin=-limit,
                         vmax=limit)
    fig.colorbar(mesh, ax=ax, label=value_label)
    if measured.all() and size.max() > threshold and size.min() < threshold:
        contour = ax.contour(xs, ys, np.abs(z), levels=[threshold], colors="k",
                             linewidths=1.6)
        ax.clabel(contour, fmt={threshold: f"threshold {threshold:g}"}, fontsize=7)
    if noise is not None:
        near = np.abs(np.abs(z) - threshold) < np.broadcast_to(noise, z.shape)
        for j, y in enumerate(ys):
            for i, x in enumerate(xs):
                if near[j, i]:
                    ax.plot(x, y, "x", color="0.3", ms=7)
    if unconverged is not None and np.any(unconverged):
        jj, ii = np.nonzero(np.asarray(unconverged))
        ax.plot(np.asarray(xs)[ii], np.asarray(ys)[jj], "s", mfc="none", mec="k", ms=22)
        ax.plot([], [], "s", mfc="none", mec="k", ms=9, label="not converged")  # legend's
    ax.plot(*paper, marker="*", color="gold", mec="k", ms=16, label=star_label, ls="none")
    for j, y in enumerate(ys):
        for i, x in enumerate(xs):
            ax.text(x, y, f"{z[j, i]:+.1f}" if measured[j, i] else "n/m", ha="center",
                    va="center", fontsize=7)
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    gaps = "" if measured.all() else (
        f"\n{'not measured' if not measured.any() else 'n/m: not measured'}"
        + (f" ({missing})" if missing else ""))
    ax.set_title(prefix + title + gaps, fontsize=10 if not gaps else 8,
                 color="tab:red" if prefix else "k", wrap=True)
    ax.legend(loc="upper left", bbox_to_anchor=(0.0, -0.12), fontsize=8, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def sobol_bars(rows_by_outcome, path, prefix=""):
    """First-order and total indices with their 95 % intervals, one panel per outcome; an
    index whose interval is wider than itself is drawn hollow (not ranked on)."""
    fig, axes = plt.subplots(1, len(rows_by_outcome), figsize=(5.2 * len(rows_by_outcome), 4.2),
                             squeeze=False)
    for ax, (outcome, rows) in zip(axes[0], rows_by_outcome.items()):
        labels = [r["label"] for r in rows]
        y = np.arange(len(rows))
        for offset, key, colour in ((-0.18, "S1", "tab:blue"), (0.18, "ST", "tab:orange")):
            values = np.array([r[key] for r in rows])
            conf = np.array([r[f"{key}_conf"] for r in rows])
            resolved = conf < np.abs(values)
            ax.barh(y + offset, values, 0.34, xerr=conf, color=np.where(resolved, colour, "w"),
                    edgecolor=colour, label=f"{key} (hollow: interval wider than the index)",
                    capsize=3)
        ax.set_yticks(y, labels, fontsize=8)
        ax.invert_yaxis()
        ax.axvline(0, color="k", lw=0.6)
        ax.set_xlabel("Sobol index")
        ax.set_title(prefix + outcome, fontsize=9, color="tab:red" if prefix else "k")
        ax.grid(alpha=0.3, axis="x")
    axes[0][0].legend(loc="upper left", bbox_to_anchor=(0.0, -0.15), fontsize=7, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def distributions(samples_by_case, *, x_label, threshold, path, title, prefix=""):
    """Empirical distribution functions of |outcome| per case (the Monte Carlo and each
    mitigation), the threshold marked."""
    fig, ax = plt.subplots(figsize=(7.5, 4.4))
    for name, values in samples_by_case.items():
        v = np.sort(np.abs(np.asarray(values, dtype=float)))
        v = v[np.isfinite(v)]
        if v.size:
            ax.step(v, np.arange(1, v.size + 1) / v.size, where="post",
                    label=f"{name} (n = {v.size})")
    if threshold is not None:
        ax.axvline(threshold, color="k", ls="--", lw=0.8)
        ax.text(threshold, 0.02, f" threshold {threshold:g}", fontsize=7)
    ax.set_xlabel(x_label)
    ax.set_ylabel("share of runs at or below")
    ax.set_title(prefix + title, fontsize=10, color="tab:red" if prefix else "k")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def lines(line_tables, mu_s_values, *, split_threshold, pull_threshold, noise, path,
          prefix=""):
    """One row per line (a factor varied alone): the lasting split (%) and the pull (deg) at
    each of the factor's values, in the spec's order and evenly spaced (a value such as 0 for
    a rigid mount has no place on a linear axis), a curve per μs; the thresholds dashed, the
    numerical noise (``noise``: split %, pull deg) as a band around zero, each point's own
    error as its bar (refined runs: their steps'), a square where it has not converged."""
    fig, axes = plt.subplots(len(line_tables), 2, figsize=(9.0, 2.6 * len(line_tables) + 0.4),
                             squeeze=False)
    for row, line in zip(axes, line_tables):
        values = list(dict.fromkeys(p["value"] for p in line["points"]))
        for ax, key, limit, band, unit in ((row[0], "split_pct", split_threshold, noise[0],
                                            "lasting split [%]"),
                                           (row[1], "pull_deg", pull_threshold, noise[1],
                                            "pull [deg]")):
            for mu_s in mu_s_values:
                pts = [p for p in line["points"] if p["mu_s"] == mu_s]
                x = [values.index(p["value"]) for p in pts]
                bars = ax.errorbar(x, [p[key] for p in pts],
                                   yerr=[np.nan_to_num(p.get(f"{key}_error", 0.0)) for p in pts],
                                   fmt="o-", capsize=3, label=f"μs = {mu_s:g}")
                open_ = [p for p in pts if p.get(f"{key}_converged") == "no"]
                ax.plot([values.index(p["value"]) for p in open_], [p[key] for p in open_],
                        "s", mfc="none", mec=bars[0].get_color(), ms=11)
            for sign in (1, -1):
                ax.axhline(sign * limit, color="k", ls="--", lw=0.8)
            ax.axhspan(-band, band, color="0.85", zorder=0, label="numerical noise")
            ax.set_xticks(range(len(values)), [f"{v:g}" for v in values], fontsize=8)
            ax.set_xlabel(line["label"], fontsize=8)
            ax.set_ylabel(unit, fontsize=8)
            ax.grid(alpha=0.3)
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=8,
               frameon=False)
    axes[0][0].set_title("lasting front load split change (dashed: threshold)", fontsize=9)
    axes[0][1].set_title("heading change hands off (dashed: threshold)", fontsize=9)
    if prefix:
        fig.suptitle(prefix.rstrip(": "), color="tab:red", fontsize=10)
    fig.tight_layout(rect=(0, 0.05, 1, 0.95 if prefix else 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)
