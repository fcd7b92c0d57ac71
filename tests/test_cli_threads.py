"""The command line's ``--threads``: the compiled kernels' thread count for one command,
before or after the command's name, checked against what the process can use, and put
back afterwards (``main`` is also called in-process)."""

import numba
import pytest

from agglomtool import cli


def _seen(monkeypatch):
    """Replace the reference command by one that records the kernels' thread count."""
    seen = []

    def command(args):
        seen.append(numba.get_num_threads())
        return 0

    monkeypatch.setattr(cli, "_cmd_reference", command)
    return seen


@pytest.mark.parametrize("argv", [["--threads", "1", "reference"],
                                  ["reference", "--threads", "1"]])
def test_the_command_runs_on_the_threads_asked_for(monkeypatch, argv):
    seen = _seen(monkeypatch)
    before = numba.get_num_threads()
    assert cli.main(argv) == 0
    assert seen == [1]
    assert numba.get_num_threads() == before  # put back


def test_without_the_option_the_thread_count_is_left_alone(monkeypatch):
    seen = _seen(monkeypatch)
    assert cli.main(["reference"]) == 0
    assert seen == [numba.get_num_threads()]


@pytest.mark.parametrize("n", [0, -2, numba.config.NUMBA_NUM_THREADS + 1])
def test_a_count_the_process_cannot_use_is_refused(monkeypatch, capsys, n):
    seen = _seen(monkeypatch)
    assert cli.main(["--threads", str(n), "reference"]) == cli.EXIT_BAD_INPUT
    err = capsys.readouterr().err
    assert f"--threads {n}" in err
    assert f"1 to {numba.config.NUMBA_NUM_THREADS}" in err and "NUMBA_NUM_THREADS" in err
    assert seen == []  # the command did not run


def test_the_threads_are_put_back_after_a_failing_command(monkeypatch):
    before = numba.get_num_threads()

    def command(args):
        raise ValueError("bad input")

    monkeypatch.setattr(cli, "_cmd_reference", command)
    assert cli.main(["--threads", "1", "reference"]) == cli.EXIT_BAD_INPUT
    assert numba.get_num_threads() == before
