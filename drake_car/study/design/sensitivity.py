"""Which design parameters decide the outcomes: the points of the study's maps (2-D slices)
and Sobol's global sensitivity indices (SALib: Saltelli's sampling, first-order S1 and total
ST indices with bootstrap confidence intervals), pure functions of the study's spec and the
outcomes."""

import math

import numpy as np

from drake_car.study.design.spec import factor


def factor_values(factor, points):
    """``points`` values spanning the factor's range (geometric with ``log``)."""
    if factor.log:
        return list(np.geomspace(factor.low, factor.high, points))
    return list(np.linspace(factor.low, factor.high, points))


def map_points(study, spec):
    """The points of a 2-D slice: [{x_key: x, y_key: y}, ...] (the other factors at the
    base scene's values: the study's car's)."""
    fx, fy = factor(study, spec.x), factor(study, spec.y)
    return [{spec.x: x, spec.y: y} for y in factor_values(fy, spec.points)
            for x in factor_values(fx, spec.points)]


def sobol_problem(study):
    bounds = [[math.log10(f.low), math.log10(f.high)] if f.log else [f.low, f.high]
              for f in study.factors]
    return {"num_vars": len(study.factors), "names": [f.key for f in study.factors],
            "bounds": bounds}


def sobol_points(study, *, seed=2026):
    """Saltelli's sample for first-order and total indices: N (D + 2) points, N the study's
    base samples (a power of 2), as [{key: value}, ...]."""
    from SALib.sample import sobol
    problem = sobol_problem(study)
    samples = sobol.sample(problem, study.sobol_base_samples, calc_second_order=False,
                           seed=seed)
    points = []
    for row in samples:
        point = {}
        for f, value in zip(study.factors, row):
            point[f.key] = 10.0 ** value if f.log else float(value)
        points.append(point)
    return points


def sobol_indices(study, outcome, *, seed=2026):
    """S1, ST and their 95 % confidence half-widths per factor for ``outcome`` (one value per
    ``sobol_points`` point, in order). ``resolved``: the interval is narrower than the index,
    so ranking on it means something."""
    from SALib.analyze import sobol
    result = sobol.analyze(sobol_problem(study), np.asarray(outcome, dtype=float),
                           calc_second_order=False, seed=seed)
    rows = []
    for i, f in enumerate(study.factors):
        s1, s1c, st, stc = (float(result[k][i]) for k in ("S1", "S1_conf", "ST", "ST_conf"))
        rows.append({"factor": f.key, "label": f.label or f.key, "S1": s1, "S1_conf": s1c,
                     "ST": st, "ST_conf": stc, "resolved": bool(stc < abs(st))})
    return sorted(rows, key=lambda r: -r["ST"])
