"""The ``railexu contact`` sub-command: a quasi-static wheel/rail check."""

from __future__ import annotations

import argparse
import math

from railexu.cli.common import CliError, check_option, parse_range, quantity
from railexu.contact.standard_gauge import STANDARD_FLANGE_BACK_M, STANDARD_GAUGE_M
from railexu.errors import ComputationError

#: Largest sweep (lateral positions, amplitudes) the command accepts.
MAX_SWEEP_POINTS = 10001
#: Largest lateral displacement of the check [m]: a rail head is about 70 mm wide, so 100 mm
#: off the centre line a wheel is off its rail.
MAX_LATERAL_M = 0.1
#: Largest conicity amplitude [m]: EN 15302 evaluates up to the flangeway clearance, a few
#: millimetres; 50 mm is far beyond any flange contact.
MAX_AMPLITUDE_M = 0.05


def checked_range(text: str, name: str) -> tuple[float, ...]:
    """:func:`parse_range` after checking the number of values, before anything is allocated.

    Raises:
        CliError: ``FROM:TO:STEP`` with more than :data:`MAX_SWEEP_POINTS` values (e.g.
            ``0:1:1e-18``) or a non-finite number.
    """
    parts = text.strip().split(":")
    if len(parts) == 3:
        try:
            start, stop, step = (float(p) for p in parts)
        except ValueError as exc:
            raise CliError(f"{name} {text!r}: expected numbers as FROM:TO:STEP") from exc
        if not all(math.isfinite(v) for v in (start, stop, step)):
            raise CliError(f"{name} {text!r}: FROM, TO and STEP must be finite numbers")
        if step > 0 and stop >= start:
            count = math.floor((stop - start) / step + 0.5) + 1
            if count > MAX_SWEEP_POINTS:
                raise CliError(
                    f"{name} {text!r}: {count:.3g} values, at most {MAX_SWEEP_POINTS} allowed; "
                    "use a larger STEP"
                )
    elif text.count(",") >= MAX_SWEEP_POINTS:
        raise CliError(f"{name}: more than {MAX_SWEEP_POINTS} values")
    return parse_range(text, name)


def add_parser(sub) -> argparse.ArgumentParser:
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
    p.add_argument(
        "--wheel", default="S1002", help="wheel profile of both wheels: built-in or file"
    )
    p.add_argument("--wheel-left", default=None, help="left wheel profile (overrides --wheel)")
    p.add_argument("--wheel-right", default=None, help="right wheel profile (overrides --wheel)")
    p.add_argument("--rail", default="UIC60", help="built-in rail profile or file (.prr, y-z)")
    p.add_argument("--inclination", default="1:40", help="rail inclination: 1:40, 1:20 or none")
    p.add_argument(
        "--gauge",
        type=quantity("m"),
        default=STANDARD_GAUGE_M,
        help="track gauge [m] (14 mm below top)",
    )
    p.add_argument(
        "--flange-back",
        type=quantity("m"),
        default=STANDARD_FLANGE_BACK_M,
        help="flange-back distance [m]",
    )
    p.add_argument("--radius", type=quantity("m"), default=0.46, help="nominal rolling radius [m]")
    p.add_argument("--radius-left", type=quantity("m"), default=None, help="left wheel radius [m]")
    p.add_argument(
        "--radius-right", type=quantity("m"), default=None, help="right wheel radius [m]"
    )
    p.add_argument(
        "--normal",
        choices=("hertz", "kik_piotrowski"),
        default="hertz",
        help="hertz (default), or kik_piotrowski: its non-Hertzian patch and creep forces "
        "reported beside Hertz at each pressed contact point (kp_* columns)",
    )
    p.add_argument(
        "--rolling",
        choices=("free", "nominal"),
        default="free",
        help="free: pitch rate with zero pitch moment (default); nominal: speed / radius",
    )
    p.add_argument(
        "--lateral", default="0:0.010:0.0005", help="lateral displacements FROM:TO:STEP [m]"
    )
    p.add_argument(
        "--yaw-per-lateral",
        type=quantity("rad/m"),
        default=0.0,
        help="yaw = factor x lateral [rad/m]",
    )
    p.add_argument(
        "--load", type=quantity("N"), default=10000.0, help="vertical load per wheel [N]"
    )
    p.add_argument("--speed", type=quantity("m/s"), default=2.0, help="forward speed [m/s]")
    p.add_argument("--friction", type=quantity("1"), default=0.3, help="friction coefficient [-]")
    p.add_argument(
        "--shear-modulus", type=quantity("Pa"), default=82e9, help="shear modulus G [Pa]"
    )
    p.add_argument("--poisson", type=quantity("1"), default=0.28, help="Poisson's ratio [-]")
    p.add_argument(
        "--creep",
        default="polach_fastsim",
        help="creep law: polach_fastsim (default), polach, polach_2005, kalker_linear, fastsim",
    )
    p.add_argument(
        "--amplitudes",
        default="0.0005:0.010:0.0005",
        help="amplitudes for the equivalent conicity FROM:TO:STEP [m]",
    )
    p.add_argument("--out", required=True, help="output folder")
    p.set_defaults(func=command)
    return p


def _check_options(args: argparse.Namespace) -> None:
    """Every quantity option within its range (:data:`railexu.cli.common.LIMITS`)."""
    for option in ("--gauge", "--flange-back", "--radius", "--yaw-per-lateral", "--load",
                   "--speed", "--friction", "--poisson", "--shear-modulus"):  # fmt: skip
        check_option(option, getattr(args, option[2:].replace("-", "_")))
    for side in ("left", "right"):
        radius = getattr(args, f"radius_{side}")
        if radius is not None:
            check_option("--radius", radius)
    _check_inclination(args.inclination)
    if not args.flange_back < args.gauge:
        raise CliError(
            f"--flange-back {args.flange_back:g} m: must be less than --gauge {args.gauge:g} m"
        )


def _check_inclination(text: str) -> float:
    """The rail inclination as an angle, refused unless finite and within 0 .. 1:10 (the
    range of track files, ``railexu.track.schema.MAX_INCLINATION_RAD``)."""
    from railexu.contact.placement import PlacementError, parse_inclination
    from railexu.track.schema import MAX_INCLINATION_RAD

    try:
        angle = parse_inclination(text)
    except PlacementError as exc:
        raise CliError(f"--inclination: {exc}") from None
    if not (math.isfinite(angle) and 0.0 <= angle <= MAX_INCLINATION_RAD):
        raise CliError(
            f"--inclination {text!r}: {angle:g} rad, expected 0 .. "
            f"{MAX_INCLINATION_RAD:g} rad ('none' .. '1:10'; usual: 1:20, 1:40)"
        )
    return angle


def _check_sweep(
    values: tuple[float, ...], option: str, low: float, high: float, why: str
) -> tuple[float, ...]:
    """Every value of a sweep within ``low`` (exclusive if 0) .. ``high`` [m]."""
    for v in values:
        if not (low <= v <= high) or (low == 0.0 and v == 0.0):
            raise CliError(
                f"{option} {v:g} m: expected {'> 0' if low == 0.0 else f'>= {low:g}'}"
                f" and <= {high:g} m ({why})"
            )
    return values


def command(args: argparse.Namespace) -> int:
    import warnings

    from railexu.contact.check import ContactCheckSettings, contact_check
    from railexu.contact.parameters import ContactParameters
    from railexu.report.contact_files import write_contact_check

    _check_options(args)

    params = ContactParameters(
        shear_modulus_Pa=args.shear_modulus,
        poisson=args.poisson,
        friction=args.friction,
        creep_model=args.creep,
    )
    lateral = _check_sweep(checked_range(args.lateral, "--lateral"), "--lateral",
                           -MAX_LATERAL_M, MAX_LATERAL_M, "100 mm off centre a wheel is off "
                           "its rail")  # fmt: skip
    amplitudes = _check_sweep(checked_range(args.amplitudes, "--amplitudes"), "--amplitudes",
                              0.0, MAX_AMPLITUDE_M, "EN 15302 amplitudes are a few mm, up to "
                              "the flangeway clearance")  # fmt: skip
    wheel_left = args.wheel_left or args.wheel
    wheel_right = args.wheel_right or args.wheel
    radius_left = args.radius if args.radius_left is None else args.radius_left
    radius_right = args.radius if args.radius_right is None else args.radius_right
    settings = ContactCheckSettings(
        wheel=wheel_left,
        wheel_right=None if wheel_right == wheel_left else wheel_right,
        rail=args.rail,
        inclination=args.inclination,
        gauge_m=args.gauge,
        flange_back_m=args.flange_back,
        radius_m=radius_left,
        radius_right_m=None if radius_right == radius_left else radius_right,
        rolling=args.rolling,
        normal_model=args.normal,
        lateral_m=lateral,
        yaw_per_lateral_rad_per_m=args.yaw_per_lateral,
        load_N=args.load,
        speed_m_per_s=args.speed,
        contact=params,
        conicity_amplitudes_m=amplitudes,
    )
    with warnings.catch_warnings():  # the skipped positions are reported below, once each
        warnings.simplefilter("ignore", RuntimeWarning)
        result = contact_check(settings)
        if not result.pressed:
            first_y, first = result.failures[0]
            raise ComputationError(
                f"every lateral position ({len(result.failures)}) was skipped, "
                f"no results written; at {first_y * 1e3:.3f} mm: {first} (check the gauge, "
                "flange-back distance, profiles and --lateral)"
            )
        written = write_contact_check(result, args.out)
    n_two = sum(
        1
        for p in result.pressed
        for side in ("left", "right")
        if sum(q.loaded for q in p.result.wheel(side)) >= 2
    )
    n_points = sum(1 for r in result.rows if r["status"] == "ok")
    print(
        f"railexu contact: {len(result.pressed)} lateral positions, {n_points} loaded "
        f"contact points ({n_two} wheel states with two-point contact), {args.rolling} rolling"
    )
    print(
        f"  equilibrium lateral position (Delta r = 0): {result.equilibrium_lateral_m * 1e3:.3f} mm"
    )
    for y, message in result.failures:
        print(f"  warning: lateral position {y * 1e3:.3f} mm failed: {message}")
    for a, c in zip(result.conicity_amplitude_m, result.conicity, strict=True):
        if abs(a * 1e3 - 3.0) < 1e-9:
            print(f"  equivalent conicity at 3 mm amplitude: {c:.4f}")
    print(f"  wrote {len(written)} files to {args.out}")
    return 0
