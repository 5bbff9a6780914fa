"""The car's front strut at rest, what loads it, and the strut rig's side load that reproduces
it.

The car's normal force at rest is eq. 4 on the strut's prismatic joint's reaction in the car at
its static equilibrium (``sim.simulate.static_equilibrium``: the lubricated car settled on
vertical tyres), as the strut friction computes it (``strut_load``): the reaction on the
knuckle at the guide, its moment moved to the overlap's middle (``model.struts.
strut_geometry``), the components perpendicular to the strut's axis, eq. 4 in the law's form.

What loads the strut (``StrutAtRest.shares_N``): the knuckle and its wheel are held by the
ball joint (a force through its centre: the lower arm, and the anti-roll bar through the arm,
have no moment about it), the strut, the tie rod (a force at the steering arm), the coil spring
(a force along its line, from the seat on the knuckle) and loaded by the tyre and their
weights. Their moments about the ball joint balance; the piston rod hangs from the top mount's
universal joint, which carries no bending moment, so the strut's share is a transverse force
through the top mount, and each load's share of it is the force at the top mount that balances
that load's moment alone (they add up to the strut's). ``strut.corner_side_force_N`` is the
closed form of the tyre's vertical share alone, with the spring's line through the ball joint.

The rig (``StrutAtRest.rig_options``) reproduces the strut's load: a side force |F| at the top
mount (``side_force_point_below_top_m = 0``), whose reaction is |F| and the moment |F| a about
the overlap's middle, a the top mount's distance from it, as in the car. What remains between
the two (``StrutAtRest.rig_difference_N``): the rod's and slider's weight, which the car's rod
carries to the top mount and the rig (tared, no gravity) does not, and the rod's rest position
(the car's overlap at rest against l). The rig's N then follows the stroke as its side force
moves with the knuckle (``strut.eq4_normal_force_N``).
"""

import dataclasses
import math

import numpy as np

from drake_car.law.friction.frd import StrutFrictionParameters, normal_force
from drake_car.model.parameters import GRAVITY_MPS2
from drake_car.model.struts import strut_geometry
from drake_car.scene.manoeuvres import Settle
from drake_car.scene.scene import Scene
from drake_car.sim.equilibrium import equilibrium_scene
from drake_car.sim.rigs.strut import StrutRigOptions, corner_side_force_N, rest_normal_force_N
from drake_car.sim.simulate import SceneRunner, static_equilibrium

WHEEL = {"left": "fl", "right": "fr"}
# Where the rig loaded as the car's strut at rest applies its side force (see the module): the
# top mount. The rig study's loops and synthetic loop use it, and a measured loop is fitted
# with it unless its test says another (``study.rig.measured.rig_of_loop``).
SIDE_FORCE_POINT_BELOW_TOP_M = 0.0


@dataclasses.dataclass
class StrutAtRest:
    """A front strut of a scene's car at its static equilibrium. ``force_N`` and
    ``moment_Nm``: the transverse reaction on the knuckle and the bending moment about the
    overlap's middle, in the joint's frame; ``normal_N``: eq. 4 of them (the law's form and
    preload); ``stroke_m``, ``overlap_m``: q and d = l - q at rest; ``corner_load_N``: the
    corner's vertical load at rest (its tyres vertical: no lateral force); ``rod_weight_N``:
    the rod's and slider's weight across the strut's axis; ``shares_N``: each load's share of
    the strut's transverse force, as a force at the top mount along it."""

    side: str
    front: object  # FrontSuspensionParameters
    law: StrutFrictionParameters
    stroke_m: float
    overlap_m: float
    force_N: tuple
    moment_Nm: tuple
    normal_N: float
    corner_load_N: float
    rod_weight_N: float
    shares_N: dict

    @property
    def transverse_force_N(self):
        return float(np.linalg.norm(self.force_N))

    @property
    def bending_moment_Nm(self):
        return float(np.linalg.norm(self.moment_Nm))

    @property
    def lever_m(self):
        """Where the strut's load acts: its line's distance from the overlap's middle."""
        return self.bending_moment_Nm / self.transverse_force_N

    def rig_options(self, **changes) -> StrutRigOptions:
        """The rig loaded as the car's strut at rest: the side force |F| at the top mount."""
        return StrutRigOptions(**{"side_force_N": self.transverse_force_N,
                                  "side_force_point_below_top_m":
                                      SIDE_FORCE_POINT_BELOW_TOP_M, **changes})

    def rig_normal_N(self):
        """The rig's N at rest under ``rig_options()`` (eq. 4 at the design position)."""
        return rest_normal_force_N(self.front, self.rig_options(), self.law)

    def rig_difference_N(self):
        """A bound on what the rig does not hold of the car's N at rest: the rod's and
        slider's weight across the axis, W, carried by the car's rod to the top mount, changes
        F by at most W and the moment about the middle by at most W times the rod's length
        (top mount to piston, the longest lever it can have), so N by at most W (1 + rod / d)
        (N = |M/d + F| moves by at most |ΔF| + |ΔM|/d); the rest position q changes d = l - q
        and the lever a by q/2: N's moment term (M/d)²/N by |q|/d (1 + d / 2a) of itself."""
        front = self.front
        rod = front.guide_below_top_mount_m + front.guide_length_l_m
        d = min(self.overlap_m, front.guide_length_l_m)
        moment_term = (self.bending_moment_Nm / self.overlap_m) ** 2 / self.normal_N
        position = moment_term * abs(self.stroke_m) / d * (1.0 + d / (2.0 * self.lever_m))
        return self.rod_weight_N * (1.0 + rod / d) + position

    def summary(self):
        """The numbers a report gives (JSON-ready)."""
        options = self.rig_options()
        closed = corner_side_force_N(self.front, self.corner_load_N)
        return {"side": self.side, "car_normal_N": self.normal_N,
                "transverse_force_N": self.transverse_force_N,
                "bending_moment_Nm": self.bending_moment_Nm, "lever_m": self.lever_m,
                "top_mount_to_middle_m": (self.front.guide_below_top_mount_m
                                          + 0.5 * self.front.guide_length_l_m),
                "stroke_m": self.stroke_m, "overlap_m": self.overlap_m,
                "corner_load_N": self.corner_load_N, "shares_N": dict(self.shares_N),
                "rig_side_force_N": options.side_force_N,
                "rig_side_force_point_below_top_m": options.side_force_point_below_top_m,
                "rig_normal_N": self.rig_normal_N(),
                "rig_difference_bound_N": self.rig_difference_N(),
                "corner_side_force_N": closed,
                "corner_side_force_normal_N": rest_normal_force_N(
                    self.front, dataclasses.replace(options, side_force_N=closed), self.law)}


def strut_at_rest(scene: Scene, side="left") -> StrutAtRest:
    """The front strut of ``scene``'s car at its static equilibrium (cached,
    ``static_equilibrium``): the loads of one step from rest there, on the settling scene's
    car (lubricated, vertical tyres), with ``scene``'s friction law (or the paper's, when the
    scene has none) for eq. 4's form and preload."""
    law = scene.friction.law if scene.friction is not None else StrutFrictionParameters()
    settle = equilibrium_scene(scene)
    runner = SceneRunner(dataclasses.replace(
        settle, manoeuvre=Settle(duration_s=settle.time_step_s)))
    runner.built.initial_positions = static_equilibrium(
        scene, runner.built.plant.num_positions(runner.built.car.instance)).positions
    runner.run()
    built, root = runner.built, runner.root
    q, d, f_t, m_t, n = strut_load(built, root, side, law)
    loads = built.tyre.GetOutputPort("tyre_loads").Eval(built.tyre.GetMyContextFromRoot(root))
    axis = _strut_axis_in_world(built, root, side)
    mass = scene.car.mass.piston_rod_kg + scene.car.mass.strut_slider_kg
    weight = mass * GRAVITY_MPS2 * math.sqrt(max(0.0, 1.0 - axis[2] ** 2))
    return StrutAtRest(side=side, front=scene.car.front, law=law, stroke_m=q, overlap_m=d,
                       force_N=tuple(f_t), moment_Nm=tuple(m_t), normal_N=n,
                       corner_load_N=float(loads[("fl", "fr", "rl", "rr").index(WHEEL[side])]),
                       rod_weight_N=float(weight), shares_N=_shares_N(built, root, side))


def strut_load(built, root_context, side, law):
    """A front strut's load in a car's Diagram ``built`` (``sim.build.CarDiagram``) at
    ``root_context``, as the strut friction takes it: (q, d, the transverse reaction force on
    the knuckle, the transverse bending moment about the overlap's middle, N of eq. 4 in
    ``law``'s form), from the plant's reaction output (the last step's)."""
    plant, car = built.plant, built.car
    context = plant.GetMyContextFromRoot(root_context)
    prismatic, _ = car.strut_joints(side)
    reaction = plant.get_reaction_forces_output_port().Eval(context)[prismatic.index()]
    q = float(prismatic.get_translation(context))
    geometry = strut_geometry(car.params.front, side)
    d = geometry["overlap_m"][0] + geometry["overlap_m"][1] * q
    offset = geometry["moment_arm_offset_m"][0] + geometry["moment_arm_offset_m"][1] * q
    axis = np.asarray(prismatic.translation_axis(), dtype=float)
    axis /= np.linalg.norm(axis)
    f = np.asarray(reaction.translational(), dtype=float)
    m = np.asarray(reaction.rotational(), dtype=float) + offset * np.cross(axis, f)
    f_t, m_t = f - f.dot(axis) * axis, m - m.dot(axis) * axis
    n = normal_force(f_t, m_t, d, law.preload_force_N, law.mu_s, law.normal_force_form,
                     axis=axis, mirrored=geometry["mirrored"])
    return q, d, f_t, m_t, float(n)


def _strut_axis_in_world(built, root_context, side):
    prismatic, _ = built.car.strut_joints(side)
    context = built.plant.GetMyContextFromRoot(root_context)
    axis = np.asarray(prismatic.translation_axis(), dtype=float)
    rotation = prismatic.frame_on_child().CalcPoseInWorld(context).rotation()
    return rotation.multiply(axis / np.linalg.norm(axis))


def _shares_N(built, root_context, side):
    """Each load's share of the strut's transverse force (module docstring): the force at the
    top mount, perpendicular to the strut, whose moment about the ball joint balances that
    load's, along the strut's own (so the shares add up to its magnitude, up to what is not
    in the plane). Loads: the tyre, the spring, the tie rod, the weights of the knuckle and
    the wheel; "strut" the strut's own, "balance" what the moments leave (~0 at rest)."""
    plant, car = built.plant, built.car
    context = plant.GetMyContextFromRoot(root_context)
    gravity = np.array([0.0, 0.0, -GRAVITY_MPS2])

    def point(frame):
        return plant.GetFrameByName(frame, car.instance).CalcPoseInWorld(context).translation()

    ball = point(f"ball_joint_knuckle_{side}")
    knuckle = plant.GetBodyByName(f"knuckle_{side}", car.instance)
    wheel = car.wheel_bodies()[WHEEL[side]]
    moments = {}
    # The tyre: the applier's force on the wheel (its moment about the wheel's origin too).
    applier = next(s for s in built.diagram.GetSystems() if s.get_name() == "tyre_forces")
    tyre = np.zeros(3)
    for force in applier.get_spatial_forces_output_port().Eval(
            applier.GetMyContextFromRoot(root_context)):
        if force.body_index == wheel.index():
            where = wheel.EvalPoseInWorld(context).multiply(force.p_BoBq_B)
            tyre += (np.cross(where - ball, force.F_Bq_W.translational())
                     + force.F_Bq_W.rotational())
    moments["tyre"] = tyre
    # The spring: k (L - L0) along its line, on the seat on the knuckle.
    upper, lower = point(f"spring_upper_seat_{side}"), point(f"spring_lower_seat_{side}")
    spring = car.springs[("front", side)]
    length = np.linalg.norm(upper - lower)
    tension = spring.stiffness_Npm * (length - spring.free_length_m)
    moments["spring"] = np.cross(lower - ball, tension * (upper - lower) / length)
    # The tie rod at rest: what its inner joint and its weight put on it, at the knuckle.
    inner = plant.GetJointByName(f"tie_rod_inner_{side}", car.instance)
    reactions = plant.get_reaction_forces_output_port().Eval(context)
    on_rod = inner.frame_on_child().CalcPoseInWorld(context).rotation().multiply(
        reactions[inner.index()].translational())
    tie_rod = on_rod + inner.child_body().get_mass(context) * gravity
    moments["tie_rod"] = np.cross(point(f"tie_rod_outer_{side}") - ball, tie_rod)
    for name, body in (("knuckle_weight", knuckle), ("wheel_weight", wheel)):
        centre = body.EvalPoseInWorld(context).multiply(body.CalcCenterOfMassInBodyFrame(context))
        moments[name] = np.cross(centre - ball, body.get_mass(context) * gravity)
    prismatic, _ = car.strut_joints(side)
    pose = prismatic.frame_on_child().CalcPoseInWorld(context)
    reaction = reactions[prismatic.index()]
    strut_force = pose.rotation().multiply(reaction.translational())
    strut_moment = (np.cross(pose.translation() - ball, strut_force)
                    + pose.rotation().multiply(reaction.rotational()))
    axis = _strut_axis_in_world(built, root_context, side)
    transverse = strut_force - strut_force.dot(axis) * axis
    along = transverse / np.linalg.norm(transverse)
    first = np.cross(axis, along)
    lever = point(f"top_mount_{side}") - ball
    basis = np.column_stack([np.cross(lever, along), np.cross(lever, first)])

    def share(moment):  # the top mount's force (in the plane across the axis) balancing it
        coefficients, *_ = np.linalg.lstsq(basis, -moment, rcond=None)
        return float(coefficients[0])

    shares = {name: share(moment) for name, moment in moments.items()}
    shares["strut"] = float(np.linalg.norm(transverse))
    shares["balance"] = share(-(sum(moments.values()) + strut_moment))
    return shares
