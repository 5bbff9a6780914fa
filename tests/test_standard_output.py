"""Standard output that cannot be written (a full disk behind ``> file``, ``> /dev/full``; a
reader that stopped, ``| head``) is not the run's failure: the work goes on and is written,
and the command says in one line on stderr that only its printed lines were lost (exit 1); a
reader that stopped reading hears nothing more (exit 0). Before, a full disk behind stdout
was reported as "error: No space left on device", exit 2, as if the run had failed."""

import errno
import sys

import pytest

from drake_car.commands import cli


class _Refusing:
    """A stdout whose writes fail as the kernel refuses them."""

    def __init__(self, error):
        self.error, self.tried = error, 0

    def write(self, text):
        self.tried += 1
        raise self.error

    def flush(self):
        raise self.error


def _command(done):
    def main(argv):
        print("front axle 6000 N", flush=True)  # fails at once
        done.append("work")  # the work goes on after the failed line
        print("wrote DIR")
    return main


@pytest.mark.parametrize("error, code, said", [
    (OSError(errno.ENOSPC, "No space left on device"), 1,
     "error: standard output: No space left on device; the command finished, but"),
    (BrokenPipeError(errno.EPIPE, "Broken pipe"), None, ""),
])
def test_a_stdout_that_cannot_be_written_does_not_fail_the_work(error, code, said, monkeypatch,
                                                                capsys):
    stream = _Refusing(error)
    monkeypatch.setattr(sys, "stdout", stream)
    done = []
    if code is None:
        cli.run_main(_command(done), [])
    else:
        with pytest.raises(SystemExit) as stopped:
            cli.run_main(_command(done), [])
        assert stopped.value.code == code
    assert done == ["work"]
    assert stream.tried == 1  # tried once, then left alone
    assert sys.stdout is stream  # given back to whoever set it
    err = capsys.readouterr().err
    assert err.startswith(said) and len(err.splitlines()) == (1 if said else 0)


def test_a_run_failure_with_stdout_lost_is_still_the_run_failure(monkeypatch, capsys):
    monkeypatch.setattr(sys, "stdout", _Refusing(OSError(errno.ENOSPC, "No space")))

    def main(argv):
        print("starting", flush=True)
        raise cli.RunFailed("the car left the road at 3.2 s")
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(main, [])
    assert stopped.value.code == 2
    assert capsys.readouterr().err.strip() == "error: the car left the road at 3.2 s"


def test_a_closed_stdout_is_left_closed_and_the_work_goes_on(monkeypatch, capsys):
    # `command >&-`: Python's sys.stdout is None and print() writes nothing; wrapping it made
    # the first print an AttributeError traceback.
    monkeypatch.setattr(sys, "stdout", None)
    done = []
    cli.run_main(_command(done), [])
    assert done == ["work"] and sys.stdout is None
    assert capsys.readouterr().err == ""
