"""The paper's study's friction sets, as its scenes have them: which runs form the study (cases a
and b × any number of friction sets, each set in both cases), each set's number and what it is
(μs, μd, the strut's viscous damping: all from the scene that ran), and the sets each claim
compares (``SetRoles``).

The paper ran three sets: (0, 0) lubricated, (0.2, 0.15) "practically realistic", (0.4, 0.3)
"very high". Its claims name them: claims 1 and 2 are about the highest friction (curve 3), claim
1 compares it with the lower sets, claim 6 is about Fig. 16's set (μs = 0.2). A user's two or
five sets run the same claims: the highest dry set is the paper's set 3, the others its sets 1-2,
and Fig. 16's set is the dry set nearest the paper's μs = 0.2; a claim that needs a dry set is
not applicable when none ran.
"""

import dataclasses
import typing

from drake_car.law.errors import InputError
from drake_car.scene.manoeuvres import LaneChange

CASES = ("a", "b")
# What a study run must log.
STUDY_CHANNELS = ("chassis", "steering", "struts", "tyres", "friction")
# The paper's Fig. 16: its set 2 (μs = 0.2, μd = 0.15).
FIG16_MU_S = 0.2


class StudyError(InputError):
    """The runs given are not the paper's study (cases × friction sets); says what is wrong."""


@dataclasses.dataclass
class FrictionSet:
    """A friction set of the study, as its scenes have it: (μs, μd) of the dry struts (μs = 0:
    no dry friction) and the strut's viscous damping."""

    number: int
    mu_s: float
    mu_d: float
    damping_Nspm: float

    @property
    def dry(self):
        return self.mu_s > 0

    @property
    def label(self):
        damper = f"{self.damping_Nspm:g} N s/m"
        if not self.dry:
            return f"{self.number}: μs = 0 (" + (f"lubricated, {damper})" if self.damping_Nspm
                                                  else "no friction, no damping)")
        return (f"{self.number}: μs = {self.mu_s:g}, μd = {self.mu_d:g}"
                + (f", {damper}" if self.damping_Nspm else ""))

    def describe(self):
        """What the set is, in words, from its values (never assumed from the paper's)."""
        damping = (f"{self.damping_Nspm:g} N s/m of viscous damping" if self.damping_Nspm
                   else "no viscous damping")
        if not self.dry:
            return (f"lubricated strut: no dry friction, {damping}" if self.damping_Nspm
                    else "no dry friction and no viscous damping (an undamped strut)")
        return f"dry strut: static μs = {self.mu_s:g}, kinetic μd = {self.mu_d:g}, {damping}"


@dataclasses.dataclass(frozen=True)
class SetRoles:
    """The sets each claim compares: ``high`` the highest-friction dry set (the paper's set 3;
    None when no set is dry), ``others`` every other set (the paper's sets 1-2), ``fig16`` the
    dry set nearest the paper's μs = 0.2 (None when no set is dry)."""

    numbers: typing.Tuple[int, ...]
    high: typing.Optional[int]
    fig16: typing.Optional[int]

    @property
    def others(self):
        return tuple(n for n in self.numbers if n != self.high)


def set_roles(sets) -> SetRoles:
    """``SetRoles`` of the FrictionSets ``sets`` (any iterable, repeats allowed)."""
    by_number = {f.number: f for f in sets}
    dry = [f for f in by_number.values() if f.dry]
    high = max(dry, key=lambda f: (f.mu_s, f.mu_d, f.damping_Nspm, f.number), default=None)
    fig16 = min(dry, key=lambda f: (abs(f.mu_s - FIG16_MU_S), f.mu_s, f.number), default=None)
    return SetRoles(tuple(sorted(by_number)), None if high is None else high.number,
                    None if fig16 is None else fig16.number)


def numbers_text(numbers):
    """"set 1", "sets 1, 2", "no other set"."""
    numbers = list(numbers)
    if not numbers:
        return "no other set"
    return ("set " if len(numbers) == 1 else "sets ") + ", ".join(str(n) for n in numbers)


def friction_of(scene):
    """(μs, μd, strut damping) of a scene's front struts."""
    damping = scene.car.front.strut_damping_Nspm
    if scene.friction is None:
        return 0.0, 0.0, damping
    return scene.friction.law.mu_s, scene.friction.law.mu_d, damping


def check_study_scenes(scenes: dict):
    """Refuses (StudyError) scenes that are not the paper's study: lane changes from static
    equilibrium, cases a and b × one or more friction sets (each set in both cases, once), one
    timeline. Returns name -> (case, FrictionSet), the sets numbered 1, 2, ... by (μs, μd,
    damping). Run it before simulating: it needs only the scenes."""
    if not scenes:
        raise StudyError("the study has no runs")
    sets = sorted({friction_of(s) for s in scenes.values()})
    numbered = {key: FrictionSet(i + 1, *key) for i, key in enumerate(sets)}
    out, grid = {}, []
    for name, scene in scenes.items():
        if not isinstance(scene.manoeuvre, LaneChange):
            raise StudyError(f"run {name}: the study needs lane changes, not "
                             f"{type(scene.manoeuvre).__name__}")
        if scene.simulator.start != "static_equilibrium":
            raise StudyError(f"run {name}: Δd is measured from static equilibrium; the run "
                             "must start there (simulator.start)")
        missing = [g for g in STUDY_CHANNELS if scene.logging.channels is not None
                   and g not in scene.logging.channels and (g != "friction" or scene.friction)]
        if missing:
            raise StudyError(f"run {name}: the study needs the logged channels {missing}")
        friction = numbered[friction_of(scene)]
        grid.append((scene.manoeuvre.case, friction.number))
        out[name] = (scene.manoeuvre.case, friction)
    full = {(c, n) for c in CASES for n in range(1, len(sets) + 1)}
    if len(grid) != len(set(grid)) or set(grid) != full:
        raise StudyError(f"the paper's study is cases a and b × its friction sets, each set "
                         f"once in each case; the scenes give (case, set) {sorted(grid)} with "
                         f"the sets (μs, μd, damping) {sets}")
    timelines = {dataclasses.astuple(s.manoeuvre.timeline) for s in scenes.values()}
    if len(timelines) != 1:
        raise StudyError("the study's runs must share one timeline")
    return out


def roles_of(roles: dict) -> SetRoles:
    """``SetRoles`` of a study's roles (name -> (case, FrictionSet))."""
    return set_roles(f for _, f in roles.values())
