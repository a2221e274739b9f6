"""Choose, while a run goes on, between the one-thread and the threaded force function.

The wheelsets' contacts on threads (:mod:`railexu.runtime.threads`) make the seed scenario's
integration about a fifth shorter on an idle 2-core machine, but on a machine that is busy with
other work they cost far more than they save: every call of the threaded force function waits
until the operating system gives its second thread a core, and with a load of 26 on 2 cores the
seed run took 180 s of wall time with threads against 23 s without (``docs/performance.md``).
Which is faster depends on the load *now*, so the choice is measured, not guessed:

- the calls are counted in **windows** of :data:`WINDOW_CALLS` calls, and each window's wall
  time per call is measured (the force function's results are the same to the last bit either
  way, :func:`railexu.model.forces.generalized_forces_threaded`, so switching changes no number);
- from time to time one window is run with the **other** function (a probe); the run switches
  to it when :data:`CONFIRMATIONS` probes in a row, each after one window of the current
  function, were faster than that window by more than :data:`MARGIN` (one faster window may be
  a cheaper stretch of the run);
- a probe is started only when the wall time since the last probe is at least
  ``1 / PROBE_SHARE`` times that probe's own duration, so that probing costs at most
  :data:`PROBE_SHARE` of the run's wall time even when the other function is very slow;
- the first probe comes right after the first threaded window, so that a run started on a
  busy machine leaves the threads after a few windows.
"""

from __future__ import annotations

import time
from collections.abc import Callable

#: force-function calls per measured window (a few milliseconds idle)
WINDOW_CALLS = 64
#: the other function must take less than this share of the current one's time per call
MARGIN = 0.9
#: consecutive probes, each after one window of the current function, that must win to switch
CONFIRMATIONS = 2
#: the largest share of the run's wall time that probing the other function may cost
PROBE_SHARE = 0.02

SERIAL, THREADED = 0, 1


class ThreadChoice:
    """The force function to call next, chosen from measured wall times (see the module).

    Args:
        serial: the one-thread compiled force function.
        threaded: the threaded one (same arguments, same results).
        clock: a wall clock in seconds (tests pass their own).
    """

    def __init__(
        self, serial: Callable, threaded: Callable, clock: Callable[[], float] = time.perf_counter
    ):
        self._entries = (serial, threaded)
        self._clock = clock
        self.mode = THREADED
        self.current = threaded
        self._probing = False
        self._wins = 0
        self._probe_start = 0.0
        self._next_probe_at = clock()
        self._last_s_per_call: list[float | None] = [None, None]
        #: calls made with the one-thread and the threaded function, and the switches made
        self.calls = [0, 0]
        self.switches = 0

    def window_done(self, wall_s: float, calls: int) -> Callable:
        """Take the wall time [s] of the last ``calls`` calls (made with :attr:`current`) and
        return the function for the next window."""
        per_call = wall_s / max(calls, 1)
        used = THREADED if self.current is self._entries[THREADED] else SERIAL
        self.calls[used] += calls
        now = self._clock()
        if self._probing:
            self._probing = False
            before = self._last_s_per_call[self.mode]
            self._last_s_per_call[used] = per_call
            won = before is not None and per_call < MARGIN * before
            self._wins = self._wins + 1 if won else 0
            if self._wins >= CONFIRMATIONS:
                self.mode = used
                self.switches += 1
                self._wins = 0
            if self._wins:
                # one win may be noise (a costlier stretch of the run): probe again after one
                # window of the current function
                self._next_probe_at = now
            else:
                probe_s = max(now - self._probe_start, 0.0)
                self._next_probe_at = now + probe_s / PROBE_SHARE
        else:
            self._last_s_per_call[self.mode] = per_call
            if now >= self._next_probe_at:
                self._probing = True
                self._probe_start = now
                self.current = self._entries[1 - self.mode]
                return self.current
        self.current = self._entries[self.mode]
        return self.current

    def threaded_share(self) -> float:
        """The share of the calls made with the threaded function (0 to 1)."""
        total = self.calls[SERIAL] + self.calls[THREADED]
        return self.calls[THREADED] / total if total else 0.0
