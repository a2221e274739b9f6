"""What a vehicle file of format 1 meant where the current format means something else.

A format-1 file is either read exactly as railexu read it then, or refused with the key, what
it meant in format 1 and what to write now (``docs/vehicle-format.md``, "Format versions"):

- ``contact.creep_model`` absent meant Polach (1999) with spin, ``polach`` (the default became
  ``polach_fastsim`` with format 2): such a file is read with ``creep: polach``, as before;
- ``category`` did not exist (until issue 26 a missing one silently meant ``locomotive``, whose
  EN 14363 limits differ from a wagon's): refused, the file must name it;
- the height (``position`` z) of a suspension element's point on a wheelset was ignored: the
  element acted on the axle's centre line. Since issue 26 a point above or below the axle is on
  the axlebox and its moment passes into the axle (``docs/suspension.md``, "Elements at a
  wheelset"): a format-1 element at a wheelset whose height is not the axle's is refused.

The contact keys renamed by format 2 (``creep_model``, ``polach_2005``, ``damping_model``,
``normal_damping``) are translated by :mod:`railexu.vehicle.vehicle`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from railexu.inputs import Section
from railexu.vehicle.parts import Wheelset
from railexu.vehicle.schema import CATEGORIES

#: The creep law of a format-1 file without ``contact.creep_model`` (format 1's default).
FORMAT_1_CREEP_MODEL = "polach"
#: A point closer than this to a wheelset's axle height is on the axle [m]; the model's
#: ``railexu.model.assembly.AXLE_HEIGHT_TOLERANCE_M``, which this layer cannot import.
AXLE_HEIGHT_TOLERANCE_M = 1.0e-6


def format_1_contact_defaults(data: dict) -> dict:
    """``data`` with format 1's default creep law written out where the file names none."""
    contact = data.get("contact")
    if contact is None:
        contact = {}
    if not isinstance(contact, dict) or "creep_model" in contact or "creep" in contact:
        return data
    return {**data, "contact": {**contact, "creep": {"model": FORMAT_1_CREEP_MODEL}}}


def check_format_1_category(top: Section) -> None:
    """Refuse a format-1 file without ``category`` with what it meant and what to write."""
    if "category" not in top.data:
        top.fail(
            "missing key 'category': format 1 had none and railexu took every vehicle for a "
            "locomotive until issue 26 (EN 14363 limits depend on it); write 'category: "
            f"locomotive' to keep that, or the right one of {', '.join(CATEGORIES)}"
        )


def check_format_1_elements(top: Section, wheelsets: Sequence[Wheelset]) -> None:
    """Refuse a format-1 element whose point on a wheelset is not at the axle's height.

    Format 1 applied such an element at the axle's centre line whatever height the file gave;
    now the point is on the axlebox at that height and the force's moment about the axle's
    centre passes into the axle, which changes the wheel-load transfer in curves.
    """
    radius = {w.name: w.nominal_radius_m for w in wheelsets}
    for name, raw in top.items("suspension", False):
        if not isinstance(raw, dict):
            continue
        sec = top.child("suspension", name)
        on_axle = [b for b in _bodies(raw) if b in radius]
        height = _height(raw)
        for body in on_axle:
            if height is None or abs(height - radius[body]) <= AXLE_HEIGHT_TOLERANCE_M:
                continue
            r = radius[body]
            sec.fail(
                f"format 1 applied this element at wheelset {body}'s axle centre (z = {r:g} m, "
                f"the nominal radius) whatever height was given; the current format applies it "
                f"on the axlebox at z = {height:g} m and carries its moment into the axle. Write "
                f"position z = {r:g} m to keep format 1's result, or 'format_version: 2' to "
                "use the given height",
                key="position",
            )


def _bodies(raw: dict) -> list[str]:
    bodies = raw.get("bodies")
    return [b for b in bodies if isinstance(b, str)] if isinstance(bodies, list) else []


def _height(raw: dict) -> float | None:
    """The element's z in m as the schema reads it (already validated), or None."""
    from railexu.units import to_si

    position: Any = raw.get("position")
    value = position.get("z", 0.0) if isinstance(position, dict) else None
    if isinstance(position, list) and len(position) == 3:
        value = position[2]
    try:
        return None if value is None else float(to_si(value, "m"))
    except (TypeError, ValueError):
        return None
