"""railexu.runtime.warm_process: a call made in the warm process gives what the same call gives
here, and whatever goes wrong there (an error, a dead process, arguments that cannot be pickled),
the call is made here instead."""

from __future__ import annotations

import contextlib
import os
import signal
import time

import pytest

from railexu.runtime.helpers import CpuWatch
from railexu.runtime.warm_process import WarmProcess

needs_fork = pytest.mark.usefixtures("forking")  # tests/conftest.py

#: the tests of where a call runs wait for the warm process however busy the machine is (only a
#: dead warm process counts as starved): a loaded test machine may starve it
PATIENT = CpuWatch(min_share=0.0)


def _pid_and_sum(*values):
    return os.getpid(), sum(values)


def _fails_outside(pid):
    if os.getpid() != pid:
        raise RuntimeError("fails in the warm process")
    return "here"


def _always_fails():
    raise ValueError("a bad assessment")


@needs_fork
def test_a_call_runs_in_the_warm_process_after_its_preload():
    with WarmProcess(preload=("json",), watch=PATIENT) as warm:
        assert warm.ready
        pid, total = warm.call(_pid_and_sum, 1.5, 2.5)
        assert pid not in (os.getpid(), None) and total == 4.0
        assert warm.call(_pid_and_sum, 1)[0] == pid  # the same process, call after call
    assert not warm.ready


@needs_fork
def test_a_call_that_fails_there_runs_here():
    with WarmProcess(watch=PATIENT) as warm:
        assert warm.call(_fails_outside, os.getpid()) == "here"


@needs_fork
def test_an_error_is_raised_here():
    with WarmProcess() as warm, pytest.raises(ValueError, match="a bad assessment"):
        warm.call(_always_fails)


@needs_fork
def test_a_dead_warm_process_leaves_the_call_to_this_one():
    with WarmProcess() as warm:
        warm._worker.kill()
        warm._worker.join()
        assert warm.call(_pid_and_sum, 1)[0] == os.getpid()
        assert not warm.ready


@needs_fork
def test_arguments_that_cannot_be_pickled_are_used_here():
    with WarmProcess(watch=PATIENT) as warm:
        assert warm.call(_pid_and_sum, 1, 2)[0] != os.getpid()
        # a lambda cannot be pickled: this call runs here (and ends the warm process)
        assert warm.call(lambda: os.getpid()) == os.getpid()


@needs_fork
def test_the_warm_process_ignores_ctrl_c_and_ends_with_close():
    warm = WarmProcess(watch=PATIENT)
    worker = warm._worker
    time.sleep(0.5)  # let it install its handlers
    os.kill(worker.pid, signal.SIGINT)  # Ctrl-C at a terminal reaches the whole process group
    assert warm.call(_pid_and_sum, 1)[0] == worker.pid
    warm.close()
    assert not worker.is_alive()


def test_without_a_warm_process_every_call_runs_here():
    warm = WarmProcess(start=False)
    assert not warm.ready
    assert warm.call(_pid_and_sum, 2, 3) == (os.getpid(), 5)
    with pytest.raises(RuntimeError, match="no call was started"):
        warm.finish()


def _slow_warm_up():
    time.sleep(0.6)


def _failing_warm_up():
    raise RuntimeError("no fonts")


@needs_fork
def test_warmed_says_when_the_warm_up_is_done():
    """``railexu run`` starts the contacts' threads only once the warm process no longer needs
    the second core; a failed warm-up counts as done, and so does a dead warm process."""
    with WarmProcess(warm_up=_slow_warm_up, watch=PATIENT) as warm:
        assert not warm.warmed()
        deadline = time.monotonic() + 30
        while not warm.warmed() and time.monotonic() < deadline:
            time.sleep(0.05)
        assert warm.warmed()
    with WarmProcess(warm_up=_failing_warm_up) as warm:
        deadline = time.monotonic() + 30
        while not warm.warmed() and time.monotonic() < deadline:
            time.sleep(0.05)
        assert warm.warmed() and warm.ready
    warm = WarmProcess(warm_up=_slow_warm_up)
    os.kill(warm._worker.pid, signal.SIGKILL)
    warm._worker.join()
    assert warm.warmed()
    warm.close()
    assert WarmProcess(start=False).warmed()


def _spin(seconds):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        pass
    return os.getpid()


@needs_fork
def test_a_starved_warm_process_is_not_waited_for():
    """A warm process that gets no processor time (here: stopped, as a busy machine's scheduler
    would leave it) is not waited for: after one window of the watch the call runs here, the
    warm process is ended, and ``warmed`` no longer holds the contacts' threads back."""
    watch = CpuWatch(window_s=0.2, min_share=0.2)
    with WarmProcess(warm_up=_slow_warm_up, watch=watch) as warm:
        pid = warm.pid
        os.kill(pid, signal.SIGSTOP)
        try:
            assert not warm.warmed()  # the first look starts the watch's window
            time.sleep(0.3)
            assert warm.warmed()  # starved: the threads need not wait for it
            start = time.monotonic()
            assert warm.call(_spin, 0.0) == os.getpid()
            waited = time.monotonic() - start
            assert warm.starved_out  # the figures are then written here, without a fork
        finally:
            with contextlib.suppress(ProcessLookupError):  # it was killed: nothing to resume
                os.kill(pid, signal.SIGCONT)
        assert not warm.ready
    # one window and its polling, not the warm process's time (no timing asserted beyond a
    # bound a hundred times the window: this is about not hanging)
    assert waited < 20.0


@needs_fork
def test_a_busy_warm_process_that_progresses_is_waited_for():
    with WarmProcess(watch=CpuWatch(window_s=1.0, min_share=0.005)) as warm:  # any progress
        assert warm.call(_spin, 1.0) == warm.pid


def test_the_switch_turns_the_warm_process_off(monkeypatch):
    from railexu.errors import InputError
    from railexu.runtime.helpers import ENV_SWITCH

    monkeypatch.setenv(ENV_SWITCH, "0")
    warm = WarmProcess()
    assert not warm.ready and warm.call(_pid_and_sum, 1) == (os.getpid(), 1)
    monkeypatch.setenv(ENV_SWITCH, "maybe")
    with pytest.raises(InputError, match="RAILEXU_HELPER_PROCESSES.*expected 0"):
        WarmProcess()


def test_a_free_core_is_read_from_the_runnable_tasks(tmp_path):
    """``free_core``: the runnable tasks (this process among them) against the cores."""
    from railexu.runtime.helpers import free_core

    cores = os.cpu_count() or 1
    stat = tmp_path / "stat"
    stat.write_text("cpu  1 2 3\nprocs_running 1\nprocs_blocked 0\n")  # only this process
    assert free_core(str(stat))
    stat.write_text(f"procs_running {cores + 1}\n")  # every core busy besides this process
    assert not free_core(str(stat))
    assert free_core(str(tmp_path / "missing"))  # not readable: as before
