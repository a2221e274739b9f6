"""The ``railexu critical-speed`` sub-command."""

from __future__ import annotations

import argparse

from railexu.cli.common import quantity, split_overrides


def add_parser(sub) -> None:
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
    p.add_argument(
        "--speed-min", type=quantity("m/s"), default=5.0, help="lowest speed searched [m/s]"
    )
    p.add_argument(
        "--speed-max", type=quantity("m/s"), default=80.0, help="highest speed searched [m/s]"
    )
    p.add_argument("--tolerance", type=quantity("m/s"), default=1.0, help="bisection bracket [m/s]")
    p.add_argument(
        "--threshold", type=quantity("m"), default=0.003, help="hunting amplitude threshold [m]"
    )
    p.add_argument(
        "--initial-lateral", type=quantity("m"), default=0.004, help="lateral disturbance [m]"
    )
    p.add_argument("--distance", type=quantity("m"), default=300.0, help="distance per run [m]")
    p.add_argument("--linear-points", type=int, default=31, help="speeds of the linear analysis")
    p.add_argument(
        "--linearization",
        default="equivalent_conicity",
        choices=("equivalent_conicity", "profiles"),
        help="linear contact: cones of the equivalent conicity, or the profiles' tangent",
    )
    p.add_argument(
        "--deceleration", type=quantity("m/s^2"), default=0.5, help="ramp deceleration [m/s^2]"
    )
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a value of the vehicle file")  # fmt: skip
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--quiet", action="store_true", help="no progress messages")
    p.set_defaults(func=command)


def command(args: argparse.Namespace) -> int:
    from railexu.report.stability_files import write_critical_speed
    from railexu.stability import (
        CriticalSpeedSettings,
        critical_speed,
        parse_methods,
        print_messages,
    )
    from railexu.track.track import ideal_straight_track, load_track
    from railexu.vehicle.vehicle import load_vehicle

    vehicle_set, track_set = split_overrides(args.set)
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
            mode = f", {result['linear_mode']} mode" if method == "linear" and result.get(
                "linear_mode") else ""  # fmt: skip
            print(f"  {label}: {fmt(result[key])}{mode}" + (f"  [{note}]" if note else ""))
            if method == "linear":
                for name, m in (section.get("modes") or {}).items():
                    print(f"    {name}: zero damping at {fmt(m['critical_speed_m_per_s'])}")
    if result.get("comparison"):
        print(f"  note: {result['comparison']}")
    print(f"  wrote {len(written)} files to {args.out}")
    return 0
