"""A vehicle's admissible speed and cant deficiency applied to a programme (issue 27: "the
vehicle's admissible speed and cant deficiency from the command line").

EN 14363:2016 runs the straight-track zone at the maximum test speed, 1.1 times the vehicle's
admissible speed (``MAX_TEST_SPEED_FACTOR``, the factor the shipped programmes' comments
state), no curve section above that speed (the curve zones' ``speed_max``), and the curve zones
at cant deficiencies up to the admissible one, evaluated at it (the two-dimensional
evaluation's limit conditions). :func:`admissible_overrides` turns the two
values into the programme's own ``--set`` items, so that the programme file stays the one
record of what was run and an explicit ``--set-programme`` of the user, applied after them,
still wins.
"""

from __future__ import annotations

import math

from railexu.assessment.acceptance.programme import Programme
from railexu.errors import InputError

#: the maximum test speed over the admissible speed (EN 14363:2016, test conditions of the
#: straight-track zone: V_adm + 10 %)
MAX_TEST_SPEED_FACTOR = 1.1
#: a section's speed is refused above this by the programme's checks [m/s]
MAX_SPEED_M_PER_S = 150.0
#: the largest admissible cant deficiency taken [m] (tilting trains reach about 0.3 m)
MAX_CANT_DEFICIENCY_M = 0.3


def admissible_overrides(
    programme: Programme,
    speed_m_per_s: float | None = None,
    cant_deficiency_m: float | None = None,
) -> tuple[str, ...]:
    """The ``dotted.key=value`` items of ``programme`` for an admissible speed [m/s] and an
    admissible cant deficiency [m] (either may be None: that one is left as the file has it).

    Every straight zone's ``speed`` and every curve zone's ``speed_max`` (the maximum test speed)
    become ``1.1 speed_m_per_s``; every curve zone spread over
    cant deficiency gets ``cant_deficiency_max`` and ``evaluate_at.cant_deficiency`` equal to
    ``cant_deficiency_m`` (a curve zone given by its speed is left as it is).

    Raises:
        InputError: a value that is not a finite positive number, a speed whose test speed
            exceeds 150 m/s, a cant deficiency above 0.3 m or below a zone's
            ``cant_deficiency_min`` (naming the zone and the key to lower).
    """
    items: list[str] = []
    if speed_m_per_s is not None:
        _check("admissible speed", speed_m_per_s, "m/s",
               MAX_SPEED_M_PER_S / MAX_TEST_SPEED_FACTOR)  # fmt: skip
        test_speed = MAX_TEST_SPEED_FACTOR * speed_m_per_s
        items += [f"zones.{z.name}.{'speed' if z.kind == 'straight' else 'speed_max'}="
                  f"{test_speed!r} m/s" for z in programme.zones]  # fmt: skip
    if cant_deficiency_m is not None:
        _check("admissible cant deficiency", cant_deficiency_m, "m", MAX_CANT_DEFICIENCY_M)
        for z in programme.zones:
            if z.kind != "curve" or z.cant_deficiency_m is None:
                continue
            if cant_deficiency_m < z.cant_deficiency_m[0]:
                raise InputError(
                    f"admissible cant deficiency {cant_deficiency_m * 1e3:g} mm is below zone "
                    f"{z.name!r}'s lowest section cant deficiency "
                    f"{z.cant_deficiency_m[0] * 1e3:g} mm: lower it with --set-programme "
                    f"zones.{z.name}.cant_deficiency_min=...",
                    source=programme.source, key=f"zones.{z.name}.cant_deficiency_min",
                )  # fmt: skip
            value = f"{cant_deficiency_m!r} m"
            items += [f"zones.{z.name}.cant_deficiency_max={value}",
                      f"zones.{z.name}.evaluate_at.cant_deficiency={value}"]  # fmt: skip
    return tuple(items)


def _check(what: str, value: float, unit: str, maximum: float) -> None:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputError(f"{what}: expected a number in {unit}, got {value!r}")
    if not (math.isfinite(value) and 0.0 < value <= maximum):
        raise InputError(f"{what} {value!r} {unit}: expected a finite number in (0, {maximum:g}] "
                         f"{unit}")  # fmt: skip
