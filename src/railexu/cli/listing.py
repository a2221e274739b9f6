"""The ``railexu list`` sub-command: the shipped vehicles, tracks, studies, acceptance
programmes and profiles."""

from __future__ import annotations

import argparse

WHAT = ("vehicles", "tracks", "studies", "programmes", "profiles")


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "list",
        help="the shipped vehicles, tracks, studies, programmes and profiles, with descriptions",
        description=(
            "List what ships with railexu by name: each name works wherever a file goes "
            "(`railexu run eu07 --track straight_irregular`)."
        ),
    )
    p.add_argument(
        "what", nargs="*", metavar="WHAT", help=f"what to list: {', '.join(WHAT)} (default: all)"
    )
    p.set_defaults(func=command)
    return p


def command(args: argparse.Namespace) -> int:
    from railexu.cli.common import CliError
    from railexu.errors import did_you_mean

    for item in args.what:
        if item not in WHAT:
            raise CliError(f"cannot list {item!r}.{did_you_mean(item, WHAT)}")
    print(listing_text(args.what or WHAT))
    return 0


def listing_text(what: tuple[str, ...] | list[str] = WHAT) -> str:
    """The text of ``railexu list``: one line per shipped item, grouped by kind."""
    from railexu.inputs.catalog import shipped_files

    lines: list[str] = []
    for kind in what:
        if kind == "profiles":
            items = _profiles()
        else:
            catalog_kind = {
                "vehicles": "vehicle",
                "tracks": "track",
                "studies": "study",
                "programmes": "programme",
            }[kind]
            items = [(f.name, f.description) for f in shipped_files(catalog_kind)]
        lines.append(f"{kind}:")
        width = max((len(n) for n, _ in items), default=0)
        for name, description in items:
            lines.append(f"  {name:<{width}}  {_shorten(description)}")
        lines.append("")
    return "\n".join(lines).rstrip()


_PROFILE_TEXT = {
    "S1002": "wheel: S1002 (EN 13715), analytic",
    "MBench_S1002": "wheel: S1002 of the Manchester contact benchmark (SIMPACK .prw, packaged)",
    "UIC60": "rail: UIC60 / 60E1 (EN 13674-1), circular arcs",
    "60E1": "rail: the same as UIC60",
    "MBench_UIC60": "rail: UIC60 of the Manchester benchmark, canted 1:40 (SIMPACK .prr)",
    "cone:<conicity>": "wheel: a cone of the given slope (e.g. cone:0.05), for analytic checks",
    "round:<radius_m>": "rail: a circular head of the given radius (e.g. round:0.3)",
    "flat": "rail: a flat head",
}


def _profiles() -> list[tuple[str, str]]:
    from railexu.profiles import registry

    names = (
        *registry.BUILTIN_WHEELS,
        *registry.PARAMETRIC_WHEELS,
        *registry.BUILTIN_RAILS,
        *registry.PARAMETRIC_RAILS,
    )
    return [(name, _PROFILE_TEXT.get(name, "")) for name in names]


def _shorten(text: str, limit: int = 110) -> str:
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 3].rstrip() + "..."
