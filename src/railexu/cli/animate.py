"""The ``railexu animate`` sub-command: the contact view and the plan view of a finished run."""

from __future__ import annotations

import argparse
import sys
import time

from railexu.cli.common import quantity


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "animate",
        help="animate a finished run: the contact on the profiles, the vehicle from above",
        description=(
            "Animate a finished run from its folder's state.npz (written by railexu run; also "
            "in a study's case folders), without re-running it: the contact view (a wheelset's "
            "cross-section on its rails with contact points, ellipse widths and force vectors) "
            "and the plan view (the vehicle from above, lateral motion and yaw exaggerated, "
            "flange contacts red). Writes contact.gif and plan.gif (or .mp4) into the folder."
        ),
    )
    p.add_argument("folder", help="output folder of railexu run (or a study's case folder)")
    p.add_argument(
        "--view",
        action="append",
        choices=("contact", "plan"),
        help="view to draw; repeat for both (default: both)",
    )
    p.add_argument(
        "--format",
        default="gif",
        choices=("gif", "mp4"),
        help="gif (Pillow) or mp4 (needs imageio-ffmpeg: pip install 'railexu[animation]')",
    )
    p.add_argument("--fps", type=quantity("1/s"), default=20.0, help="frames per second")
    p.add_argument("--start", type=quantity("s"), help="start of the time window [s]")
    p.add_argument("--end", type=quantity("s"), help="end of the time window [s]")
    p.add_argument(
        "--playback",
        type=quantity("1"),
        default=1.0,
        help="simulated seconds per second of animation (0.25: four times slower)",
    )
    p.add_argument(
        "--wheelset", type=int, default=1, help="wheelset of the contact view (1: the leading)"
    )
    p.add_argument(
        "--exaggeration",
        type=quantity("1"),
        default=50.0,
        help="factor on lateral motion and yaw in the plan view",
    )
    p.add_argument(
        "--force-scale",
        type=quantity("1"),
        metavar="MM_PER_KN",
        help="arrow length per force in the contact view [mm/kN] (default: the normal force "
        "of 95 %% of the frames at most 45 mm long)",
    )
    p.add_argument("--trace", action="store_true", help="trace the contact positions")
    p.add_argument("--dpi", type=int, default=80, help="resolution of the frames [dpi]")
    p.add_argument("--out", help="folder for the animations (default: the run's folder)")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.set_defaults(func=command)
    return p


def command(args: argparse.Namespace) -> int:
    from railexu.cli.common import CliError
    from railexu.report.animate import AnimationSettings, animate_run

    if args.wheelset < 1:
        raise CliError(f"--wheelset {args.wheelset}: wheelsets are numbered from 1 (the leading)")
    settings = AnimationSettings(
        fps=args.fps,
        start_s=args.start,
        end_s=args.end,
        playback=args.playback,
        wheelset=args.wheelset - 1,
        exaggeration=args.exaggeration,
        force_scale_mm_per_kN=args.force_scale,
        trace=args.trace,
        dpi=args.dpi,
    )
    t0 = time.perf_counter()
    written = animate_run(
        args.folder,
        views=tuple(args.view or ("contact", "plan")),
        fmt=args.format,
        settings=settings,
        out_dir=args.out,
        progress=not args.quiet,
    )
    elapsed = time.perf_counter() - t0
    for path in written.values():
        print(f"railexu animate: wrote {path}")
    if not args.quiet:
        print(f"railexu animate: {elapsed:.1f} s", file=sys.stderr)
    return 0
