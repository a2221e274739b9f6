"""Markdown tables of schemas for ``docs/*-format.md``, written between marker comments.

A doc holds a region ``<!-- schema:NAME begin -->`` ... ``<!-- schema:NAME end -->`` whose
content :func:`render_schemas` generates; :func:`update_region` replaces it and
:func:`region_is_current` tells whether a doc is up to date (a test checks it).
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from railexu.inputs.schema import OPTIONAL, REQUIRED, Field, Schema

_UNIT_NAMES = {"1": "-", "": ""}


def _default_text(f: Field) -> str:
    if f.default is REQUIRED:
        return "required"
    if f.default is OPTIONAL:
        return "-"
    value = f.default
    if isinstance(value, dict):
        return f"`{value[f.selector]}`" if f.selector in value else "none"
    if value == "":
        return '""'
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, tuple | list):
        return "[" + ", ".join(f"{v:g}" if isinstance(v, float) else str(v) for v in value) + "]"
    return str(value)


def _allowed_text(f: Field) -> str:
    choices = f.allowed_choices()
    if choices:
        return ", ".join(f"`{c}`" for c in choices)
    parts = []
    if f.positive:
        parts.append("> 0")
    if f.minimum is not None:
        parts.append(f">= {f.minimum:g}")
    if f.maximum is not None:
        parts.append(f"<= {f.maximum:g}")
    if f.kind == "vector":
        parts.insert(0, "[" + ", ".join(f.components) + "] or {" + ", ".join(f.components) + "}")
    if f.kind == "sided":
        parts.insert(0, "one value, or {left, right}")
    return "; ".join(parts)


def _kind_text(f: Field) -> str:
    if f.kind == "number_list":
        return f"list of {_UNIT_NAMES.get(f.unit, f.unit)}".rstrip()
    if f.kind in ("quantity", "vector", "sided") and f.unit:
        return _UNIT_NAMES.get(f.unit, f.unit)
    return {
        "text": "text",
        "integer": "integer",
        "boolean": "true/false",
        "text_list": "list of text",
        "section": "section",
        "named": "names -> entries",
        "model": "model",
        "inclination": "ratio or rad",
    }.get(f.kind, f.kind)


def markdown_table(schema: Schema) -> str:
    """One markdown table: key, unit, default, allowed values, description."""
    rows = ["| key | unit | default | allowed | description |", "|---|---|---|---|---|"]
    for f in schema.fields:
        doc = f.doc.replace("|", "\\|")
        rows.append(
            f"| `{f.key}` | {_kind_text(f)} | {_default_text(f)} | {_allowed_text(f)} | {doc} |"
        )
    return "\n".join(rows)


def render_schemas(schemas: Sequence[tuple[str, Schema]]) -> str:
    """Headed tables of several schemas (``(heading, schema)`` pairs) and their models."""
    out = []
    for heading, schema in schemas:
        out.append(f"#### {heading}\n")
        if schema.doc:
            out.append(schema.doc + "\n")
        out.append(markdown_table(schema) + "\n")
    return "\n".join(out).rstrip() + "\n"


def _markers(name: str) -> tuple[str, str]:
    return f"<!-- schema:{name} begin (generated: python -m railexu.schema --write-docs) -->", (
        f"<!-- schema:{name} end -->"
    )


def update_region(text: str, name: str, content: str) -> str:
    """``text`` with the region of ``name`` replaced by ``content`` (the markers are kept).

    Raises:
        ValueError: the doc has no such region.
    """
    begin, end = _markers(name)
    pattern = re.compile(re.escape(begin) + r".*?" + re.escape(end), re.DOTALL)
    if not pattern.search(text):
        raise ValueError(f"no region {begin!r} ... {end!r}")
    return pattern.sub(lambda _: f"{begin}\n\n{content}\n{end}", text, count=1)


def region_is_current(text: str, name: str, content: str) -> bool:
    """The region ``name`` of ``text`` holds exactly ``content``."""
    try:
        return update_region(text, name, content) == text
    except ValueError:
        return False


def empty_region(name: str) -> str:
    """The two markers of a region, for a new doc."""
    begin, end = _markers(name)
    return f"{begin}\n{end}"
