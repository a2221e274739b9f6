"""The ``railexu run`` sub-command: one vehicle on one track."""

from __future__ import annotations

import argparse
import sys
from functools import partial

from railexu.cli.common import EXIT_FAILED, EXIT_OK, CliError, quantity, split_overrides
from railexu.runtime import gc_pause


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "run",
        help="simulate a vehicle running on a track",
        description=(
            "Simulate a vehicle at constant speed on a track (ideal straight track by default), "
            "starting from static equilibrium with a lateral offset. Writes timeseries.csv, "
            "summary.json and figures to --out. The defaults are the seed paper's scenario: "
            "10 m/s, 2 mm initial lateral offset, 150 m. Values take units: --speed '108 km/h', "
            "--distance 2km, --initial-lateral '2 mm'; a bare number is SI."
        ),
    )
    p.add_argument("vehicle", help="vehicle: a shipped name (railexu list) or a YAML file")
    p.add_argument(
        "--track", help="track: a shipped name or a YAML file (default: ideal straight track)"
    )
    p.add_argument(
        "--speed",
        type=quantity("m/s"),
        default=_DefaultSpeed(10.0),
        help="forward speed [m/s] (the start speed with --traction-torque or --brake-force)",
    )
    p.add_argument(
        "--speed-profile",
        metavar="FILE.csv",
        help="prescribed speed along the track: a CSV of "
        "distance, speed rows (m, m/s, or cells with units), constant acceleration between them "
        "(docs/run-settings-format.md)",
    )
    p.add_argument(
        "--traction-torque",
        type=quantity("N m"),
        help="traction torque on each driven wheelset "
        "[N m]; frees the forward motion (docs/traction-and-braking.md)",
    )
    p.add_argument(
        "--brake-force",
        type=quantity("N"),
        help="tread-brake force on each wheel [N]; frees the forward motion",
    )
    p.add_argument("--driven", metavar="WS1,WS2", help="the driven wheelsets (default: all)")
    p.add_argument(
        "--time-limit",
        type=quantity("s"),
        help="free motion: end the run at this time if the "
        "distance is not reached (default: 3 x distance / start speed)",
    )
    p.add_argument("--distance", type=quantity("m"), default=150.0, help="distance to run [m]")
    p.add_argument(
        "--initial-lateral",
        type=quantity("m"),
        default=0.002,
        help="initial lateral offset of the whole vehicle [m]",
    )
    p.add_argument("--step", type=quantity("s"), default=0.002, help="integration step [s]")
    p.add_argument(
        "--output-interval", type=quantity("s"), help="output interval [s] (default: 5 ms)"
    )
    p.add_argument(
        "--evaluate-from",
        type=quantity("m"),
        help="start of the evaluation window of every statistic [m] (default: after the "
        "start-up, 20 m or a tenth of the run)",
    )
    p.add_argument(
        "--evaluate-to", type=quantity("m"), help="end of the evaluation window [m] (default: end)"
    )
    p.add_argument(
        "--contact-outputs",
        action="store_true",
        help="record every contact point (position, angle, creepages, forces) in the time series",
    )
    p.add_argument(
        "--wear",
        metavar="LAW",
        help="after the run, the wear and rolling contact fatigue (FI_surf, WLRM) of every wheel "
        "and rail by this wear law, archard_jendel or energy_usfd, into the folder: wear.csv, "
        "wear.json, summary.json's wear, wear.png; turns --contact-outputs on (docs/wear.md)",
    )
    p.add_argument(
        "--solver",
        default="generalized_alpha",
        choices=("generalized_alpha", "trapezoidal"),
        help="Exudyn's implicit solver",
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
    p.add_argument(
        "--plots",
        default="png",
        metavar="FORMATS",
        help="figure formats, comma-separated: png, svg, or none",
    )
    p.add_argument("--no-plots", action="store_true", help="write data only (as --plots none)")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.add_argument(
        "--no-helper-processes",
        action="store_true",
        help="do all the work in this one process: no warm process preparing the assessment and "
        "the figures during the run, no forked figure writer (as RAILEXU_HELPER_PROCESSES=0; the "
        "results are the same)",
    )
    # the start-up's pause of the garbage collector ends in command(), after the warm process's
    # fork (railexu.runtime.gc_pause)
    p.set_defaults(func=command, resumes_collection=True)
    return p


#: what the assessment imports (scipy.signal's filters among them): the warm process's preload
_WARM_MODULES = ("scipy.signal", "railexu.results.evaluate", "railexu.simulation.curving")


class _DefaultSpeed(float):
    """The default of ``--speed``: a float that tells it was not given."""


def _longitudinal_options(args: argparse.Namespace) -> dict:
    """``RunSettings`` keywords of the speed options: a constant speed, a profile, or free motion
    with traction and braking."""
    from railexu.operation.run_settings import speed_profile_from_csv
    from railexu.operation.traction import Schedule, Traction

    free = args.traction_torque is not None or args.brake_force is not None
    if args.speed_profile is not None:
        if not isinstance(args.speed, _DefaultSpeed) or free:
            raise CliError("--speed-profile: give no --speed (the profile's first point is the "
                           "start speed), nor traction or braking")  # fmt: skip
        return {"speed_profile": speed_profile_from_csv(args.speed_profile)}
    out = {"speed_m_per_s": float(args.speed)}
    if not free:
        if args.driven or args.time_limit is not None:
            raise CliError("--driven and --time-limit need --traction-torque or --brake-force")
        return out
    out["traction"] = Traction(
        torque_N_m=Schedule.constant(args.traction_torque or 0.0),
        brake_force_N=Schedule.constant(args.brake_force or 0.0),
        wheelsets=tuple(w.strip() for w in (args.driven or "").split(",") if w.strip()),
        time_limit_s=args.time_limit,
    )
    return out


def _wear_law(text: str | None) -> str | None:
    """``--wear`` value -> the wear law's name (None: no wear)."""
    from railexu.errors import did_you_mean
    from railexu.operation.run_settings import WEAR_LAWS

    if text is None:
        return None
    name = text.strip().lower()
    if name not in WEAR_LAWS:
        hint = did_you_mean(name, WEAR_LAWS)  # a close name, else the known ones
        known = "" if "Known:" in hint else f" Known: {', '.join(WEAR_LAWS)}"
        raise CliError(f"--wear {text!r}: unknown wear law.{hint}{known}")
    return name


def plot_formats(text: str, no_plots: bool = False) -> tuple[str, ...]:
    """``--plots`` value -> figure formats (empty: no figures)."""
    from railexu.errors import did_you_mean
    from railexu.report.figures import FORMATS

    items = [t.strip().lower() for t in text.split(",") if t.strip()]
    if no_plots or items == ["none"]:
        return ()
    if not items:  # '' or ',': a scripting slip, not a choice of no figures
        raise CliError(f"--plots {text!r}: give png, svg (comma-separated) or none")
    for item in items:
        if item not in FORMATS:
            raise CliError(
                f"--plots {text!r}: unknown format {item!r}.{did_you_mean(item, FORMATS)}"
            )
    return tuple(dict.fromkeys(items))


def command(args: argparse.Namespace) -> int:
    # the checks that need no numerical library first: a misspelt name fails at once
    from railexu.errors import RunInterrupted
    from railexu.inputs.catalog import find_input
    from railexu.report.file_jobs import warm_up_figures
    from railexu.report.folder import OutputFolder
    from railexu.runtime.helpers import free_core, helpers_enabled
    from railexu.runtime.warm_process import WarmProcess

    formats = plot_formats(args.plots, args.no_plots)
    wear_law = _wear_law(args.wear)
    # names are looked up before the output folder exists (`railexu run eu07 --out eu07`)
    vehicle_file = find_input("vehicle", args.vehicle)
    track_file = find_input("track", args.track) if args.track else None
    # the run's modules (Exudyn, numba, the model) before the warm process forks: it gets them
    # without importing them again (what it is handed after the run needs them)
    from railexu.report.run_files import write_run
    from railexu.results.run import RunSettings, print_progress, run
    from railexu.track.track import ideal_straight_track, load_track
    from railexu.vehicle.vehicle import load_vehicle

    folder = OutputFolder(args.out, "run").prepare()  # before any work: a bad --out fails now
    # a process that gets ready for the assessment and the figures while the run integrates
    # (railexu.runtime.warm_process): the results are the same as without it
    # a bad RAILEXU_HELPER_PROCESSES is told now, before the run
    helpers = not args.no_helper_processes and helpers_enabled()
    # without a free core the warm process would only add its processor time (issue 26)
    warm = WarmProcess(
        _WARM_MODULES,
        partial(warm_up_figures, formats) if formats else None,
        start=helpers and free_core(),
    )
    gc_pause.resume()  # after the imports and the fork: the warm process keeps it paused
    try:
        vehicle_set, track_set = split_overrides(args.set)
        vehicle = load_vehicle(vehicle_file, vehicle_set)
        if track_file is not None:
            track = load_track(track_file, track_set)
        elif track_set:
            raise CliError("--set track.KEY=VALUE needs a --track file")
        else:
            track = ideal_straight_track()
        settings = RunSettings(
            **_longitudinal_options(args),
            distance_m=args.distance,
            initial_lateral_m=args.initial_lateral,
            time_step_s=args.step,
            output_interval_s=args.output_interval,
            solver=args.solver,
            evaluate_from_m=args.evaluate_from,
            evaluate_to_m=args.evaluate_to,
            contact_outputs=args.contact_outputs,
            wear_law=wear_law,
        )
        if not args.quiet:
            print(
                f"railexu run: {vehicle.name} on {track.name}, {settings.speed_m_per_s:g} m/s, "
                f"{settings.distance_m:g} m, initial lateral "
                f"{settings.initial_lateral_m * 1e3:g} mm",
                file=sys.stderr,
            )
        progress = None if args.quiet else print_progress()
        # from here until the manifest says complete, a stop leaves a folder that says it is
        # incomplete: a signal after the integration, in the assessment, is no exception
        folder.mark_incomplete()
        try:
            result = run(vehicle, track, settings, progress, warm)
        except RunInterrupted as exc:  # Ctrl-C or SIGTERM: the results so far are written
            if exc.result is None:
                _say_incomplete(args.out, "before the results were written")
                raise
            result = exc.result
        except KeyboardInterrupt:  # after the integration, before the writing
            _say_incomplete(args.out, "before the results were written")
            raise
        except Exception:  # no result (a model that cannot be built): the older folder stays
            folder.unmark_if_untouched()
            raise
        for warning in result.summary.get("warnings", []):
            print(f"railexu run: warning: {warning}", file=sys.stderr)
        try:
            written = write_run(
                result, folder, bool(formats), formats or ("png",), warm, None if helpers else 1
            )
            folder.finish()
        except KeyboardInterrupt:  # Ctrl-C or SIGTERM while writing: the folder says so
            _say_incomplete(args.out, "while writing the results")
            raise
    finally:
        warm.close()
        folder.release()
    print(format_summary(result.summary))
    print(f"  wrote {len(written)} files to {args.out}")
    return EXIT_OK if result.status["state"] == "completed" else EXIT_FAILED


def _say_incomplete(out: str, when: str) -> None:
    print(
        f"railexu run: stopped {when}: {out} is marked incomplete (railexu report, plot and "
        "animate refuse it)",
        file=sys.stderr,
    )


def format_summary(summary) -> str:
    """A few lines for the console from a run's summary (a ``RunSummary`` or the dict of
    ``summary.json``): status, evaluation window, motion, every criterion with its limit and
    verdict, hunting, ride comfort."""
    st = summary["status"]
    lines = [f"status: {st['state']} at {st['distance_m']:.1f} m" + (
        f" ({st['reason']})" if st.get("reason") else ""
    )]  # fmt: skip
    rt = summary.get("realtime_factor")
    if rt is not None:
        lines.append(f"real-time factor: {rt:.1f} (simulated seconds per wall-clock second)")
    win = summary.get("evaluation_window") or {}
    if win.get("from_m") is not None:
        lines.append(f"evaluated from {win['from_m']:.1f} m to {win['to_m']:.1f} m ({win['rule']})")
    for ws in summary.get("wheelsets", []):
        if ws.get("max_abs_lateral_m") is None:
            continue
        lines.append(
            f"  {ws['name']}: max |lateral| {ws['max_abs_lateral_m'] * 1e3:.2f} mm, final "
            f"amplitude {ws['final_amplitude_m'] * 1e3:.2f} mm"
        )
    fc = summary.get("flange_contact", {})
    if fc.get("occurred"):
        lines.append(f"flange contact from {fc['first_distance_m']:.1f} m")
    else:
        lines.append("no flange contact")
    lines.append(_hunting_line(summary.get("hunting") or {}))
    lines.extend(_oscillation_lines(summary.get("hunting") or {}))
    if summary.get("max_abs_lateral_force_N") is not None:
        lines.append(
            f"max |Y| (raw samples, unfiltered; not a verdict): "
            f"{summary['max_abs_lateral_force_N'] / 1e3:.2f} kN"
        )
    assessment = summary.get("assessment") or {}
    for name, c in (assessment.get("criteria") or {}).items():
        lines.append("  " + _criterion_line(name, c))
    if assessment.get("exceedances"):
        lines.append(f"SAFETY CRITERIA EXCEEDED: {', '.join(assessment['exceedances'])}")
    yq = summary.get("max_Y_over_Q") or {}
    if yq.get("nadal_limit") is not None:
        lines.append(f"  (Nadal's flange-climb limit for this flange and friction: "
                     f"{yq['nadal_limit']:.2f}, information)")  # fmt: skip
    lines.extend(_comfort_lines(summary.get("comfort") or {}))
    lines.extend(_wear_lines(summary.get("wear")))
    return "\n".join(lines)


def _wear_lines(wear: dict | None) -> list[str]:
    """The wear block of a worn run (docs/wear.md, "Per run"): per wheel one line."""
    if not wear:
        return []
    if not wear.get("computed"):
        return [f"wear ({wear.get('law')}): not computed ({wear.get('reason', '')})"]
    head = f"wear ({wear['law']}, {wear['window_rule']})"
    if not wear.get("complete", True):
        head += f": {wear.get('note', '')}"
    lines = [head + ":"]
    for w, r in zip(wear["wheels"], wear["rails"], strict=True):
        fi = w["fi_surf_max"]
        fi_text = "-" if fi is None else f"{fi:.3f} at s = {w['fi_surf_max_at_mm']:.1f} mm"
        lines.append(
            f"  {w['wheelset']} {w['side']}: wheel {w['removed_area_per_km_mm2']:.4g} mm^2/km, "
            f"depth up to {w['max_depth_per_km_um']:.3g} um/km at s = {w['max_depth_at_mm']:.1f} "
            f"mm, FI_surf max {fi_text}; rail {r['removed_area_per_axle_um2']:.3g} um^2 per axle"
        )
    return lines


_CRITERION_LABELS = {
    "y_over_q": ("Y/Q (EN 14363)", 1.0, ""),
    "sum_y": ("sum Y, track shifting (EN 14363)", 1e-3, " kN"),
    "running_stability": ("running stability, rms sum Y (EN 14363)", 1e-3, " kN"),
    "wheel_unloading": ("wheel unloading dQ/Q0", 1.0, ""),
    "flange_climb": ("flange climb, Y/Q 2 m against Nadal", 1.0, ""),
}


def _criterion_line(name: str, c: dict) -> str:
    label, scale, unit = _CRITERION_LABELS.get(name, (name, 1.0, ""))
    if c.get("value") is None:
        return f"{label}: not evaluated" + (f" ({c['note']})" if c.get("note") else "")
    verdict = {True: "pass", False: "EXCEEDED", None: "-"}[c.get("pass")]
    where = f" at {c['where']}" if c.get("where") else ""
    if c.get("distance_m") is not None:
        where += f", {c['distance_m']:.1f} m"
    limit = c["limit"] * scale if c.get("limit") is not None else float("nan")
    return f"{label}: {c['value'] * scale:.3g}{unit} (limit {limit:.3g}{unit}) {verdict}{where}"


def _hunting_line(h: dict) -> str:
    verdict = h.get("verdict") or ("hunting" if h.get("detected") else "no hunting")
    text = f"hunting: {'YES' if h.get('detected') else 'no'} ({verdict}"
    if h.get("amplitude_m") is not None:
        text += f", amplitude {h['amplitude_m'] * 1e3:.2f} mm"
    if h.get("frequency_Hz") is not None:
        text += f", {h['frequency_Hz']:.2f} Hz, wavelength {h['wavelength_m']:.2f} m"
    return text + ")"


def _oscillation_lines(h: dict) -> list[str]:
    """One line per sustained or growing oscillation of a wheelset (issue 28)."""
    from railexu.assessment.hunting import describe_oscillation

    return [f"  {describe_oscillation(o)}" for o in h.get("oscillations") or []]


def _comfort_lines(comfort: dict) -> list[str]:
    points = comfort.get("points") or {}
    if not points:
        return [f"ride comfort: not evaluated ({comfort.get('note', 'no accelerations')})"]
    lines = [f"ride comfort ({comfort.get('note', '')}):"]
    for name, p in points.items():
        parts = []
        if p.get("N_MV") is not None:
            parts.append(f"N_MV {p['N_MV']:.2f} ({p['N_MV_details']['class']})")
        for key, label in (("sperling_lateral_Wz", "Wz lateral"),
                           ("sperling_vertical_Wz", "Wz vertical")):  # fmt: skip
            if p.get(key) is not None:
                parts.append(f"{label} {p[key]:.2f}")
        lines.append(f"  {name}: " + ", ".join(parts))
    return lines
