"""The measured choice between the threaded and the one-thread force function
(railexu.runtime.thread_choice): on a busy machine the threads are left after one window, on an
idle one they are kept, and probing the other function costs at most PROBE_SHARE of the wall
time."""

from __future__ import annotations

import pytest

from railexu.runtime import thread_choice as tc


def serial() -> None:
    """Stands for the one-thread force function."""


def threaded() -> None:
    """Stands for the threaded force function."""


class Machine:
    """A wall clock advanced by simulated force calls whose cost depends on the function and on
    the time (the load)."""

    def __init__(self, cost_s):
        self.now = 0.0
        self.cost_s = cost_s  # cost_s(function, now) -> seconds per call

    def clock(self) -> float:
        return self.now

    def run(self, choice: tc.ThreadChoice, windows: int) -> dict:
        spent = {serial: 0.0, threaded: 0.0}
        function = choice.current
        for _ in range(windows):
            wall = tc.WINDOW_CALLS * self.cost_s(function, self.now)
            self.now += wall
            spent[function] += wall
            function = choice.window_done(wall, tc.WINDOW_CALLS)
        return spent


def test_busy_machine_leaves_the_threads_and_probing_costs_at_most_its_share():
    # a load of ~26 on 2 cores (measured): 5 ms per threaded call against 0.25 ms on one thread
    machine = Machine(lambda f, now: 5e-3 if f is threaded else 2.5e-4)
    choice = tc.ThreadChoice(serial, threaded, clock=machine.clock)
    spent = machine.run(choice, 20_000)
    assert choice.mode == tc.SERIAL
    all_serial = 20_000 * tc.WINDOW_CALLS * 2.5e-4
    # the threaded windows (the first and the probes) cost at most the probe share of the run
    # (plus the first window and the first probe, which come before the rule applies)
    first_windows = 2 * tc.WINDOW_CALLS * 5e-3
    assert spent[threaded] <= tc.PROBE_SHARE * (all_serial + spent[threaded]) + first_windows
    assert machine.now < 1.07 * all_serial


def test_idle_machine_keeps_the_threads():
    # idle 2 cores: the threads make a call about a fifth shorter
    machine = Machine(lambda f, now: 8e-5 if f is threaded else 1e-4)
    choice = tc.ThreadChoice(serial, threaded, clock=machine.clock)
    machine.run(choice, 20_000)
    assert choice.mode == tc.THREADED
    assert choice.threaded_share() > 0.9
    assert choice.switches == 0


@pytest.mark.parametrize("windows_busy", [200, 2_000])
def test_the_threads_come_back_when_the_load_goes(windows_busy):
    busy_until = windows_busy * tc.WINDOW_CALLS * 2.5e-4

    def cost(f, now):
        if now < busy_until:
            return 5e-3 if f is threaded else 2.5e-4
        return 8e-5 if f is threaded else 1e-4

    machine = Machine(cost)
    choice = tc.ThreadChoice(serial, threaded, clock=machine.clock)
    machine.run(choice, windows_busy + 20_000)
    assert choice.mode == tc.THREADED
    assert choice.switches == 2


def test_no_switch_within_the_margin():
    # the other function 5 % faster: within the margin (10 %), no switching back and forth
    machine = Machine(lambda f, now: 9.5e-5 if f is serial else 1e-4)
    choice = tc.ThreadChoice(serial, threaded, clock=machine.clock)
    machine.run(choice, 5_000)
    assert choice.switches == 0
