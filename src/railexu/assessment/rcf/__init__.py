"""Rolling contact fatigue indices per contact: Ekberg's surface fatigue index and Burstow's
Whole Life Rail Model damage function (:mod:`.indices`, docs/wear.md)."""

from railexu.assessment.rcf.indices import fi_surf, wlrm_damage

__all__ = ["fi_surf", "wlrm_damage"]
