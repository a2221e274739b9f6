"""The ``railexu creep`` sub-command: one contact from prescribed kinematics, every creep law.

The check engineers run to compare creep laws: given the contact ellipse (semi-axes, or the
curvature sums ``A, B`` of the gap ``A x^2 + B y^2`` and the normal load, from which Hertz gives
the ellipse), the creepages and the spin, print the tangential forces and the spin moment on the
wheel (docs/conventions.md) of each law.
"""

from __future__ import annotations

import argparse
import math

from railexu.cli.common import CliError, check_option, quantity
from railexu.errors import ComputationError


def _cell(value: float, width: int, decimals: int) -> str:
    """``value`` in ``width`` characters: fixed point, or scientific if that does not fit."""
    text = f"{value:{width}.{decimals}f}"
    return text if text.startswith(" ") else f"{value:{width}.3e}"


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "creep",
        help="creep forces of one contact from given ellipse, load, creepages and spin",
        description=(
            "Evaluate one wheel-rail contact with prescribed kinematics and print the creep "
            "forces and spin moment on the wheel for each creep law. Give the ellipse by its "
            "semi-axes (--semi-axes A_M B_M) or by the curvature sums of the gap "
            "(--curvatures A_PER_M B_PER_M, Hertz)."
        ),
    )
    p.add_argument("--load", type=quantity("N"), required=True, help="normal force Q [N]")
    p.add_argument("--semi-axes", nargs=2, type=quantity("m"), metavar=("A_M", "B_M"), default=None,
                   help="semi-axes a (rolling direction) and b [m]")  # fmt: skip
    p.add_argument(
        "--curvatures",
        nargs=2,
        type=quantity("1/m"),
        metavar=("A", "B"),
        default=None,
        help="gap curvature sums A, B of A x^2 + B y^2 [1/m] (Hertz)",
    )
    p.add_argument("--xi", type=quantity("1"), default=0.0, help="longitudinal creepage [-]")
    p.add_argument("--eta", type=quantity("1"), default=0.0, help="lateral creepage [-]")
    p.add_argument("--spin", type=quantity("1/m"), default=0.0, help="spin creepage [1/m]")
    p.add_argument("--friction", type=quantity("1"), default=0.3,
                   help="friction coefficient [-]")  # fmt: skip
    p.add_argument(
        "--shear-modulus", type=quantity("Pa"), default=82e9, help="shear modulus G [Pa]"
    )
    p.add_argument("--poisson", type=quantity("1"), default=0.28, help="Poisson's ratio [-]")
    p.add_argument(
        "--speed", type=quantity("m/s"), default=10.0, help="speed [m/s] (polach_2005 only)"
    )
    p.add_argument("--creep", default="all", help="a creep law, or 'all' (default)")
    p.set_defaults(func=command)
    return p


def command(args: argparse.Namespace) -> int:
    from railexu.contact.creep import creep_forces, spin_blend_weight, spin_moment
    from railexu.contact.hertz import hertz_contact
    from railexu.contact.kalker import kalker_coefficients
    from railexu.contact.parameters import CREEP_MODELS, ContactParameters, creep_model_code

    for option in ("--load", "--xi", "--eta", "--spin", "--friction", "--poisson"):
        check_option(option, getattr(args, option[2:]))
    check_option("--shear-modulus", args.shear_modulus)
    check_option("--speed", args.speed)
    params = ContactParameters(
        shear_modulus_Pa=args.shear_modulus, poisson=args.poisson, friction=args.friction
    )
    if (args.semi_axes is None) == (args.curvatures is None):
        raise CliError("give exactly one of --semi-axes A_M B_M or --curvatures A B")
    if args.semi_axes is not None:
        a, b = (check_option("--semi-axes", v) for v in args.semi_axes)
    else:
        ca, cb = (check_option("--curvatures", v) for v in args.curvatures)
        h = hertz_contact(ca, cb, args.load, params.effective_modulus_Pa)
        a, b = h.a_m, h.b_m
        print(f"Hertz: a = {a * 1e3:.4f} mm, b = {b * 1e3:.4f} mm, p0 = {h.p0_Pa / 1e6:.1f} MPa")
    check_option("a/b", a / b)
    laws = CREEP_MODELS if args.creep == "all" else (CREEP_MODELS[creep_model_code(args.creep)],)
    g = params.shear_modulus_Pa
    c11, c22, c23 = kalker_coefficients(a / b, params.poisson)
    mu_q = params.friction * args.load
    weight = spin_blend_weight(args.spin, args.load, params.friction, a, b, g, c23)
    print(
        f"a/b = {a / b:.4f}, c11 = {c11:.4f}, c22 = {c22:.4f}, c23 = {c23:.4f}, "
        f"mu Q = {mu_q:.1f} N, FASTSIM weight of polach_fastsim = {weight:.3f}"
    )
    print(f"{'law':<16}{'Fx [N]':>12}{'Fy [N]':>12}{'Mz [N m]':>12}{'|F|/muQ':>10}")
    for law in laws:
        fx, fy = creep_forces(
            law, args.xi, args.eta, args.spin, args.load, a, b, g, c11, c22, c23,
            params.friction, args.speed,
        )  # fmt: skip
        mz = spin_moment(
            law, args.xi, args.eta, args.spin, args.load, a, b, g, c11, c22, c23, params.friction
        )
        ratio = (fx * fx + fy * fy) ** 0.5 / mu_q if mu_q > 0.0 else float("nan")
        if not all(math.isfinite(v) for v in (fx, fy, mz)):
            raise ComputationError(f"creep law {law}: no finite force for these inputs")
        print(f"{law:<16}{_cell(fx, 12, 1)}{_cell(fy, 12, 1)}{_cell(mz, 12, 3)}{ratio:10.3f}")
    return 0
