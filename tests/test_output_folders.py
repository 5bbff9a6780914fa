"""What a rerun may delete (review rv44): an output replaced whole deletes only what it wrote
itself; a folder of runs kept for reuse is never inside (or around) a folder replaced whole;
a calibration's --out FILE is checked before the work and leaves no temporary file; a mount
point as --out is refused before the work. Made-up folders in tmp_path, no runs."""

import json
import os
from pathlib import Path

import pytest

from drake_car.commands import accuracy as accuracy_command
from drake_car.commands import calibrate as calibrate_command
from drake_car.commands import cli
from drake_car.commands import paper as paper_command
from drake_car.results import folder
from drake_car.results.folder import MARKER, OutputError, output_folder

ROOT = Path(__file__).resolve().parents[1]


def _write_output(out, files=("history.csv", "plots/loops.png")):
    with output_folder(out) as staging:
        for name in files:
            (staging / name).parent.mkdir(parents=True, exist_ok=True)
            (staging / name).write_text(name)


def _refused(capsys, main, argv, *named):
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(main, argv)
    err = capsys.readouterr().err
    assert stopped.value.code == 2 and len(err.strip().splitlines()) == 1, err
    for text in named:
        assert text in err, err
    return err


def test_a_rerun_replaces_its_own_output_whole(tmp_path):
    out = tmp_path / "res"
    _write_output(out, ("old.csv", "plots/a.png"))
    _write_output(out, ("new.csv",))
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "README.md", "new.csv"]


@pytest.mark.parametrize("plant, kind", [
    (lambda res: _write_output(res / "inner"), "another drake_car output"),
    (lambda res: _write_output(res / "tyre", ("tyre.csv",)), "another drake_car output"),
    (lambda res: ((res / "sw").mkdir(), (res / "sw" / "sweep.json").write_text("{}")),
     "a sweep folder"),
    (lambda res: (res / "notes.txt").write_text("mine"),
     "a file the previous output did not write"),
    (lambda res: (res / "plots" / "mine.png").write_text("mine"),
     "a file the previous output did not write"),
    (lambda res: (res / "mine").mkdir(), "a folder the previous output did not write"),
])
def test_a_rerun_refuses_to_delete_what_its_output_did_not_write(plant, kind, tmp_path):
    """The review's case: friction-rig --out res, then outputs and a user's folder inside
    res; a second run into res removed them all without a word."""
    res = tmp_path / "res"
    _write_output(res)
    plant(res)
    before = sorted(str(p.relative_to(res)) for p in res.rglob("*"))
    with pytest.raises(OutputError, match=rf"--out {res}: the previous output there holds "
                                          rf".* \({kind}\).*move that out of it, or give "
                                          "another --out"):
        _write_output(res, ("again.csv",))
    assert sorted(str(p.relative_to(res)) for p in res.rglob("*")) == before
    assert not list(tmp_path.glob(".res.*"))  # no temporary folder left beside it


def test_a_file_that_came_into_the_output_during_the_run_costs_no_finished_result(tmp_path):
    """An editor's swap file written into the old output while a long run works: the run's
    finished output may not replace it (the file is not the old output's), so it is kept
    beside it under a visible name, said in the error, not deleted (review rv45)."""
    res = tmp_path / "res"
    _write_output(res, ("a.csv",))
    with pytest.raises(OutputError, match=r"this run's output is kept in .*res\.kept-1"):
        with output_folder(res) as staging:
            (staging / "b.csv").write_text("hours of work")
            (res / ".a.csv.swp").write_text("editor")  # during the run
    assert (tmp_path / "res.kept-1" / "b.csv").read_text() == "hours of work"
    assert (res / "a.csv").exists() and (res / ".a.csv.swp").exists()  # the old, untouched
    assert not list(tmp_path.glob(".res.partial-*"))


def test_an_output_from_before_the_listing_is_checked_for_outputs_inside(tmp_path):
    """An old MARKER lists nothing: its own files cannot be told from a user's (replaced as
    before), but another output or a sweep folder inside it still stops the rerun."""
    res = tmp_path / "res"
    res.mkdir()
    (res / MARKER).write_text("")
    (res / "stale.csv").write_text("from an earlier run")
    _write_output(res / "inner")
    with pytest.raises(OutputError, match=r"inner \(another drake_car output\)"):
        _write_output(res)
    (res / "inner" / MARKER).unlink()
    for path in (res / "inner").rglob("*"):
        if path.is_file():
            path.unlink()
    (res / "inner" / "index.csv").write_text("")
    with pytest.raises(OutputError, match=r"inner \(a sweep folder\)"):
        _write_output(res)
    for path in sorted((res / "inner").rglob("*"), reverse=True):
        path.rmdir() if path.is_dir() else path.unlink()
    (res / "inner").rmdir()
    _write_output(res, ("new.csv",))
    assert not (res / "stale.csv").exists() and (res / "new.csv").is_file()


@pytest.mark.parametrize("where", ["same", "inside", "around"])
@pytest.mark.parametrize("command", [paper_command, accuracy_command])
def test_runs_kept_for_reuse_are_apart_from_out(command, where, tmp_path, capsys,
                                                 monkeypatch):
    """The review's case: paper --out pp1 --runs_dir pp1/prd_in ran, then replaced pp1 whole,
    its runs with it. Refused before any work, nothing written."""
    monkeypatch.chdir(ROOT)

    def work(*args, **kwargs):
        raise AssertionError("the work began before --runs_dir was checked")
    monkeypatch.setattr(command, "load_study_file" if command is paper_command else
                        "load_scene", work)
    out = tmp_path / "pp1"
    runs = {"same": out, "inside": out / "prd_in", "around": tmp_path}[where]
    if where == "around":
        out = tmp_path / "runs_here" / "pp1"
    err = _refused(capsys, command.main, ["--out", str(out), "--runs_dir", str(runs)],
                   f"--runs_dir {runs}", f"--out {out}", "give folders apart")
    assert ("is inside" if where == "inside" else where == "same" and " is --out" or
            "holds") in err
    assert not out.exists() and not (tmp_path / "runs_here").exists()


def test_calibrate_refuses_a_folder_as_out_before_the_work(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    (tmp_path / "caldir").mkdir()

    def calibrate(*args, **kwargs):
        raise AssertionError("calibrated before --out was checked")
    monkeypatch.setattr(calibrate_command, "calibrate", calibrate)
    _refused(capsys, calibrate_command.main, ["--out", str(tmp_path / "caldir")],
             f"--out {tmp_path / 'caldir'}: is a folder; give a file's path")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["caldir"]


def test_calibrate_writes_its_file_whole_and_nothing_beside_it(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    found = {"profile": {"amplitude_m": 0.01, "second_lobe": 1.0},
             "residual": {"shift_m": 3.7, "heading_change_deg": 0.0}, "iterations": [],
             "cost": {"runs": 1, "wall_s": 0.0, "cpu_s": 0.0}}
    monkeypatch.setattr(calibrate_command, "calibrate", lambda *a, **k: found)
    monkeypatch.setattr(calibrate_command.lane_change_cache, "store", lambda *a: None)
    out = tmp_path / "sub" / "cal.json"
    calibrate_command.main(["--out", str(out)])
    assert json.loads(out.read_text())["profile"] == found["profile"]
    assert sorted(p.name for p in out.parent.iterdir()) == ["cal.json"]


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes in a read-only folder")
def test_calibrate_refuses_a_read_only_folder_naming_out(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    ro = tmp_path / "ro"
    ro.mkdir(mode=0o500)
    _refused(capsys, calibrate_command.main, ["--out", str(ro / "cal.json")],
             f"--out {ro / 'cal.json'}")


def test_a_mount_point_as_out_is_refused_before_the_work(tmp_path, monkeypatch):
    """A mount point (an empty tmpfs, a Docker volume) cannot be renamed: the output, which
    replaces its folder by a rename, would fail only after the work."""
    mount = tmp_path / "volume"
    mount.mkdir()
    ismount = os.path.ismount
    monkeypatch.setattr(os.path, "ismount", lambda p: Path(p) == mount or ismount(p))
    worked = []
    with pytest.raises(OutputError, match=rf"--out {mount}: a mount point.*--out "
                                          rf"{mount / 'results'}"):
        with output_folder(mount):
            worked.append(True)
    assert not worked and not any(mount.iterdir())
    _write_output(mount / "results")  # inside it: written as any folder


@pytest.mark.skipif(not Path("/proc/self/mountinfo").is_file(), reason="no mountinfo")
def test_mount_points_are_told_from_folders():
    assert folder.is_mount_point(Path("/proc"))
    assert not folder.is_mount_point(Path(__file__).parent)


def test_a_name_that_is_not_utf8_is_refused_before_the_work(tmp_path, capsys):
    # The output's README and provenance name their folder in UTF-8 text: a name with a byte
    # that is no UTF-8 (a Latin-1 "ÿ") failed with a traceback after the work.
    out = Path(os.fsdecode(os.fsencode(tmp_path) + b"/r\xff"))
    from drake_car.commands import tyre as tyre_command
    _refused(capsys, tyre_command.main,
             ["--tir", str(ROOT / "tests/data/tyres/Sedan_Pac02Tire.tir"), "--out", str(out)],
             "is not UTF-8", r"r\xff")
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize("command, what, options", [
    ("ride", "ride study", ["--classes", "A", "--speeds", "60"]),
    ("design", "design study", ["--quick"]),
])
def test_a_second_study_on_one_folder_is_refused_at_once(command, what, options, tmp_path,
                                                         capsys, monkeypatch):
    # A study adds runs to its folder and rewrites its results: two at once on one folder
    # would mix their files (the sweep's own lock is held only while runs are written).
    import importlib
    monkeypatch.chdir(ROOT)
    main = importlib.import_module(f"drake_car.commands.{command}").main
    out = tmp_path / "study"
    with folder.study_lock(out, what):
        _refused(capsys, main, ["--out", str(out), "--quiet", *options],
                 f"--out {out}: another {what}")
    assert not out.exists()  # refused before its sweep folder was made


def test_renames_that_belong_together_finish_before_a_signal_acts():
    import signal
    from drake_car.results.signals import signals_held
    done = []
    with pytest.raises(KeyboardInterrupt):
        with signals_held():
            os.kill(os.getpid(), signal.SIGINT)
            done.append("renamed")  # reached: the interrupt waits for the block's end
    assert done == ["renamed"]
