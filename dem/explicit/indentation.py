"""Sphere indentation (seed 000, Sec. 3): relax under gravity, then drive a rigid sphere down.

Two phases: relaxation under gravity until the kinetic energy is below a tolerance, then a rigid
frictionless sphere driven down at constant speed onto a block, recording the indenter load
``P`` against its travel ``delta``. The run can be checkpointed and resumed bit for bit.

Counting, contact law and integration are documented in :mod:`dem.contact_nodes`,
:mod:`dem.kernels.contact_force` and :mod:`dem.kernels.integrate`.

Definitions of the results (:class:`IndentationResult`):

- ``delta`` [m]: indenter travel since the start of indentation, where the sphere just touches
  the top of the loaded block in its relaxed pose.
- ``load`` ``P`` [N]: mean indenter force over each recording interval, ``Delta W / Delta
  delta`` with ``W`` the work done by the indenter (so the area under the curve is ``W``).
- peak load ``P_max`` [N] and deflection at peak ``delta_peak`` [m]: the largest recorded ``P``
  and its ``delta``.
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
import os
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from dem.explicit.model import STATE_ARRAYS, ExplicitModel
from dem.explicit.results import (
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
from dem.kernels.integrate import (
    quat_to_rot,
)
from dem.scene import Scene
from dem.units import MM

logger = logging.getLogger(__name__)
# -- indentation driver with checkpoints -------------------------------------------------------


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
) -> IndentationResult:
    """Relax a scene under gravity, then indent one block at constant speed.

    Parameters
    ----------
    scene : Scene
    settings : ExplicitSettings
    indentation : IndentationSettings, optional
    relaxation : RelaxationSettings, optional
    checkpoint : path, optional
        ``.npz`` file. If it exists and was written for the same scene and settings, the run
        resumes from it; it is rewritten every ``checkpoint_every_s`` of wall time and at the
        end. A resumed run gives the same curve as an uninterrupted one.
    checkpoint_every_s : float
        [s] of wall time.
    stop_after_chunks : int, optional
        Testing hook: abandon the run after this many chunks of the indentation phase (after
        writing a checkpoint), raising ``KeyboardInterrupt``.

    Returns
    -------
    IndentationResult
    """
    indentation = indentation or IndentationSettings()
    relaxation = relaxation or RelaxationSettings()
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
        st = _RunState(key=key)
        relax_info = model.relax(relaxation)
        st.relax = relax_info
        top = model.scene.assembly.blocks[block]
        quat_to_rot(model.quat, model.rot)
        top_world = top.vertices @ model.rot[block].T + (
            model.pos[block] - model.rot[block] @ model.ref_centroid[block]
        )
        shift = model.pos[block] - model.ref_centroid[block]
        centre_xy = (
            model._top_centre(block)[:2] + shift[:2]
            if indentation.axis_xy is None
            else np.asarray(indentation.axis_xy, dtype=float)
        )
        st.centre0 = np.array(
            [centre_xy[0], centre_xy[1], top_world[:, 2].max() + indentation.tip_radius]
        )
        st.t0 = model.t
        if ckpt is not None:
            st.save(ckpt, model)
    else:
        logger.info("resumed from %s at delta=%.4g mm", ckpt, st.delta_now / MM)
    velocity = np.array([0.0, 0.0, -indentation.speed])
    ind = {"centre0": st.centre0, "t0": st.t0, "radius": indentation.tip_radius,
           "velocity": velocity}  # fmt: skip
    steps_per_record = max(1, round(indentation.record_interval / (indentation.speed * model.dt)))
    n_steps_total = math.ceil(indentation.max_deflection / (indentation.speed * model.dt))
    last_ckpt = time.perf_counter()
    last_log = time.perf_counter()
    loop_start = time.perf_counter()
    steps_start = st.steps
    chunks = 0
    while st.steps < n_steps_total and not st.finished:
        n = min(steps_per_record, n_steps_total - st.steps)
        acc = model.advance(n, indenter=ind)
        st.steps += n
        st.work += acc[1]
        delta = indentation.speed * (model.t - st.t0)
        d_prev = st.delta_now
        p_mean = acc[1] / (delta - d_prev) if delta > d_prev else acc[0]
        st.delta_now = delta
        st.record(model, delta, p_mean, acc[1])
        if delta >= st.next_snapshot:
            _, _, ef, ep, _ = model.contact_wrenches(None)
            pairs, force, point = interface_resultants(
                model.pair_node, model.pair_block, model.node_block, ef, ep
            )
            st.snapshots.append({"delta": delta, "pairs": pairs, "force": force,
                                 "point": point, "kind": "run"})  # fmt: skip
            st.next_snapshot += indentation.snapshot_interval
        if p_mean > st.best_load:
            st.best_load = p_mean
            st.peak = {name: getattr(model, name).copy() for name in STATE_ARRAYS}
            st.peak["t"] = np.array(model.t)
        if indentation.stop_when_out:
            summary = curve_summary(np.array(st.delta), np.array(st.load),
                                    indentation.ultimate_fraction, indentation.out_confirm) \
                if st.below_since(indentation) else None  # fmt: skip
            if summary is not None and math.isfinite(summary["ultimate_deflection"]):
                st.finished = True
        if indentation.stop_below_peak_fraction is not None:
            # the drop must persist over STOP_PERSIST of travel (not an impact transient)
            if p_mean < indentation.stop_below_peak_fraction * st.best_load:
                if st.below_from is None:
                    st.below_from = delta
                elif delta - st.below_from >= STOP_PERSIST:
                    st.finished = True
            else:
                st.below_from = None
        now = time.perf_counter()
        if now - last_log >= settings.progress_every_s:
            rate = (st.steps - steps_start) / (now - loop_start)
            eta = (n_steps_total - st.steps) / rate if rate > 0 else float("nan")
            logger.info(
                "indent %s: delta=%.4f mm P=%.3f N (peak %.3f N) %.0f steps/s, at most %.0f s "
                "left", scene.name, delta / MM, p_mean, st.best_load, rate, eta,
            )  # fmt: skip
            last_log = now
        chunks += 1
        if ckpt is not None and (
            now - last_ckpt >= checkpoint_every_s
            or (stop_after_chunks is not None and chunks >= stop_after_chunks)
        ):
            st.save(ckpt, model)
            last_ckpt = now
        if stop_after_chunks is not None and chunks >= stop_after_chunks:
            raise KeyboardInterrupt(f"stopped after {chunks} chunks (test hook)")
    st.finished = True
    loop_s = time.perf_counter() - loop_start
    if ckpt is not None:
        st.save(ckpt, model)
    wall_s = time.perf_counter() - wall0
    return _make_result(model, st, indentation, settings, relaxation, ind, wall_s, setup_s,
                        loop_s, st.steps - steps_start)  # fmt: skip


@dataclass
class _RunState:
    """Everything of an indentation run that a checkpoint must hold besides the model state."""

    key: str
    steps: int = 0
    work: float = 0.0
    delta_now: float = 0.0
    best_load: float = -math.inf
    finished: bool = False
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
    peak: dict = field(default_factory=dict)
    snapshots: list = field(default_factory=list)
    next_snapshot: float = 0.0
    below_from: float | None = None

    def record(self, model: ExplicitModel, delta: float, load: float, dwork: float) -> None:
        self.delta.append(delta)
        self.load.append(load)
        self.time.append(model.t - self.t0)
        self.kinetic.append(model.kinetic_energy())
        self.elastic.append(model.elastic_energy())
        self.work_hist.append(self.work)
        self.poses_pos.append(model.pos.copy())
        self.poses_quat.append(model.quat.copy())
        self.entries.append(int(np.count_nonzero(model.out_depth > 0)))

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
        data = {name: getattr(model, name) for name in STATE_ARRAYS}
        data.update({f"peak_{k}": v for k, v in self.peak.items()})
        scalars = {
            "key": self.key, "steps": self.steps, "work": self.work, "delta_now": self.delta_now,
            "best_load": self.best_load, "finished": self.finished, "t0": self.t0,
            "t": model.t, "relax": self.relax, "n_rebuilds": model.n_rebuilds,
            "next_snapshot": self.next_snapshot,
            "below_from": self.below_from,
            "snapshots": [(snap["delta"], snap["kind"]) for snap in self.snapshots],
        }  # fmt: skip
        for k, snap in enumerate(self.snapshots):
            for name in ("pairs", "force", "point"):
                data[f"snap{k}_{name}"] = snap[name]
        data["scalars"] = np.array(json.dumps(scalars, default=float))
        data["centre0"] = self.centre0
        for name in ("delta", "load", "time", "kinetic", "elastic", "work_hist", "entries"):
            data[f"rec_{name}"] = np.asarray(getattr(self, name))
        n = model.n_blocks
        data["rec_pos"] = np.asarray(self.poses_pos).reshape(-1, n, 3)
        data["rec_quat"] = np.asarray(self.poses_quat).reshape(-1, n, 4)
        tmp = path.with_name(path.name + ".tmp.npz")
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez(tmp, **data)
        os.replace(tmp, path)

    @classmethod
    def from_file(cls, path: Path, key: str, model: ExplicitModel) -> _RunState | None:
        with np.load(path) as data:
            scalars = json.loads(str(data["scalars"]))
            if scalars["key"] != key:
                logger.warning("checkpoint %s is for other settings: starting afresh", path)
                return None
            for name in STATE_ARRAYS:
                setattr(model, name, data[name].copy())
            m = len(model.pair_node)
            model.out_force = np.zeros((m, 3))
            model.out_point = np.zeros((m, 3))
            model.out_depth = np.zeros(m)
            model.t = float(scalars["t"])
            model.n_rebuilds = int(scalars["n_rebuilds"])
            st = cls(key=key)
            for name in (
                "steps",
                "work",
                "delta_now",
                "best_load",
                "finished",
                "t0",
                "relax",
                "next_snapshot",
            ):
                setattr(st, name, scalars[name])
            st.steps = int(st.steps)
            st.centre0 = data["centre0"].copy()
            for name in ("delta", "load", "time", "kinetic", "elastic", "work_hist", "entries"):
                setattr(st, name, data[f"rec_{name}"].tolist())
            st.poses_pos = list(data["rec_pos"].copy())
            st.poses_quat = list(data["rec_quat"].copy())
            st.peak = {k[5:]: data[k].copy() for k in data.files if k.startswith("peak_")}
            st.snapshots = [
                {"delta": d, "kind": kind, **{n: data[f"snap{k}_{n}"].copy()
                                              for n in ("pairs", "force", "point")}}
                for k, (d, kind) in enumerate(scalars["snapshots"])
            ]  # fmt: skip
        return st


def _make_result(model, st, indentation, settings, relaxation, ind, wall_s, setup_s, loop_s,
                 steps_run) -> IndentationResult:  # fmt: skip
    delta = np.asarray(st.delta)
    load = np.asarray(st.load)
    summary = curve_summary(delta, load, indentation.ultimate_fraction, indentation.out_confirm)
    pos = np.asarray(st.poses_pos).reshape(-1, model.n_blocks, 3)
    quat = np.asarray(st.poses_quat).reshape(-1, model.n_blocks, 4)
    snapshots = list(st.snapshots)
    peak_state = {}
    if st.peak:
        saved = {name: getattr(model, name).copy() for name in STATE_ARRAYS}
        saved_t = model.t
        for name in STATE_ARRAYS:
            setattr(model, name, st.peak[name].copy())
        model.t = float(st.peak["t"])
        _resize_out(model)
        centre = st.centre0 + ind["velocity"] * (model.t - st.t0)
        sphere = (centre, indentation.tip_radius, ind["velocity"])
        peak_state = export_peak_state(model, sphere)
        peak_state["delta"] = np.array(indentation.speed * (model.t - st.t0))
        peak_state["load"] = np.array(st.best_load)
        _, _, ef, ep, _ = model.contact_wrenches(sphere)
        pairs, force, point = interface_resultants(
            model.pair_node, model.pair_block, model.node_block, ef, ep
        )
        snapshots.append({"delta": float(peak_state["delta"]), "pairs": pairs, "force": force,
                          "point": point, "kind": "peak"})  # fmt: skip
        for name in STATE_ARRAYS:
            setattr(model, name, saved[name])
        model.t = saved_t
        _resize_out(model)
    snapshots.sort(key=lambda snap: snap["delta"])
    n_nodes = model.nodes.n_nodes + len(model.ind_block)
    info = {
        "dt": model.dt,
        "dt_critical": model.dt_critical,
        "omega_max": model.omega_max,
        "alpha": model.alpha,
        "beta": model.beta,
        "n_nodes": n_nodes,
        "n_entries": int(len(model.pair_node)),
        "steps_indentation": int(st.steps),
        "steps_relaxation": int(st.relax.get("steps", 0)),
        "relax": st.relax,
        "parallel": bool(model.parallel),
        "wall_s": wall_s,
        "setup_s": setup_s,
        "loop_s": loop_s,
        "steps_this_session": int(steps_run),
        "cost_per_node_step_s": loop_s / max(1, steps_run) / max(1, n_nodes),
        "cost_per_entry_step_s": loop_s / max(1, steps_run) / max(1, len(model.pair_node)),
        "settings": asdict(settings),
        "indentation": asdict(indentation),
        "relaxation": asdict(relaxation),
        "loaded_block": int(model.indenter_block),
    }
    return IndentationResult(
        delta=delta, load=load, time=np.asarray(st.time), kinetic=np.asarray(st.kinetic),
        elastic=np.asarray(st.elastic), work=np.asarray(st.work_hist), block_pos=pos,
        block_quat=quat, snapshots=snapshots, peak_state=peak_state, info=info, **summary,
    )  # fmt: skip


def _resize_out(model: ExplicitModel) -> None:
    m = len(model.pair_node)
    model.out_force = np.zeros((m, 3))
    model.out_point = np.zeros((m, 3))
    model.out_depth = np.zeros(m)
