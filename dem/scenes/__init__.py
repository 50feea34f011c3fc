"""Scene builders: the seeds' specimens and the generic shapes users start from.

``from dem.scenes import tis_panel, running_bond_wall, stack, voussoir_arch, barrel_vault``
gives the builder functions (each returns a :class:`dem.Scene`); the modules of the same
names hold their helpers and closed forms. The paper specimens take paper units with a suffix
(``a_mm``); the generic builders take SI units.
"""

from dem.scenes.arch import voussoir_arch
from dem.scenes.return_walls import wall_with_returns
from dem.scenes.running_bond_wall import running_bond_wall
from dem.scenes.seed001_walls import chee_liang_specimen, orduna_panel, restrepo_specimen
from dem.scenes.stack import stack
from dem.scenes.tis_panel import tis_panel
from dem.scenes.vault import barrel_vault

__all__ = [
    "barrel_vault",
    "chee_liang_specimen",
    "orduna_panel",
    "restrepo_specimen",
    "running_bond_wall",
    "stack",
    "tis_panel",
    "voussoir_arch",
    "wall_with_returns",
]
