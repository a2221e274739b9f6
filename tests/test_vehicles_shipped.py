"""The shipped two-axle wagon (empty and loaded) and the extended coach of docs/vehicles.md.

Each is checked against data from outside the code: the published masses and axle loads
(exact), the static deflection of its suspension against the published spring characteristic
or the hand calculation F / k (2 %), the car body's bounce and pitch frequencies against
sqrt(k / m) from the suspension stiffnesses (5 %), the wagon's empty and loaded states against
each other; and each one builds and completes a short run. Reference numbers:
tests/data/shipped_vehicles.yaml.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg
import yaml

from railexu.inputs.catalog import shipped_names
from railexu.model.statics import static_equilibrium
from railexu.vehicle.vehicle import load_vehicle

DATA = yaml.safe_load(
    (Path(__file__).parent / "data" / "shipped_vehicles.yaml").read_text(encoding="utf-8")
)
WAGON = DATA["hbbins_tt_309"]
SPRING = DATA["parabolic_spring_225kN"]
COACH = DATA["manchester_vehicle_1"]
G = 9.81
NAMES = ("hbbins_empty", "hbbins_loaded", "manchester_coach_extended")
WAGON_BODY_KG = {"hbbins_empty": 13500.0, "hbbins_loaded": 42000.0}

# Tolerances (physical grounds):
#: static deflections: the statics shares the body's weight over the four springs exactly (a
#: symmetric vehicle); 2 % covers the rounding of the table's helper-contact point (0.01 %)
#: and the small load the wheelset's own spring seat and the contact stiffness take.
DEFLECTION_RTOL = 0.02
#: natural frequencies: the hand calculation takes the wheelsets (and the coach's bogie frames
#: for pitch) as rigid ground and ignores the coupling of pitch with the longitudinal motion
#: through the springs' height below the centre of gravity (2-3 % on these vehicles).
FREQUENCY_RTOL = 0.05


def axle_loads_N(vehicle) -> dict[str, float]:
    """Static load of each wheelset on the rails [N]: the sum of its two wheel loads in the
    statics, contact points 0.75 m from the centre (the tape circles)."""
    loads = static_equilibrium(vehicle, [0.75] * len(vehicle.wheelsets)).wheel_loads_N
    return {ws.name: float(loads[i].sum()) for i, ws in enumerate(vehicle.wheelsets)}


def two_stage_deflection_m(force_N: float) -> float:
    """Deflection of the two-stage parabolic spring under ``force_N`` from its published
    flexibilities: the main spring alone up to the helper contact, both stages above it."""
    contact = SPRING["helper_contact_N"]
    main, complete = SPRING["flexibility_main_m_per_N"], SPRING["flexibility_complete_m_per_N"]
    if force_N <= contact:
        return force_N * main
    return contact * main + (force_N - contact) * complete


def two_stage_stiffness_N_per_m(force_N: float) -> float:
    """Tangent stiffness of the two-stage spring at ``force_N`` (published flexibilities)."""
    if force_N <= SPRING["helper_contact_N"]:
        return 1.0 / SPRING["flexibility_main_m_per_N"]
    return 1.0 / SPRING["flexibility_complete_m_per_N"]


def body_modes_Hz(vehicle) -> dict[str, float]:
    """Bounce and pitch frequencies of the car body from the built model, linearised about its
    rest state (Exudyn's ``ComputeLinearizedSystem``; undamped: ``K v = w^2 M v``): the modes
    with the largest share of their kinetic energy in the body's vertical and pitch motion."""
    from railexu.model.assembly import VehicleModel
    from railexu.track.track import ideal_straight_track

    model = VehicleModel(vehicle, ideal_straight_track(), 1.0, 0.0, 10.0)
    M, K, _ = (np.asarray(a) for a in model.mbs.ComputeLinearizedSystem())
    w2, vectors = scipy.linalg.eig(K, M)
    mass = np.abs(np.diag(M))
    body = list(model.ltg["car_body"])
    best: dict[str, tuple[float, float]] = {}
    for lam, vec in zip(w2, vectors.T, strict=True):
        lam, vec = lam.real, vec.real
        if not 0.1 < lam < (2 * math.pi * 20.0) ** 2:
            continue
        energy = mass * vec[: mass.size] ** 2
        share = energy / energy.sum()
        for name, k in (("bounce", 2), ("pitch", 4)):
            if share[body[k]] > best.get(name, (0.0, 0.0))[0]:
                best[name] = (share[body[k]], math.sqrt(lam) / (2 * math.pi))
    return {name: f for name, (_, f) in best.items()}


def test_the_vehicles_ship_by_name():
    names = shipped_names("vehicle")
    for name in NAMES:
        assert name in names
        vehicle = load_vehicle(name)
        assert vehicle.sources, name
        for entry in (*vehicle.bodies, *vehicle.wheelsets):
            if name.startswith("hbbins"):
                assert entry.estimate, (name, entry.name)  # no public source gives them


@pytest.mark.parametrize("name", ["hbbins_empty", "hbbins_loaded"])
def test_wagon_masses_and_axle_loads_are_the_published_ones(name):
    """Tare 16.3 t; loaded to the maximum payload, 16.3 + 28.5 t (exact); two equal axle loads of
    half the weight (force balance), within the 22.5 t maximum; wheelbase and wheels as
    published."""
    vehicle = load_vehicle(name)
    total = WAGON["tare_kg"] + (WAGON["max_payload_kg"] if name.endswith("loaded") else 0)
    assert vehicle.total_mass_kg == total
    loads = axle_loads_N(vehicle)
    for ws in vehicle.wheelsets:
        assert loads[ws.name] == pytest.approx(total * G / 2, rel=1e-9)
        assert loads[ws.name] <= WAGON["max_axle_load_kg"] * G
        assert ws.axle_load_N == pytest.approx(total * G / 2, rel=1e-12)
        assert 2 * ws.nominal_radius_m == WAGON["wheel_diameter_m"]
    assert vehicle.wheelbases_m["car_body"] == WAGON["wheelbase_m"]


def test_coach_masses_and_axle_loads_are_the_benchmark_ones():
    vehicle = load_vehicle("manchester_coach_extended")
    total = COACH["body_mass_kg"] + 2 * COACH["bogie_mass_kg"] + 4 * COACH["wheelset_mass_kg"]
    assert vehicle.total_mass_kg == total
    for load in axle_loads_N(vehicle).values():
        assert load == pytest.approx(total * G / 4, rel=1e-9)


@pytest.mark.parametrize("name", ["hbbins_empty", "hbbins_loaded"])
def test_wagon_spring_deflection_is_the_published_characteristic(name):
    """Each parabolic spring carries a quarter of the body's weight; its static deflection is
    that of the published two-stage characteristic (1.68 mm/kN to the helper contact at 38.8 kN,
    0.55 mm/kN above): 55.6 mm empty, 100.5 mm loaded."""
    vehicle = load_vehicle(name)
    statics = static_equilibrium(vehicle, [0.75] * 2)
    weight_share = WAGON_BODY_KG[name] * G / 4
    springs = [el.name for el in vehicle.suspension if el.name.startswith("spring_")]
    assert len(springs) == 4
    for spring in springs:
        force = -statics.element_forces[spring][2]
        assert force == pytest.approx(weight_share, rel=1e-6)  # symmetric: a quarter each
        assert statics.static_deflections[spring] == pytest.approx(
            two_stage_deflection_m(weight_share), rel=DEFLECTION_RTOL
        )


def test_coach_static_deflections_are_force_over_stiffness():
    """Primary springs: body and frames over eight axleboxes, 45.65 kN / 1220 kN/m = 37.4 mm;
    air springs: the body over four, 78.48 kN / 430 kN/m = 182.5 mm."""
    vehicle = load_vehicle("manchester_coach_extended")
    statics = static_equilibrium(vehicle, [0.75] * 4)
    primary_force = (COACH["body_mass_kg"] + 2 * COACH["bogie_mass_kg"]) * G / 8
    air_force = COACH["body_mass_kg"] * G / 4
    checked = 0
    for el in vehicle.suspension:
        if el.name.startswith("primary_"):
            k, expected = COACH["primary_vertical_stiffness_N_per_m"], primary_force
        elif el.name.startswith("air_spring_"):
            k, expected = COACH["secondary_vertical_stiffness_N_per_m"], air_force
        else:
            continue
        deflection = -statics.element_forces[el.name][2] / k
        assert deflection == pytest.approx(expected / k, rel=DEFLECTION_RTOL), el.name
        checked += 1
    assert checked == 12


def hand_frequencies_Hz(name: str) -> dict[str, float]:
    """sqrt(k / m) / 2 pi of the car body on its suspension: bounce on the four corners' vertical
    stiffness, pitch on the same stiffness at the half wheelbase (or half bogie spacing)."""
    if name.startswith("hbbins"):
        m = WAGON_BODY_KG[name]
        vehicle = load_vehicle(name)
        pitch_inertia = vehicle.bodies[0].inertia_kg_m2[1]
        k = two_stage_stiffness_N_per_m(m * G / 4)
        a = WAGON["wheelbase_m"] / 2
    else:
        m, pitch_inertia = COACH["body_mass_kg"], COACH["body_pitch_inertia_kg_m2"]
        primary = 2 * COACH["primary_vertical_stiffness_N_per_m"]  # two axleboxes per side
        k = 1.0 / (1.0 / COACH["secondary_vertical_stiffness_N_per_m"] + 1.0 / primary)
        a = COACH["bogie_semi_spacing_m"]
    return {
        "bounce": math.sqrt(4 * k / m) / (2 * math.pi),
        "pitch": math.sqrt(4 * k * a**2 / pitch_inertia) / (2 * math.pi),
    }


@pytest.mark.parametrize("name", NAMES)
def test_body_bounce_and_pitch_frequencies_match_the_hand_calculation(name):
    model = body_modes_Hz(load_vehicle(name))
    hand = hand_frequencies_Hz(name)
    for mode in ("bounce", "pitch"):
        assert model[mode] == pytest.approx(hand[mode], rel=FREQUENCY_RTOL), mode


def test_wagon_empty_and_loaded_differ_only_in_body_and_operating_point():
    """The loaded file is the empty one with the payload on the car body: the same wheelsets,
    spring tables, links and stops; 28.5 t more; the springs 44.9 mm further down (published
    characteristic); and nearly the same bounce frequency (the helper stage's purpose)."""
    empty, loaded = load_vehicle("hbbins_empty"), load_vehicle("hbbins_loaded")
    assert loaded.total_mass_kg - empty.total_mass_kg == WAGON["max_payload_kg"]
    for a, b in zip(empty.wheelsets, loaded.wheelsets, strict=True):
        assert (a.mass_kg, a.inertia_kg_m2, a.position_m) == (b.mass_kg, b.inertia_kg_m2,
                                                              b.position_m)  # fmt: skip
    for a, b in zip(empty.suspension, loaded.suspension, strict=True):
        if a.name.startswith("spring_"):
            assert (a.deflection_m, a.force_N) == (b.deflection_m, b.force_N)
        else:
            assert a == b, a.name
    d_empty = static_equilibrium(empty, [0.75] * 2).static_deflections["spring_ws1_left"]
    d_loaded = static_equilibrium(loaded, [0.75] * 2).static_deflections["spring_ws1_left"]
    hand = two_stage_deflection_m(42000 * G / 4) - two_stage_deflection_m(13500 * G / 4)
    assert d_loaded - d_empty == pytest.approx(hand, rel=DEFLECTION_RTOL)
    f_empty = hand_frequencies_Hz("hbbins_empty")["bounce"]
    f_loaded = hand_frequencies_Hz("hbbins_loaded")["bounce"]
    assert f_loaded / f_empty == pytest.approx(1.0, abs=0.02)


@pytest.mark.parametrize("name", NAMES)
def test_short_run_on_straight_track(name):
    """10 m at 10 m/s from the seed's 2 mm offset: the run completes, no flange contact, the
    wheel loads stay near their static values."""
    from railexu.results.run import RunSettings, run

    vehicle = load_vehicle(name)
    result = run(vehicle, settings=RunSettings(speed_m_per_s=10.0, distance_m=10.0))
    assert result.status["state"] == "completed", result.status
    ts = result.timeseries
    static = axle_loads_N(vehicle)
    for i, ws in enumerate(vehicle.wheelsets):
        lateral = ts[f"ws{i + 1}_lateral_m"]
        assert np.max(np.abs(lateral)) < 4e-3  # no flange contact (flangeway about 8 mm)
        q = ts[f"ws{i + 1}_left_Q_N"] + ts[f"ws{i + 1}_right_Q_N"]
        # the axle load oscillates about its static value by less than 10 %
        assert np.mean(q) == pytest.approx(static[ws.name], rel=0.1)
