"""Reading CONTACT's ``.ref_out`` (wheel-rail module) for the S&C tests: per case the wheelset
position, the total vertical force and per patch its reference location, angle and normal
force, in SI units."""

from __future__ import annotations

from pathlib import Path


def _floats(line: str) -> list[float]:
    return [float(v) for v in line.split()]


def read_ref_out(path: Path) -> list[dict]:
    """The cases of a ``.ref_out`` file: ``s_m, y_m, z_m, fx_n, fy_n, fz_n, patches`` (the
    total forces on the rail in track axes; each patch
    ``x_m, y_m, z_m, delta_rad, fn_n, fx_n, fs_n``: the normal force and the tangential forces
    along the track and laterally in the contact plane; ``y, z`` in the rail profile's
    coordinates; and its kinematics ``veloc_m_per_s, cksi, ceta, cphi_per_m``: CONTACT's
    rolling speed and creepages, spin in 1/m; ``zcp_w_m`` the reference point's height in the
    wheel's axes, ``approach_m`` the patch's approach)."""
    lines = path.read_text(errors="replace").splitlines()
    cases: list[dict] = []
    for i, line in enumerate(lines):
        head = line.split()
        if head[:1] == ["S_WS"]:
            s, y, z = _floats(lines[i + 1])[:3]
            cases.append({"s_m": s * 1e-3, "y_m": y * 1e-3, "z_m": z * 1e-3, "patches": []})
        elif head[:1] == ["FX(TR)"]:
            fx, fy, fz = _floats(lines[i + 1])[:3]
            cases[-1].update({"fx_n": fx, "fy_n": fy, "fz_n": fz})
        elif head[:1] == ["XCP(TR)"]:
            v = _floats(lines[i + 1])
            cases[-1]["patches"].append(
                {"x_m": v[0] * 1e-3, "y_m": v[4] * 1e-3, "z_m": v[5] * 1e-3, "delta_rad": v[3]}
            )
        elif head[:2] == ["FN", "FX"]:
            fn, fx, fs = _floats(lines[i + 1])[:3]
            cases[-1]["patches"][-1].update({"fn_n": fn, "fx_n": fx, "fs_n": fs})
        elif head[:1] == ["XCP(W)"]:
            cases[-1]["patches"][-1]["zcp_w_m"] = _floats(lines[i + 1])[2] * 1e-3
        elif head[:1] == ["FN/G"]:
            cases[-1]["patches"][-1]["approach_m"] = _floats(lines[i + 1])[3] * 1e-3
        elif head[:1] == ["CHI"] and cases and cases[-1]["patches"]:
            v = _floats(lines[i + 1])
            cases[-1]["patches"][-1].update(
                {"veloc_m_per_s": v[2] * 1e-3, "cksi": v[3], "ceta": v[4], "cphi_per_m": v[5] * 1e3}
            )
    return cases
