"""The ``railexu`` command: a thin shell over the public functions.

Each sub-command parses its arguments into the settings object of a public function, calls it
and reports. ``main(argv=None)`` returns the exit status (0 success, 1 failed run, 2 bad input).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

import numpy as np


class CliError(ValueError):
    """Bad command-line input."""


def parse_range(text: str, name: str = "range") -> tuple[float, ...]:
    """Values from ``FROM:TO:STEP`` (inclusive of TO within half a step), or a single value,
    or a comma-separated list."""
    text = text.strip()
    try:
        if ":" in text:
            parts = [float(p) for p in text.split(":")]
            if len(parts) != 3:
                raise CliError(f"{name} {text!r}: expected FROM:TO:STEP")
            start, stop, step = parts
            if step <= 0 or stop < start:
                raise CliError(f"{name} {text!r}: need STEP > 0 and TO >= FROM")
            n = int(np.floor((stop - start) / step + 0.5)) + 1
            return tuple(float(np.round(start + i * step, 12)) for i in range(n))
        return tuple(float(v) for v in text.split(","))
    except ValueError as exc:
        if isinstance(exc, CliError):
            raise
        raise CliError(f"{name} {text!r}: expected numbers as FROM:TO:STEP or a,b,c") from exc


def _add_contact_parser(sub) -> None:
    p = sub.add_parser(
        "contact",
        help="quasi-static wheel/rail check over lateral displacements",
        description=(
            "Press a rolling wheelset onto its rails at each lateral displacement and report "
            "every contact point (position, radius, angle, ellipse, creepages, creep forces), "
            "the rolling radius difference and the equivalent conicity. The defaults are the "
            "Manchester contact benchmark (new S1002 on UIC60 1:40)."
        ),
    )
    p.add_argument("--wheel", default="S1002", help="built-in wheel profile or file (.prw, y-z)")
    p.add_argument("--rail", default="UIC60", help="built-in rail profile or file (.prr, y-z)")
    p.add_argument("--inclination", default="1:40", help="rail inclination: 1:40, 1:20 or none")
    p.add_argument("--gauge", type=float, default=1.435, help="track gauge [m] (14 mm below top)")
    p.add_argument("--flange-back", type=float, default=1.360, help="flange-back distance [m]")
    p.add_argument("--radius", type=float, default=0.46, help="nominal rolling radius [m]")
    p.add_argument(
        "--lateral", default="0:0.010:0.0005", help="lateral displacements FROM:TO:STEP [m]"
    )
    p.add_argument(
        "--yaw-per-lateral", type=float, default=0.0, help="yaw = factor x lateral [rad/m]"
    )
    p.add_argument("--load", type=float, default=10000.0, help="vertical load per wheel [N]")
    p.add_argument("--speed", type=float, default=2.0, help="forward speed [m/s]")
    p.add_argument("--friction", type=float, default=0.3, help="friction coefficient [-]")
    p.add_argument("--shear-modulus", type=float, default=82e9, help="shear modulus G [Pa]")
    p.add_argument("--poisson", type=float, default=0.28, help="Poisson's ratio [-]")
    p.add_argument(
        "--creep",
        default="polach",
        help="creep law: polach, polach_2005, kalker_linear, fastsim",
    )
    p.add_argument(
        "--amplitudes",
        default="0.0005:0.010:0.0005",
        help="amplitudes for the equivalent conicity FROM:TO:STEP [m]",
    )
    p.add_argument("--out", required=True, help="output folder")
    p.set_defaults(func=_cmd_contact)


def _cmd_contact(args: argparse.Namespace) -> int:
    from .contact.check import ContactCheckSettings, contact_check, write_contact_check
    from .contact.evaluation import ContactParameters

    params = ContactParameters(
        shear_modulus_Pa=args.shear_modulus,
        poisson=args.poisson,
        friction=args.friction,
        creep_model=args.creep,
    )
    settings = ContactCheckSettings(
        wheel=args.wheel,
        rail=args.rail,
        inclination=args.inclination,
        gauge_m=args.gauge,
        flange_back_m=args.flange_back,
        radius_m=args.radius,
        lateral_m=parse_range(args.lateral, "--lateral"),
        yaw_per_lateral_rad_per_m=args.yaw_per_lateral,
        load_N=args.load,
        speed_m_per_s=args.speed,
        contact=params,
        conicity_amplitudes_m=parse_range(args.amplitudes, "--amplitudes"),
    )
    result = contact_check(settings)
    written = write_contact_check(result, args.out)
    n_two = sum(
        1
        for p in result.pressed
        for side in ("left", "right")
        if sum(q.loaded for q in p.result.wheel(side)) >= 2
    )
    print(
        f"railexu contact: {len(result.pressed)} lateral positions, {len(result.rows)} loaded "
        f"contact points ({n_two} wheel states with two-point contact)"
    )
    for a, c in zip(result.conicity_amplitude_m, result.conicity, strict=True):
        if abs(a * 1e3 - 3.0) < 1e-9:
            print(f"  equivalent conicity at 3 mm amplitude: {c:.4f}")
    print(f"  wrote {len(written)} files to {args.out}")
    return 0


def _add_run_parser(sub) -> None:
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
    p.set_defaults(func=_cmd_run)


def _split_overrides(items: Sequence[str]) -> tuple[list[str], list[str]]:
    vehicle, track = [], []
    for item in items:
        (track if item.startswith("track.") else vehicle).append(item.removeprefix("track."))
    return vehicle, track


def _cmd_run(args: argparse.Namespace) -> int:
    from .simulation import RunSettings, print_progress, run, write_run
    from .track import ideal_straight_track, load_track
    from .vehicle import load_vehicle

    vehicle_set, track_set = _split_overrides(args.set)
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


def _add_plot_parser(sub) -> None:
    p = sub.add_parser(
        "plot",
        help="redraw the plots of a run (or a study) from its files",
        description=(
            "Redraw the plots of a run folder (timeseries.csv, summary.json) or of a study "
            "folder (results.csv, study.json: each result against each varied value, maps "
            "when two vary)."
        ),
    )
    p.add_argument("folder", help="output folder of railexu run or railexu study")
    p.set_defaults(func=_cmd_plot)


def _cmd_plot(args: argparse.Namespace) -> int:
    from pathlib import Path

    from .plots import run_figures, save_figure
    from .results import TimeSeries, read_summary
    from .study import is_study_folder, plot_study

    folder = Path(args.folder)
    if is_study_folder(folder):
        written = plot_study(folder)
        print(f"railexu plot: wrote {len(written)} study plots to {folder}")
        return 0
    ts_path = folder / "timeseries.csv"
    if not ts_path.exists():
        raise CliError(f"{folder}: no timeseries.csv (not an output folder of railexu run)")
    ts = TimeSeries.from_csv(ts_path)
    summary = read_summary(folder / "summary.json") if (folder / "summary.json").exists() else None
    title = ""
    if summary:
        speed = (summary.get("settings") or {}).get("speed_m_per_s")
        title = f"{summary.get('vehicle', '')}" + (f" at {speed:g} m/s" if speed else "")
    written = []
    for name, fig in run_figures(ts, summary, title).items():
        written.extend(save_figure(fig, folder / name))
    print(f"railexu plot: wrote {len(written)} files to {folder}")
    return 0


def _add_critical_speed_parser(sub) -> None:
    p = sub.add_parser(
        "critical-speed",
        help="critical speed: linear eigenvalues, nonlinear bisection, ramp",
        description=(
            "Find the critical speed of a vehicle on (ideal straight) track: the speed where the "
            "hunting mode's damping crosses zero (linear, with the equivalent conicity and "
            "Kalker's linear creep), the speed between a stable and an unstable run after a "
            "lateral disturbance (bisection), and the speed where a hunting limit cycle vanishes "
            "on a slow deceleration (ramp). Writes critical_speed.json and plots to --out."
        ),
    )
    p.add_argument("vehicle", help="vehicle file (YAML)")
    p.add_argument("--track", help="track file (YAML); default: ideal straight track")
    p.add_argument("--methods", default="linear,bisection,ramp", help="comma-separated methods")
    p.add_argument("--speed-min", type=float, default=5.0, help="lowest speed searched [m/s]")
    p.add_argument("--speed-max", type=float, default=80.0, help="highest speed searched [m/s]")
    p.add_argument("--tolerance", type=float, default=1.0, help="bisection bracket [m/s]")
    p.add_argument("--threshold", type=float, default=0.003, help="hunting amplitude threshold [m]")
    p.add_argument("--initial-lateral", type=float, default=0.004, help="lateral disturbance [m]")
    p.add_argument("--distance", type=float, default=300.0, help="distance per run [m]")
    p.add_argument("--linear-points", type=int, default=31, help="speeds of the linear analysis")
    p.add_argument(
        "--linearization",
        default="equivalent_conicity",
        choices=("equivalent_conicity", "profiles"),
        help="linear contact: cones of the equivalent conicity, or the profiles' tangent",
    )
    p.add_argument("--deceleration", type=float, default=0.5, help="ramp deceleration [m/s^2]")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a value of the vehicle file")  # fmt: skip
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--quiet", action="store_true", help="no progress messages")
    p.set_defaults(func=_cmd_critical_speed)


def _cmd_critical_speed(args: argparse.Namespace) -> int:
    from .stability import (
        CriticalSpeedSettings,
        critical_speed,
        parse_methods,
        print_messages,
        write_critical_speed,
    )
    from .track import ideal_straight_track, load_track
    from .vehicle import load_vehicle

    vehicle_set, track_set = _split_overrides(args.set)
    vehicle = load_vehicle(args.vehicle, vehicle_set)
    track = load_track(args.track, track_set) if args.track else ideal_straight_track()
    settings = CriticalSpeedSettings(
        methods=parse_methods(args.methods),
        speed_min_m_per_s=args.speed_min,
        speed_max_m_per_s=args.speed_max,
        tolerance_m_per_s=args.tolerance,
        threshold_m=args.threshold,
        initial_lateral_m=args.initial_lateral,
        distance_m=args.distance,
        linear_points=args.linear_points,
        linearization=args.linearization,
        ramp_deceleration_m_per_s2=args.deceleration,
    )
    result = critical_speed(vehicle, track, settings, None if args.quiet else print_messages())
    written = write_critical_speed(result, args.out)

    def fmt(v):
        return f"{v:.2f} m/s ({v * 3.6:.1f} km/h)" if v is not None else "not found in range"

    print(f"railexu critical-speed: {vehicle.name}")
    for key, label in (
        ("linear_m_per_s", "linear"),
        ("nonlinear_bisection_m_per_s", "nonlinear, bisection"),
        ("nonlinear_ramp_m_per_s", "nonlinear, ramp"),
    ):
        method = label.split(", ")[-1]
        if method in settings.methods:
            section = result.get(method) or {}
            note = section.get("note") or (
                "unstable at every speed in range" if section.get("unstable_in_range") else ""
            )
            print(f"  {label}: {fmt(result[key])}" + (f"  [{note}]" if note else ""))
    print(f"  wrote {len(written)} files to {args.out}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="railexu",
        description="Railway vehicle dynamics on Exudyn: contact checks, runs, studies.",
    )
    from . import __version__

    parser.add_argument("--version", action="version", version=f"railexu {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    _add_contact_parser(sub)
    _add_run_parser(sub)
    from .study import add_study_parser

    add_study_parser(sub)
    _add_critical_speed_parser(sub)
    _add_plot_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``railexu`` command; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except (ValueError, FileNotFoundError) as exc:
        # bad input: every loader raises a ValueError subclass naming file, key and expectation
        print(f"railexu {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except RuntimeError as exc:
        print(f"railexu {args.command}: failed: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
