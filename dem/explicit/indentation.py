"""Sphere indentation (seed 000, Sec. 3): relax under gravity, then drive a rigid sphere down.

Two phases: relaxation under gravity until the kinetic energy is below a tolerance, then a rigid
frictionless sphere driven down at constant speed onto a block, recording the indenter load
``P`` against its travel ``delta``. The run can be checkpointed and resumed bit for bit.

Counting, contact law and integration are documented in :mod:`dem.contact_nodes`,
:mod:`dem.kernels.contact_force` and :mod:`dem.kernels.integrate`.

Definitions of the results (:class:`IndentationResult`):

- ``delta`` [m]: indenter travel since the start of indentation, where the sphere's lowest
  point is level with the highest vertex of the loaded block in its relaxed pose: it just
  touches a level top. Under a top that is not level (an inclined face, an axis off a tilted
  block) the tip travels some way before it touches: ``info["delta_first_contact"]`` is the
  first recorded ``delta`` with a positive load, and a warning gives it when it exceeds the
  margin (subtract it to count from the contact).
- ``load`` ``P`` [N]: mean indenter force over each recording interval, ``Delta W / Delta
  delta`` with ``W`` the work done by the indenter (so the area under the curve is ``W``).
- peak load ``P_max`` [N] and deflection at peak ``delta_peak`` [m]: the largest recorded ``P``
  and its ``delta``. ``peak_reached``: ``P`` fell after it to ``stop_below_peak_fraction``
  of it, or to :data:`~dem.explicit.results.PEAK_DROP_FRACTION` of it if that is None; when
  False (the run ended, or was stopped, with the load still rising or level) ``P_max`` is only
  the largest load so far, a lower bound, and a warning says so.
- ultimate deflection ``delta_u`` [m]: the first ``delta`` after the peak at which ``P`` falls
  to ``ultimate_fraction * P_max`` and stays there for ``out_confirm`` of further travel (the
  loaded block has slipped out); NaN if the run ended before.
- loading energy ``LE`` [J]: the work of the indenter up to ``delta_u`` (up to the end of the
  run if ``delta_u`` was not reached), ``int_0^{delta_u} P d delta``.
"""

from __future__ import annotations

import hashlib
import json
import logging
import math
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from dem.estimate import ErrorBudget, check_error_budget
from dem.explicit.checkpoint import CheckpointError, read_checkpoint, write_checkpoint
from dem.explicit.indentation_error import indentation_estimates
from dem.explicit.model import ExplicitModel
from dem.explicit.results import (
    PEAK_DROP_FRACTION,
    IndentationResult,
    curve_summary,
    export_peak_state,
    interface_resultants,
)
from dem.explicit.settings import (
    STOP_PERSIST,
    ExplicitSettings,
    IndentationSettings,
    RelaxationSettings,
)
from dem.explicit.state import ExplicitState
from dem.explicit.unmodelled import UnmodelledContactError
from dem.scene import Scene
from dem.units import MM

logger = logging.getLogger(__name__)


def _settings_key(scene: Scene, settings, relaxation, indentation) -> str:
    payload = json.dumps(
        [scene.to_dict(), asdict(settings), asdict(relaxation), asdict(indentation)],
        sort_keys=True,
        default=str,
    )
    return hashlib.sha256(payload.encode()).hexdigest()[:16]


def simulate_indentation(
    scene: Scene,
    settings: ExplicitSettings,
    indentation: IndentationSettings | None = None,
    relaxation: RelaxationSettings | None = None,
    checkpoint: str | Path | None = None,
    checkpoint_every_s: float = 60.0,
    stop_after_chunks: int | None = None,
    error: ErrorBudget = "none",
) -> IndentationResult:
    """Relax a scene under gravity, then indent one block at constant speed; optionally
    estimate the errors of the curve's numbers.

    Parameters
    ----------
    scene : Scene
    settings : ExplicitSettings
    indentation : IndentationSettings, optional
    relaxation : RelaxationSettings, optional
    checkpoint : path, optional
        ``.npz`` file. If it exists and was written for the same scene and settings, the run
        resumes from it; it is rewritten every ``checkpoint_every_s`` of wall time and at the
        end. A resumed run gives the same curve as an uninterrupted one. (The reruns of the
        error estimate are not checkpointed.)
    checkpoint_every_s : float
        [s] of wall time.
    stop_after_chunks : int, optional
        Testing hook: abandon the run after this many chunks of the indentation phase (after
        writing a checkpoint), raising ``KeyboardInterrupt``.
    error : {"none", "cheap", "full"}
        What ``result.estimates`` measures (:mod:`dem.explicit.indentation_error`): ``"none"``
        nothing (unknown bars), ``"cheap"`` the sampling of the curve and the loading rate
        (one more run at half the speed), ``"full"`` also the time step and the node spacing
        (a run each at half of it).

    Returns
    -------
    IndentationResult
        With ``estimates``: peak load, deflection at peak, loading energy and ultimate
        deflection with their error bars.
    """
    check_error_budget(error)
    indentation = indentation or IndentationSettings()
    relaxation = relaxation or RelaxationSettings()
    result = _run_once(scene, settings, indentation, relaxation,
                       (checkpoint, checkpoint_every_s, stop_after_chunks))  # fmt: skip

    def run(settings_: ExplicitSettings, indentation_: IndentationSettings) -> IndentationResult:
        return _run_once(scene, settings_, indentation_, relaxation, (None, math.inf, None))

    result.estimates = indentation_estimates(run, settings, indentation, result, error)
    return result


def _run_once(scene, settings, indentation, relaxation, checkpointing) -> IndentationResult:
    """One run of :func:`simulate_indentation` (no error estimate); ``checkpointing`` is
    ``(path or None, every [s], stop_after_chunks)``."""
    checkpoint, every_s, stop_after_chunks = checkpointing
    wall0 = time.perf_counter()
    block = indentation.block
    if block is None:
        if "central_block" not in scene.meta:
            raise ValueError("IndentationSettings.block is None and the scene has no central_block")
        block = int(scene.meta["central_block"])
    model = ExplicitModel(scene, settings, block, indentation.tip_radius, indentation.axis_xy)
    setup_s = time.perf_counter() - wall0
    key = _settings_key(scene, settings, relaxation, indentation)
    ckpt = Path(checkpoint) if checkpoint is not None else None
    st = _RunState.from_file(ckpt, key, model) if ckpt is not None and ckpt.exists() else None
    if st is None:
        st = _RunState(key=key, relax=model.relax(relaxation), t0=model.t)
        st.centre0 = _sphere_start(model, block, indentation)
        model.check_indenter(st.centre0, indentation.tip_radius, start=True)
        if ckpt is not None:
            st.save(ckpt, model)
    else:
        logger.info("resumed from %s at delta=%.4g mm", ckpt, st.delta_now / MM)
    ind = {"centre0": st.centre0, "t0": st.t0, "radius": indentation.tip_radius,
           "velocity": np.array([0.0, 0.0, -indentation.speed])}  # fmt: skip
    loop = _indent(model, st, ind, indentation, (ckpt, every_s, stop_after_chunks))
    st.finished = True
    if ckpt is not None:
        st.save(ckpt, model)
    wall_s = time.perf_counter() - wall0
    return _make_result(model, st, indentation, settings, relaxation, ind, wall_s, setup_s, loop)


def _indent(model: ExplicitModel, st: _RunState, ind: dict, indentation: IndentationSettings,
            checkpointing: tuple) -> tuple[float, float, int]:  # fmt: skip
    """Drive the sphere down from ``st`` to the end of the run (or a stop criterion), record by
    record; ``checkpointing`` as :func:`_run_once`. Returns the loop's wall and process-CPU
    times [s] and the steps it ran."""
    ckpt, every_s, stop_after_chunks = checkpointing
    steps_per_record = max(1, round(indentation.record_interval / (indentation.speed * model.dt)))
    n_steps_total = math.ceil(indentation.max_deflection / (indentation.speed * model.dt))
    last_ckpt = last_log = loop_start = time.perf_counter()
    loop_cpu0 = time.process_time()
    steps_start = st.steps
    chunks = 0
    while st.steps < n_steps_total and not st.finished:
        n = min(steps_per_record, n_steps_total - st.steps)
        try:
            acc = model.advance(n, indenter=ind)
            centre = st.centre0 + ind["velocity"] * (model.t - st.t0)
            overlap = model.check_indenter(centre, indentation.tip_radius)
            st.indenter_overlap_max = max(st.indenter_overlap_max, overlap)
        except UnmodelledContactError as exc:
            # the curve up to the last record holds; past it the blocks (or the indenter and a
            # block) pass through each other
            logger.warning("indent %s stopped: %s", model.scene.name, exc)
            st.stopped_by = str(exc)
            break
        p_mean, delta = st.advance(model, n, acc, indentation)
        st.check_stop(p_mean, delta, indentation)
        now = time.perf_counter()
        if now - last_log >= model.settings.progress_every_s:
            rate = (st.steps - steps_start) / (now - loop_start)
            _log_progress(model, st, p_mean, delta, rate, n_steps_total)
            last_log = now
        chunks += 1
        stop_now = stop_after_chunks is not None and chunks >= stop_after_chunks
        if ckpt is not None and (now - last_ckpt >= every_s or stop_now):
            st.save(ckpt, model)
            last_ckpt = now
        if stop_now:
            raise KeyboardInterrupt(f"stopped after {chunks} chunks (test hook)")
    loop_s = time.perf_counter() - loop_start
    return loop_s, time.process_time() - loop_cpu0, st.steps - steps_start


def _log_progress(model, st, p_mean: float, delta: float, rate: float, n_steps_total: int):
    """One progress line at INFO level (``rate`` in steps per second of wall time)."""
    logger.info(
        "indent %s: delta=%.4f mm P=%.3f N (peak %.3f N) %.0f steps/s, at most %.0f s left",
        model.scene.name, delta / MM, p_mean, st.best_load, rate,
        (n_steps_total - st.steps) / rate if rate > 0 else float("nan"),
    )  # fmt: skip


def _sphere_start(model: ExplicitModel, block: int, indentation: IndentationSettings) -> np.ndarray:
    """(3,) centre of the sphere just touching the top of the relaxed loaded block [m]."""
    top = model.scene.assembly.blocks[block]
    rot = model.rotations()[block]
    top_world = top.vertices @ rot.T + (model.pos[block] - rot @ model.ref_centroid[block])
    shift = model.pos[block] - model.ref_centroid[block]
    centre_xy = (
        model._top_centre(block)[:2] + shift[:2]
        if indentation.axis_xy is None
        else np.asarray(indentation.axis_xy, dtype=float)
    )
    return np.array([centre_xy[0], centre_xy[1], top_world[:, 2].max() + indentation.tip_radius])


_RECORDS = ("delta", "load", "time", "kinetic", "elastic", "work_hist", "entries")
_SCALARS = ("steps", "work", "delta_now", "best_load", "finished", "t0", "relax",
            "next_snapshot", "below_from", "stopped_by", "indenter_overlap_max")  # fmt: skip
_SCALARS_ADDED = {"stopped_by": "", "indenter_overlap_max": float("nan")}
"""Scalars that older checkpoints lack, with the value a resumed run takes (nan: unknown)."""


@dataclass
class _RunState:
    """Everything of an indentation run that a checkpoint must hold besides the model state."""

    key: str
    steps: int = 0
    work: float = 0.0
    delta_now: float = 0.0
    best_load: float = -math.inf
    finished: bool = False
    stopped_by: str = ""
    indenter_overlap_max: float = 0.0
    centre0: np.ndarray = field(default_factory=lambda: np.zeros(3))
    t0: float = 0.0
    relax: dict = field(default_factory=dict)
    delta: list = field(default_factory=list)
    load: list = field(default_factory=list)
    time: list = field(default_factory=list)
    kinetic: list = field(default_factory=list)
    elastic: list = field(default_factory=list)
    work_hist: list = field(default_factory=list)
    poses_pos: list = field(default_factory=list)
    poses_quat: list = field(default_factory=list)
    entries: list = field(default_factory=list)
    peak: ExplicitState | None = None
    snapshots: list = field(default_factory=list)
    next_snapshot: float = 0.0
    below_from: float | None = None

    def advance(self, model: ExplicitModel, n: int, acc: np.ndarray, ind: IndentationSettings):
        """Book ``n`` steps just run: record, snapshot, peak. Returns ``(P, delta)``."""
        self.steps += n
        self.work += acc[1]
        delta = ind.speed * (model.t - self.t0)
        d_prev = self.delta_now
        p_mean = acc[1] / (delta - d_prev) if delta > d_prev else acc[0]
        self.delta_now = delta
        self.record(model, delta, p_mean)
        if delta >= self.next_snapshot:
            self.snapshots.append(_snapshot(model, None, delta, "run"))
            self.next_snapshot += ind.snapshot_interval
        if p_mean > self.best_load:
            self.best_load = p_mean
            self.peak = model.snapshot()
        return p_mean, delta

    def check_stop(self, p_mean: float, delta: float, ind: IndentationSettings) -> None:
        """Set ``finished`` once the block is out, or the load stays below the stop fraction."""
        if ind.stop_when_out and self.below_since(ind):
            summary = curve_summary(np.array(self.delta), np.array(self.load),
                                    ind.ultimate_fraction, ind.out_confirm)  # fmt: skip
            if math.isfinite(summary["ultimate_deflection"]):
                self.finished = True
        if ind.stop_below_peak_fraction is not None:
            # the drop must persist over STOP_PERSIST of travel (not an impact transient)
            if p_mean < ind.stop_below_peak_fraction * self.best_load:
                if self.below_from is None:
                    self.below_from = delta
                elif delta - self.below_from >= STOP_PERSIST:
                    self.finished = True
            else:
                self.below_from = None

    def record(self, model: ExplicitModel, delta: float, load: float) -> None:
        self.delta.append(delta)
        self.load.append(load)
        self.time.append(model.t - self.t0)
        self.kinetic.append(model.kinetic_energy())
        self.elastic.append(model.elastic_energy())
        self.work_hist.append(self.work)
        self.poses_pos.append(model.pos.copy())
        self.poses_quat.append(model.quat.copy())
        self.entries.append(int(np.count_nonzero(model.scratch.out_depth > 0)))

    def below_since(self, ind: IndentationSettings) -> bool:
        """Cheap pre-test: the loads over the last ``out_confirm`` of travel (and the record
        just before it) are all below the ultimate fraction of the peak."""
        if len(self.load) < 2 or self.best_load <= 0:
            return False
        d = np.asarray(self.delta)
        first = int(np.searchsorted(d, d[-1] - ind.out_confirm, side="left"))
        if first < 1:
            return False
        tail = np.asarray(self.load[first - 1 :])
        return bool(np.all(tail <= ind.ultimate_fraction * self.best_load))

    def save(self, path: Path, model: ExplicitModel) -> None:
        """Write the model state, the peak state, the records and the snapshots."""
        arrays = model.state.to_arrays("state.")
        if self.peak is not None:
            arrays.update(self.peak.to_arrays("peak."))
        for k, snap in enumerate(self.snapshots):
            for name in ("pairs", "force", "point"):
                arrays[f"snap{k}.{name}"] = snap[name]
        arrays["centre0"] = self.centre0
        for name in _RECORDS:
            arrays[f"rec.{name}"] = np.asarray(getattr(self, name))
        n = model.n_blocks
        arrays["rec.pos"] = np.asarray(self.poses_pos).reshape(-1, n, 3)
        arrays["rec.quat"] = np.asarray(self.poses_quat).reshape(-1, n, 4)
        meta = {name: getattr(self, name) for name in _SCALARS}
        meta.update(key=self.key, snapshots=[(s["delta"], s["kind"]) for s in self.snapshots])
        write_checkpoint(path, arrays, json.loads(json.dumps(meta, default=float)))

    @classmethod
    def from_file(cls, path: Path, key: str, model: ExplicitModel) -> _RunState | None:
        """The run stored in ``path`` with the model restored to it; None if for another key.

        Raises
        ------
        CheckpointError
            If the file is damaged or not a checkpoint of ours.
        """
        arrays, meta = read_checkpoint(path)
        if meta.get("key") != key:
            logger.warning("checkpoint %s is for other settings: starting afresh", path)
            return None
        try:
            model.restore(ExplicitState.from_arrays(arrays, "state."))
            kept = [name for name in _SCALARS if name not in _SCALARS_ADDED]
            st = cls(key=key, **{name: meta[name] for name in kept})
            for name, value in _SCALARS_ADDED.items():
                setattr(st, name, meta.get(name, value))
            st.steps = int(st.steps)
            if "peak.t" in arrays:
                st.peak = ExplicitState.from_arrays(arrays, "peak.")
            st.centre0 = arrays["centre0"].copy()
            for name in _RECORDS:
                setattr(st, name, arrays[f"rec.{name}"].tolist())
            st.poses_pos = list(arrays["rec.pos"].copy())
            st.poses_quat = list(arrays["rec.quat"].copy())
            st.snapshots = [
                {"delta": d, "kind": kind,
                 **{n: arrays[f"snap{k}.{n}"].copy() for n in ("pairs", "force", "point")}}
                for k, (d, kind) in enumerate(meta["snapshots"])
            ]  # fmt: skip
        except KeyError as exc:
            raise CheckpointError(path, f"lacks the entry {exc.args[0]!r}") from None
        return st


def _snapshot(model: ExplicitModel, sphere, delta: float, kind: str) -> dict:
    """Interface resultants at the current state (see :func:`interface_resultants`)."""
    _, _, ef, ep, _ = model.contact_wrenches(sphere)
    contacts = model.state.contacts
    pairs, force, point = interface_resultants(contacts.node, contacts.block,
                                               model.surface.block, ef, ep)  # fmt: skip
    return {"delta": delta, "pairs": pairs, "force": force, "point": point, "kind": kind}


def _make_result(model, st, indentation, settings, relaxation, ind, wall_s, setup_s,
                 loop) -> IndentationResult:  # fmt: skip
    """The result of a run; ``loop`` is the wall and process-CPU time of the indentation loop
    [s] and the steps it ran."""
    loop_s, loop_cpu_s, steps_run = loop
    delta = np.asarray(st.delta)
    load = np.asarray(st.load)
    summary = curve_summary(delta, load, indentation.ultimate_fraction, indentation.out_confirm,
                            indentation.stop_below_peak_fraction or PEAK_DROP_FRACTION)  # fmt: skip
    if not summary["peak_reached"]:
        logger.warning(
            "indent %s: the peak was not reached (the load never fell below %.2g of its largest "
            "value %.4g N, at %.4g mm of %.4g mm; %s): peak_load is the largest load so far, "
            "a lower bound", model.scene.name,
            indentation.stop_below_peak_fraction or PEAK_DROP_FRACTION,
            summary["peak_load"], summary["deflection_at_peak"] / MM,
            delta[-1] / MM if len(delta) else 0.0, st.stopped_by or "the run reached its end",
        )  # fmt: skip
    pos = np.asarray(st.poses_pos).reshape(-1, model.n_blocks, 3)
    quat = np.asarray(st.poses_quat).reshape(-1, model.n_blocks, 4)
    snapshots = list(st.snapshots)
    peak_state = {}
    if st.peak is not None:
        saved = model.snapshot()
        model.restore(st.peak)
        centre = st.centre0 + ind["velocity"] * (model.t - st.t0)
        sphere = (centre, indentation.tip_radius, ind["velocity"])
        peak_state = export_peak_state(model, sphere)
        peak_state["delta"] = np.array(indentation.speed * (model.t - st.t0))
        peak_state["load"] = np.array(st.best_load)
        snapshots.append(_snapshot(model, sphere, float(peak_state["delta"]), "peak"))
        model.restore(saved)
    snapshots.sort(key=lambda snap: snap["delta"])
    touching = np.flatnonzero(load > 0)
    first_contact = float(delta[touching[0]]) if len(touching) else math.nan
    if first_contact > settings.margin:
        logger.warning(
            "indent %s: the tip first touched after %.4g mm of travel (the top of block %d "
            "under it is below its highest vertex): delta counts from the start above that "
            "vertex", model.scene.name, first_contact / MM, model.indenter_block,
        )  # fmt: skip
    n_nodes = model.nodes.n_nodes + len(model.indenter.block)
    info = {
        "dt": model.dt,
        "dt_critical": model.dt_critical,
        "omega_max": model.omega_max,
        "step_check": model.step_check.as_dict(),
        "alpha": model.alpha,
        "beta": model.beta,
        "n_nodes": n_nodes,
        "n_entries": model.n_entries,
        "steps_indentation": int(st.steps),
        "steps_relaxation": int(st.relax.get("steps", 0)),
        "relax": st.relax,
        "parallel": bool(model.parallel),
        "wall_s": wall_s,
        "setup_s": setup_s,
        "loop_s": loop_s,
        "steps_this_session": int(steps_run),
        "cost_per_node_step_s": loop_s / max(1, steps_run) / max(1, n_nodes),
        "cpu_per_node_step_s": loop_cpu_s / max(1, steps_run) / max(1, n_nodes),
        "cost_per_entry_step_s": loop_s / max(1, steps_run) / max(1, model.n_entries),
        "settings": asdict(settings),
        "indentation": asdict(indentation),
        "relaxation": asdict(relaxation),
        "loaded_block": int(model.indenter_block),
        "stopped_by": st.stopped_by,
        "indenter_overlap_max": st.indenter_overlap_max,
        "delta_first_contact": first_contact,
    }
    return IndentationResult(
        delta=delta, load=load, time=np.asarray(st.time), kinetic=np.asarray(st.kinetic),
        elastic=np.asarray(st.elastic), work=np.asarray(st.work_hist), block_pos=pos,
        block_quat=quat, snapshots=snapshots, peak_state=peak_state, info=info, **summary,
    )  # fmt: skip
