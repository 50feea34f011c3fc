"""Step control of the static path following (:mod:`dem.static.path`) on a small scene."""

import numpy as np

from dem.scene import Scene, proportional_to_weight
from dem.scenes.seed001_walls import SPECIMENS
from dem.static import StaticSettings, solve_collapse
from dem.static.dead_load import solve_dead_load
from dem.static.model import Model
from dem.static.newton import Corrector, Outcome
from dem.static.path import PathFollower


def _block_on_base():
    box = lambda lo, hi: np.array(  # noqa: E731
        [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    )
    blocks = [box((-1, -1, -0.2), (1, 1, 0)), box((-0.1, -0.15, 0), (0.1, 0.15, 0.5))]
    scene = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=0.7)
    return scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))


def test_control_follows_the_path_after_a_few_failed_steps_at_the_last_step_length():
    # Rule (module notes of dem.static.path): after `switch_after` consecutive failed steps
    # the fixed control gives way to the path direction, whose first step is as long as the
    # last converged increment. Before, the fixed control halved its step 14 times (to
    # min_step_ratio) first, each failure costing up to 40 Newton iterations, and the arc
    # restarted at the first increment's length: seed 001 S6 with return walls of blocks
    # (resultant law) then stalled after 715 s.
    settings = StaticSettings(switch_after=3, on_failure="return")
    model = Model(_block_on_base(), settings)
    corrector = Corrector(model, settings)
    dead, _ = solve_dead_load(corrector)
    path = PathFollower(model, corrector, dead)
    for _ in range(2):
        out = path._step()
        assert out.converged
        assert path._accept(out) is None
    du = path.last_du.copy()
    failed = Outcome(False, path.point, settings.max_iterations, out.floor)
    for _ in range(2):
        assert path._failed(failed) is None
        assert not path.switched
    assert path._failed(failed) is None
    assert path.switched
    np.testing.assert_allclose(path.w, du / np.linalg.norm(du))
    np.testing.assert_allclose(path.dc, np.linalg.norm(du))


def test_failed_newton_work_is_counted_apart(monkeypatch):
    """``n_failed_iterations`` is the sum of the iterations of the live steps' Newton solves
    that did not converge, counted here at the corrector (path control: ``con.w`` set); a wall
    with return walls of blocks has some."""
    outcomes = []
    solve = Corrector.solve

    def counted(self, start, con, *args, **kwargs):
        out = solve(self, start, con, *args, **kwargs)
        if con.w is not None:
            outcomes.append(out)
        return out

    monkeypatch.setattr(Corrector, "solve", counted)
    spec = SPECIMENS["restrepo-S15"]
    settings = StaticSettings(interface_model="resultant", mu=spec.joint.mu)
    result = solve_collapse(spec.build(return_walls="blocks"), settings)
    failed = sum(o.iterations for o in outcomes if not o.converged)
    assert result.n_failed_iterations == failed > 0
    assert result.n_failed_iterations < result.n_iterations
