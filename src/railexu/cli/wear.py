"""The ``railexu wear`` sub-command: a vehicle's wheel profiles worn over a route's mileage
(:func:`railexu.study.wear.loop.wear_loop`, docs/wear.md)."""

from __future__ import annotations

import argparse
import sys

from railexu.cli.common import EXIT_FAILED, EXIT_OK, CliError, quantity


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Add ``wear`` to the ``railexu`` parser's sub-parsers; its function returns 0 when the
    mileage was reached with every case completed, 1 otherwise (the folder says why)."""
    p = subparsers.add_parser(
        "wear",
        help="wheel profile wear over a route's mileage (the wear loop)",
        description=(
            "Run every section of the route (both directions where it says so) with the "
            "current wheel profiles, wear each wheel by the chosen law, step the mileage so that "
            "no wheel loses more than --max-depth per step, update the profiles and repeat "
            "until --mileage. Writes OUT/steps.csv (Sh, Sd, qR, conicity, removed area, RCF "
            "and rail wear per step), OUT/wear.json, OUT/step_NNN/profiles*/*.txt "
            "(profiles railexu reads back; a step made again keeps every attempt: profiles/, "
            "profiles_again1/, ..., steps.csv's profiles_folder names the accepted one), "
            "OUT/step_NNN/route*/ (each step's cases as a study: railexu study's files; a stopped "
            "loop resumes from them and OUT/step_NNN/cases*/*.npz) and OUT/figures/. "
            "docs/wear.md."
        ),
    )
    p.add_argument("vehicle", help="vehicle file or shipped name, e.g. wheelset")
    p.add_argument("route", help="route file (YAML, docs/wear.md)")
    p.add_argument("--mileage", type=quantity("m"), required=True,
                   help="mileage to reach, e.g. '5000 km' (a bare number: m)")  # fmt: skip
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--law", default="archard_jendel",
                   help="wear law: archard_jendel (default) or energy_usfd")  # fmt: skip
    p.add_argument("--max-depth", type=quantity("m"), default=1e-4,
                   help="largest depth taken off any wheel per step (default 0.1 mm)")  # fmt: skip
    p.add_argument("--step", type=quantity("m"), default=None,
                   help="fixed mileage per step instead of --max-depth")  # fmt: skip
    p.add_argument("--smoothing", type=quantity("m"), default=3e-3,
                   help="the depth's Gaussian smoothing, its sigma (default 3 mm)")  # fmt: skip
    p.add_argument("--workers", type=int, default=None,
                   help="local worker processes for a step's cases (default: the number of "
                   "CPUs; 0: run in this process), as railexu study")  # fmt: skip
    p.add_argument("--scheduler",
                   help="run a step's cases on a Dask cluster: scheduler address "
                   "tcp://host:port (needs pip install railexu[dask]), as railexu "
                   "study")  # fmt: skip
    p.add_argument("--max-steps", type=int, default=100, help="most steps (default 100)")
    p.add_argument("--failure-halvings", type=int, default=2,
                   help="when the route does not complete at a step's profiles (a case "
                   "diverged even at 0.25 ms), make that step again with half the depth at "
                   "most this many times in a row, then stop (default 2; 0: stop at "
                   "once)")  # fmt: skip
    p.add_argument("--flank-rise-tolerance", type=quantity("m"), default=0.0,
                   help="the flange rule: stop when a worn flange's radius rises again "
                   "towards its root by at least this much, e.g. '5 um' (default 0: any rise; "
                   "0 .. 1 mm; docs/wear.md)")  # fmt: skip
    p.add_argument("--no-plots", action="store_true", help="do not draw the figures")
    p.set_defaults(func=command)
    return p


def command(args: argparse.Namespace) -> int:
    if args.scheduler is None and args.workers != 0:
        # the study's local workers: their fork server preloads on another core meanwhile
        from railexu.runtime import fork_server

        fork_server.start()
    from railexu.report.wear_figures import wear_figures
    from railexu.study.wear.loop import _wheel_keys, wear_loop
    from railexu.vehicle.vehicle import load_vehicle

    if (args.workers is not None and args.workers < 0) or args.max_steps < 1:
        raise CliError("--workers must be >= 0 and --max-steps >= 1")
    vehicle = load_vehicle(args.vehicle)
    first = {}
    for key, i, side in _wheel_keys(vehicle):
        ws = vehicle.wheelsets[i]
        first[key] = ws.wheel_profile if side == "left" else ws.profile_right
    result = wear_loop(
        vehicle, args.route, args.mileage / 1000.0, args.out, law=args.law,
        step_rule="fixed" if args.step else "max_depth", max_depth_m=args.max_depth,
        step_km=args.step / 1000.0 if args.step else None, smoothing_m=args.smoothing,
        workers=args.workers, max_steps=args.max_steps, scheduler=args.scheduler,
        failure_halvings=args.failure_halvings, flank_rise_tolerance_m=args.flank_rise_tolerance,
        log=lambda line: print(line, file=sys.stderr, flush=True),
    )  # fmt: skip
    if not args.no_plots:
        for path in wear_figures(args.out, first):
            print(f"figure: {path}")
    last = result.steps[-1]
    print(f"wear: {last['mileage_km']:.6g} km in {last['step']} step(s); {args.out}/steps.csv")
    if not result.complete:
        print(f"wear: not complete: {result.reason}", file=sys.stderr)
    return EXIT_OK if result.complete else EXIT_FAILED
