"""The ``railexu contact`` command: the Manchester benchmark settings run end to end."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from railexu.cli import CliError, main, parse_range

MANCHESTER = [
    "contact", "--wheel", "S1002", "--rail", "UIC60", "--inclination", "1:40",
    "--gauge", "1.435", "--flange-back", "1.360", "--radius", "0.46",
    "--lateral", "0:0.010:0.0005", "--yaw-per-lateral", "2.4", "--load", "10000",
    "--speed", "2", "--friction", "0.3", "--shear-modulus", "82e9", "--poisson", "0.28",
    "--creep", "polach",
]  # fmt: skip

REQUIRED = [
    "lateral_m",
    "yaw_rad",
    "roll_rad",
    "side",
    "point",
    "wheel_lateral_m",
    "rail_lateral_m",
    "rolling_radius_m",
    "contact_angle_rad",
    "normal_force_N",
    "a_m",
    "b_m",
    "creep_long",
    "creep_lat",
    "spin_per_m",
    "force_long_N",
    "force_lat_N",
]


def test_manchester_benchmark_runs(tmp_path, capsys):
    out = tmp_path / "mb"
    assert main([*MANCHESTER, "--out", str(out)]) == 0
    assert "equivalent conicity at 3 mm" in capsys.readouterr().out
    with (out / "contact.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert set(REQUIRED) <= set(rows[0])
    laterals = sorted({float(r["lateral_m"]) for r in rows})
    assert len(laterals) == 21 and laterals[-1] == pytest.approx(0.010)
    for y in laterals:
        for side in ("left", "right"):
            pts = [r for r in rows if float(r["lateral_m"]) == y and r["side"] == side]
            assert pts, f"no contact on the {side} wheel at y = {y}"
            # each wheel carries its load (vertical force of all its points)
            assert sum(float(r["force_z_track_N"]) for r in pts) == pytest.approx(10000.0, abs=0.1)
            assert {int(r["point"]) for r in pts} == set(range(1, len(pts) + 1))
            # yaw = 2.4 rad/m x lateral
            assert float(pts[0]["yaw_rad"]) == pytest.approx(2.4 * y, abs=1e-12)
    # flange contact on the left wheel at the largest displacement (y > 0 is to the left)
    last = [r for r in rows if float(r["lateral_m"]) == laterals[-1] and r["side"] == "left"]
    assert max(np.degrees(float(r["contact_angle_rad"])) for r in last) > 40.0
    conicity = np.loadtxt(out / "conicity.csv", delimiter=",", skiprows=1)
    assert conicity.shape == (20, 2) and np.all(conicity[:, 1] > 0.0)
    for stem in ("contact_points", "delta_r", "contact_angle", "conicity"):
        assert (out / f"{stem}.png").stat().st_size > 1000
        assert (out / f"{stem}.svg").stat().st_size > 1000


def test_unknown_profile_gives_clear_error(tmp_path, capsys):
    status = main(["contact", "--wheel", "S1020", "--out", str(tmp_path)])
    assert status == 2
    err = capsys.readouterr().err
    assert "unknown wheel profile 'S1020'" in err and "S1002" in err


def test_unknown_creep_law_gives_did_you_mean(tmp_path, capsys):
    status = main(["contact", "--creep", "polac", "--lateral", "0", "--out", str(tmp_path)])
    assert status == 2
    assert "polach" in capsys.readouterr().err


def test_parse_range():
    assert parse_range("0:0.010:0.0005")[-1] == pytest.approx(0.010)
    assert len(parse_range("0:0.010:0.0005")) == 21
    assert parse_range("0.001,0.002") == (0.001, 0.002)
    with pytest.raises(CliError, match="FROM:TO:STEP"):
        parse_range("0:1")
    with pytest.raises(CliError):
        parse_range("a:b:c")
