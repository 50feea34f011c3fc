"""Explicit LS-DEM-style dynamics of rigid convex blocks (seed 000).

The model (seed 000, Sec. 2): rigid blocks (6 dofs each, quaternions), fixed blocks not
integrated, contact by surface nodes with tributary areas and a traction penalty ``k_n d A n``
(Eq. (2)), regularised Coulomb friction with shear history (Eq. (1)), global viscous damping
and an explicit (symplectic Euler) time step chosen from the stiffness and masses present.

Modules, one concern each:

- :mod:`~dem.explicit.settings`: frozen settings of the solver and of the indentation driver;
- :mod:`~dem.explicit.state`: the groups of arrays the kernels take (``Bodies``, ``Shapes``,
  ``Nodes``, ``Law``, ``Scratch``, ``Indenter``) and ``ExplicitState``, what evolves (block
  motion, neighbour list with its friction history, time): snapshots and checkpoints hold it;
- :mod:`~dem.explicit.timestep`: highest frequency and stable time step;
- :mod:`~dem.explicit.step_check`: the time step against the contacts present at each
  neighbour-list rebuild (the run stops if it is unstable for them);
- :mod:`~dem.explicit.model`: the scene prepared for dynamics (nodes, neighbour list, advance,
  relaxation, support check);
- :mod:`~dem.explicit.indentation`: the sphere-indentation driver (seed 000) with checkpoints;
- :mod:`~dem.explicit.indentation_error`: the error bars of its numbers (curve sampling,
  loading rate, time step, node spacing);
- :mod:`~dem.explicit.lateral`: the tilting-table / live-load driver to collapse;
- :mod:`~dem.explicit.continuation`: the lateral multiplier's error bar (bracket, loading
  rate, time step, node spacing) and its continuation in joint stiffness to rigid blocks;
- :mod:`~dem.explicit.diagnosis`: the block pairs in contact at a state, with their forces;
- :mod:`~dem.explicit.stiffness`: ``k_n`` from the material and settings for masonry;
- :mod:`~dem.explicit.checkpoint`: checkpoint files (``.npz`` plus JSON, no pickles);
- :mod:`~dem.explicit.results`: result objects and post-processing.
"""

from dem.explicit.continuation import RigidContinuation
from dem.explicit.indentation import simulate_indentation
from dem.explicit.lateral import LiveLoadRamp, MotionCriteria, TiltingTable, simulate_lateral
from dem.explicit.model import ExplicitModel
from dem.explicit.results import (
    IndentationResult,
    LateralResult,
    curve_summary,
    export_peak_state,
    interface_resultants,
)
from dem.explicit.settings import (
    ExplicitSettings,
    IndentationSettings,
    RelaxationSettings,
    SimulationError,
)
from dem.explicit.stiffness import k_n_from_material, masonry_settings
from dem.explicit.unmodelled import UnmodelledContactError

__all__ = [
    "ExplicitModel",
    "ExplicitSettings",
    "IndentationResult",
    "IndentationSettings",
    "LateralResult",
    "LiveLoadRamp",
    "MotionCriteria",
    "RelaxationSettings",
    "RigidContinuation",
    "SimulationError",
    "UnmodelledContactError",
    "TiltingTable",
    "curve_summary",
    "export_peak_state",
    "interface_resultants",
    "k_n_from_material",
    "masonry_settings",
    "simulate_indentation",
    "simulate_lateral",
]
