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
        "--no-quasi-static",
        action="store_true",
        help="leave out the twist and yaw-resistance tests (the verdict is then incomplete)",
    )
    p.set_defaults(func=command)
    return p


def command(args: argparse.Namespace) -> int:
    from railexu.study.acceptance import run_acceptance

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
    )
    return 0 if result.verdict == "pass" else EXIT_FAILED
