"""Acceptance programme files (railexu.assessment.acceptance.programme): the shipped files load,
each section's conditions follow EN 13803's relation ``V^2 = g R (I + D) / b`` (checked by hand
with b = 1.5 m, g = 9.81 m/s^2), the track quality reaches its targets in the band, and bad
files are refused naming the file, the line and the key."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import pytest

from railexu.assessment.acceptance.programme import load_programme
from railexu.errors import InputError
from railexu.inputs.catalog import find_input, shipped_names
from railexu.track.irregularities import get_spectrum

SHIPPED = ("freight_wagon", "locomotive", "coach")
MINIMAL = """\
format_version: 1
name: test programme
category: wagon
statistics: {k_safety: 2.2, k_ride: 3.0, prediction_quantile: 0.95}
zones:
  straight:
    kind: straight
    speed: 100 km/h
    n_sections: 3
    min_sections: 3
    section_length: 100 m
    method: one_dimensional
    track_quality: {level: QN1, alignment_sd_min: 0.7 mm, alignment_sd_max: 1.2 mm,
                    level_sd_min: 1.0 mm, level_sd_max: 1.6 mm}
  curves:
    kind: curve
    radius_min: 300 m
    radius_max: 500 m
    cant: 150 mm
    cant_deficiency_min: 50 mm
    cant_deficiency_max: 130 mm
    n_sections: 6
    min_sections: 5
    section_length: 70 m
    method: two_dimensional
    regressors: [cant_deficiency, curvature]
    evaluate_at: {cant_deficiency: 130 mm, radius: 300 m}
    track_quality: {level: QN2, alignment_sd_min: 1.0 mm, alignment_sd_max: 1.0 mm,
                    level_sd_min: 2.0 mm, level_sd_max: 2.0 mm}
"""


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "programme.yaml"
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


@pytest.mark.parametrize("name", SHIPPED)
def test_the_shipped_programmes_load_with_sections_of_every_zone(name):
    programme = load_programme(name)
    assert name in shipped_names("programme")
    assert programme.category in ("wagon", "locomotive", "coach") and not programme.quick
    kinds = {z.kind for z in programme.zones}
    assert kinds == {"straight", "curve"}
    for zone in programme.zones:
        sections = zone.sections()
        assert len(sections) == zone.n_sections >= zone.min_sections
        assert len({s.seed for s in sections}) == len(sections)
    quick = load_programme(name, quick=True)
    assert all(z.reduced and z.n_sections <= 4 for z in quick.zones)


def test_curve_sections_follow_the_cant_deficiency_relation(tmp_path):
    zone = load_programme(_write(tmp_path, MINIMAL)).zone("curves")
    sections = zone.sections()
    radii = [s.radius_m for s in sections]
    assert radii == pytest.approx([300, 340, 380, 420, 460, 500])  # even steps of 40 m
    for s in sections:
        assert 0.05 <= s.cant_deficiency_m <= 0.13
        # EN 13803: V^2 = g R (I + D) / b with b = 1.5 m
        assert s.speed_m_per_s**2 == pytest.approx(
            9.81 * s.radius_m * (s.cant_deficiency_m + 0.15) / 1.5
        )
    # section 0 at the fraction 0.5 of the range: 50 + 0.5 x 80 = 90 mm
    assert sections[0].cant_deficiency_m == pytest.approx(0.09)
    assert [s.direction for s in sections[:2]] == ["left", "right"]
    # cant deficiency and curvature are not collinear (the regression has a spread)
    cds = [s.cant_deficiency_m for s in sections]
    assert abs(_correlation(cds, [1 / r for r in radii])) < 0.9


def _correlation(a, b) -> float:
    n = len(a)
    ma, mb = sum(a) / n, sum(b) / n
    cov = sum((x - ma) * (y - mb) for x, y in zip(a, b, strict=True))
    return cov / math.sqrt(sum((x - ma) ** 2 for x in a) * sum((y - mb) ** 2 for y in b))


def test_track_quality_reaches_both_targets_in_the_band(tmp_path):
    section = load_programme(_write(tmp_path, MINIMAL)).zone("curves").sections()[0]
    spectrum = get_spectrum("german_low")
    rms_a, rms_v = spectrum.band_rms("lateral", 3, 25), spectrum.band_rms("vertical", 3, 25)
    scale = max(1.0e-3 / rms_a, 2.0e-3 / rms_v)  # targets 1.0 mm alignment, 2.0 mm level
    assert section.irregularities == {
        "type": "spectrum",
        "spectrum": "german_low",
        "seed": 1,
        "amplitude_scale": pytest.approx(scale),
    }
    assert section.quality["level_sd_achieved_m"] == pytest.approx(2.0e-3)  # the binding one
    assert section.quality["alignment_sd_achieved_m"] >= 1.0e-3


def test_overrides_and_the_quick_variant(tmp_path):
    path = _write(tmp_path, MINIMAL)
    programme = load_programme(path, overrides=["zones.straight.speed=80 km/h"])
    assert programme.zone("straight").sections()[0].speed_m_per_s == pytest.approx(80 / 3.6)
    quick = load_programme(path, quick=True)
    assert quick.zone("curves").n_sections == 4  # 3 coefficients + 1
    assert quick.zone("curves").min_sections == 4 and quick.zone("curves").reduced


@pytest.mark.parametrize(
    ("change", "message", "where"),
    [
        (("    speed: 100 km/h\n", "    sped: 100 km/h\n"), "unknown key", "zones.straight.sped"),
        (("    speed: 100 km/h\n", "    speed: .nan\n"), "finite", "zones.straight.speed"),
        (("    radius_min: 300 m\n", ""), "radius_min", "zones.curves"),
        (("    min_sections: 5\n", "    min_sections: 3\n"), "at least 4 sections",
         "zones.curves.min_sections"),
        (("    cant_deficiency_max: 130 mm\n", "    cant_deficiency_max: 30 mm\n"),
         "cant_deficiency_min", "zones.curves.cant_deficiency_max"),
        (("category: wagon", "category: tram"), "not one of", "category"),
        (("    method: one_dimensional\n", "    method: two_dimensional\n"),
         "straight zone", "zones.straight"),
        (("    n_sections: 6\n", "    n_sections: 4\n"), "min_sections", "zones.curves"),
        (("prediction_quantile: 0.95}", "prediction_quantile: 0.95, stability_method: normall}"),
         "not one of", "statistics.stability_method"),
    ],
)  # fmt: skip
def test_bad_files_are_refused_naming_file_line_and_key(tmp_path, change, message, where):
    path = _write(tmp_path, MINIMAL.replace(*change, 1))
    with pytest.raises(InputError, match=message) as info:
        load_programme(path)
    assert str(path) in str(info.value) and where in str(info.value)
    assert info.value.line is not None


def test_limits_set_by_the_programme_carry_their_unit_and_note(tmp_path):
    text = MINIMAL.replace(
        "statistics:", "limits:\n  Y_qst: {value: 55 kN, note: national rule}\nstatistics:"
    )
    programme = load_programme(_write(tmp_path, text))
    assert programme.limits == {"Y_qst": (55e3, "national rule")}
    bad = MINIMAL.replace("statistics:", "limits:\n  Y_max: {value: 1, note: x}\nstatistics:")
    with pytest.raises(InputError, match="unknown quantity 'Y_max'"):
        load_programme(_write(tmp_path, bad))


def test_names_and_missing_files():
    assert find_input("programme", "coach").name == "coach.yaml"
    with pytest.raises(InputError, match="no file or shipped programme named 'wagon'"):
        load_programme("wagon")
    with pytest.raises(InputError, match="file not found"):
        load_programme("missing/programme.yaml")
