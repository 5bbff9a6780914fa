"""A newcomer's review of the tool on their own car (rev40): an unwritable --out is refused
naming --out and the reason before any work; a run's saved scene that names files relative to
the folder it ran in says where to rerun it from; the paper and handling commands' --scene (the
study's scenes file) given one scene says how to give the car; the combined-slip note. The
one-line refusals of a table are in test_bad_input.py."""

import errno
import json
import os
from pathlib import Path

import pytest

from drake_car.commands import cli, handling, paper, ride
from drake_car.commands import run as run_command
from drake_car.results import folder
from drake_car.results.folder import OutputError, output_folder
from drake_car.results.provenance import provenance
from drake_car.scene.study_file import flow_yaml, suggestion
from drake_car.study.paper.report_sections import runs_and_files

ROOT = Path(__file__).resolve().parents[1]
SHORT = ["--scene", "scenes/paper_study.yaml:a_1", "--scene_text",
         "simulator: {end_time_s: 0.05}", "--quiet"]


def refused(main, args, capsys):
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(main, [str(a) for a in args])
    assert stopped.value.code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return err


def no_writing(monkeypatch, folder, unnamed=errno.EROFS):
    """Making a file in ``folder`` fails: an unnamed one with ``unnamed`` (EROFS: a read-only
    mount; EOPNOTSUPP: a file system without them, as sysfs and procfs), a named one with
    EACCES (what root meets in /sys, where ``os.access`` says yes)."""
    real_open = os.open

    def fake_open(path, flags, *args, **kwargs):
        if Path(path) == folder and flags & getattr(os, "O_TMPFILE", 0) == getattr(
                os, "O_TMPFILE", -1):
            raise OSError(unnamed, os.strerror(unnamed), str(path))
        if Path(path).parent == folder and flags & os.O_CREAT:
            raise OSError(errno.EACCES, "Permission denied", str(path))
        return real_open(path, flags, *args, **kwargs)
    monkeypatch.setattr(os, "open", fake_open)


def test_an_unwritable_out_is_refused_naming_it_before_any_work(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    no_writing(monkeypatch, tmp_path)

    def work(*args, **kwargs):
        raise AssertionError("the work began before --out was checked")
    for name in ("load_study_file", "load_scene_file"):  # this code's and the code before's
        monkeypatch.setattr(paper, name, work, raising=False)
    monkeypatch.setattr(ride, "ride_scenes", work)
    out = tmp_path / "out"
    for main, args in [(paper.main, []), (ride.main, ["--classes", "A", "--speeds", "60"]),
                       (run_command.main, SHORT)]:
        err = refused(main, args + ["--out", out], capsys)
        assert f"error: --out {out}: cannot write in {tmp_path} (Read-only file system)" in err
    assert list(tmp_path.iterdir()) == []


def _unnamed_files(path):
    """Whether ``path``'s filesystem makes unnamed files (O_TMPFILE: not on every platform)."""
    try:
        os.close(os.open(path, os.O_TMPFILE | os.O_WRONLY, 0o600))
        return True
    except (AttributeError, OSError):
        return False


@pytest.mark.parametrize("unnamed", [errno.EOPNOTSUPP, errno.EACCES])
def test_the_writable_check_falls_back_to_a_named_file_and_changes_nothing(tmp_path, unnamed,
                                                                          monkeypatch):
    stamp = tmp_path.stat().st_mtime_ns
    folder.check_writable(tmp_path / "out", tmp_path)  # nothing made
    assert list(tmp_path.iterdir()) == []
    if _unnamed_files(tmp_path):  # the folder's time kept too, where no named file is needed
        assert tmp_path.stat().st_mtime_ns == stamp
    no_writing(monkeypatch, tmp_path, unnamed)
    reason = "Permission denied"  # of the named file, or of the unnamed one itself
    with pytest.raises(OutputError, match=rf"^--out {tmp_path}/out: cannot write in "
                                          rf"{tmp_path} \({reason}\)"):
        folder.check_writable(tmp_path / "out", tmp_path)


def test_a_refused_lock_file_is_said_of_out(tmp_path, monkeypatch):
    # root in /sys: the lock's open fails (EACCES) although os.access said yes
    def exclusive(path):
        raise PermissionError(errno.EACCES, "Permission denied", str(path))
    monkeypatch.setattr(folder, "exclusive", exclusive)
    out = tmp_path / "out"
    with pytest.raises(OutputError, match=rf"^--out {out}: {tmp_path}/\.out\.lock: Permission "
                                          "denied$"):
        with output_folder(out):
            pass
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux's /proc")
def test_out_in_proc_is_refused_naming_out(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    for name in ("load_study_file", "load_scene_file"):  # never reached
        monkeypatch.setattr(paper, name, None, raising=False)
    err = refused(paper.main, ["--out", "/proc/drake_car_out"], capsys)
    assert "error: --out /proc/drake_car_out: " in err


def test_a_rerun_from_another_folder_says_where_the_run_was_made(tmp_path, capsys, monkeypatch):
    made = tmp_path / "made"
    (made / "cars").mkdir(parents=True)
    (made / "cars" / "mine.yaml").write_text((ROOT / "urdf/cars/bmw_320i.yaml").read_text())
    monkeypatch.chdir(made)
    run_command.main(["--scene", str(ROOT / "scenes/paper_study.yaml:a_1"), "--scene_text",
                      "{car_file: cars/mine.yaml, simulator: {end_time_s: 0.05}}", "--quiet",
                      "--out", str(tmp_path / "a")])
    record = json.loads((tmp_path / "a" / "run.json").read_text())
    assert record["provenance"]["working_folder"] == str(made)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    err = refused(run_command.main, ["--scene", tmp_path / "a" / "scene.yaml", "--out",
                                     tmp_path / "b"], capsys)
    assert "car file not found" in err
    assert (f"{tmp_path / 'a' / 'scene.yaml'} was run in {made}, where its cars/mine.yaml "
            f"are: rerun it from there (cd {made})") in err
    assert not (tmp_path / "b").exists()


def test_the_paper_report_says_where_to_rerun_a_scene_naming_working_folder_files():
    s = {"runs": {}, "figures": {}, "provenance": {"working_folder": "/home/me/car"},
         "working_folder_files": ["cars/hatch.yaml", "tyres/mine.tir"]}
    text = "\n".join(runs_and_files(s))
    assert ("rerun it from `/home/me/car`, where its `cars/hatch.yaml`, `tyres/mine.tir` are "
            "(the scene names them relative to that folder): `cd /home/me/car && drake-car-run "
            "--scene <run>/scene.yaml --out DIR`") in text
    s["working_folder_files"] = []
    assert "rerun it with `drake-car-run --scene <run>/scene.yaml" in "\n".join(
        runs_and_files(s))


def test_provenance_records_the_working_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert provenance()["working_folder"] == str(tmp_path)


@pytest.mark.parametrize("main, name", [(paper.main, "paper"), (handling.main, "handling")])
def test_the_study_commands_say_what_their_scene_is_and_how_to_give_a_car(
        main, name, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "my.yaml").write_text(
        "car:\n  name: mine\n  car_file: cars/bmw_320i.yaml\n  car: {front: {guide_length_l_m: "
        "0.2}}\n  tyres: !MagicFormula {tir_file: 'tyres/pacejka2006_205_60R15.tir', "
        "combined_slip: false}\n")
    err = refused(main, ["--scene", "my.yaml:car", "--out", tmp_path / "out"], capsys)
    (line,) = [x for x in err.splitlines() if x.startswith("error:")]
    given = ("--scene_text '{car_file: cars/bmw_320i.yaml, car: {front: {guide_length_l_m: "
             "0.2}}, tyres: !MagicFormula {tir_file: tyres/pacejka2006_205_60R15.tir, "
             "combined_slip: false}}'")
    assert line.startswith(f"error: --scene my.yaml:car: drake-car-{name}'s --scene is the ")
    assert line.endswith(given), line
    assert not (tmp_path / "out").exists()


def test_the_suggested_scene_text_reads_back_as_the_entry_s_values():
    from pydrake.common.yaml import yaml_load
    raw = {"car_file": "/a b/c.yaml", "tyres": {"_tag": "!MagicFormula", "tir_file": "true",
                                               "combined_slip": True}, "car": {"x": [1.5, -2]}}
    assert yaml_load(data=flow_yaml(raw)) == raw
    assert suggestion({}) == ("--scene_text '{car_file: FILE, tyres: !MagicFormula {tir_file: "
                              "FILE}}'")


@pytest.mark.parametrize("value", [1e-05, 1e16, -2.5e-7, 0.5, 3, ".inf", "cars/x.yaml", True])
def test_a_suggested_value_reads_back_as_itself(value):
    """Flow YAML of any value reads back equal: YAML 1.1 reads ``1e-05`` (no dot) as a string
    and a bare ``.inf`` as a float."""
    from pydrake.common.yaml import yaml_load
    raw = {"car": {"front": {"value": value}}}
    assert yaml_load(data=flow_yaml(raw)) == raw
