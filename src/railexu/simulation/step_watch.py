"""What Exudyn's solver did with the step: the steps taken, the steps it cut, the smallest.

Exudyn's implicit solver (``ti.adaptiveStep``, set in
:func:`railexu.simulation.simulate._solver_settings`) halves the step when Newton does not
converge within its iteration limits and retries, down to ``ti.minimumStepSize``; after
``adaptiveStepRecoverySteps`` easy steps it doubles it again. Exudyn keeps no count of these
cuts (``it.minStepSize`` is the lower limit, not the smallest step taken; ``it.currentStepIndex``
counts the accepted steps plus one; checked with Exudyn 1.13.6, ``docs/dev/exudyn-api.md``), so
:class:`StepWatch` reads them from the two user functions the solver calls: the pre-step
function before **every attempt** of a step (a rejected attempt is retried with a smaller step
and calls it again) and the post-step function after every **accepted** step (and once with the
initial state). Cost: one Python call and a few float operations per attempt (the pre-step
function costs about 0.5 us per step, ``docs/dev/exudyn-api.md``; a run's step costs hundreds).

:meth:`StepWatch.facts` gives the ``solver`` block's step facts of ``summary.json``
(``docs/performance.md``, "Every summary.json"); :meth:`StepWatch.warning` the warning line of a
run whose step was cut.
"""

from __future__ import annotations

import math

#: A step shorter than the user's by more than this fraction counts as cut (round-off of the
#: step's end times ``t0 + k h`` is ~1e-16 relative; a halving is 0.5).
_SHORT = 1e-6


class StepWatch:
    """Counts the solver's attempts and accepted steps of one run with the user's step
    ``time_step_s`` [s] and end time ``end_time_s`` [s]."""

    def __init__(self, time_step_s: float, end_time_s: float) -> None:
        self.h = float(time_step_s)
        self.end_time_s = float(end_time_s)
        self.attempts = 0
        self.steps = 0
        self.rejected = 0
        self.short_steps = 0
        self.smallest_s = math.inf
        self.first_cut_time_s: float | None = None
        self.t_last: float | None = None  # end time of the last accepted step (or the start)
        self.pending = False  # an attempt started and neither accepted nor rejected yet

    def attempt(self, t: float) -> None:
        """The pre-step function's call: an attempt of the step ending at ``t`` [s] starts.
        An attempt still pending was rejected (the solver retries with a smaller step)."""
        if self.pending:
            self._reject()
        self.attempts += 1
        self.pending = True

    def not_attempted(self) -> None:
        """The pre-step function stopped the run: the step last announced is not computed."""
        self.attempts -= 1
        self.pending = False

    def accepted(self, t: float) -> None:
        """The post-step function's call at ``t`` [s]: the initial state (first call) or an
        accepted step ending at ``t``."""
        if self.t_last is not None:
            dt = t - self.t_last
            self.steps += 1
            # the last step may end short at the end time (the steps after a cut need not
            # land on it): not a cut of its own
            at_end = abs(t - self.end_time_s) <= 1e-9 * max(1.0, self.end_time_s)
            if not (at_end and dt < self.h):
                self.smallest_s = min(self.smallest_s, dt)
                if dt < self.h * (1.0 - _SHORT):
                    self.short_steps += 1
        self.t_last = t
        self.pending = False

    def finish(self, failed: bool) -> None:
        """After the solver returned (``failed``: it raised): an attempt still pending was
        rejected (the one the solver gave up on at its minimum step)."""
        if self.pending and failed:
            self._reject()
        self.pending = False

    def _reject(self) -> None:
        self.rejected += 1
        if self.first_cut_time_s is None:
            self.first_cut_time_s = self.t_last if self.t_last is not None else 0.0

    def facts(self) -> dict:
        """The step facts for the ``solver`` block (SI units in the key names)."""
        # the step's length from end times ~1e-16 relative apart: 10 digits
        smallest = float(f"{self.smallest_s:.10g}") if math.isfinite(self.smallest_s) else None
        if smallest is None and self.steps > 0:
            smallest = self.h  # one step only, ending at the end time
        return {
            "time_step_s": self.h,
            "steps": self.steps,
            "step_attempts": self.attempts,
            "step_cuts": self.rejected,
            "steps_below_time_step": self.short_steps,
            "first_cut_time_s": self.first_cut_time_s,
            "smallest_step_s": smallest,
        }

    def warning(self, distance_at=None) -> str | None:
        """The warning line of a run whose step the solver cut (None if it did not);
        ``distance_at(t)`` [m] places the first cut along the track."""
        if self.rejected == 0:
            return None
        t = self.first_cut_time_s or 0.0
        where = f" ({distance_at(t):.2f} m)" if distance_at is not None else ""
        smallest = self.facts()["smallest_step_s"]
        small = f"{smallest * 1e3:.4g} ms" if smallest is not None else "none accepted"
        return (
            f"the solver cut the step {self.rejected} times (Newton did not converge; first at "
            f"t = {t:.4f} s{where}): {self.short_steps} of {self.steps} steps shorter than the "
            f"{self.h * 1e3:g} ms asked, the smallest {small}; summary.json's solver block has "
            "the facts. A cut step is the solver's sign of a stiff event (an impact, a contact "
            "jump): check that the result there converges with a smaller step"
        )
