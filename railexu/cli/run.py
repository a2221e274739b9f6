"""The ``railexu run`` sub-command: one vehicle on one track."""

from __future__ import annotations

import argparse
import sys

from .common import CliError, split_overrides


def add_parser(sub) -> None:
    p = sub.add_parser(
        "run",
        help="simulate a vehicle running on a track",
        description=(
            "Simulate a vehicle at constant speed on a track (ideal straight track by default), "
            "starting from static equilibrium with a lateral offset. Writes timeseries.csv, "
            "summary.json and plots (PNG and SVG) to --out. The defaults are the seed paper's "
            "scenario: 10 m/s, 2 mm initial lateral offset, 150 m."
        ),
    )
    p.add_argument("vehicle", help="vehicle file (YAML), e.g. vehicles/eu07.yaml")
    p.add_argument("--track", help="track file (YAML); default: ideal straight track")
    p.add_argument("--speed", type=float, default=10.0, help="forward speed [m/s]")
    p.add_argument("--distance", type=float, default=150.0, help="distance to run [m]")
    p.add_argument(
        "--initial-lateral", type=float, default=0.002, help="initial lateral offset [m]"
    )
    p.add_argument("--step", type=float, default=0.002, help="integration step [s]")
    p.add_argument("--output-interval", type=float, help="output interval [s] (default 5 ms)")
    p.add_argument(
        "--solver", default="generalized_alpha", choices=("generalized_alpha", "trapezoidal")
    )
    p.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="override a value of the vehicle file (dotted path, e.g. "
        "bodies.car_body.mass='47 t'); 'track.KEY=VALUE' overrides the track file",
    )
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--no-plots", action="store_true", help="write data only")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.set_defaults(func=command)


def command(args: argparse.Namespace) -> int:
    from ..report.run_files import write_run
    from ..simulation import RunSettings, print_progress, run
    from ..track import ideal_straight_track, load_track
    from ..vehicle import load_vehicle

    vehicle_set, track_set = split_overrides(args.set)
    vehicle = load_vehicle(args.vehicle, vehicle_set)
    if args.track:
        track = load_track(args.track, track_set)
    elif track_set:
        raise CliError("--set track.KEY=VALUE needs a --track file")
    else:
        track = ideal_straight_track()
    settings = RunSettings(
        speed_m_per_s=args.speed,
        distance_m=args.distance,
        initial_lateral_m=args.initial_lateral,
        time_step_s=args.step,
        output_interval_s=args.output_interval,
        solver=args.solver,
    )
    if not args.quiet:
        print(
            f"railexu run: {vehicle.name} on {track.name}, {settings.speed_m_per_s:g} m/s, "
            f"{settings.distance_m:g} m, initial lateral {settings.initial_lateral_m * 1e3:g} mm",
            file=sys.stderr,
        )
    result = run(vehicle, track, settings, progress=None if args.quiet else print_progress())
    written = write_run(result, args.out, plots=not args.no_plots)
    print(format_summary(result.summary))
    print(f"  wrote {len(written)} files to {args.out}")
    return 0 if result.status["state"] == "completed" else 1


def format_summary(summary: dict) -> str:
    """A few lines for the console from a run's ``summary.json`` content."""
    st = summary["status"]
    lines = [f"status: {st['state']} at {st['distance_m']:.1f} m" + (
        f" ({st['reason']})" if st.get("reason") else ""
    )]  # fmt: skip
    rt = summary.get("realtime_factor")
    if rt is not None:
        lines.append(f"real-time factor: {rt:.1f} (simulated seconds per wall-clock second)")
    for ws in summary.get("wheelsets", []):
        lines.append(
            f"  {ws['name']}: max |lateral| {ws['max_abs_lateral_m'] * 1e3:.2f} mm, final "
            f"amplitude {ws['final_amplitude_m'] * 1e3:.2f} mm"
        )
    fc = summary.get("flange_contact", {})
    if fc.get("occurred"):
        lines.append(f"flange contact from {fc['first_distance_m']:.1f} m")
    else:
        lines.append("no flange contact")
    h = summary.get("hunting", {})
    if h.get("detected"):
        lines.append(
            f"hunting: wavelength {h['wavelength_m']:.2f} m, {h['frequency_Hz']:.2f} Hz, "
            f"amplitude {h['amplitude_m'] * 1e3:.2f} mm"
        )
    else:
        lines.append("no hunting (the lateral motion decays or stays below the threshold)")
    if "max_abs_lateral_force_N" in summary:
        lines.append(f"max |Y|: {summary['max_abs_lateral_force_N'] / 1e3:.2f} kN")
    yq = summary.get("max_Y_over_Q") or {}
    if yq.get("value") is not None:
        mean = yq.get("value_2m")
        mean_text = f"2 m mean {mean:.3f}, " if mean is not None else ""
        lines.append(f"max Y/Q: {yq['value']:.3f} ({mean_text}Nadal limit {yq['nadal_limit']:.2f})")
    sy = summary.get("max_sum_Y_N") or {}
    if sy.get("value") is not None:
        lines.append(
            f"max sum Y (2 m mean): {sy['value'] / 1e3:.2f} kN (EN 14363 limit "
            f"{sy['limit_N'] / 1e3:.1f} kN)"
        )
    return "\n".join(lines)
