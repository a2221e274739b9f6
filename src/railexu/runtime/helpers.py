"""What every helper process of a command obeys: the switch that turns them off, and the watch
that tells whether a helper gets the processor.

railexu's helper processes (the warm process of ``railexu run``,
:mod:`railexu.runtime.warm_process`, and the forked figure writers of
:mod:`railexu.report.file_jobs`) only ever save time: the command's own process never waits
for one that does not progress. :class:`CpuWatch` reads a helper's processor time (Linux's
``/proc/PID/stat``, ``utime + stime``; the helpers exist on Linux only) over windows of
:data:`WINDOW_S`: a helper that got less than :data:`MIN_CPU_SHARE` of a core in a window is
*starved* (a busy machine gives it no processor time, or it is gone), and the command's process
then does the helper's work itself. The results are the same whichever process computes them.

No helper outlives its command: :func:`end_with_parent`, called first in every helper, asks Linux
to send it SIGTERM when the command's process dies, even by SIGKILL.

A helper starts only where the machine has a free core (:func:`free_core`): without one, its
processor time (its own imports and exit) would only add to the command's wall time.

``RAILEXU_HELPER_PROCESSES=0`` in the environment (or ``railexu run --no-helper-processes``)
turns the helpers off: everything runs in the command's own process.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import time
from collections.abc import Callable

from railexu.errors import InputError

#: the environment variable that turns the helper processes off (0) or on (1, the default)
ENV_SWITCH = "RAILEXU_HELPER_PROCESSES"
_OFF = ("0", "off", "no", "false")
_ON = ("", "1", "on", "yes", "true")

#: the window over which a helper's progress is judged [s]: the longest the command's process
#: waits for a helper that gets no processor time before it does the work itself
WINDOW_S = 0.2
#: the share of one core below which a helper counts as starved: a fifth of a core, i.e. a
#: helper that would take five times as long as an unhindered process (railexu's assumption)
MIN_CPU_SHARE = 0.2


def helpers_enabled() -> bool:
    """False when ``RAILEXU_HELPER_PROCESSES`` turns the helper processes off.

    Raises:
        InputError: a value other than 0/1, off/on, no/yes, false/true.
    """
    value = os.environ.get(ENV_SWITCH, "").strip().lower()
    if value in _ON:
        return True
    if value in _OFF:
        return False
    raise InputError(
        f"expected 0 (no helper processes) or 1 (the default), got {value!r}",
        source="environment",
        key=ENV_SWITCH,
    )


def free_core(stat_path: str = "/proc/stat", samples: int = 5) -> bool:
    """Whether the machine has a core that no runnable task uses now: the median of ``samples``
    readings (1 ms apart) of Linux's ``procs_running`` (the runnable tasks, this process
    among them) less this process, below the cores. A helper started without a free core
    only adds its processor time to the command's wall time (issue 26). True where it cannot
    be read (not Linux).

    Args:
        stat_path: the kernel's statistics file (a test gives its own).
        samples: readings to take.
    """
    counts = []
    for i in range(samples):
        try:
            with open(stat_path) as fh:
                line = next(ln for ln in fh if ln.startswith("procs_running"))
            counts.append(int(line.split()[1]))
        except (OSError, StopIteration, ValueError, IndexError):
            return True
        if i + 1 < samples:
            time.sleep(0.001)
    counts.sort()
    return counts[len(counts) // 2] - 1 < (os.cpu_count() or 1)


def cpu_seconds(pid: int) -> float | None:
    """The processor time (user + system) process ``pid`` has used [s]; None when it is gone,
    a zombie, or not readable (no ``/proc``)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            fields = fh.read().rsplit(b")", 1)[1].split()
    except (OSError, IndexError):
        return None
    if fields[0] in (b"Z", b"X"):
        return None
    ticks = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100
    return (int(fields[11]) + int(fields[12])) / ticks


class CpuWatch:
    """Whether helper processes progress: :meth:`starved` is True for a process that got less
    than ``min_share`` of a core over the last window of ``window_s`` seconds, or is gone.

    The first window starts when a process is first asked about; each verdict starts a new one.
    """

    def __init__(self, window_s: float | None = None, min_share: float | None = None) -> None:
        self.window_s = WINDOW_S if window_s is None else window_s
        self.min_share = MIN_CPU_SHARE if min_share is None else min_share
        self._start: dict[int, tuple[float, float]] = {}

    def restart(self, pid: int) -> None:
        """Start a new window for ``pid`` now (a wait begins: what it did before does not
        count)."""
        self._start.pop(pid, None)
        self.starved(pid)

    def starved(self, pid: int) -> bool:
        """True when ``pid`` is gone, or got less than the minimum share of a core over the
        window that has just ended; False while the window runs or when it progressed."""
        now = time.monotonic()
        first = self._start.get(pid)
        if first is not None and now - first[0] < self.window_s:
            return False
        cpu = cpu_seconds(pid)
        if cpu is None:
            return True
        self._start[pid] = (now, cpu)
        if first is None:
            return False
        return (cpu - first[1]) < self.min_share * (now - first[0])


def end_with_parent(parent_pid: int, orphaned: Callable[[], None]) -> None:
    """In a helper process: Linux sends it SIGTERM when its parent dies, even by SIGKILL
    (``prctl(PR_SET_PDEATHSIG)``); ``orphaned()`` is called when the parent ``parent_pid`` (read
    before the fork) is already gone, which the request cannot catch."""
    if sys.platform.startswith("linux"):
        import ctypes

        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGTERM))  # PR_SET_PDEATHSIG
    if os.getppid() != parent_pid:
        orphaned()
