"""The ``railexu critical-speed`` sub-command."""

from __future__ import annotations

import argparse

from railexu.cli.common import EXIT_FAILED, quantity, split_overrides


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
        "--deceleration",
        type=quantity("m/s^2"),
        default=0.2,
        help="ramp deceleration [m/s^2] (a second ramp at twice it checks rate independence)",
    )
    p.add_argument("--ramp-settle", type=quantity("m"), default=200.0,
                   help="ramp: distance at the highest speed before the ramp [m]")  # fmt: skip
    p.add_argument("--ramp-budget", type=quantity("m"), default=20000.0,
                   help="ramp: the most distance one ramp may run [m]")  # fmt: skip
    p.add_argument("--branch-step", type=quantity("m/s"), default=5.0,
                   help="branch: speed step of the first stage [m/s]")  # fmt: skip
    p.add_argument("--max-runs", type=int, default=30,
                   help="branch: the most plateaus in all (its budget)")  # fmt: skip
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
        ramp_settle_m=args.ramp_settle,
        ramp_budget_m=args.ramp_budget,
        branch_step_m_per_s=args.branch_step,
        max_runs=args.max_runs,
    )
    result = critical_speed(vehicle, track, settings, None if args.quiet else print_messages())
    written = write_critical_speed(result, args.out)

    print(f"railexu critical-speed: {vehicle.name}")
    for line in summary_lines(result, settings.methods):
        print(f"  {line}")
    if result.get("comparison"):
        print(f"  note: {result['comparison']}")
    print(f"  wrote {len(written)} files to {args.out}")
    unfinished = unfinished_methods(result)
    if unfinished:
        print(f"  NOT CONVERGED: {', '.join(unfinished)} (exit code {EXIT_FAILED})")
        return EXIT_FAILED
    return 0


#: Statuses of a nonlinear method that did not reach a verdict within its budget.
UNFINISHED = ("budget exhausted", "run stopped", "restart lost the cycle",
              "restart lost the branch", "no verdict", "rate-dependent")  # fmt: skip


def unfinished_methods(result: dict) -> list[str]:
    """``["branch (budget exhausted)", ...]``: the methods that did not finish (:data:`UNFINISHED`);
    the command then exits with ``EXIT_FAILED`` (its results are written all the same)."""
    out = []
    for method in ("branch", "ramp", "bisection"):
        status = (result.get(method) or {}).get("status")
        if status in UNFINISHED:
            out.append(f"{method} ({status})")
    return out


def _fmt(v) -> str:
    return f"{v:.2f} m/s ({v * 3.6:.1f} km/h)" if v is not None else "not found in range"


def summary_lines(result: dict, methods) -> list[str]:
    """The printed summary: each method's critical speed with its note; for the linear analysis
    the critical mode, whether it stays unstable above (or its band), every followed mode's
    unstable bands and the table of least damped modes per speed."""
    lines = []
    labels = {
        "linear": "linear",
        "branch": "nonlinear, limit-cycle branch",
        "bisection": "nonlinear, bisection",
        "ramp": "nonlinear, ramp",
    }
    for method, label in labels.items():
        if method not in methods:
            continue
        section = result.get(method) or {}
        key = "linear_m_per_s" if method == "linear" else f"nonlinear_{method}_m_per_s"
        note = section.get("note") or (
            "unstable at every speed in range" if section.get("unstable_in_range") else ""
        )
        if method == "linear":
            lines.extend(_linear_lines(section, note))
        else:
            lines.append(f"{label}: {_fmt(result.get(key))}" + (f"  [{note}]" if note else ""))
            lines.extend(_method_status(method, section))
            if section.get("disturbance"):
                lines.append(f"  disturbance: {section['disturbance']}")
            if section.get("judged_by"):
                lines.append(f"  judged by: {section['judged_by']}")
            for p in section.get("branch") or []:
                amp = p.get("amplitude_m")
                amp_text = f"{amp * 1e3:.2f} mm" if amp is not None else "-"
                speed = p["speed_m_per_s"]
                lines.append(f"    {speed:6.2f} m/s: {p['classification']}, {amp_text}")
    return lines


def _method_status(method: str, section: dict) -> list[str]:
    """``status: converged, resolution 1.25 m/s`` (branch, ramp) or the bisection bracket; the
    ramp's two rates and whether they agree."""
    parts = []
    if section.get("status"):
        parts.append(section["status"])
    res = section.get("resolution_m_per_s")
    if res is not None:
        parts.append(f"resolution {res:.2f} m/s")
    if method == "bisection" and section.get("bracket_m_per_s"):
        lo, hi = section["bracket_m_per_s"]
        parts.append(f"bracket {lo:.2f} to {hi:.2f} m/s")
    lines = [f"  status: {', '.join(parts)}"] if parts else []
    if method == "bisection" and section.get("run_duration"):
        lines.append(f"  runs: {section['run_duration']}")
    for r in section.get("ramps") or []:
        v = r.get("critical_speed_m_per_s")
        found = f"{v:.2f} m/s" if v is not None else r.get("note", "not found")
        lines.append(f"    ramp at {r['deceleration_m_per_s2']:g} m/s^2 over {r['distance_m']:.0f} "
                     f"m: {found} ({r['status']})")  # fmt: skip
    fold = section.get("fold")
    if fold:
        lo, hi = fold["bracket_m_per_s"]
        amp = fold.get("amplitude_m")
        lines.append(
            f"  fold of the branch followed from the top: between {lo:.2f} and "
            f"{hi:.2f} m/s"
            + (f" ({amp * 1e3:.2f} mm at {hi:.2f} m/s)" if amp else "")
            + f", discontinuity: {fold.get('discontinuity')}"
        )
    search = section.get("fold_search") or {}
    if not fold and search.get("discontinuity") == "continuous":
        lo, hi = search["levels"][-1]["bracket_m_per_s"]
        lines.append(f"  no fold: the largest fall of the branch ({lo:.2f} to {hi:.2f} m/s) "
                     "is continuous (it spreads over the refined sub-steps)")  # fmt: skip
    low = section.get("lowest_cycle") if method == "branch" else None
    if low and low.get("amplitude_m"):
        lines.append(
            f"  a sustained cycle at the lowest speed run, {low['speed_m_per_s']:.2f} m/s: "
            f"{low['amplitude_m'] * 1e3:.2f} mm"
        )
    if method == "branch" and section.get("critical_amplitude_m"):
        lines.append(
            f"  lowest sustained cycle: {section['critical_amplitude_m'] * 1e3:.2f} mm "
            f"at {section['critical_speed_m_per_s']:.2f} m/s"
        )
    if method == "ramp" and section.get("fold_m_per_s"):
        lines.append(
            f"  the cycle followed from the plateau ends at {section['fold_m_per_s']:.2f} m/s"
            + (" (both rates agree)" if section.get("fold_rate_independent") else "")
        )
    if method == "ramp" and section.get("drift_per_period") is not None:
        lines.append(
            f"  branch drift on the ramp: {section['drift_per_period']:.2%} per period (band 1 %)"
        )
    if section.get("warning"):
        lines.append(f"  warning: {section['warning']}")
    if section.get("rate_independent") is not None:
        same = "agree" if section["rate_independent"] else "DISAGREE (no verdict)"
        diff = section.get("rate_difference_m_per_s")
        lines.append(f"  the two rates {same} within their resolutions"
                     + (f" (difference {diff:.2f} m/s)" if diff is not None else ""))  # fmt: skip
    if section.get("fold_rate_independent") is False:
        lines.append("  the two rates DISAGREE on the fold (no verdict)")
    return lines


def _linear_lines(lin: dict, note: str) -> list[str]:
    mode = lin.get("critical_mode")
    text = f"linear: {_fmt(lin.get('critical_speed_m_per_s'))}"
    if mode:
        band = lin.get("critical_band_m_per_s") or [None, None]
        if lin.get("critical_mode_stays_unstable"):
            text += f", {mode} mode, unstable from there up to the highest speed analysed"
        else:
            text += f", {mode} mode, unstable only up to {_fmt(band[1])}, stable again above"
    lines = [text + (f"  [{note}]" if note else "")]
    persistent = lin.get("persistent_critical_speed_m_per_s")
    if persistent is not None and persistent != lin.get("critical_speed_m_per_s"):
        lines.append(f"linear, a mode stays unstable above: {_fmt(persistent)} "
                     f"({lin.get('persistent_mode')} mode)")  # fmt: skip
    damped = []
    for name, m in (lin.get("modes") or {}).items():
        bands = m.get("unstable_bands_m_per_s") or []
        if not bands:
            damped.append(name)
            continue
        where = "; ".join(_band_text(b) for b in bands)
        energy = ", ".join(f"{k} {v:.0%}" for k, v in (m.get("energy") or {}).items())
        lines.append(f"  {name}: {where}" + (f"  (energy: {energy})" if energy else ""))
    if damped:
        lines.append(f"  damped over the range: {', '.join(damped)}")
    table = lin.get("least_damped") or []
    if table:
        lines.append("  least damped modes per speed (damping ratio, frequency):")
        for row in table:
            cells = ", ".join(f"{c['mode']} {c['damping_ratio']:+.3f} {c['frequency_Hz']:.2f} Hz"
                              for c in row["modes"][:3])  # fmt: skip
            lines.append(f"    {row['speed_m_per_s']:6.1f} m/s: {cells}")
    return lines


def _band_text(band) -> str:
    lo, hi = band
    lo_text = "below the range" if lo is None else f"{lo:.1f} m/s"
    hi_text = "above the range" if hi is None else f"{hi:.1f} m/s"
    return f"unstable from {lo_text} to {hi_text}"
