"""The ``railexu acceptance`` sub-command: a vehicle through an EN 14363 programme."""

from __future__ import annotations

import argparse

from railexu.cli.common import EXIT_FAILED


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Add the ``acceptance`` sub-command; its function returns 0 when the verdict is pass, 1
    when it is fail or incomplete."""
    p = subparsers.add_parser(
        "acceptance",
        help="take a vehicle through an EN 14363 running-behaviour programme",
        description=(
            "Run every section of every test zone of an EN 14363:2016 programme (a study per "
            "zone, in parallel and resumable), evaluate each zone statistically against the "
            "limits of the vehicle's category, run the twist and bogie yaw-resistance tests, "
            "and write OUT/acceptance.json with the verdict (pass, fail or incomplete), "
            "OUT/zones/<zone>/ (each zone's study) and OUT/figures/ (docs/acceptance.md). "
            "`railexu report OUT` writes the report page."
        ),
    )
    p.add_argument("vehicle", help="vehicle file or shipped name (railexu list)")
    p.add_argument("--out", required=True, help="output folder (an earlier one is resumed)")
    p.add_argument(
        "--programme",
        help="programme file or shipped name (default: the shipped one of the vehicle's "
        "category: freight_wagon, locomotive or coach)",
    )
    p.add_argument(
        "--quick",
        action="store_true",
        help="the reduced programme (few sections): a trend, never an acceptance verdict",
    )
    p.add_argument("--workers", type=int, default=None, help="local worker processes")
    p.add_argument("--scheduler", help="a Dask scheduler address tcp://host:port")
    p.add_argument(
        "--set", action="append", default=[], metavar="KEY=VALUE", help="change the vehicle"
    )
    p.add_argument(
        "--set-programme",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="change the programme, e.g. zones.straight.speed=110km/h",
    )
    p.add_argument(
        "--admissible-speed",
        metavar="SPEED",
        help="the vehicle's admissible speed, e.g. 160km/h: the straight zones run at 1.1 times "
        "it (EN 14363's maximum test speed) and no curve section faster (default: the vehicle "
        "file's admissible_speed, if any)",
    )
    p.add_argument(
        "--admissible-cant-deficiency",
        metavar="CANT",
        help="the vehicle's admissible cant deficiency, e.g. 130mm: the curve zones' sections "
        "reach it and are evaluated at it (default: the vehicle file's "
        "admissible_cant_deficiency, if any)",
    )
    p.add_argument(
        "--no-quasi-static",
        action="store_true",
        help="leave out the twist and yaw-resistance tests (the verdict is then incomplete)",
    )
    p.set_defaults(func=command)
    return p


def command(args: argparse.Namespace) -> int:
    from railexu.study.acceptance import run_acceptance
    from railexu.units import to_si

    speed = cant = None
    if args.admissible_speed is not None:
        speed = _option_si("--admissible-speed", args.admissible_speed, "m/s", to_si)
    if args.admissible_cant_deficiency is not None:
        cant = _option_si("--admissible-cant-deficiency", args.admissible_cant_deficiency, "m",
                          to_si)  # fmt: skip
    result = run_acceptance(
        args.vehicle,
        args.out,
        programme=args.programme,
        quick=args.quick,
        workers=args.workers,
        scheduler=args.scheduler,
        vehicle_overrides=args.set,
        programme_overrides=args.set_programme,
        quasi_static=not args.no_quasi_static,
        admissible_speed_m_per_s=speed,
        admissible_cant_deficiency_m=cant,
    )
    return 0 if result.verdict == "pass" else EXIT_FAILED


def _option_si(option: str, text: str, unit: str, to_si) -> float:
    """``text`` of ``option`` in SI ``unit``; a value without its unit is refused (160 would
    be read as m/s, not km/h)."""
    from railexu.errors import InputError

    try:
        float(text)
    except ValueError:
        pass
    else:
        raise InputError(f"{option} {text}: give the unit, e.g. '160km/h' or '130mm'")
    try:
        return to_si(text, unit)
    except InputError as exc:
        raise InputError(f"{option}: {exc}") from None
