"""Virtual acceptance (``railexu acceptance``): a vehicle taken through an EN 14363:2016
running-behaviour programme as a study of one case per test section, with the statistical
evaluation per test zone, the quasi-static tests and a verdict (``docs/acceptance.md``).
"""

from railexu.study.acceptance.runner import (
    ACCEPTANCE_JSON,
    AcceptanceResult,
    default_programme,
    run_acceptance,
)

#: the front door's name (``railexu.acceptance``)
acceptance = run_acceptance

__all__ = [
    "acceptance",
    "ACCEPTANCE_JSON",
    "AcceptanceResult",
    "default_programme",
    "run_acceptance",
]
