"""``railexu creep``: one contact from prescribed kinematics (called through add_parser)."""

from __future__ import annotations

import argparse

import pytest

from railexu.cli import creep
from railexu.cli.common import CliError


def _run(argv):
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers()
    creep.add_parser(sub)
    args = parser.parse_args(["creep", *argv])
    return args.func(args)


def test_conformal_case_from_curvatures(capsys):
    """CONTACT's ``conformal`` case 1 (tests/data/contact_validation): A, B, Q, creepages, spin.
    The default law's Fy is within 10 % of mu Q = 30 kN of the exact 25 920 N (measured 24 490)."""
    assert _run([
        "--load", "100000", "--curvatures", "0.76859", "0.98039", "--xi", "-0.004",
        "--eta", "-0.0098995", "--spin", "-1.5372", "--creep", "polach_fastsim",
    ]) == 0  # fmt: skip
    out = capsys.readouterr().out
    line = next(ln for ln in out.splitlines() if ln.startswith("polach_fastsim"))
    fy = float(line.split()[2])
    assert abs(fy - 25920.0) < 0.1 * 30000.0
    assert "Hertz: a = 7.84" in out  # Hertz's a for these curvatures (0.2 %: 4 digits printed)


def test_all_laws_and_semi_axes(capsys):
    assert _run(["--load", "82000", "--semi-axes", "0.008", "0.004", "--eta", "-0.000625",
                 "--spin", "0.625"]) == 0  # fmt: skip
    out = capsys.readouterr().out
    for law in ("kalker_linear", "polach", "polach_2005", "fastsim", "polach_fastsim"):
        assert law in out


def test_needs_exactly_one_ellipse_description():
    with pytest.raises(CliError, match="exactly one"):
        _run(["--load", "1000"])
