"""railexu: railway vehicle dynamics on the Exudyn multibody engine.

The front door: the main public functions and types, loaded on first use (``import railexu`` is
cheap; Exudyn, numba and matplotlib are imported only by what needs them)::

    import railexu

    vehicle = railexu.load_vehicle("eu07")            # a shipped name or a path
    track = railexu.load_track("straight_irregular")
    result = railexu.run(vehicle, track, railexu.RunSettings(speed_m_per_s=20.0))
    print(result.summary["hunting"])
    railexu.write_run(result, "runs/eu07_20")

- :func:`load_vehicle`, :func:`load_track`: read and validate input files (or shipped names);
- :func:`run`, :class:`RunSettings`, :class:`RunResult`, :func:`write_run`: one run;
- :func:`contact_check`, :class:`ContactCheckSettings`, :class:`ContactParameters`: the
  quasi-static wheel/rail check of ``railexu contact``;
- :func:`critical_speed`, :class:`CriticalSpeedSettings`: linear and nonlinear critical speeds;
- :func:`load_study`, :func:`run_study`, :class:`StudyResult`: parameter studies;
- :func:`acceptance`, :class:`AcceptanceResult`: a vehicle through an EN 14363 programme;
- :func:`wear_loop`, :class:`WearLoopResult`: the wheel profiles worn over a route's mileage
  (``railexu wear``, docs/wear.md);
- :class:`TimeSeries`: a run's recorded signals; :func:`shipped_files`: what ships by name;
- :class:`InputError`: the one exception type for bad input.

The package is layered along the physics and the flow; each layer imports only the ones below
it: ``errors``, ``units`` -> ``inputs`` -> ``profiles`` -> ``contact`` -> ``track``, ``vehicle``
-> ``model`` -> ``simulation`` -> analysis (``results``, ``stability``, ``assessment``) ->
``report`` (figures and files) -> ``study`` -> ``cli`` (``tests/test_layers.py`` checks it).
All quantities inside the code are SI (m, kg, s, N, rad).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from railexu.version import __version__ as __version__

# public name -> module that defines it (imported on first access, PEP 562)
_PUBLIC = {
    "InputError": "railexu.errors",
    "load_vehicle": "railexu.vehicle.vehicle",
    "Vehicle": "railexu.vehicle.vehicle",
    "load_track": "railexu.track.track",
    "Track": "railexu.track.track",
    "RunSettings": "railexu.operation.run_settings",
    "run": "railexu.results.run",
    "RunResult": "railexu.simulation.simulate",
    "TimeSeries": "railexu.results",
    "write_run": "railexu.report.run_files",
    "contact_check": "railexu.contact.check",
    "ContactCheckSettings": "railexu.contact.check",
    "ContactCheckResult": "railexu.contact.check",
    "ContactParameters": "railexu.contact.evaluation",
    "critical_speed": "railexu.stability",
    "CriticalSpeedSettings": "railexu.stability",
    "load_study": "railexu.study",
    "run_study": "railexu.study",
    "StudyResult": "railexu.study",
    "shipped_files": "railexu.inputs.catalog",
    "acceptance": "railexu.study.acceptance",
    "AcceptanceResult": "railexu.study.acceptance",
    "wear_loop": "railexu.study.wear.loop",
    "WearLoopResult": "railexu.study.wear.loop",
}

__all__ = [
    "AcceptanceResult",
    "ContactCheckResult",
    "ContactCheckSettings",
    "ContactParameters",
    "CriticalSpeedSettings",
    "InputError",
    "RunResult",
    "RunSettings",
    "StudyResult",
    "TimeSeries",
    "Track",
    "Vehicle",
    "WearLoopResult",
    "acceptance",
    "contact_check",
    "critical_speed",
    "load_study",
    "load_track",
    "load_vehicle",
    "run",
    "run_study",
    "shipped_files",
    "wear_loop",
    "write_run",
]

if TYPE_CHECKING:  # for type checkers and IDEs; at run time the names load lazily
    from railexu.contact.check import ContactCheckResult, ContactCheckSettings, contact_check
    from railexu.contact.evaluation import ContactParameters
    from railexu.errors import InputError
    from railexu.inputs.catalog import shipped_files
    from railexu.operation.run_settings import RunSettings
    from railexu.report.run_files import write_run
    from railexu.results import TimeSeries
    from railexu.results.run import run
    from railexu.simulation.simulate import RunResult
    from railexu.stability import CriticalSpeedSettings, critical_speed
    from railexu.study import StudyResult, load_study, run_study
    from railexu.study.acceptance import AcceptanceResult
    from railexu.study.acceptance import run_acceptance as acceptance
    from railexu.study.wear.loop import WearLoopResult, wear_loop
    from railexu.track.track import Track, load_track
    from railexu.vehicle.vehicle import Vehicle, load_vehicle


def __getattr__(name: str) -> Any:
    module = _PUBLIC.get(name)
    if module is None:
        raise AttributeError(f"module 'railexu' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(list(globals()) + __all__)
