r"""Static DEM of rigid blocks with elastic-plastic interfaces, followed to collapse.

The incremental analysis of seed 001 (Sec. 2.3), in general form: rigid blocks with six dofs
each, joints with an interface law, the dead load applied first, then the live load scaled by
lambda and followed under displacement-type control until the assembly collapses.

Modules, one concern each:

- :mod:`dem.static.settings`: :class:`StaticSettings` and the settings of each interface law;
- :mod:`dem.static.laws`: the interface laws as objects (resultant, fibre);
- :mod:`dem.static.model`: unknowns, kinematics ``q = H U``, loads, stiffness assembly;
- :mod:`dem.static.mechanism`: is there a mechanism the live load can drive at all;
- :mod:`dem.static.newton`: the Newton corrector of one step;
- :mod:`dem.static.dead_load`: the dead load in increments with automatic cutting;
- :mod:`dem.static.path`: the path following (step control, cascades, control switch, end);
- :mod:`dem.static.solve`: :func:`solve_collapse`;
- :mod:`dem.static.result`: :class:`StaticResult`, :class:`NoCollapseError`.

Units SI: m, N, Pa, rad.
"""

from dem.kernels.interface_law import (
    STATE_CRUSHED,
    STATE_DETACHED,
    STATE_ELASTIC,
    STATE_FLEXURE,
    STATE_SHEAR,
)
from dem.static.dead_load import DeadLoadError
from dem.static.laws import ALPHA_TABLE_A1, interface_alpha
from dem.static.result import (
    COLLAPSE_TERMINATIONS,
    NoCollapseError,
    StaticResult,
    StaticSolverError,
    state_labels,
)
from dem.static.settings import FibreLawSettings, ResultantLawSettings, StaticSettings
from dem.static.solve import solve_collapse

__all__ = [
    "ALPHA_TABLE_A1",
    "COLLAPSE_TERMINATIONS",
    "STATE_CRUSHED",
    "STATE_DETACHED",
    "STATE_ELASTIC",
    "STATE_FLEXURE",
    "STATE_SHEAR",
    "DeadLoadError",
    "FibreLawSettings",
    "NoCollapseError",
    "ResultantLawSettings",
    "StaticResult",
    "StaticSettings",
    "StaticSolverError",
    "interface_alpha",
    "solve_collapse",
    "state_labels",
]
