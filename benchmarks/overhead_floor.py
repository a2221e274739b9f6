"""The floor under issue 11's overhead budget (1 s outside the integration) on this machine.

What the seed command (``railexu run eu07``) cannot avoid, whatever railexu's own code does,
each part measured here:

- *start-up and imports*: a new Python process that imports only the libraries the run's
  process needs (numpy, SciPy's interpolation, roots, special functions, FFT and image filters,
  numba, Exudyn, PyYAML; ``RUN_LIBRARIES``), with the collector paused and BLAS on one thread as
  the console script has them; median of five;
- *numba's first call*: the first call of one small cached compiled function in a new process
  that has imported those libraries (numba builds its typing and lowering registries there);
  median of five;
- *figure axes*: the seed run's six figures with their data removed (figure, axes, ticks, grid,
  labels, titles, legends: everything but the lines and shaded spans), drawn and saved as PNG in
  a warm process (matplotlib imported, one figure drawn, as the command's warm process has it),
  processor time, median of three; divided by the two processes that draw them in the command.
  The same figures with their data are printed beside them: the data add little.

The sum is the overhead of a command with figures that only imports, starts numba and draws
empty axes: the budget cannot be lower than that with these libraries and these figures. It
leaves out what a run also needs (building the model, the assessment, the time series and
state files, the processes' exit). Run: ``python benchmarks/overhead_floor.py`` (about 30 s;
``benchmarks/realtime.py`` prints it too). Compare the parts of one run of this script with
each other and with ``realtime.py``'s overhead of the same hour, not across machines or days.
"""

from __future__ import annotations

import gc
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: the libraries that the process of ``railexu run`` imports (the assessment's ``scipy.signal``
#: and matplotlib are imported by its warm process, on the other core)
RUN_LIBRARIES = (
    "numpy",
    "scipy.interpolate",
    "scipy.optimize",
    "scipy.special",
    "scipy.fft",
    "scipy.ndimage",
    "numba",
    "exudyn",
    "yaml",
)
#: a new process's imports of :data:`RUN_LIBRARIES`, started as the console script starts
#: (``railexu.console``): the collector paused, then BLAS on one thread
IMPORT_CODE = (
    "from railexu.runtime import gc_pause\n"
    "gc_pause.pause()\n"
    "import railexu.runtime.blas_threads\n"
    "import " + ", ".join(RUN_LIBRARIES) + "\n"
)
_FIRST_CALL = """
import time
from railexu.contact.hertz import hertz_coefficients_nb, hertz_table
table = hertz_table()
t = time.perf_counter()
hertz_coefficients_nb(table, 1.0, 2.0, 1.1e11)
print(time.perf_counter() - t)
"""
#: the processes that draw a run's figures in the command (its warm process and a fork of it)
FIGURE_PROCESSES = 2


def import_seconds(repeat: int = 5) -> float:
    """Wall time of a new process that imports :data:`RUN_LIBRARIES` (median of ``repeat``)."""
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        subprocess.run([sys.executable, "-c", IMPORT_CODE], check=True)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def first_call_seconds(repeat: int = 5) -> float:
    """numba's first call of a cached compiled function in a new process that has imported
    :data:`RUN_LIBRARIES` (median of ``repeat``)."""
    code = IMPORT_CODE + _FIRST_CALL
    times = []
    for _ in range(repeat):
        done = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)
        times.append(float(done.stdout.decode().split()[-1]))
    return statistics.median(times)


def figure_seconds(repeat: int = 3) -> tuple[float, float]:
    """Processor time of the seed run's six figures drawn and saved as PNG in this process after
    the warm-up: ``(without their data, with it)``, medians of ``repeat``."""
    from railexu import RunSettings, load_vehicle, run
    from railexu.report.figures import save_figure
    from railexu.report.file_jobs import warm_up_figures
    from railexu.report.run_figures import run_figure_names, run_figures

    settings = RunSettings(speed_m_per_s=10.0, distance_m=150.0, initial_lateral_m=0.002)
    result = run(load_vehicle(ROOT / "vehicles" / "eu07.yaml"), None, settings)
    warm_up_figures()
    ts, summary = result.timeseries, result.summary
    names = run_figure_names(ts)
    times: dict[bool, list[float]] = {True: [], False: []}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(repeat):
            for empty in (True, False):
                total = 0.0
                for name in names:
                    gc.collect()
                    gc.disable()  # as in the command's figure processes (railexu.runtime.gc_pause)
                    start = time.process_time()
                    fig = run_figures(ts, summary, "EU07", names=[name])[name]
                    if empty:
                        _remove_data(fig)
                    save_figure(fig, Path(tmp) / name, formats=("png",))
                    total += time.process_time() - start
                    gc.enable()
                times[empty].append(total)
    return statistics.median(times[True]), statistics.median(times[False])


def _remove_data(fig) -> None:
    """Remove the lines, collections and patches of every axes of ``fig``, keeping its limits,
    ticks, grid, labels, titles and legends."""
    for ax in fig.axes:
        xlim, ylim = ax.get_xlim(), ax.get_ylim()
        for artist in [*ax.lines, *ax.collections, *ax.patches]:
            artist.remove()
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)


def report() -> float:
    """Measure and print the floor; returns it [s]."""
    imports = import_seconds()
    first_call = first_call_seconds()
    empty, full = figure_seconds()
    figures = empty / FIGURE_PROCESSES
    floor = imports + first_call + figures
    print("the floor under the seed command's overhead (issue 11's budget: 1 s), measured now:")
    rows = [
        ("start-up and imports of the run's libraries, new process", imports, ""),
        ("numba's first call of a cached function, new process", first_call, ""),
        (
            f"six figures without data, {empty:.2f} s of CPU / {FIGURE_PROCESSES} processes",
            figures,
            f"  (with their data: {full:.2f} s of CPU)",
        ),
        ("sum", floor, ""),
        ("sum without figures (--no-plots)", floor - figures, ""),
    ]
    for label, seconds, note in rows:
        print(f"  {label:62s} {seconds:5.2f} s{note}")
    print("  not in the sum: building the model, the assessment, the data files, the exit")
    return floor


if __name__ == "__main__":
    report()
