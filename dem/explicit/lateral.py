"""Lateral load to collapse: a tilting table or a ramped and held live load.

The scene is first relaxed under its dead load. Then the load multiplier ``lambda`` is raised
in steps: each step ramps the load at a slow rate to the next value and holds it, and the
blocks are judged at the end of the hold (:class:`MotionCriteria`):

- *moving*: a block moved more than ``displacement_tol`` during the step (ramp and hold;
  the hold goes on, up to ``max_hold``, while blocks are faster than ``speed_tol``), or the
  step moved the blocks far more than the stiffest response so far and they stopped (a
  mechanism arrested after finite rotations, :class:`MotionCriteria` ``onset_fraction``);
- *stable*: every block came to rest (speed below ``speed_tol``) first, or ``max_hold``
  ended with every block below ``displacement_tol`` (vibration, elastic creep).

On the first moving step the state of the last stable step is restored and the step is halved
until the bracket ``lambda_stable < lambda* <= lambda_moving`` is ``step / 2^refinements``
wide. A block just past its threshold by ``epsilon`` in ``lambda`` accelerates at about
``a epsilon``, ``a = (1 - c) g / s`` with ``c`` the local damping and ``s`` the mass scaling;
it is found moving if it is faster than ``speed_tol`` at the end of the hold and then travels
the moving limit within the longest hold ``T = max_hold hold``: the bracket can sit above
``lambda*`` by at most ``max(speed_tol / (a hold), 2 limit / (a T^2))`` (``detection_lambda``
in the result). Mass scaling divides ``speed_tol`` by ``s`` (every motion under gravity is
``s`` times slower).

Load patterns (:class:`TiltingTable`, :class:`LiveLoadRamp`) say what ``lambda`` means:

- Tilting table (Restrepo-Velez et al. 2014, seed 001 Table 2): gravity turned by ``theta``
  about a horizontal axis, ``g (sin theta d - cos theta e_z)`` with ``d`` the horizontal
  direction of the tilt; ``lambda = tan theta``. For rigid blocks with Coulomb friction the
  collapse depends on the direction of the total load only, so ``tan theta`` is the multiplier of
  a live load equal to the weight along ``d`` (what the static DEM and limit analysis compute).
- Live load: the dead load plus ``lambda`` times the scene's live pattern
  ``scene.loads.live_wrench``.

The default settings (:func:`dem.explicit.stiffness.masonry_settings`) switch global viscous
damping off: mass-proportional damping resists rigid-body motion itself (a sliding block would
creep at ``a / alpha``) and would hide the mechanism. Local damping damps the vibrations
instead; it slows a mechanism but does not stop it.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import asdict, dataclass, replace
from typing import Protocol

import numpy as np

from dem.estimate import ErrorBudget, Estimate, check_error_budget
from dem.explicit.continuation import (
    BUDGET_SOURCES,
    RigidContinuation,
    bracket_estimate,
    rerun_source,
    rigid_limit,
)
from dem.explicit.diagnosis import pair_forces
from dem.explicit.model import ExplicitModel, require_free_block
from dem.explicit.results import LateralResult
from dem.explicit.settings import ExplicitSettings, RelaxationSettings
from dem.explicit.stiffness import masonry_settings
from dem.scene import Scene, weight_wrench

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class MotionCriteria:
    """When a block counts as moving (thresholds relative to the scene's block size).

    With ``size`` the median cube root of the free blocks' volumes [m] and ``g`` the gravity:

    Attributes
    ----------
    speed_fraction : float
        ``speed_tol = speed_fraction sqrt(g size)`` [m/s]; a block's speed is
        ``|v| + |omega| R`` (the fastest point of its bounding sphere). Default 1e-3.
    displacement_fraction : float
        ``displacement_tol = displacement_fraction size`` [m]; a block's displacement is
        ``|c - c_0| + R angle`` (the farthest point). Default 5e-2: above the elastic
        deflection of a load step (soft joints bend a 1 m wall by about 1 mm per step of 0.05,
        and it creeps on during the hold), so that a mechanism is told from deformation.
    onset_fraction : float
        ``onset_tol = onset_fraction size`` [m]; default 2e-3. A step whose largest block
        displacement exceeds both ``onset_tol`` and ``onset_ratio`` times what the response
        so far gives for its increment (the largest displacement per unit ``lambda`` of the
        full stable steps before it, bisections aside: near collapse the response softens) is
        a moving step even if the motion
        stopped: a mechanism that formed and was then arrested by the blocks bearing on each
        other after a finite rotation (two columns side by side tip about their own toes and
        overlap by ``b (1 - cos theta)``), which the rigid-block methods, in small
        displacements, count as the collapse.
    onset_ratio : float
        See ``onset_fraction``; default 10 (an elastic response grows smoothly from step to
        step; a mechanism jumps by one to two orders of magnitude).
    """

    speed_fraction: float = 1e-3
    displacement_fraction: float = 5e-2
    onset_fraction: float = 2e-3
    onset_ratio: float = 10.0

    def __post_init__(self):
        for name in ("speed_fraction", "displacement_fraction", "onset_fraction"):
            value = getattr(self, name)
            if not (math.isfinite(value) and 0 < value < 1):
                raise ValueError(f"MotionCriteria.{name} must be in (0, 1), got {value}")
        if not (math.isfinite(self.onset_ratio) and self.onset_ratio > 1):
            raise ValueError(f"MotionCriteria.onset_ratio must be > 1, got {self.onset_ratio}")


@dataclass(frozen=True)
class _Schedule:
    """Ramp-and-hold steps of ``lambda`` (shared by both load patterns).

    Attributes
    ----------
    step : float
        First increment of ``lambda``; default 0.05.
    hold : float or None
        Hold at each value [s]; None: ``2 sqrt(size / g)`` with ``size`` the median block size
        of :class:`MotionCriteria` (the time a block-sized motion needs to show).
    ramp : float or None
        Time to ramp from one value to the next [s]; None: ``hold``.
    max_hold : float
        Longest hold, as a multiple of ``hold``, while blocks have not come to rest; default 8.
    max_lambda : float
        Stop without collapse at this multiplier; default 1.
    refinements : int
        The bracket is bisected until it is ``step / 2^refinements`` wide; default 4.
    start : float
        First multiplier held [-], reached by one ramp at the rate ``step / ramp``; the steps
        of ``step`` go on from it. Default 0 (steps from 0). A warm start below a collapse
        multiplier known from a softer run of the same scene (the rigid-limit continuation)
        skips the steps far from collapse.
    develop : bool
        Follow the motion at ``lambda_moving`` to confirm the mechanism (default True; the
        runs of an error estimate, which only need the bracket, skip it).
    criteria : MotionCriteria
    """

    step: float = 0.05
    hold: float | None = None
    ramp: float | None = None
    max_hold: float = 8.0
    max_lambda: float = 1.0
    refinements: int = 4
    start: float = 0.0
    develop: bool = True
    criteria: MotionCriteria = MotionCriteria()

    def __post_init__(self):
        for name in ("step", "max_lambda"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and positive, got {value}")
        for name in ("hold", "ramp"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and positive [s], got {value}")
        if not (math.isfinite(self.max_hold) and self.max_hold >= 1):
            raise ValueError(f"max_hold must be >= 1 (a multiple of hold), got {self.max_hold}")
        if int(self.refinements) != self.refinements or self.refinements < 0:
            raise ValueError(f"refinements must be an integer >= 0, got {self.refinements}")
        if not (math.isfinite(self.start) and 0 <= self.start < self.max_lambda):
            raise ValueError(f"start must be in [0, max_lambda), got {self.start}")


class LoadPattern(Protocol):
    """What a driver does to the external load as ``lambda`` changes."""

    def wrench(self, scene: Scene, lam: float) -> np.ndarray:
        """(n_blocks, 6) external forces and moments at multiplier ``lam`` [N, N m]."""


@dataclass(frozen=True)
class TiltingTable(_Schedule):
    """Gravity turned about a horizontal axis; ``lambda = tan(theta)``.

    Attributes
    ----------
    direction : (3,) tuple
        Horizontal direction ``d`` towards which the table tilts (the lateral component of
        gravity points along it); default the horizontal part of the scene's live load (its
        net force) if it has one, else ``+y``. A live load without a horizontal part (vertical,
        or moments only) gives no direction: refused with ``ValueError``, give ``direction``.
    """

    direction: tuple | None = None

    def __post_init__(self):
        super().__post_init__()
        if self.direction is not None:
            d = np.asarray(self.direction, dtype=float)
            if d.shape != (3,) or not np.all(np.isfinite(d)) or abs(d[2]) > 1e-12 or not d.any():
                raise ValueError(
                    f"TiltingTable.direction must be a non-zero horizontal 3-vector, got "
                    f"{self.direction}"
                )

    def wrench(self, scene: Scene, lam: float) -> np.ndarray:
        g = float(np.linalg.norm(scene.loads.gravity))
        if g == 0.0:
            raise ValueError(
                f"TiltingTable: scene {scene.name!r} has no gravity (loads.gravity = 0): a "
                "tilting table turns gravity; give the scene gravity, or a live load and "
                "LiveLoadRamp"
            )
        theta = math.atan(lam)
        gravity = g * (math.sin(theta) * self.unit_direction(scene) - math.cos(theta) * _EZ)
        return weight_wrench(scene.assembly, gravity) + scene.loads.dead_wrench

    def unit_direction(self, scene: Scene) -> np.ndarray:
        """The horizontal unit vector ``d``."""
        if self.direction is not None:
            d = np.asarray(self.direction, dtype=float)
            return d / np.linalg.norm(d)
        live_wrench = scene.loads.live_wrench
        if not np.any(live_wrench):
            return np.array([0.0, 1.0, 0.0])
        live = live_wrench[:, :3].sum(axis=0)
        horizontal = np.array([live[0], live[1], 0.0])
        if np.linalg.norm(horizontal) <= HORIZONTAL_TOL * np.abs(live_wrench[:, :3]).sum():
            raise ValueError(
                f"TiltingTable: scene {scene.name!r} has a live load without a horizontal "
                f"component (net force {live.tolist()} N), which gives no direction to tilt "
                "towards: a tilting table needs a live load with a horizontal component or "
                "TiltingTable(direction=...); for a vertical live load use LiveLoadRamp"
            )
        return horizontal / np.linalg.norm(horizontal)


@dataclass(frozen=True)
class LiveLoadRamp(_Schedule):
    """Dead load plus ``lambda`` times ``scene.loads.live_wrench``."""

    def wrench(self, scene: Scene, lam: float) -> np.ndarray:
        if not np.any(scene.loads.live_wrench):
            raise ValueError(f"scene {scene.name!r} has no live load: use TiltingTable")
        return scene.dead_wrench + lam * scene.loads.live_wrench


_EZ = np.array([0.0, 0.0, 1.0])
HORIZONTAL_TOL = 1e-12
"""A live load's net horizontal force at most this fraction of the sum of its force
magnitudes counts as none (round-off): :class:`TiltingTable` refuses it as a direction."""
DEVELOP_FACTOR = 4.0
"""Once bracketed, the mechanism is followed until a block has moved this many displacement
thresholds; the blocks past one threshold are the moving blocks."""


def simulate_lateral(
    scene: Scene,
    settings: ExplicitSettings | None = None,
    driver: TiltingTable | LiveLoadRamp | None = None,
    relaxation: RelaxationSettings | None = None,
    error: ErrorBudget = "none",
    continuation: RigidContinuation | None = None,
) -> LateralResult:
    """Relax a scene, then raise a lateral load in ramp-and-hold steps until blocks move;
    optionally estimate the multiplier's error and continue it to rigid blocks.

    Parameters
    ----------
    scene : Scene
    settings : ExplicitSettings, optional
        Default :func:`dem.explicit.stiffness.masonry_settings` (``k_n`` from ``E / L`` of the
        blocks in series with the joint stiffness, nodes reaching the block edges, local
        damping instead of global damping).
    driver : TiltingTable or LiveLoadRamp, optional
        Default ``TiltingTable()``.
    relaxation : RelaxationSettings, optional
    error : {"none", "cheap", "full"}
        What ``result.estimate`` measures beyond the bracket (:mod:`dem.explicit.continuation`):
        ``"none"`` nothing (an unknown bar), ``"cheap"`` the loading rate (one more run at
        half the rate, started just below the bracket; the time step and the node spacing
        are then listed in ``estimate.omitted``), ``"full"`` also the time step and the node
        spacing (a run each at half of it).
    continuation : RigidContinuation, optional
        Also run at stiffer joints and extrapolate to rigid blocks (``result.rigid``,
        ``result.levels``).

    Returns
    -------
    LateralResult
        ``collapsed`` is True only if a moving step was found below ``max_lambda``;
        ``estimate`` the collapse multiplier at the material stiffness with its error,
        ``rigid`` its rigid limit (None without a collapse or a continuation).

    Raises
    ------
    ValueError
        Every block fixed, or a scene the driver cannot load (``TiltingTable`` without
        gravity, ``LiveLoadRamp`` without a live load).
    SimulationError
        A block or group of blocks has no support (named), or the run blew up.
    """
    wall0 = time.perf_counter()
    check_error_budget(error)
    driver = driver or TiltingTable()
    # refuse a scene with nothing to move or that the driver cannot load before building a model
    require_free_block(scene)
    driver.wrench(scene, 0.0)
    settings = settings or masonry_settings(scene)
    relaxation = relaxation or RelaxationSettings(max_steps=400000)

    def run(settings_, driver_):
        return _run_once(scene, settings_, driver_, relaxation)

    result = run(settings, driver)
    material = bracket_estimate(result)
    if material is None:
        return result
    if error == "none":
        material = Estimate.unknown(material.value, "error budget 'none'")
    else:  # the sources of "full" this budget does not pay for are named (dem.estimate notes)
        missing = [s for s in BUDGET_SOURCES["full"] if s not in BUDGET_SOURCES[error]]
        material = replace(material, omitted=(*material.omitted, *missing))
    for name in BUDGET_SOURCES[error]:
        width, cost = rerun_source(run, settings, driver, result, name)
        material = material.with_source(name, width, cost)
    rigid, levels = None, []
    if continuation is not None:
        rigid, levels = rigid_limit(run, settings, driver, result, material, continuation)
    return replace(result, estimate=material, rigid=rigid, levels=levels,
                   wall_s=time.perf_counter() - wall0)  # fmt: skip


def _run_once(scene: Scene, settings: ExplicitSettings, driver, relaxation) -> LateralResult:
    """One run of :func:`simulate_lateral` (no error estimate)."""
    wall0 = time.perf_counter()
    wrench0 = driver.wrench(scene, 0.0)
    model = ExplicitModel(scene, settings)
    model.set_external_wrench(wrench0)
    relax_info = model.relax(relaxation)
    run = _RampHold(model, driver, scene)
    outcome = run.to_collapse()
    model.restore(outcome["state_stable"])
    at_rest = pair_forces(model)
    width = outcome["lambda_moving"] - outcome["lambda_stable"]
    if not math.isfinite(width):
        width = driver.step / 2**driver.refinements
    return LateralResult(
        collapsed=outcome["collapsed"],
        lambda_stable=outcome["lambda_stable"],
        lambda_moving=outcome["lambda_moving"],
        moving_blocks=outcome["moving_blocks"],
        mechanism_confirmed=outcome["mechanism_confirmed"],
        arrested=outcome["arrested"],
        contacts_at_rest=at_rest,
        record_lambda=np.asarray(run.rec_lambda),
        record_displacement=np.asarray(run.rec_disp),
        record_time=np.asarray(run.rec_time),
        record_stable=np.asarray(run.rec_stable, dtype=bool),
        detection_lambda=run.detection_lambda(width),
        speed_tol=run.speed_tol,
        displacement_tol=run.disp_tol,
        wall_s=time.perf_counter() - wall0,
        settings=asdict(settings),
        driver={"kind": type(driver).__name__, **_plain(asdict(driver))},
        info={
            "dt": model.dt,
            "omega_max": model.omega_max,
            "step_check": model.step_check.as_dict(),
            "n_nodes": model.nodes.n_nodes,
            "relax": relax_info,
            "steps": run.steps,
            "hold_s": run.hold,
            "ramp_s": run.ramp,
        },  # fmt: skip
    )


def _plain(d: dict) -> dict:
    return {k: (list(v) if isinstance(v, tuple) else v) for k, v in d.items()}


class _RampHold:
    """The ramp-and-hold loop with bisection of the first moving step (module docstring)."""

    def __init__(self, model: ExplicitModel, driver, scene: Scene):
        self.model, self.driver, self.scene = model, driver, scene
        free = model.free_blocks
        g = float(np.linalg.norm(scene.loads.gravity)) or 9.81
        size = float(np.median(np.cbrt(scene.assembly.volume[free])))
        crit = driver.criteria
        # inertial masses scaled by s slow every motion under gravity by s
        scaling = model.settings.mass_scaling
        self.speed_tol = crit.speed_fraction * math.sqrt(g * size) / scaling
        self.disp_tol = crit.displacement_fraction * size
        self.onset_tol = crit.onset_fraction * size
        self.compliance = 0.0  # largest displacement per unit lambda of the stable steps [m]
        self.hold = driver.hold if driver.hold is not None else 2.0 * math.sqrt(size / g)
        self.ramp = driver.ramp if driver.ramp is not None else self.hold
        # near the threshold a block accelerates at (1 - local damping) g epsilon / s
        self.accel = (1.0 - model.settings.local_damping) * g / scaling
        self.ref_pos = model.pos.copy()
        self.ref_quat = model.quat.copy()
        self.rec_lambda, self.rec_disp, self.rec_time, self.rec_stable = [], [], [], []
        self.steps = 0

    def detection_lambda(self, width: float) -> float:
        """Largest overshoot of the bracket above the threshold that the criteria allow
        (module docstring): a block past it by ``epsilon`` accelerates at ``a epsilon``
        (``a = (1 - c) g / s``); it is still slower than ``speed_tol`` at the end of a hold if
        ``epsilon < speed_tol / (a hold)``, and it moves the onset limit (for a bracket of
        ``width``) within the longest hold ``T`` if ``epsilon > 2 limit / (a T^2)``: the
        larger of the two."""
        longest = self.driver.max_hold * self.hold
        limit = self.disp_tol
        if self.compliance > 0.0:
            onset = max(self.onset_tol, self.driver.criteria.onset_ratio * self.compliance * width)
            limit = min(limit, onset)
        return max(
            self.speed_tol / (self.accel * self.hold), 2.0 * limit / (self.accel * longest**2)
        )

    def to_collapse(self) -> dict:
        """Step ``lambda`` up to the first moving step, then bisect the bracket."""
        driver = self.driver
        lam, n_stable = 0.0, 0
        width = driver.step / 2**driver.refinements
        lam_moving, moving_blocks = math.nan, np.zeros(0, dtype=np.int64)
        saved = self.model.snapshot()
        while True:
            if math.isnan(lam_moving):
                base = driver.start if driver.start > 0 else driver.step
                target = min(base + driver.step * n_stable, driver.max_lambda)
            elif lam_moving - lam > width * (1 + 1e-9):
                target = 0.5 * (lam + lam_moving)
            else:
                break
            stable, moving = self._step(lam, target)
            if stable:
                stable, moving = self._onset(target - lam)
            self._record(target, stable)
            if stable:
                lam, n_stable = target, n_stable + 1
                saved = self.model.snapshot()
                if math.isnan(lam_moving) and lam >= driver.max_lambda:
                    logger.info("no block moved up to lambda=%.4g", lam)
                    break
            else:
                lam_moving, moving_blocks = target, moving
                if lam_moving - lam > width * (1 + 1e-9):
                    self.model.restore(saved)
        confirmed = arrested = False
        if math.isfinite(lam_moving) and driver.develop:
            moving_blocks, confirmed, arrested = self._develop(lam, lam_moving, redo=stable)
        return {
            "mechanism_confirmed": confirmed,
            "arrested": arrested,
            "collapsed": math.isfinite(lam_moving),
            "lambda_stable": lam,
            "lambda_moving": lam_moving,
            "moving_blocks": moving_blocks,
            "state_stable": saved,
        }

    def _onset(self, increment: float) -> tuple[bool, np.ndarray]:
        """Whether a step that came to rest moved as a mechanism that was arrested
        (:class:`MotionCriteria` ``onset_fraction``): (stable, moving blocks). Updates the
        stiffest response of the stable steps."""
        start_pos, start_quat = self.step_start
        disp = self.model.block_displacement(start_pos, start_quat)
        limit = max(self.onset_tol, self.driver.criteria.onset_ratio * self.compliance * increment)
        if self.compliance > 0.0 and disp.max() > limit:
            logger.info("a step of %.4g moved blocks by %.3g m, %.3g times the stiffest "
                        "response so far: a mechanism that was arrested", increment,
                        disp.max(), disp.max() / (self.compliance * increment))  # fmt: skip
            return False, np.flatnonzero(disp > limit).astype(np.int64)
        if increment >= self.driver.step * (1 - 1e-9):  # a full step, not a bisection
            self.compliance = max(self.compliance, disp.max() / increment)
        return True, np.zeros(0, dtype=np.int64)

    def _develop(self, lam: float, lam_moving: float, redo: bool) -> tuple[np.ndarray, bool, bool]:
        """Follow the motion at ``lam_moving`` until a block has moved ``DEVELOP_FACTOR``
        displacement thresholds (at most ``2 max_hold`` holds); returns the blocks that moved
        more than the threshold (the onset limit for an arrested mechanism) or still move
        faster than ``speed_tol``, whether the mechanism is confirmed (the motion grew, or it
        jumped past the onset limit of :meth:`_onset` again and stopped: arrested) and
        whether it was arrested.

        ``redo``: the model is at the last stable step, so ramp to ``lam_moving`` again first.
        """
        if redo:
            self._step(lam, lam_moving)
        start_pos, start_quat = self.step_start
        model = self.model
        n_check = max(1, round(0.25 * self.hold / model.dt))
        n_max = round(2.0 * self.driver.max_hold * self.hold / model.dt)
        done = 0
        disp = model.block_displacement(start_pos, start_quat)
        while disp.max() < DEVELOP_FACTOR * self.disp_tol and done < n_max:
            self._advance(n_check)
            done += n_check
            disp = model.block_displacement(start_pos, start_quat)
        self._record(lam_moving, False)
        grew = bool(disp.max() >= DEVELOP_FACTOR * self.disp_tol)
        onset = max(
            self.onset_tol, self.driver.criteria.onset_ratio * self.compliance * (lam_moving - lam)
        )
        arrested = not grew and self.compliance > 0.0 and bool(disp.max() > onset)
        moving = (disp > (onset if arrested else self.disp_tol)) | (
            model.block_speed() > self.speed_tol
        )
        if arrested:
            logger.info(
                "lambda=%.4g: the mechanism stopped after %.3g m (blocks bearing on each other "
                "after finite rotations): arrested", lam_moving, disp.max(),
            )  # fmt: skip
        elif not grew:
            logger.warning(
                "lambda=%.4g: no block moved %g displacement thresholds while the motion was "
                "followed; the mechanism is not confirmed", lam_moving, DEVELOP_FACTOR,
            )  # fmt: skip
        return np.flatnonzero(moving).astype(np.int64), grew or arrested, arrested

    def _step(self, lam0: float, lam1: float) -> tuple[bool, np.ndarray]:
        """Ramp from ``lam0`` to ``lam1`` and hold; (stable, moving blocks)."""
        model = self.model
        start_pos, start_quat = model.pos.copy(), model.quat.copy()
        self.step_start = (start_pos, start_quat)
        # the rate of a step of ``step`` over ``ramp``, and never faster (the warm start)
        n_ramp = max(1, round(self.ramp * max(1.0, (lam1 - lam0) / self.driver.step) / model.dt))
        chunk = max(1, min(model.settings.chunk_steps, n_ramp))
        done = 0
        while done < n_ramp:
            n = min(chunk, n_ramp - done)
            frac = (done + n) / n_ramp
            model.set_external_wrench(self.driver.wrench(self.scene, lam0 + frac * (lam1 - lam0)))
            self._advance(n)
            done += n
        n_hold = max(1, round(self.hold / model.dt))
        self._advance(n_hold)
        # while blocks are faster than speed_tol, hold on (up to max_hold) until they stop or
        # one has moved past the displacement threshold: elastic creep and vibration stop or
        # stay below it, a mechanism does not
        extra, n_max = 0, round((self.driver.max_hold - 1.0) * n_hold)
        while True:
            moved = model.block_displacement(start_pos, start_quat) > self.disp_tol
            if np.any(moved):
                return False, np.flatnonzero(moved).astype(np.int64)
            fast = model.block_speed() > self.speed_tol
            if not np.any(fast):
                return True, np.zeros(0, dtype=np.int64)
            if extra >= n_max:
                logger.info("lambda=%.4g: blocks %s still move after max_hold but less than "
                            "the displacement threshold: stable", lam1,
                            np.flatnonzero(fast)[:10].tolist())  # fmt: skip
                return True, np.zeros(0, dtype=np.int64)
            n = min(max(1, n_hold // 4), n_max - extra)
            self._advance(n)
            extra += n

    def _advance(self, n: int) -> None:
        self.model.advance(n)
        self.steps += n

    def _record(self, lam: float, stable: bool) -> None:
        disp = self.model.block_displacement(self.ref_pos, self.ref_quat)
        self.rec_lambda.append(lam)
        self.rec_disp.append(float(disp.max()) if len(disp) else 0.0)
        self.rec_time.append(self.model.t)
        self.rec_stable.append(stable)
