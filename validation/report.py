"""Rows of a validation table and their JSON + markdown files (the contract of DESIGN.md).

Writes are atomic and together: a case runs inside :func:`staged`, which gives it a private
staging directory (:func:`output_dir`) for its side products (``.npz``, scenes, mechanisms);
:func:`write_results` writes the table there, and only when the case has finished are the
files moved into place with ``os.replace``, the side products first and ``CASE.json`` last
(it lists each side product with its SHA-256, so a reader can check that they belong
together). A case that fails, or a run that is killed, leaves the previous results whole.
"""

from __future__ import annotations

import contextlib
import contextvars
import dataclasses
import hashlib
import json
import math
import os
import shutil
import uuid
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from dem.estimate import Estimate
from validation import provenance
from validation.provenance import git_commit as _git_commit  # noqa: F401 (crosscheck.files)
from validation.provenance import versions as _versions  # noqa: F401 (crosscheck.files)

RESULTS_DIR = Path(__file__).parent / "results"
"""The committed results of full runs, all from one commit (``MANIFEST.json``)."""
QUICK_RESULTS_DIR = Path(__file__).parent / "results-quick"
"""Where quick runs write (git-ignored): a quick run never touches :data:`RESULTS_DIR`."""
RESULTS_ENV = "BLOCKMECH_RESULTS"
"""Environment variable naming the results folder readers use: ``quick``, ``full`` (the
default) or a path."""
STAGING_PREFIX = ".staging-"
"""Staging directories ``OUT/.staging-CASE-PID`` (git-ignored)."""

_STAGING: contextvars.ContextVar[Path | None] = contextvars.ContextVar("staging", default=None)
_FINAL: contextvars.ContextVar[Path | None] = contextvars.ContextVar("final", default=None)


def is_published(source: str) -> bool:
    """A reference from a seed's table or reported experiment (its difference is a model
    error), as opposed to a numerical reference (closed form, exact count, another method)."""
    s = source.lower()
    return s.startswith("seed ") and ("table" in s or "experiment" in s)


def printed_precision(printed: str, rounded: bool = False) -> float:
    """The precision of a number as a source prints it, its :attr:`Row.reference_error`: one
    unit in the last printed digit (``"16.2"`` -> 0.1, ``"168"`` -> 1, ``"2.25e9"`` -> 1e7),
    which holds whether the source rounded or truncated; half a unit where the source states
    that it rounds to nearest (``rounded``)."""
    text = printed.strip().lower()
    mantissa, _, exponent = text.partition("e")
    try:
        float(text)
    except ValueError:
        raise ValueError(f"printed_precision needs a number as printed, got {printed!r}") from None
    decimals = len(mantissa.partition(".")[2])
    unit = 10.0 ** (-decimals + (int(exponent) if exponent else 0))
    return 0.5 * unit if rounded else unit


REFERENCE_KINDS = ("value", "upper bound", "lower bound")
"""What a row's reference is (:attr:`Row.reference_kind`)."""


@dataclass
class Row:
    """One line of a validation table.

    Parameters
    ----------
    quantity
        What is compared, with its unit, e.g. ``"block volume 5x5 theta=2.5 [mm^3]"``.
    ours
        Our value, or our :class:`~dem.estimate.Estimate` (value and error bar; it sets
        ``error_sources``), or None when a method does not apply to the row.
    reference
        The independent value (closed form, seed table, other method), or None.
    source
        Where ``reference`` comes from, e.g. ``"seed 001 Table 1"`` or ``"closed form"``.
    wall_s
        Wall time of the computation that produced ``ours`` [s].
    settings
        Anything needed to reproduce the row (solver settings, discretisation, seed).
    extra
        Further columns (other methods' values, flags such as ``within_bounds``).
    error_sources
        Source -> half-width of ``ours``' error bar (same unit, >= 0; ``{"exact": 0}`` for an
        exact value). A numeric ``ours`` given without them has an unknown error
        (``{"not estimated": inf}``), never a silent zero.
    error_notes
        How the bar was estimated (levels, order assumed).
    reference_kind
        What ``reference`` is: ``"value"`` (the default: ours should equal it, so it should lie
        in our bar), ``"upper bound"`` (ours should lie at or below it) or ``"lower bound"``
        (at or above it). A bound is an inequality, never an equality to miss.
    reference_error
        Half-width of the reference's own bar (same unit, >= 0; 0 for a closed form;
        :func:`printed_precision` for a seed value quoted to a few digits): a value agrees when
        the two bars overlap, a bound holds when they reach the allowed side.
    model_difference
        How the reference's model differs from ours (an assumption of a seed's formula that our
        model tests, an approximate closed form, a calibrated model), empty when the reference
        is a value of our own model (exact closed form, count, another method on the same
        model). A seed's table or experiment is always another model (:func:`is_published`).
        A reference of another model outside our bar is a model error, never a numerical one.
    error_omits
        Known error sources the bar does not cover (:attr:`dem.estimate.Estimate.omitted`, set
        from an Estimate): a reference outside such a bar is a ``"partial bar"``.
    cost
        Whether ``ours`` is a cost of the run (a wall time [s] on this machine, a memory) rather
        than a result: a cost has no converged value for a bar to enclose (it changes with the
        machine and its load), so a cost row has no error bar (``ours_error`` None, no
        ``error_sources``) and prints as ``value (cost)``; its reference is a budget
        (``reference_kind="upper bound"``), met or not by the plain comparison.
    """

    quantity: str
    ours: float | Estimate | None
    reference: float | None = None
    source: str = ""
    wall_s: float | None = None
    settings: dict[str, Any] = field(default_factory=dict)
    extra: dict[str, Any] = field(default_factory=dict)
    error_sources: dict[str, float] = field(default_factory=dict)
    error_notes: str = ""
    reference_kind: str = "value"
    reference_error: float = 0.0
    model_difference: str = ""
    error_omits: list[str] = field(default_factory=list)
    cost: bool = False

    def __post_init__(self) -> None:
        if self.reference_kind not in REFERENCE_KINDS:
            raise ValueError(
                f"row {self.quantity!r}: reference_kind must be one of {REFERENCE_KINDS}, "
                f"got {self.reference_kind!r}"
            )
        if not (self.reference_error >= 0.0):  # False for NaN
            raise ValueError(
                f"row {self.quantity!r}: reference_error must be >= 0, got {self.reference_error!r}"
            )
        if self.cost:
            self._check_cost()
        elif isinstance(self.ours, Estimate):
            est = self.ours
            if self.error_sources:
                raise ValueError(f"row {self.quantity!r}: give an Estimate or error_sources")
            self.ours = est.value
            self.error_sources = dict(est.sources)
            self.error_notes = self.error_notes or est.notes
            self.error_omits = list(dict.fromkeys([*self.error_omits, *est.omitted]))
        elif self.ours is None:
            self.error_sources = {}
        else:
            self.ours = float(self.ours)
            if math.isnan(self.ours):
                raise ValueError(
                    f"row {self.quantity!r}: ours is NaN; give None (no value) and say why"
                )
            if not self.error_sources:
                self.error_sources = dict(Estimate.unknown(self.ours).sources)
            else:  # validated by Estimate
                self.error_sources = dict(Estimate(self.ours, self.error_sources).sources)

    def _check_cost(self) -> None:
        if isinstance(self.ours, Estimate) or self.error_sources or self.ours is None:
            raise ValueError(
                f"row {self.quantity!r}: a cost row takes a plain number, without error sources"
            )
        self.ours = float(self.ours)
        if not (math.isfinite(self.ours) and self.ours >= 0.0):
            raise ValueError(f"row {self.quantity!r}: a cost must be finite and >= 0")
        if self.reference is not None and self.reference_kind == "value":
            raise ValueError(
                f"row {self.quantity!r}: a cost's reference is a budget, give reference_kind "
                "'upper bound' (or 'lower bound')"
            )

    @property
    def estimate(self) -> Estimate | None:
        """``ours`` with its error bar, or None (no ``ours``, or a :attr:`cost`)."""
        if self.ours is None or self.cost:
            return None
        return Estimate(self.ours, self.error_sources, notes=self.error_notes,
                        omitted=tuple(self.error_omits))  # fmt: skip

    @property
    def ours_error(self) -> float | None:
        """Half-width of ``ours``' error bar (``inf`` when unknown), None without ``ours``."""
        est = self.estimate
        return None if est is None else est.error

    @property
    def rel_error(self) -> float | None:
        """|ours - reference| / |reference|, or the absolute error when the reference is 0."""
        if self.ours is None or self.reference is None:
            return None
        diff = abs(float(self.ours) - float(self.reference))
        scale = abs(float(self.reference))
        return diff / scale if scale > 0 else diff

    @property
    def reference_inside(self) -> bool | None:
        """Whether ours agrees with the reference within the bars: for a value, whether it lies
        in ``ours ± ours_error``; for an upper (lower) bound, whether ``ours - ours_error`` is
        at most (``ours + ours_error`` at least) the bound widened by ``reference_error``.
        None: nothing to compare, or either error is unknown, so the bars say nothing. A
        :attr:`cost` is compared with its budget as it is (it has no bar)."""
        if self.cost and self.reference is not None:
            if self.reference_kind == "upper bound":
                return self.ours <= self.reference
            return self.ours >= self.reference
        est = self.estimate
        if est is None or self.reference is None or not math.isfinite(est.error):
            return None
        if not math.isfinite(self.reference_error):
            return None
        ref = float(self.reference)
        if self.reference_kind == "upper bound":
            return est.lo <= ref + self.reference_error
        if self.reference_kind == "lower bound":
            return est.hi >= ref - self.reference_error
        if self.reference_error > 0.0:
            return est.overlaps(Estimate(ref, {"reference": self.reference_error}))
        return est.contains(ref)

    @property
    def reference_is_model(self) -> bool:
        """Whether the reference belongs to another model (:attr:`model_difference`, or a
        seed's table or experiment)."""
        return bool(self.model_difference) or is_published(self.source)

    @property
    def error_kind(self) -> str | None:
        """Why ours disagrees with the reference (:attr:`reference_inside` False): ``"model"``
        when the reference belongs to another model (:attr:`reference_is_model`: the physics
        differs, which no refinement removes), ``"numerical"`` when it is a value of our own
        model (our bar is too small, or a method is wrong; for a bound, the bound is broken);
        ``"partial bar"`` when our bar omits known sources (:attr:`error_omits`), so it does
        not claim to hold the converged answer; ``"over budget"`` for a :attr:`cost` that misses
        its budget; None when they agree or nothing is compared."""
        if self.reference_inside is not False:
            return None
        if self.cost:
            return "over budget"
        if self.reference_is_model:
            return "model"
        return "partial bar" if self.error_omits else "numerical"

    def to_dict(self) -> dict[str, Any]:
        out = dataclasses.asdict(self)
        out["reference"] = {"value": self.reference, "source": self.source}
        del out["source"]
        out["ours_error"] = self.ours_error
        out["rel_error"] = self.rel_error
        out["reference_inside"] = self.reference_inside
        out["reference_is_model"] = self.reference_is_model
        out["error_kind"] = self.error_kind
        return out

    def ours_text(self) -> str:
        """``value ± error`` rounded to the digits the error supports (``-`` without ours)."""
        if self.cost:
            return f"{self.ours:.3g} (cost)"
        est = self.estimate
        return "-" if est is None else est.format()


def results_dir(quick: bool) -> Path:
    """Where a run writes: :data:`QUICK_RESULTS_DIR` for a quick run, else :data:`RESULTS_DIR`."""
    return QUICK_RESULTS_DIR if quick else RESULTS_DIR


def reading_dir() -> Path:
    """The results folder that readers (figures, benchmarks) use: :data:`RESULTS_ENV` set to
    ``quick`` gives :data:`QUICK_RESULTS_DIR`, ``full`` or unset :data:`RESULTS_DIR`, anything
    else is a path."""
    choice = os.environ.get(RESULTS_ENV, "full")
    return {"full": RESULTS_DIR, "quick": QUICK_RESULTS_DIR}.get(choice, Path(choice))


def output_dir() -> Path:
    """Where a running case writes its side products: its staging directory inside
    :func:`staged`; outside a run (a test or a script calling a case's function) the folder
    :data:`RESULTS_ENV` names, or the quick folder, never the committed full results."""
    stage = _STAGING.get()
    if stage is not None:
        return stage
    chosen = reading_dir()
    return QUICK_RESULTS_DIR if chosen == RESULTS_DIR else chosen


def input_path(name: str) -> Path:
    """Another case's output ``name`` as a running case reads it: from the folder the run
    writes to (the quick folder for a quick run) when it is there, else from the committed
    full results (read only). Outside a run: :func:`reading_dir` ``/ name``."""
    final = _FINAL.get()
    if final is not None and (final / name).exists():
        return final / name
    return (RESULTS_DIR if final is not None else reading_dir()) / name


def final_path(name: str) -> str:
    """Where the side product ``name`` of a running case lands once the run ends (relative to
    the repository when it is inside it), for the files that name each other."""
    path = (_FINAL.get() or reading_dir()) / name
    try:
        return str(path.resolve().relative_to(provenance.REPO))
    except ValueError:
        return str(path.resolve())


def _jsonable(value: Any) -> Any:
    """Plain JSON types; NaN and inf become strings so that the file stays valid JSON."""
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if hasattr(value, "tolist"):
        return _jsonable(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    return value


def _fmt(value: Any) -> str:
    if value is None:
        return "-"
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, (int, float)):
        return f"{value:.6g}"
    return str(value)


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            digest.update(chunk)
    return digest.hexdigest()


def _write_atomic(path: Path, text: str) -> None:
    """Write through a temporary file in the same directory, then ``os.replace``. The file
    gets the mode of any other written file (0666 less the umask), not mkstemp's 0600."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.parent / f".{path.name}.{os.getpid()}.{uuid.uuid4().hex}.tmp"
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


@contextlib.contextmanager
def staged(case: str, out_dir: Path | None = None) -> Iterator[Path]:
    """Run a case's writes in a staging directory and move them into ``out_dir`` (default
    :data:`RESULTS_DIR`) only when the block ends without an exception (module notes). Stale
    staging directories of the same case (a killed run) are removed first."""
    out_dir = Path(RESULTS_DIR if out_dir is None else out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    for stale in out_dir.glob(f"{STAGING_PREFIX}{case}-*"):
        # only this case's (its name then a pid): "tis-friction" must not take the live
        # staging directory of "tis-friction-uq" running beside it
        if stale.name.removeprefix(f"{STAGING_PREFIX}{case}-").isdigit():
            shutil.rmtree(stale, ignore_errors=True)
    stage = out_dir / f"{STAGING_PREFIX}{case}-{os.getpid()}"
    stage.mkdir()
    token, final = _STAGING.set(stage), _FINAL.set(out_dir)
    try:
        yield stage
        _commit(stage, out_dir, case)
    finally:
        _STAGING.reset(token)
        _FINAL.reset(final)
        shutil.rmtree(stage, ignore_errors=True)


def _commit(stage: Path, out_dir: Path, case: str) -> None:
    """Move every staged file into ``out_dir``: side products, then ``CASE.md``, then
    ``CASE.json``."""
    last = [stage / f"{case}.md", stage / f"{case}.json"]
    files = [p for p in sorted(stage.rglob("*")) if p.is_file() and p not in last]
    for src in [*files, *(p for p in last if p.exists())]:
        dest = out_dir / src.relative_to(stage)
        dest.parent.mkdir(parents=True, exist_ok=True)
        os.replace(src, dest)


def write_results(
    case: str,
    rows: list[Row],
    *,
    quick: bool,
    wall_s: float,
    notes: str = "",
    out_dir: Path | None = None,
) -> tuple[Path, Path]:
    """Write ``CASE.json`` and ``CASE.md`` (each atomically) and return their paths.

    ``out_dir`` defaults to :func:`output_dir` (the staging directory of a running case). The
    JSON lists the side products already written there with their SHA-256, and records the
    commit, whether the working tree was clean (``git_clean``, ``git_dirty_files``), the date
    and the wall time.
    """
    out_dir = output_dir() if out_dir is None else Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    own = {f"{case}.json", f"{case}.md"}
    side = (
        {
            str(p.relative_to(out_dir)): _sha256(p)
            for p in sorted(out_dir.rglob("*"))
            if p.is_file() and p.name not in own and not p.name.startswith(".")
        }
        if _STAGING.get() == out_dir
        else {}
    )
    payload = {
        "case": case,
        "quick": quick,
        **provenance.stamp(),
        "versions": provenance.versions(),
        "wall_s": wall_s,
        "notes": notes,
        "side_products": side,
        "rows": [r.to_dict() for r in rows],
    }
    md_path, json_path = out_dir / f"{case}.md", out_dir / f"{case}.json"
    _write_atomic(md_path, markdown(payload, rows))
    _write_atomic(json_path, json.dumps(_jsonable(payload), indent=1) + "\n")
    return json_path, md_path


ERROR_LEGEND = (
    "`ours` is `value ± error`: the error bar of our method's own model (discretisation: load "
    "step, grid, mesh, end of path, duality gap), rounded to the digits it supports; `± ?` is "
    "an error not estimated. `ref in bar`: whether the reference lies in that bar; where it does "
    "not, `model` marks a reference from a seed's table or experiment (the physics of our model "
    "differs from the experiment: a model error, which no refinement removes) and `numerical` a "
    "closed form or another method (our bar is too small, or a method is wrong). A reference of "
    "another model (an approximate closed form, an assumption our model tests) says how it "
    "differs in its source cell (`other model: ...`) and is a `model` error too. A bar marked "
    "`(without ...)` omits the sources it names (the error budget did not pay for them): a "
    "reference outside it is a `partial bar`, not a numerical error. A reference "
    "that is a bound is an inequality: `below the bound` / `above the bound` says on which side "
    "of it ours lies within both bars (`yes` on the side it must, `no` on the wrong one). A "
    "`(cost)` is what the run spent (a wall time on a shared machine), not a result: it has no "
    "bar, and its reference is a budget it meets or not (`over budget`)."
)


def _source_cell(row: Row) -> str:
    if not row.model_difference:
        return row.source
    return f"{row.source} (other model: {row.model_difference})".lstrip()


def _inside_cell(row: Row) -> str:
    if row.reference is None or row.ours is None:
        return "-"
    if row.reference_inside is None:
        return "?"
    if row.reference_kind == "value":
        return "yes" if row.reference_inside else f"no ({row.error_kind})"
    below = row.reference_kind == "upper bound"
    side = "below" if below == row.reference_inside else "above"
    verdict = "yes" if row.reference_inside else f"no ({row.error_kind})"
    return f"{verdict}: {side} the bound"


def markdown(payload: dict[str, Any], rows: list[Row]) -> str:
    """The table of a case as markdown: header with commit, clean flag, date and wall time,
    the notes, the error legend, then one line per row."""
    extra_keys: list[str] = []
    for r in rows:
        extra_keys += [k for k in r.extra if k not in extra_keys]
    header = ["quantity", "ours", "reference", "source", "rel_error", "ref in bar", "wall_s"]
    header += extra_keys
    clean = payload["git_clean"]
    flag = {False: " (dirty tree)", True: "", None: " (tree state unknown)"}[clean]
    lines = [
        f"# {payload['case']}{' (quick)' if payload['quick'] else ''}",
        "",
        f"commit `{payload['git_commit'][:12]}`{flag}, {payload['date']}, "
        f"total {payload['wall_s']:.2f} s",
        "",
    ]
    if payload["notes"]:
        lines += [payload["notes"], ""]
    lines += [ERROR_LEGEND, ""]
    lines += ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        cells = [r.quantity, r.ours_text(), r.reference, _source_cell(r), r.rel_error,
                 _inside_cell(r)]  # fmt: skip
        cells += [r.wall_s, *(r.extra.get(k) for k in extra_keys)]
        lines.append("| " + " | ".join(_fmt(c) for c in cells) + " |")
    return "\n".join(lines) + "\n"
