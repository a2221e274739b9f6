"""The hump between two rails across a flangeway (issue 29, speed): the kernel keeps a lower
bound of it instead of refining it (``kernel.HUMP_SEPARATE_M``). Checked against the gap
itself sampled densely between the two minima (the definition of the hump: the highest gap
between them), and that the bound gives the minima the weights the sampled hump gives.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel
from railexu.contact.placement import symmetric_wheelset
from railexu.contact.variable_tables import section_rail_arrays
from railexu.profiles.variable import VariableProfile, read_slcs

DATA = Path(__file__).parent / "data" / "switches_crossings" / "profiles"


def test_hump_across_the_flangeway_is_a_lower_bound_with_full_weights():
    """CONTACT's ``uk_interrupt_v2`` at s = 160 mm, the S1002 wheel at y = 3.5 mm pressed onto
    nose and wing rail (``benchmarks/sc_contact.py``'s case): the two penetrating minima on
    the two rails are separated by a hump of centimetres over the flangeway; the kernel's
    ``cand_h`` is at least 1 mm, at most the highest gap sampled every 0.01 mm between them
    (a lower bound), and the minima's weights are those the sampled hump gives, to the last
    bit."""
    geo = symmetric_wheelset(
        "MBench_S1002", "MBench_UIC60", nominal_radius_m=0.46, inclination="1:40",
        gauge_m=1.435, flange_back_distance_m=1.36,
    )  # fmt: skip
    model = WheelsetContactModel(geo)
    rail = VariableProfile(read_slcs(DATA / "uk_interrupt_v2.slcs", scale_to_mm=1000.0))
    rtab, rinfo = section_rail_arrays(rail, 0.16, geo.left, rail_origin_m=(0.75, 0.0),
                                      x_max_m=0.06)  # fmt: skip
    cy, cz = 0.0035, 0.4609236
    cand = [np.full(K.MAX_POINTS, np.nan) for _ in range(3)]
    n = K.find_contact_candidates(model.wtab_l, model.winfo_l, rtab, rinfo, cy, cz, 0.0, 0.0,
                                  float(model.params[K.P_SCAN]), *cand)  # fmt: skip
    cand_s, cand_g, cand_h = cand
    ctx = K._make_ctx(model.winfo_l, rinfo, cy, cz, 0.0, 0.0)
    separated = [i for i in range(n - 1) if cand_h[i] >= K.HUMP_SEPARATE_M]
    assert separated, "expected two minima across the flangeway"
    for i in separated:
        assert cand_g[i] < 0.0 and cand_g[i + 1] < 0.0
        s = np.arange(cand_s[i], cand_s[i + 1], 1e-5)
        highest = max(K._gap_at(x, model.wtab_l, rtab, ctx)[0] for x in s)
        assert K.HUMP_SEPARATE_M <= cand_h[i] <= highest
    weights = np.zeros(K.MAX_POINTS)
    K.candidate_weights(n, cand_g, cand_h, weights)
    exact = cand_h.copy()
    for i in separated:
        s = np.arange(cand_s[i], cand_s[i + 1], 1e-5)
        exact[i] = max(K._gap_at(x, model.wtab_l, rtab, ctx)[0] for x in s)
    weights_exact = np.zeros(K.MAX_POINTS)
    K.candidate_weights(n, cand_g, exact, weights_exact)
    assert np.array_equal(weights[:n], weights_exact[:n])
