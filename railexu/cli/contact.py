"""The ``railexu contact`` sub-command: a quasi-static wheel/rail check."""

from __future__ import annotations

import argparse

from .common import parse_range


def add_parser(sub) -> None:
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
    p.set_defaults(func=command)


def command(args: argparse.Namespace) -> int:
    from ..contact.check import ContactCheckSettings, contact_check
    from ..contact.evaluation import ContactParameters
    from ..report.contact_files import write_contact_check

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
