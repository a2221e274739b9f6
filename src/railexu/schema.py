"""The schemas of every input file, and the generated key tables of ``docs/*-format.md``.

Each input declares its keys once: :data:`railexu.vehicle.schema.VEHICLE`,
:data:`railexu.track.schema.TRACK`, :data:`railexu.operation.run_settings.RUN_SCHEMA`,
:data:`railexu.study.spec.STUDY` and :data:`railexu.assessment.acceptance.programme.PROGRAMME`.
This module gathers them (it imports the study layer, so it sits at the top of the package,
beside the command line) and keeps the docs current::

    python -m railexu.schema --write-docs     # rewrite the generated regions of docs/
    python -m railexu.schema --check-docs     # exit 1 if a doc is not current (CI, tests)
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from railexu.assessment.acceptance.programme import DOC_TABLES as PROGRAMME_TABLES
from railexu.inputs.docs import region_is_current, render_schemas, update_region
from railexu.inputs.schema import Schema
from railexu.operation.run_settings import RUN_SCHEMA
from railexu.study.spec import DOC_TABLES as STUDY_TABLES
from railexu.track.schema import DOC_TABLES as TRACK_TABLES
from railexu.vehicle.schema import DOC_TABLES as VEHICLE_TABLES

#: region name -> (doc file relative to the repository, (heading, schema) tables)
DOCS: dict[str, tuple[str, Sequence[tuple[str, Schema]]]] = {
    "vehicle": ("docs/vehicle-format.md", VEHICLE_TABLES),
    "track": ("docs/track-format.md", TRACK_TABLES),
    "run": ("docs/run-settings-format.md", (("Run settings", RUN_SCHEMA),)),
    "study": ("docs/study-format.md", STUDY_TABLES),
    "programme": ("docs/acceptance-programme-format.md", PROGRAMME_TABLES),
}


def repository_root() -> Path:
    """The folder holding ``docs/`` (a source checkout: ``src/railexu/schema.py`` is two
    folders below it)."""
    return Path(__file__).resolve().parents[2]


def rendered(name: str) -> str:
    """The generated content of the region ``name``."""
    return render_schemas(DOCS[name][1])


def stale_docs(root: Path | None = None) -> list[str]:
    """The docs whose generated region differs from the schemas (empty when all are current)."""
    root = root or repository_root()
    out = []
    for name, (doc, _) in DOCS.items():
        path = root / doc
        if not path.is_file() or not region_is_current(
            path.read_text("utf-8"), name, rendered(name)
        ):
            out.append(doc)
    return out


def write_docs(root: Path | None = None) -> list[str]:
    """Rewrite the generated region of every doc; return the docs that changed."""
    root = root or repository_root()
    changed = []
    for name, (doc, _) in DOCS.items():
        path = root / doc
        text = path.read_text("utf-8")
        new = update_region(text, name, rendered(name))
        if new != text:
            path.write_text(new, "utf-8")
            changed.append(doc)
    return changed


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m railexu.schema", description=__doc__)
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument("--write-docs", action="store_true", help="rewrite the generated tables")
    group.add_argument("--check-docs", action="store_true", help="exit 1 if a doc is stale")
    args = parser.parse_args(argv)
    if args.write_docs:
        for doc in write_docs():
            print(f"wrote {doc}")
        return 0
    stale = stale_docs()
    for doc in stale:
        print(f"{doc} is not current: run python -m railexu.schema --write-docs", file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
