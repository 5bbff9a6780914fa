"""The handling study's files: each run's own, the series as CSV, the numbers as JSON, the
figures (``figures``); ``summary`` is what summary.json holds."""

from drake_car.results.files import write_diagram_svg
from drake_car.results.files import write_csv, write_json, write_run
from drake_car.study.handling import tyre_section
from drake_car.study.handling.figures import crosscheck_figures, handling_figures

def write_outputs(out, runs, result, scene):
    """Every file of the study into ``out``; ``scene`` is the steady-state test's (its tyre's
    curves go to ``tyre/``)."""
    for name, run in runs.items():
        if name != "shipped_tyre":
            (out / name).mkdir()
            write_run(run, out / name, diagram=False)
    if "shipped_tyre" in runs:
        (out / "shipped_tyre").mkdir()
        for name, run in runs["shipped_tyre"].items():
            (out / "shipped_tyre" / name).mkdir()
            write_run(run, out / "shipped_tyre" / name, diagram=False)
    tyre_section.write(out / "tyre", scene)
    write_diagram_svg(runs["steady_state"].diagram_dot, out / "diagram.svg")
    ss, st, budget = result["steady_state"], result["step_steer"], result["budget"]
    write_csv(out / "steady_state" / "steady_state.csv", ss["series"])
    write_json(out / "steady_state" / "steady_state.json",
               {k: v for k, v in ss.items() if k != "series"})
    write_csv(out / "step_steer" / "step_steer.csv", st["series"])
    write_json(out / "step_steer" / "step_steer.json",
               {k: v for k, v in st.items() if k != "series"})
    write_csv(out / "steering.csv", result["steering"])
    write_csv(out / "budget.csv", {k: [row[k] for row in budget["rows"]]
                                   for k in ("key", "term", "gradient_deg_per_g", "share_pct",
                                             "how")})
    write_csv(out / "budget_series.csv", budget["series"])
    write_json(out / "budget.json", {k: v for k, v in budget.items() if k != "series"})
    result["figures"] = handling_figures(result, out)
    cc = result["crosscheck"]
    if "skipped" not in cc:
        (out / "crosscheck").mkdir()
        write_csv(out / "crosscheck" / "ramp.csv", cc["series_ramp"])
        write_csv(out / "crosscheck" / "step.csv", cc["series_step"])
        write_json(out / "crosscheck" / "crosscheck.json",
                   {k: v for k, v in cc.items() if not k.startswith("series")})
        result["figures"] |= crosscheck_figures(result, out)


def summary(result):
    """What summary.json holds: every number, no series."""
    def strip(d):
        return {k: (strip(v) if isinstance(v, dict) else v) for k, v in d.items()
                if k not in ("series", "series_ramp", "series_step", "steering")}
    return strip(result)
