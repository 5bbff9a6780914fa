"""The compiled (numba) law against the pure-Python law, its reference, to round-off (1e-12
relative): the Magic Formula, the contact and slips, one tyre step of four wheels, the FRD
friction law and one friction step, the tree kinematics against Drake's."""

from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from drake_car.data import resource
from drake_car.law.friction import compiled as fc
from drake_car.law.tyre import compiled as tc
from drake_car.law.tyre import packing as tp
from drake_car.law.friction.frd import (
    KINETIC, STATIC, FrictionPairLaw, StrutFrictionParameters, advance_creep, beta,
    friction_coefficient, friction_force, friction_moment, mu1, mu_kinetic, normal_force,
    shape_max_slope, shape_slope)
from drake_car.law.tyre.magic_formula import MagicFormulaTyre, linear_tyre, magic_formula
from drake_car.law.road.profiles import CosineBump, Flat, SampledProfile
from drake_car.law.tyre.contact import RadialTyre, contact_point, radial_force
from drake_car.law.tyre.slip import (
    SlipOptions, contact_kinematics, low_speed_weight, relax, steady_slips, transient_slips)

RTOL = 1e-12
TYRE = MagicFormulaTyre.from_file(str(resource("urdf/tyres/pacejka2006_205_60R15.tir")))
COEFFICIENTS = tp.pack_coefficients(TYRE)
RNG = np.random.default_rng(7)


def close(compiled, reference, scale):
    """Equal to RTOL relative, zeros to RTOL of the quantity's scale."""
    assert_allclose(np.asarray(compiled, dtype=float), np.asarray(reference, dtype=float),
                    rtol=RTOL, atol=RTOL * scale)


def forces_tuple(f):
    return (f.fx, f.fy, f.mz, f.my, f.fx0, f.fy0, f.cornering_stiffness, f.slip_stiffness,
            f.pneumatic_trail)


# Every form: the book's (the shipped file), PAC2002 (clipped to its ranges, and not), MF 6.1
# at its own pressure and at another.
TYRE_DATA = Path(__file__).parent / "data" / "tyres"
TYRES = [TYRE, MagicFormulaTyre.from_file(TYRE_DATA / "Sedan_Pac02Tire.tir"),
         MagicFormulaTyre.from_file(TYRE_DATA / "Sedan_Pac02Tire.tir", clip=False),
         MagicFormulaTyre.from_file(TYRE_DATA / "335_65R22_5_G275MSA_60psi.tir"),
         MagicFormulaTyre.from_file(TYRE_DATA / "MagicFormula61_Parameters.tir"),
         MagicFormulaTyre.from_file(TYRE_DATA / "MagicFormula62_Parameters.tir",
                                    pressure_Pa=3.1e5)]


@pytest.mark.parametrize("combined", [True, False])
@pytest.mark.parametrize("tyre", TYRES, ids=lambda t: f"{t.form}-{Path(t.name).stem}")
def test_magic_formula(combined, tyre):
    packed = tp.pack_coefficients(tyre)
    top = 3.0 * tyre.FNOMIN
    for _ in range(1000):
        fz = RNG.choice([RNG.uniform(0.01 * top, top), 0.0, -10.0])
        args = (fz, RNG.uniform(-1, 1), RNG.uniform(-0.6, 0.6), RNG.uniform(-0.2, 0.2),
                RNG.uniform(-30, 30))
        close(tc.magic_formula(packed, *args, combined),
              forces_tuple(magic_formula(tyre, *args, combined)), scale=max(abs(fz), 1.0))
        close(tc.linear_tyre(packed, *args), forces_tuple(linear_tyre(tyre, *args)),
              scale=max(abs(fz), 1.0))


def test_relax_and_roads():
    for _ in range(1000):
        args = (RNG.uniform(-0.01, 0.01), RNG.uniform(-2, 2), RNG.choice([0.0, 1e-9, 20.0]),
                RNG.uniform(0.1, 1.0), 1e-3)
        close(tc.relax(*args), relax(*args), scale=0.01)
    roads = [Flat(), CosineBump(1.0, 0.5, 0.04), CosineBump(1.0, 0.5, -0.03),
             SampledProfile([0.0, 1.0, 3.0], [0.0, 0.01, -0.01]),
             SampledProfile([0.0, 1.0, 3.0], [0.0, 0.01, -0.01], [0.0, -0.02, 0.005])]
    for road in roads:
        packed = tp.pack_road(road.check())
        for x in np.concatenate([RNG.uniform(-1, 4, 200), [0.0, 1.0, 1.5, 3.0]]):
            for y in (0.7, 0.0, -1e-9, -0.7):  # both tracks and the line between them
                close(tc.road_height(packed, x, y), road(x, y), scale=0.04)
    with pytest.raises(TypeError, match="compiled tyre knows"):
        tp.pack_road(lambda x, y: 0.0)


def reference_tyre_step(frames, twists, relaxation, advance, radial, slip, road, mirror,
                        combined, linear, magic, dt):
    """One step of four wheels from the pure-Python law, as systems.tyre composes it."""
    wrenches, loads, diagnostics = [], [0.0] * 8, []
    relaxation = list(relaxation)
    for k in range(4):
        (r00, r01, r02, px), (r10, r11, r12, py), (r20, r21, r22, pz) = frames[k].tolist()
        wx, wy, wz, vx, vy, vz = twists[k].tolist()
        axis, centre = (r01, r11, r21), (px, py, pz)
        point, deflection, _ = contact_point(centre, axis, radial.unloaded_radius_m, road)
        eps = 1e-3
        rate = (-vz if isinstance(road, Flat) else
                (road(point[0] + eps, point[1]) - road(point[0] - eps, point[1])) / (2 * eps)
                * vx + (road(point[0], point[1] + eps) - road(point[0], point[1] - eps))
                / (2 * eps) * vy - vz)
        fz = radial_force(radial, deflection, rate)
        loads[k], loads[4 + k] = fz, deflection
        force, torque = [0.0, 0.0, fz], [0.0, 0.0, 0.0]
        diagnostics += [0.0, 0.0, fz, 0.0, 0.0, 0.0, 0.0, 0.0, deflection]
        if magic:
            kin = contact_kinematics(axis, centre, (vx, vy, vz), (wx, wy, wz), point,
                                     radial.unloaded_radius_m - deflection / 3.0)
            if slip.relaxation:
                if advance:
                    if fz <= 0.0:
                        relaxation[2 * k] = relaxation[2 * k + 1] = 0.0
                    else:
                        relaxation[2 * k] = relax(relaxation[2 * k], -kin.v_sx, kin.v_cx,
                                                  slip.relaxation_length_long_m, dt)
                        relaxation[2 * k + 1] = relax(relaxation[2 * k + 1], kin.v_sy,
                                                      kin.v_cx, slip.relaxation_length_lat_m,
                                                      dt)
                kappa, alpha = transient_slips(relaxation[2 * k], relaxation[2 * k + 1], slip)
            else:
                kappa, alpha = steady_slips(kin, slip)
            m = mirror[k]
            f = (linear_tyre(TYRE, fz, kappa, m * alpha, m * kin.gamma, kin.v_cx) if linear
                 else magic_formula(TYRE, fz, kappa, m * alpha, m * kin.gamma, kin.v_cx,
                                    combined))
            fy_, mz_ = (-f.fy, -f.mz) if m < 0 else (f.fy, f.mz)
            damping = (slip.low_speed_damping_Nspm * low_speed_weight(kin.v_cx, slip)
                       if fz > 0 else 0.0)
            fx, fy = f.fx - damping * kin.v_sx, fy_ - damping * kin.v_sy
            c, s = kin.e_x[0], kin.e_x[1]
            force = [fx * c - fy * s, fx * s + fy * c, fz]
            torque = [-f.my * s, f.my * c, mz_]
            diagnostics[-9:] = [fx, fy, fz, mz_, kappa, alpha, kin.gamma, kin.v_cx, deflection]
        rotation = frames[k][:, :3]
        r = np.array(point) - np.array(centre)
        wrenches += (rotation.T @ force).tolist() + (rotation.T @ (np.array(torque)
                                                                  + np.cross(r, force))).tolist()
    return wrenches, loads, diagnostics, relaxation


def random_wheels(spin_sign=1.0):
    """Four wheels near the road, heading about +x, rolling at ~15 m/s with some slip."""
    from scipy.spatial.transform import Rotation
    frames, twists = np.zeros((5, 3, 4)), np.zeros((5, 6))
    for k in range(5):
        rotation = Rotation.from_euler("xyz", [RNG.uniform(-0.05, 0.05),
                                               RNG.uniform(-3, 3), RNG.uniform(-0.2, 0.2)])
        frames[k, :, :3] = rotation.as_matrix()
        frames[k, :, 3] = [RNG.uniform(-1, 1), RNG.uniform(-1, 1), RNG.uniform(0.27, 0.305)]
        axis = frames[k, :, 1]
        speed = RNG.uniform(-1, 16)
        twists[k, :3] = axis * spin_sign * speed / 0.29 * RNG.uniform(0.9, 1.1) \
            + RNG.uniform(-0.1, 0.1, 3)
        twists[k, 3:] = [speed, RNG.uniform(-0.5, 0.5), RNG.uniform(-0.2, 0.2)]
    return frames, twists


@pytest.mark.parametrize("case", ["relaxed", "steady", "linear", "vertical", "bump", "pure"])
def test_tyre_step(case):
    radial = RadialTyre(0.3, 2.0e5, 300.0)
    slip = SlipOptions(relaxation=case != "steady")
    road = CosineBump(-0.5, 1.5, 0.02) if case == "bump" else Flat()
    magic, linear, combined = case != "vertical", case == "linear", case != "pure"
    mirror = [1.0, -1.0, 1.0, -1.0]
    config = tp.pack_config(radial, slip, magic=magic, linear=linear, combined=combined,
                            relaxed=magic and slip.relaxation, max_load=1e9, time_step=1e-3,
                            mirror=mirror)
    wheels, driven, body = np.arange(4), np.array([0, 1]), 4
    for _ in range(100):
        frames, twists = random_wheels(spin_sign=-1.0)
        relaxation = RNG.uniform(-0.01, 0.01, 8)
        torques = RNG.uniform(-500, 500, 2)
        for advance in (False, True):
            wrenches, loads, diagnostics = np.zeros(4 * 6 + 2 + 3), np.zeros(8), np.zeros(36)
            compiled_relaxation = relaxation.copy()
            assert tc.tyre_step(frames, twists, wheels, compiled_relaxation, advance, config,
                                COEFFICIENTS, tp.pack_road(road), torques, driven, body,
                                wrenches, loads, diagnostics) == -1
            expected = reference_tyre_step(frames, twists, relaxation, advance, radial, slip,
                                           road, mirror, combined, linear, magic, 1e-3)
            close(wrenches[:24], expected[0], scale=1e4)
            close(loads, expected[1], scale=1e4)
            close(diagnostics, expected[2], scale=1e4)
            if magic and slip.relaxation:
                close(compiled_relaxation, expected[3], scale=0.01)
            # The drive torques: the knuckles' as given, the body's the sum about the spin
            # axes, reversed, in the body's frame.
            close(wrenches[24:26], torques, scale=500)
            total = torques[0] * frames[0, :, 1] + torques[1] * frames[1, :, 1]
            close(frames[4, :, :3] @ wrenches[26:], -total, scale=500)


def test_tyre_step_refuses_a_load_beyond_the_formula():
    config = tp.pack_config(RadialTyre(0.3, 2.0e5, 300.0), SlipOptions(), magic=True,
                            linear=False, combined=True, relaxed=True, max_load=1000.0,
                            time_step=1e-3, mirror=[1.0] * 4)
    frames, twists = random_wheels()
    frames[2, :, 3] = [0.0, 0.0, 0.2]  # 10 cm into the road: 20 kN
    assert tc.tyre_step(frames, twists, np.arange(4), np.zeros(8), True, config, COEFFICIENTS,
                        tp.pack_road(Flat()), np.zeros(0), np.zeros(0, dtype=np.int64), -1,
                        np.zeros(24), np.zeros(8), np.zeros(36)) in (0, 1, 2, 3)


LAWS = [FrictionPairLaw(0.4, 0.3), FrictionPairLaw(0.2, 0.15, 1e-3, 1e-5, "linear", "linear"),
        FrictionPairLaw(0.0, 0.0)]


@pytest.mark.parametrize("law", LAWS, ids=["cubic", "linear", "lubricated"])
def test_friction_law(law):
    cubic = (law.beta_shape == "cubic", law.creep_shape == "cubic")
    for _ in range(3000):
        v = RNG.choice([RNG.uniform(-3, 3) * law.dv, 0.0, law.dv, -1.5 * law.dv])
        creep = RNG.uniform(-2, 2) * law.dmax
        close(fc.mu_kinetic(v, law.mu_s, law.mu_d, law.dv), mu_kinetic(v, law), scale=1)
        close(fc.friction_coefficient(v, creep, law.mu_s, law.mu_d, law.dv, law.dmax, *cubic),
              friction_coefficient(v, creep, law), scale=1)
        close(fc.shape(abs(v) / law.dv, cubic[0]), beta(v, law), scale=1)
        for x, kind in ((abs(v) / law.dv, law.beta_shape), (creep / law.dmax, law.creep_shape)):
            close(fc.shape_slope(x, kind == "cubic"), shape_slope(x, kind), scale=1)
        close(law.mu_s * fc.shape(abs(creep) / law.dmax, cubic[1]), mu1(creep, law), scale=1)
        phase = RNG.choice([STATIC, KINETIC])
        displacement = RNG.uniform(-1, 1) * law.dmax
        close(fc.advance_creep(creep, phase, v, displacement, law.dv, law.dmax),
              advance_creep(creep, phase, v, displacement, law), scale=law.dmax)


def test_compiled_phases_are_the_laws():
    """law.friction.compiled defines STATIC and KINETIC itself (numba's on-disk cache watches
    that file only): they must stay equal to law.friction.frd's."""
    for name, compiled, reference in (("STATIC", fc.STATIC, STATIC),
                                      ("KINETIC", fc.KINETIC, KINETIC)):
        assert compiled == reference, (
            f"law.friction.compiled.{name} = {compiled}, law.friction.frd.{name} = {reference}")


def test_normal_force_forms():
    from drake_car.law.friction.frd import NORMAL_FORCE_FORMS
    axis = np.array([0.1, -0.2, 0.97])
    axis /= np.linalg.norm(axis)
    for form in NORMAL_FORCE_FORMS:
        for _ in range(500):
            f, m = RNG.uniform(-3000, 3000, 3), RNG.uniform(-300, 300, 3)
            overlap, preload = RNG.uniform(0.05, 0.2), RNG.choice([0.0, 50.0])
            close(fc.normal_force(*f, *m, overlap, preload, 0.3,
                                  NORMAL_FORCE_FORMS.index(form), *axis),
                  normal_force(f, m, overlap, preload, 0.3, form, axis=axis), scale=1e4)
            # A mirrored strut: the compiled step negates the moment before this call.
            close(fc.normal_force(*f, *(-m), overlap, preload, 0.3,
                                  NORMAL_FORCE_FORMS.index(form), *axis),
                  normal_force(f, m, overlap, preload, 0.3, form, axis=axis, mirrored=True),
                  scale=1e4)


def reference_friction_step(x, reactions, initial, fast, laws, strut_laws, struts, pairs,
                            memory):
    """One step of the friction from the pure-Python law, as systems.strut_friction composed
    it. ``struts``: (constant, initial, q, overlap, offset, axis, rod radius, mirrored) per
    strut; ``pairs``: (kind, strut, q index, v index) per pair."""
    n = len(pairs)
    creeps, phases, last_q = memory[:n], memory[n:2 * n], memory[2 * n:]
    normals = []
    for s, (constant, first, q_index, overlap, offset, axis, _, mirrored) in enumerate(struts):
        law = strut_laws[s]
        if constant is not None:
            normals.append(constant)
            continue
        if initial and first is not None:
            normals.append(first)
            continue
        q = x[q_index]
        d = overlap[0] + overlap[1] * q
        mx, my, mz, fx, fy, fz = reactions[s].tolist()
        ux, uy, uz = axis
        a = offset[0] + offset[1] * q
        mx += a * (uy * fz - uz * fy)
        my += a * (uz * fx - ux * fz)
        mz += a * (ux * fy - uy * fx)
        f_axial = fx * ux + fy * uy + fz * uz
        m_axial = mx * ux + my * uy + mz * uz
        normals.append(normal_force(
            (fx - f_axial * ux, fy - f_axial * uy, fz - f_axial * uz),
            (mx - m_axial * ux, my - m_axial * uy, mz - m_axial * uz), d,
            law.preload_force_N, law.mu_s, law.normal_force_form, axis=axis,
            mirrored=mirrored))
    out = {k: [0.0] * n for k in ("creep", "phase", "q", "actuation", "kp", "kd", "effort")}
    out["desired"], out["diagnostics"] = [0.0] * (2 * n), []
    for i, (kind, s, q_index, v_index) in enumerate(pairs):
        law, strut_law, normal = laws[i], strut_laws[s], normals[s]
        q, v = x[q_index], x[v_index]
        creep, phase = advance_creep(creeps[i], phases[i], v, q - last_q[i], law)
        out["creep"][i], out["phase"][i], out["q"][i] = creep, phase, q
        mu, b, m1, _ = friction_coefficient(v, creep, law)
        scale = (friction_force(1.0, normal) if kind == "translation" else
                 friction_moment(1.0, normal, struts[s][6], strut_law.preload_moment_Nm,
                                 strut_law.mu_s))
        force = mu * scale
        out["diagnostics"] += [v, creep, b, m1, mu, phase, normal, force]
        if not fast:
            out["actuation"][i] = force
            continue
        out["kd"][i] = max(shape_max_slope(law.beta_shape) / law.dv * law.mu_s * scale,
                           fc.MIN_GAIN)
        out["kp"][i] = fc.MIN_GAIN
        out["desired"][i] = q
        if phase == STATIC:
            out["actuation"][i] = force
            out["desired"][n + i] = v
            # The damping: the law's slope in v on the branch v is on (with the creep or
            # against it), floored by that branch's secant over the band, blended to the
            # steeper branch's below SLOW_FRACTION·Δv.
            with_creep = v == 0 or creep == 0 or (v > 0) == (creep > 0)
            branch = law.mu_s - m1 if with_creep else law.mu_s + m1
            weight = max(0.0, 1.0 - abs(v) / law.dv / fc.SLOW_FRACTION)
            secant = branch + (law.mu_s + m1 - branch) * weight
            tangent = shape_slope(abs(v) / law.dv, law.beta_shape) * branch
            out["kd"][i] = max(max(tangent, secant) / law.dv * scale, fc.MIN_GAIN)
            out["kp"][i] = max((1 - b) * shape_slope(abs(creep) / law.dmax, law.creep_shape)
                               * law.mu_s / law.dmax * scale, fc.MIN_GAIN)
            out["effort"][i] = max(law.mu_s * scale, fc.MIN_GAIN)
        else:
            out["effort"][i] = max(mu_kinetic(v, law) * scale, fc.MIN_GAIN)
    return out


@pytest.mark.parametrize("fast", [True, False])
@pytest.mark.parametrize("form", ["vector", "magnitude_sum", "contact_pair"])
def test_friction_step(fast, form):
    strut_laws = [StrutFrictionParameters(mu_s=0.4, mu_d=0.3, normal_force_form=form,
                                          preload_force_N=20.0, preload_moment_Nm=0.5),
                  StrutFrictionParameters(mu_s=0.2, mu_d=0.15, normal_force_form=form),
                  StrutFrictionParameters()]
    axis = tuple(np.array([0.1, 0.2, 0.97]) / np.linalg.norm([0.1, 0.2, 0.97]))
    struts = [(None, None, 0, (0.14, -1.0), (-0.07, 0.5), axis, 0.011, False),
              (None, 900.0, 2, (0.14, -1.0), (-0.07, 0.5), axis, 0.012, True),
              (1500.0, None, 0, (0, 0), (0, 0), (0, 0, 1), 0.01, False)]
    pairs = [("translation", 0, 0, 5), ("rotation", 0, 1, 6), ("translation", 1, 2, 7),
             ("rotation", 1, 3, 8), ("translation", 2, 4, 9)]
    laws = [strut_laws[s].translation() if kind == "translation" else strut_laws[s].rotation()
            for kind, s, _, _ in pairs]
    pair_rows = np.array([fc.pack_pair(laws[i], strut_laws[s], rotation=kind == "rotation",
                                       strut=s, q_index=qi, v_index=vi,
                                       rod_radius=struts[s][6])
                          for i, (kind, s, qi, vi) in enumerate(pairs)])
    strut_rows = np.array([fc.pack_strut(strut_laws[s], constant=c, initial=first, q_index=qi,
                                         overlap=d, offset=a, axis=u, mirrored=m)
                           for s, (c, first, qi, d, a, u, _, m) in enumerate(struts)])
    n = len(pairs)
    for _ in range(300):
        x = np.concatenate([RNG.uniform(-0.02, 0.02, 5),
                            RNG.choice([-1, 1]) * RNG.uniform(0, 2e-4, 5)])
        reactions = RNG.uniform(-2000, 2000, (3, 6))
        memory = np.concatenate([RNG.uniform(-5e-6, 5e-6, n), RNG.choice([STATIC, KINETIC], n),
                                 x[:5] - RNG.uniform(-3e-6, 3e-6, n)])
        initial = bool(RNG.integers(2))
        compiled = {"memory": memory.copy(), "actuation": np.zeros(n),
                    "diagnostics": np.zeros(8 * n), "desired": np.zeros(2 * n),
                    "gains": np.zeros(3 * n)}
        assert fc.friction_step(x, reactions, initial, fast, pair_rows, strut_rows,
                                compiled["memory"], compiled["actuation"],
                                compiled["diagnostics"], compiled["desired"],
                                compiled["gains"]) == -1
        expected = reference_friction_step(x, reactions, initial, fast, laws, strut_laws,
                                           struts, pairs, memory.tolist())
        close(compiled["memory"], expected["creep"] + expected["phase"] + expected["q"],
              scale=1e-3)
        close(compiled["actuation"], expected["actuation"], scale=1e3)
        close(compiled["diagnostics"], expected["diagnostics"], scale=1e3)
        if fast:
            close(compiled["desired"], expected["desired"], scale=1e-2)
            close(compiled["gains"], expected["kp"] + expected["kd"] + expected["effort"],
                  scale=1e3)


def test_friction_step_mirror_image_struts_are_exact():
    """Two struts, the second the first's mirror image in the plane y = 0 (its axis, its
    reaction force reflected; its moment, an axial vector, reflected and negated) and marked
    ``mirrored``: their normal forces and their pairs' every value agree bit for bit (the
    rotation pair's signed ones negated), in every normal-force form; not marked, the vector
    form's differ (issue 32: what broke the car's mirror)."""
    reflect = np.array([1.0, -1.0, 1.0])
    axis = np.array([0.1, 0.2, 0.97]) / np.linalg.norm([0.1, 0.2, 0.97])
    for form in ("vector", "magnitude_sum", "contact_pair"):
        law = StrutFrictionParameters(mu_s=0.4, mu_d=0.3, normal_force_form=form)
        for mark in (True, False):
            pairs = np.array([
                fc.pack_pair(law.rotation() if rot else law.translation(), law, rotation=rot,
                             strut=s, q_index=2 * s + rot, v_index=4 + 2 * s + rot,
                             rod_radius=0.011)
                for s in (0, 1) for rot in (False, True)])
            struts = np.array([
                fc.pack_strut(law, q_index=2 * s, overlap=(0.14, -1.0), offset=(-0.07, 0.5),
                              axis=tuple(axis * (reflect if s else 1.0)),
                              mirrored=mark and s == 1) for s in (0, 1)])
            for _ in range(200):
                q, v = RNG.uniform(-0.02, 0.02, 2), RNG.uniform(-2e-4, 2e-4, 2)
                # Translation: the same on both sides; rotation (an angle about a reflected
                # axis): negated.
                x = np.array([q[0], q[1], q[0], -q[1], v[0], v[1], v[0], -v[1]])
                moment, force = RNG.uniform(-300, 300, 3), RNG.uniform(-3000, 3000, 3)
                reactions = np.array([np.concatenate([moment, force]),
                                      np.concatenate([-reflect * moment, reflect * force])])
                creep = RNG.uniform(-5e-6, 5e-6, 2)
                memory = np.concatenate([[creep[0], creep[1], creep[0], -creep[1]],
                                         [STATIC] * 4, x[:4] - 1e-6 * np.array([1, 1, 1, -1])])
                out = {"memory": memory, "actuation": np.zeros(4),
                       "diagnostics": np.zeros(32), "desired": np.zeros(8),
                       "gains": np.zeros(12)}
                fc.friction_step(x, reactions, False, True, pairs, struts, out["memory"],
                                 out["actuation"], out["diagnostics"], out["desired"],
                                 out["gains"])
                d = out["diagnostics"].reshape(4, 8)
                if not mark:
                    if form == "vector" and d[0, 6] != d[2, 6]:
                        break
                    continue
                odd = np.array([-1.0, -1.0, 1.0, 1.0, -1.0, 1.0, 1.0, -1.0])  # v, creep, μ, F
                assert np.array_equal(d[2], d[0]), (form, "translation", d[0], d[2])
                assert np.array_equal(d[3], odd * d[1]), (form, "rotation", d[1], d[3])
                g = out["gains"].reshape(3, 4)
                assert np.array_equal(g[:, 2], g[:, 0]) and np.array_equal(g[:, 3], g[:, 1])
            else:
                assert mark or form != "vector", "the unmarked vector form should differ"


def test_friction_step_names_a_strut_out_of_its_guide():
    law = StrutFrictionParameters()
    pairs = np.array([fc.pack_pair(law.translation(), law, rotation=False, strut=0, q_index=0,
                                   v_index=1, rod_radius=0.01)])
    struts = np.array([fc.pack_strut(law, overlap=(0.1, -1.0))])
    assert fc.friction_step(np.array([0.2, 0.0]), np.zeros((1, 6)), False, True, pairs, struts,
                            np.zeros(3), np.zeros(1), np.zeros(8), np.zeros(2),
                            np.zeros(3)) == 0


def test_tree_kinematics_refuses_an_unknown_joint():
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.multibody.tree import BallRpyJoint, SpatialInertia
    from drake_car.systems.body_kinematics import BodyKinematics
    plant = MultibodyPlant(time_step=1e-3)
    body = plant.AddRigidBody("b", SpatialInertia.SolidSphereWithMass(1.0, 0.1))
    plant.AddJoint(BallRpyJoint("ball", plant.world_frame(), body.body_frame()))
    plant.Finalize()
    with pytest.raises(ValueError, match="ball_rpy joint"):
        BodyKinematics(plant, [body])
