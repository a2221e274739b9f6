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


def test_absurd_sweep_is_refused_before_allocating(tmp_path, capsys):
    """0:1:1e-18 would be 1e18 positions: refused at once with a clear message."""
    status = main(["contact", "--lateral", "0:1:1e-18", "--out", str(tmp_path / "x")])
    assert status == 2
    assert "at most" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_asymmetric_wheel_radii_equilibrium_off_centre(tmp_path, capsys):
    """Wheels of 920 and 918 mm (EN 15302's E5-E8 set-up): Delta r = 0 is off the track centre,
    the conicity is computed about it, and contact.csv has the pitch rate and spin moment."""
    out = tmp_path / "asym"
    status = main([
        "contact", "--radius-left", "0.46", "--radius-right", "0.459", "--lateral", "0:0.002:0.001",
        "--amplitudes", "0.002:0.004:0.001", "--out", str(out),
    ])  # fmt: skip
    assert status == 0
    printed = capsys.readouterr().out
    y_eq = float(printed.split("equilibrium lateral position (Delta r = 0): ")[1].split()[0])
    assert y_eq < -0.5  # mm: the larger left wheel pulls the equilibrium to the right (y < 0)
    with (out / "contact.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert {"pitch_rate_rad_per_s", "spin_moment_Nm", "status"} <= set(rows[0])
    assert all(r["status"] == "ok" for r in rows)
    conicity = np.loadtxt(out / "conicity.csv", delimiter=",", skiprows=1)
    assert np.all(np.isfinite(conicity[:, 1])) and np.all(conicity[:, 1] > 0.0)
    dr = np.loadtxt(out / "delta_r.csv", delimiter=",", skiprows=1)
    # the left wheel is 1 mm larger: Delta r(0) = 1 mm plus the change of the contact points
    # with the roll this asks for (measured 1.54 mm), so the equilibrium is at y < 0
    assert 0.001 < np.interp(0.0, dr[:, 0], dr[:, 1]) < 0.002
    assert dr[0, 0] < -0.004


def test_kik_piotrowski_columns(tmp_path):
    """--normal kik_piotrowski adds the non-Hertzian patch beside Hertz: at 3 mm (one tread
    point per wheel) its normal force is within 7 % of the Hertz force it is pressed with (the
    model's bias against exact theory is +5 %, tests/test_contact_kik_piotrowski.py)."""
    out = tmp_path / "kp"
    assert main(["contact", "--lateral", "0.003", "--amplitudes", "0.002", "--normal",
                 "kik_piotrowski", "--out", str(out)]) == 0  # fmt: skip
    with (out / "contact.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    for r in rows:
        kp = float(r["kp_normal_force_N"])
        assert kp == pytest.approx(float(r["normal_force_N"]), rel=0.07)
        assert float(r["kp_p_max_Pa"]) > 0.0 and float(r["kp_width_m"]) > 0.0
