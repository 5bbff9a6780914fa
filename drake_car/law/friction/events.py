"""Stick-slip events of friction pairs, noted where the per-step friction update already
runs (``systems.strut_friction``: one compiled call more in its update, no port read), kept in
a bounded log in the system's discrete state. No Drake here.

Events (``KIND_NAMES``), each pair's:

- **break_away** (static -> kinetic): |v| rose above Δv;
- **stick** (kinetic -> static): |v| fell to Δv or below;
- **saturation**: in a static phase the creep reached Δmax: the static friction is fully
  mobilised (μ1 = μs), and any excess of the load over the capacity μs·S now slides the pair.

Per event the log keeps (``EVENT_FIELDS``): the time of the state in which it was seen (s), the
pair, the kind (1, -1, 0), the pair's velocity v_{k+1} and the step's change of it
v_{k+1} - v_k (the SAP step's velocity change: what one step changed it by), its position, the
creep before the step, the friction the step applied (the fast scheme's implicit PD force
rebuilt from the step's own targets and gains: SAP's u = clamp(u_ff - Kp(q - q_d) - Kd(v - v_d),
±e); the reference scheme's explicit force; N or N·m), the static capacity μs·S of that step
(S = N, or N·r + M0/μs for rotation), and the ended phase's largest |v|/Δv.

How near its threshold an event was, against what one step can change (the runner's table,
``sim.slips.event_columns``, gives ``band_steps`` = Δv / |v_{k+1} - v_k|):

- a break-away with band_steps < 1 was thrown through the static band within one step: a load
  far above capacity, which any step breaks, within a step of time. With band_steps ≥ 1 the
  pair crept through the band over several steps, at a load barely above capacity; the fast
  scheme's implicit damping at low velocity adds Kd·dt of inertia to the pair (~4000 kg at 1 ms
  against ~30 kg), so whether and when such a pair breaks depends on the step;
- a stick leaves the pair within a step's travel |v|·dt ≤ Δv·dt of where any step would;
- a saturation: the margin is the **reserve**, the capacity the step's force left unused,
  (e - |u|)/e, the smallest while the pair stays at full creep (kept per pair in the log: a
  fast-scheme pair held by its implicit PD below the effort limit e = μs·S). The load's excess
  over capacity |F| - μs·S is -reserve·e while the pair holds; once it exceeds capacity the
  force is clamped at e and the excess shows as acceleration only (the pair's effective mass,
  which the friction system does not know, would turn it into newtons).

The log is a flat array: [count, each pair's largest |v|/Δv in its phase, each pair's reserve
at full creep in its phase (-1: not at full creep), then ``CAPACITY`` rows of ``EVENT_FIELDS``],
a ring: event number j (from 0) is row j mod CAPACITY. A reader that reads at least every
CAPACITY events loses none; the count tells it how many it missed otherwise.
"""

import numba
import numpy as np

EVENT_FIELDS = ("time_s", "pair", "kind", "velocity", "velocity_change", "position", "creep",
                "friction", "capacity", "peak_ratio")
BREAK_AWAY, STICK, SATURATION = 1.0, -1.0, 0.0
KIND_NAMES = {BREAK_AWAY: "break_away", STICK: "stick", SATURATION: "saturation"}
# Rows of the ring: more than the events of a chunk the runner reads at once (10 ms at 1 ms
# steps: 10 steps x 4 pairs x at most one transition each); a run records how many it lost.
CAPACITY = 64
_F = len(EVENT_FIELDS)


def log_size(n_pairs, capacity=CAPACITY):
    return 1 + 2 * n_pairs + capacity * _F


@numba.njit(cache=True)
def note_transitions(t, x, v_index, q_index, dv, dmax, capacity_scale, memory, diagnostics,
                     fast, actuation, desired, gains, log):
    """Notes the events of the step that ended in the plant state ``x`` (time ``t``) in ``log``
    (in place). Called before the friction update overwrites its state: ``memory`` is each
    pair's [creep..., phase..., position at the last step...] before the step's update,
    ``diagnostics`` the values at the step's start (8 per pair: v, creep, β, μ1, μ, phase, N,
    friction), ``actuation``, ``desired`` and ``gains`` what the plant used in the step
    (``desired`` and ``gains`` empty in the reference scheme). ``capacity_scale``: per pair (μs,
    the arm (1, or r for rotation), the preload term (0, or M0/μs)). Returns the number of
    events noted."""
    n = dv.shape[0]
    rows = (log.shape[0] - 1 - 2 * n) // _F
    noted = 0
    for i in range(n):
        v = x[v_index[i]]
        q = x[q_index[i]]
        ratio = abs(v) / dv[i]
        kinetic = ratio > 1.0
        creep, was_kinetic = memory[i], memory[n + i] != 0.0
        peak = log[1 + i]
        if ratio > peak:
            log[1 + i] = ratio
        kind = 2.0  # none
        d = diagnostics[8 * i:8 * (i + 1)]
        if fast:  # the force the step applied: SAP's implicit PD force, rebuilt
            u = (actuation[i] - gains[i] * (q - desired[i])
                 - gains[n + i] * (v - desired[n + i]))
            e = gains[2 * n + i]
            u = -e if u < -e else (e if u > e else u)
        else:
            u, e = actuation[i], 0.0
        if kinetic != was_kinetic:
            kind = BREAK_AWAY if kinetic else STICK
        elif not kinetic:
            # The creep this step's update will reach (law.friction.frd.advance_creep).
            reached = creep + (q - memory[2 * n + i])
            if abs(reached) >= dmax[i] * (1.0 - 1e-9):
                # The reserve at full creep: the static capacity the step's force left
                # unused, as a fraction of it (fast scheme; the reference scheme's force is
                # the law's, always at capacity there).
                reserve = (e - abs(u)) / e if fast and e > 0 else 0.0
                if log[1 + n + i] < 0 or reserve < log[1 + n + i]:
                    log[1 + n + i] = reserve
                if abs(creep) < dmax[i] * (1.0 - 1e-9):
                    kind = SATURATION
        if kind == 2.0:
            continue
        row = 1 + 2 * n + int(log[0] % rows) * _F
        log[row] = t
        log[row + 1] = i
        log[row + 2] = kind
        log[row + 3] = v
        log[row + 4] = v - d[0]
        log[row + 5] = q
        log[row + 6] = creep
        log[row + 7] = u
        log[row + 8] = capacity_scale[i, 0] * (d[6] * capacity_scale[i, 1]
                                               + capacity_scale[i, 2])
        log[row + 9] = peak
        log[0] += 1.0
        if kind != SATURATION:  # a new phase: its peak and reserve start again
            log[1 + i] = ratio
            log[1 + n + i] = -1.0
        noted += 1
    return noted


def read_log(log, n_pairs, since=0):
    """(rows of the events numbered ``since``.. (an array, one row per event, columns
    ``EVENT_FIELDS``), the log's count, how many of them the ring had already overwritten)."""
    count = int(log[0])
    rows = (log.shape[0] - 1 - 2 * n_pairs) // _F
    first = max(since, count - rows)
    table = log[1 + 2 * n_pairs:].reshape(rows, _F)
    out = np.array([table[j % rows] for j in range(first, count)]).reshape(-1, _F)
    return out, count, first - since
