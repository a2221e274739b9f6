"""Time and memory of building an S&C zone's station tables (issue 29).

Builds the kernel fields of a track's ``variable_rails`` zone (``model/sc_tables.py``: every
station's effective section on both sides, the station store) for the wheelset's wheels, and
prints the build's processor and wall time, the stations, the store's rows and MB. Run it
under ``/usr/bin/time -v`` for the peak resident memory:

    /usr/bin/time -v python benchmarks/sc_table_build.py uk_crossing_facing

Arguments: the track name (default ``uk_crossing_facing``), ``--set KEY=VALUE`` overrides of
the track file (e.g. ``variable_rails.station_step=10 mm``); ``--digest`` prints a digest of
the store (two versions that build the same store to the last bit print the same);
``--filter-at-stations``: the contact filter's first form (each station's table filtered at the
build) instead of the filter at the wheelset's position.
"""

from __future__ import annotations

import argparse
import hashlib
import time

from railexu.model.assembly import wheelset_geometry
from railexu.model.sc_tables import sc_kernel_fields
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("track", nargs="?", default="uk_crossing_facing")
    ap.add_argument("--set", action="append", default=[], help="track override KEY=VALUE")
    ap.add_argument("--digest", action="store_true", help="print a digest of the store's bytes")
    ap.add_argument("--filter-at-stations", action="store_true",
                    help="the contact filter's first form (filtered station tables)")  # fmt: skip
    a = ap.parse_args()
    track = load_track(a.track, a.set or None)
    geometry = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], track)
    wall, cpu = time.perf_counter(), time.process_time()
    fields = sc_kernel_fields(
        track.variable_rails, geometry, 5.0e-4, filter_at_stations=a.filter_at_stations
    )
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    tab = fields["sc_tab"]
    print(
        f"{a.track}: {fields['sc_index'].shape[0]} stations, store {tab.shape[0]} rows x "
        f"{tab.shape[1]} x {tab.shape[2]} ({tab.nbytes / 1e6:.0f} MB); build {cpu:.1f} s "
        f"processor, {wall:.1f} s wall"
    )
    if a.digest:  # two versions that build the same store to the last bit print the same
        print("store digest", hashlib.sha256(tab.tobytes()).hexdigest()[:16],
              hashlib.sha256(fields["sc_index"].tobytes()).hexdigest()[:16])  # fmt: skip


if __name__ == "__main__":
    main()
