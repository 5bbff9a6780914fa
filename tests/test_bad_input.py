"""Bad input and faults at every entry point: one line on stderr naming what is wrong and where
(the key path, or the file and line), exit status 2, nothing written, nothing left behind.

The table runs each entry point's ``main`` in this process through ``cli.run_main`` (the same
code path as the command line, without the interpreter's start-up); a few cases also run as
real processes, and a run is killed while it writes."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from drake_car.commands import cli
from drake_car.commands import run as run_command
from drake_car.commands import tyre as tyre_command

from drake_car.commands import accuracy, calibrate, design, friction_rig, handling, paper
from drake_car.commands import kinematics, settle, strut_rig

ROOT = Path(__file__).resolve().parents[1]

TIR = (ROOT / "urdf" / "tyres" / "pacejka2006_205_60R15.tir").read_text()
TYRE_DATA = Path(__file__).parent / "data" / "tyres"
SEDAN = (TYRE_DATA / "Sedan_Pac02Tire.tir").read_text()
MF61 = (TYRE_DATA / "MagicFormula61_Parameters.tir").read_text()
RUN = ["--scene", "scenes/paper_study.yaml:a_1"]


def tir_file(tmp_path, text, name="bad.tir", binary=False):
    path = tmp_path / name
    if binary:
        path.write_bytes(bytes(range(256)) * 4)
    else:
        path.write_text(text)
    return path


def tyre(path):
    return f"tyres: !MagicFormula {{tir_file: {path}}}"


def scene_text(text):
    return RUN + ["--scene_text", text]


# (label, main, argv builder (tmp_path -> list), what the message must name)
CASES = [
    ("mu_d above mu_s", run_command.main,
     lambda t: scene_text("friction: {law: {mu_s: 0.2, mu_d: 0.5}}"), "friction.law.mu_d"),
    ("negative mu", run_command.main,
     lambda t: scene_text("friction: {law: {mu_s: -0.1, mu_d: 0.0}}"), "friction.law.mu_s"),
    ("threshold velocity 0", run_command.main,
     lambda t: scene_text("friction: {law: {dv_translation_mps: 0.0}}"),
     "friction.law.dv_translation_mps"),
    ("negative maximum creep", run_command.main,
     lambda t: scene_text("friction: {law: {dmax_translation_m: -1.0e-6}}"),
     "friction.law.dmax_translation_m"),
    ("negative speed", run_command.main,
     lambda t: scene_text("manoeuvre: !LaneChange {timeline: {speed_kph: -10.0}}"),
     "manoeuvre.timeline.speed_kph"),
    ("b of 10 m", run_command.main,
     lambda t: scene_text("car: {front: {ball_joint_offset_b_m: 10.0}}"),
     "car.front.ball_joint_offset_b_m"),
    ("guide length 0", run_command.main,
     lambda t: scene_text("car: {front: {guide_length_l_m: 0.0}}"),
     "car.front.guide_length_l_m"),
    ("NaN damping", run_command.main,
     lambda t: scene_text("car: {front: {strut_damping_Nspm: .nan}}"),
     "car.front.strut_damping_Nspm"),
    ("negative top-mount stiffness", run_command.main,
     lambda t: scene_text("car: {front: {top_mount_stiffness_Npm: -1.0}}"),
     "car.front.top_mount_stiffness_Npm"),
    ("89 deg spring inclination", run_command.main,
     lambda t: scene_text("car: {front: {spring_inclination_deg: 89.0}}"),
     "car.front.spring_inclination_deg"),
    ("unsorted road samples", run_command.main,
     lambda t: scene_text("road: !SampledProfile {x_m: [0.0, 2.0, 1.0], z_m: [0, 0, 0]}"),
     "road.x_m[2]"),
    ("mismatched road samples", run_command.main,
     lambda t: scene_text("road: !SampledProfile {x_m: [0.0, 1.0], z_m: [0.0]}"), "road.x_m"),
    ("NaN road sample", run_command.main,
     lambda t: scene_text("road: !SampledProfile {x_m: [0.0, 1.0], z_m: [0.0, .nan]}"),
     "road.z_m[1]"),
    ("zero-length bump", run_command.main,
     lambda t: scene_text("road: !CosineBump {length_m: 0.0}"), "road.length_m"),
    ("infinite step", run_command.main,
     lambda t: scene_text("plant: {time_step: .inf}"), "plant.time_step"),
    ("NaN end time", run_command.main,
     lambda t: scene_text("simulator: {end_time_s: .nan}"), "simulator.end_time_s"),
    ("infinite end time", run_command.main,
     lambda t: scene_text("simulator: {end_time_s: .inf}"), "simulator.end_time_s"),
    ("infinite speed", run_command.main,
     lambda t: scene_text("manoeuvre: !LaneChange {timeline: {speed_kph: .inf}}"),
     "manoeuvre.timeline.speed_kph"),
    ("end time 1e9 s", run_command.main,
     lambda t: scene_text("simulator: {end_time_s: 1.0e9}"), "simulator.end_time_s"),
    ("a tighter SAP tolerance", run_command.main,
     lambda t: scene_text("simulator: {sap_tolerance_factor: 0.5}"),
     "simulator.sap_tolerance_factor"),
    ("a word for a number", run_command.main,
     lambda t: scene_text("friction: {law: {mu_s: high}}"), "friction.law.mu_s"),
    ("unknown key", run_command.main,
     lambda t: scene_text("friction: {law: {mu_z: 0.2}}"), "friction.law.mu_z"),
    ("unknown variant", run_command.main,
     lambda t: scene_text("road: !Bumpy {}"), "!Bumpy"),
    ("channels as a string", run_command.main,
     lambda t: scene_text("logging: {channels: chassis}"), "logging.channels"),
    ("friction channel without friction", run_command.main,
     lambda t: scene_text("logging: {channels: [friction]}"), "logging.channels[0]"),
    ("a setting with no effect", run_command.main,
     lambda t: scene_text("plant: {contact_model: point}"), "plant.contact_model"),
    ("missing scene entry", run_command.main,
     lambda t: ["--scene", "scenes/paper_study.yaml:zz"], "no scene 'zz'"),
    ("scene path is a folder", run_command.main,
     lambda t: ["--scene", "scenes"], "is a folder"),
    ("truncated .tir", run_command.main,
     lambda t: scene_text(tyre(tir_file(t, TIR.split("PDY1")[0]))), "PDY1"),
    ("non-numeric .tir value", run_command.main,
     lambda t: scene_text(tyre(tir_file(t, TIR.replace("= -0.990", "= minus")))),
     "bad.tir:43: PDY1"),
    ("FNOMIN 0", run_command.main,
     lambda t: scene_text(tyre(tir_file(t, TIR.replace("= 4000.0", "= 0.0")))), "FNOMIN"),
    ("negative tyre radius", run_command.main,
     lambda t: scene_text(tyre(tir_file(t, TIR.replace("= 0.313", "= -0.313")))),
     "UNLOADED_RADIUS"),
    ("a coefficient of 1e300", run_command.main,
     lambda t: scene_text(tyre(tir_file(t, TIR.replace("= -14.95", "= -1.0e300")))), "bad.tir"),
    ("MF-Swift .tir", run_command.main,
     lambda t: scene_text(tyre(tir_file(t, SEDAN.replace("'PAC2002'", "'MF-SWIFT'")))),
     "bad.tir: PROPERTY_FILE_FORMAT 'MF-SWIFT' is a tyre model drake_car does not implement"),
    ("MF_05 .tir by FITTYP", run_command.main,
     lambda t: scene_text(tyre(tir_file(t, MF61.replace("=    61 ", "=    5 ")))),
     "bad.tir:14: FITTYP = 5 is a Magic Formula version drake_car does not implement"),
    ("unknown unit in [UNITS]", run_command.main,
     lambda t: scene_text(tyre(tir_file(t, SEDAN.replace("'meter'", "'furlong'")))),
     "bad.tir:5: [UNITS] LENGTH = 'furlong'"),
    ("bad [SHAPE] table row", run_command.main,
     lambda t: scene_text(tyre(tir_file(t, SEDAN.replace("1.0    0.4", "1.0    wide")))),
     "bad.tir:32: cannot read line '1.0 wide' in table [SHAPE]"),
    ("coefficient in two sections", run_command.main,
     lambda t: scene_text(tyre(tir_file(t, SEDAN.replace("[LONGITUDINAL_COEFFICIENTS]",
                                                         "[LONGITUDINAL_COEFFICIENTS]\nPKY1 = 1")))),
     "PKY1 is given twice (in [LONGITUDINAL_COEFFICIENTS] and [LATERAL_COEFFICIENTS])"),
    ("MF 6.1 range reversed", run_command.main,
     lambda t: scene_text(tyre(tir_file(t, MF61.replace("=    18000 ", "=    -1 ")))),
     "bad.tir:110: FZMAX = -1 is below FZMIN = 0"),
    ("a truck's tyre on the car", run_command.main,
     lambda t: scene_text(tyre(TYRE_DATA / "335_65R22_5_G275MSA_60psi.tir")),
     "is valid for wheel loads 10752..30578 N"),
    ("relaxation lengths from an MF 6.1 file without its carcass stiffness", run_command.main,
     lambda t: scene_text(f"tyres: !MagicFormula {{tir_file: "
                          f"{tir_file(t, MF61.replace('LATERAL_STIFFNESS', '$'))}, "
                          "slip: {relaxation_lengths_from_file: true}}"),
     "bad.tir (MF 6.1) has no relaxation data (PAC2002: PTX*/PTY*; MF 6.x: "
     "LONGITUDINAL_STIFFNESS and LATERAL_STIFFNESS)"),
    ("vertical stiffness from a file without it", run_command.main,
     lambda t: scene_text("tyres: !MagicFormula {vertical_from_file: true}"),
     "tyres.vertical_from_file = True needs them: "),
    ("a tyre value the file's vertical data override", run_command.main,
     lambda t: scene_text(f"car: {{tyre: {{radial_damping_Nspm: 300.0}}}}\ntyres: !MagicFormula "
                          f"{{tir_file: {TYRE_DATA}/Sedan_Pac02Tire.tir, vertical_from_file: true}}"),
     "car.tyre.radial_damping_Nspm = 300.0 has no effect with tyres.vertical_from_file"),
    ("tyre command: unsupported format", tyre_command.main,
     lambda t: ["--tir", tir_file(t, SEDAN.replace("'PAC2002'", "'FTIRE'"))],
     "bad.tir: PROPERTY_FILE_FORMAT 'FTIRE' is a tyre model drake_car does not implement"),
    ("tyre command: missing file", tyre_command.main,
     lambda t: ["--tir", t / "nowhere.tir"], "nowhere.tir: tyre property file not found"),
    ("a binary .tir", run_command.main,
     lambda t: scene_text(tyre(tir_file(t, "", binary=True))), "not a text file"),
    ("a missing .tir", run_command.main,
     lambda t: scene_text(tyre(t / "nowhere.tir")), "nowhere.tir: tyre property file not found"),
    # a newcomer's review (rev40): where a relative file was looked for, a car file's kind
    ("a missing .tir by a relative name", run_command.main,
     lambda t: scene_text(tyre("nowhere/nope.tir")),
     "tyres.tir_file nowhere/nope.tir: tyre property file not found (looked in the working "
     f"folder ({ROOT}) and the shipped data"),
    ("an empty car file", run_command.main,
     lambda t: scene_text(f"car_file: {_empty(t)}"),
     "empty.yaml: must map the car's sections (mass, wheelbase_m"),
    ("a car file that is a folder", run_command.main,
     lambda t: scene_text(f"car_file: {t}"), "is a folder, not a car file"),
    ("paper: one scene as the study's scenes file", paper.main,
     lambda t: ["--scene", _car_scene(t) + ":car"],
     "drake-car-paper's --scene is the study's scenes file"),
    ("handling: one scene as its scenes file", handling.main,
     lambda t: ["--scene", _car_scene(t) + ":car"],
     "--scene_text '{car_file: cars/bmw_320i.yaml, tyres: !MagicFormula {tir_file: "
     "tyres/pacejka2006_205_60R15.tir}}'"),
    ("paper: a file of one car as the study's scenes file", paper.main,
     lambda t: ["--scene", _car_scene(t)], "no entry states a manoeuvre"),
    ("handling: a car file as its scenes file", handling.main,
     lambda t: ["--scene", "urdf/cars/bmw_320i.yaml"],
     "a car file (its keys mass, wheelbase_m, front, rear, ...), not scenes; "
     "drake-car-handling's --scene is the handling scenes file"),
    ("divergence", run_command.main,
     lambda t: ["--scene", "scenes/car.yaml:straight", "--scene_text",
                "car: {tyre: {radial_stiffness_Npm: 5.0e7}}\nplant: {time_step: 0.005}\n"
                "simulator: {end_time_s: 2.0}"], "diverged at t ="),
    ("step above the tyres' stability limit", run_command.main,
     lambda t: scene_text("plant: {time_step: 0.01}"), "explicit stability limit"),
    ("explicit friction above its limit", run_command.main,
     lambda t: ["--scene", "scenes/paper_study.yaml:a_3", "--scene_text",
                "friction: {scheme: reference}"], "stability limit"),
    ("--out names a file", run_command.main,
     lambda t: RUN + ["--out", _file(t)], "is a file"),
    ("--out is a foreign folder", run_command.main,
     lambda t: RUN + ["--out", _foreign(t)], "was not written by drake_car"),
    ("tyre command: a negative pressure (issue 30)", tyre_command.main,
     lambda t: ["--tir", TYRE_DATA / "MagicFormula61_Parameters.tir", "--pressure_Pa", "-5"],
     "--pressure_Pa: -5.0 must be a finite number > 0"),
    ("strut rig: options that describe no --measured loop (issue 30)", strut_rig.main,
     lambda t: ["--quick", "--side_force_N", "1000"],
     "--side_force_N describes a --measured loop's test"),
    ("strut rig: a side force's point that describes no --measured loop", strut_rig.main,
     lambda t: ["--quick", "--side_force_point_below_top_m", "0.47"],
     "--side_force_point_below_top_m describes a --measured loop's test"),
    ("strut rig: a side force's point beyond the strut", strut_rig.main,
     lambda t: ["--measured", "loop.csv", "--side_force_N", "1000",
                "--side_force_point_below_top_m", "1.5"],
     "--side_force_point_below_top_m: 1.5 must be in [0, 1] m"),
    ("strut rig: a side force's point above the top mount", strut_rig.main,
     lambda t: ["--measured", "loop.csv", "--side_force_N", "1000",
                "--side_force_point_below_top_m", "-0.1"],
     "--side_force_point_below_top_m: -0.1 must be in [0, 1] m"),
    ("rig: absurd normal force", friction_rig.main,
     lambda t: ["--normal_force_N", "1e30"], "normal_force_N"),
    ("rig: explicit step above its limit", friction_rig.main,
     lambda t: ["--friction", "{scheme: reference}"], "time_step_s"),
    ("rig: mu_d above mu_s", friction_rig.main,
     lambda t: ["--friction", "{law: {mu_s: 0.1, mu_d: 0.2}}"], "friction.law.mu_d"),
    ("settle: not a settle scene", settle.main,
     lambda t: ["--scene", "scenes/car.yaml:straight"], "!Settle"),
    ("kinematics: bad car", kinematics.main,
     lambda t: ["--scene_text", "car: {front: {guide_length_l_m: -1.0}}"],
     "car.front.guide_length_l_m"),
    ("study: not a lane change", paper.main,
     lambda t: ["--scene_text", "manoeuvre: !Straight {}"], "lane changes"),
    ("study: bad scene text", paper.main,
     lambda t: ["--scene_text", "friction: {law: {mu_s: high}}"], "friction.law.mu_s"),
    ("accuracy sweep: bad scene", accuracy.main,
     lambda t: ["--scene_text", "plant: {time_step: -1.0}"], "plant.time_step"),
    ("design study: a mitigation that makes no valid car", design.main,
     lambda t: ["--study", _study(t, "spring_inclination_deg: 6.0}",
                                  "spring_inclination_deg: 60.0}") + ":study"],
     "mitigations[2] (side-load compensating spring (inclined 6 deg)): scene_text"),
    ("design study: a factor that is no scene key", design.main,
     lambda t: ["--study", _study(t, "key: car.front.guide_length_l_m",
                                  "key: car.front.guide_length") + ":study"],
     "study.yaml: factor key 'car.front.guide_length': no field 'guide_length'"),
    ("design study: rough road into the manoeuvre", design.main,
     lambda t: ["--study", _study(t, "length_m: 25.0", "length_m: 45.0") + ":study"],
     "monte_carlo.length_m"),
    ("design study: no workers", design.main, lambda t: ["--workers", "0"], "--workers"),
    ("design study: out is a foreign folder", design.main,
     lambda t: ["--quick", "--out", _foreign(t)], "holds no design study"),
    ("design study: out is a file", design.main, lambda t: ["--out", _file(t)],
     "is a file"),
    ("study: no workers", paper.main, lambda t: ["--workers", "-1"], "--workers"),
    ("handling: bad scene text", handling.main,
     lambda t: ["--scene_text", "car: {mass: {total_mass_kg: -5.0}}"], "car.mass.total_mass_kg"),
    ("calibration: bad scene", calibrate.main,
     lambda t: ["--scene_text", "manoeuvre: !LaneChange {amplitude_m: 5.0}",
                "--out", str(t / "calibration.json")], "manoeuvre.amplitude_m"),
]


def _file(tmp_path):
    path = tmp_path / "a_file"
    path.write_text("not a folder")
    return str(path)


def _empty(tmp_path):
    path = tmp_path / "empty.yaml"
    path.write_text("")
    return str(path)


def _car_scene(tmp_path):
    """A scene file of a car alone, as ride, design and strut rig take it (FILE:car)."""
    path = tmp_path / "my.yaml"
    path.write_text("car:\n  car_file: cars/bmw_320i.yaml\n  tyres: !MagicFormula "
                    "{tir_file: tyres/pacejka2006_205_60R15.tir}\n")
    return str(path)


def _study(tmp_path, old, new):
    """The design study's spec with ``old`` replaced by ``new``, as a file in ``tmp_path``."""
    path = tmp_path / "study.yaml"
    text = (ROOT / "scenes" / "studies" / "design.yaml").read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))
    return str(path)


def _foreign(tmp_path):
    path = tmp_path / "home"
    path.mkdir()
    (path / "thesis.tex").write_text("precious")
    return str(path)


def leftovers(folder):
    """Temporary folders and locks a run left beside its output."""
    return sorted(p.name for p in folder.iterdir()
                  if ".partial-" in p.name or p.name.endswith(".lock"))


@pytest.mark.parametrize("label, main, argv, key", CASES, ids=[c[0] for c in CASES])
def test_bad_input_is_refused_cleanly(label, main, argv, key, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    args = [str(a) for a in argv(tmp_path)]
    out = tmp_path / "out"
    if "--out" not in args:
        args += ["--out", str(out)]
    before = set(tmp_path.iterdir())
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(main, args)
    assert stopped.value.code == 2, label
    err = capsys.readouterr().err
    message = [line for line in err.splitlines() if line.startswith(("error:", "usage:"))
               or ": error:" in line]
    assert message, f"{label}: no error line in {err[-500:]!r}"
    assert key in err, f"{label}: {key!r} not in {err[-500:]!r}"
    assert "Traceback" not in err
    assert not out.exists(), f"{label}: the output folder was written"
    assert not leftovers(tmp_path), f"{label}: {leftovers(tmp_path)} left behind"
    assert set(tmp_path.iterdir()) - before <= {tmp_path / "bad.tir", tmp_path / "study.yaml"}, \
        label


def test_there_are_at_least_thirty_cases():
    assert len(CASES) >= 30


@pytest.mark.parametrize("args, key", [
    (["-m", "drake_car.commands.run", "--scene", "scenes/paper_study.yaml:a_1", "--scene_text",
      "friction: {law: {mu_s: high}}"], "friction.law.mu_s"),
    (["experiments/friction_rig.py", "--mass_kg", "abc"], "--mass_kg"),
])
def test_a_real_process_exits_2_without_a_traceback(args, key, tmp_path):
    result = subprocess.run([sys.executable, *args, "--out", str(tmp_path / "out")], cwd=ROOT,
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 2
    assert key in result.stderr and "Traceback" not in result.stderr
    assert not (tmp_path / "out").exists()


def _start(tmp_path, out, *extra):
    return subprocess.Popen(
        [sys.executable, "-m", "drake_car.commands.run", "--scene", "scenes/paper_study.yaml:a_3",
         "--scene_text", "simulator: {end_time_s: 8.0}", "--out", str(out), "--quiet", *extra],
        cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _wait_for(condition, timeout=120):
    began = time.time()
    while not condition():
        assert time.time() - began < timeout, "timed out"
        time.sleep(0.05)


@pytest.mark.slow
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_run_killed_while_it_works_leaves_nothing(tmp_path, signum):
    out = tmp_path / "out"
    process = _start(tmp_path, out)
    _wait_for(lambda: any(".partial-" in p.name for p in tmp_path.iterdir()))
    time.sleep(1.0)  # into the simulation, with the temporary folder in place
    os.kill(process.pid, signum)
    process.wait(timeout=60)
    assert process.returncode != 0
    assert not out.exists()
    assert not leftovers(tmp_path), leftovers(tmp_path)


@pytest.mark.slow
def test_second_writer_is_refused_and_a_reused_folder_is_replaced_whole(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / ".drake_car_output").write_text("")
    (out / "stale.csv").write_text("from an earlier run")
    first = _start(tmp_path, out)
    _wait_for(lambda: (tmp_path / ".out.lock").exists())
    second = subprocess.run(
        [sys.executable, "-m", "drake_car.commands.run", "--scene", "scenes/paper_study.yaml:a_1",
         "--scene_text", "simulator: {end_time_s: 0.1}", "--out", str(out), "--quiet"],
        cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert second.returncode == 2 and "another run" in second.stderr
    first.wait(timeout=600)
    assert first.returncode == 0, first.stderr[-2000:]
    assert not (out / "stale.csv").exists(), "a reused folder must not mix old and new"
    assert (out / "history.csv").is_file()
    assert not leftovers(tmp_path)


def test_stale_leftovers_of_a_killed_run_are_removed(tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    stale = tmp_path / ".out.partial-999999999-deadbeef"
    stale.mkdir()
    (tmp_path / ".out.lock").write_text("999999999")
    run_command.main(RUN + ["--scene_text", "simulator: {end_time_s: 0.05}", "--quiet",
                            "--out", str(tmp_path / "out")])
    assert (tmp_path / "out" / "history.csv").is_file()
    assert not leftovers(tmp_path)
