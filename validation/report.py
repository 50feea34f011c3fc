"""Rows of a validation table and their JSON + markdown files (the contract of DESIGN.md)."""

from __future__ import annotations

import dataclasses
import datetime
import json
import math
import platform
import subprocess
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path
from typing import Any

RESULTS_DIR = Path(__file__).parent / "results"
_PACKAGES = ("numpy", "scipy", "numba", "scikit-fem", "gmsh", "meshio", "cvxpy", "clarabel")


@dataclass
class Row:
    """One line of a validation table.

    Parameters
    ----------
    quantity
        What is compared, with its unit, e.g. ``"block volume 5x5 theta=2.5 [mm^3]"``.
    ours
        Our value (None when a method does not apply to the row).
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
    """

    quantity: str
    ours: float | None
    reference: float | None = None
    source: str = ""
    wall_s: float | None = None
    settings: dict[str, Any] = field(default_factory=dict)
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def rel_error(self) -> float | None:
        """|ours - reference| / |reference|, or the absolute error when the reference is 0."""
        if self.ours is None or self.reference is None:
            return None
        diff = abs(float(self.ours) - float(self.reference))
        scale = abs(float(self.reference))
        return diff / scale if scale > 0 else diff

    def to_dict(self) -> dict[str, Any]:
        out = dataclasses.asdict(self)
        out["reference"] = {"value": self.reference, "source": self.source}
        del out["source"]
        out["rel_error"] = self.rel_error
        return out


def _git_commit() -> str:
    try:
        return subprocess.run(
            ["git", "rev-parse", "HEAD"],
            cwd=Path(__file__).parent,
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def _versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for name in _PACKAGES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


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


def write_results(
    case: str,
    rows: list[Row],
    *,
    quick: bool,
    wall_s: float,
    notes: str = "",
    out_dir: Path = RESULTS_DIR,
) -> tuple[Path, Path]:
    """Write ``CASE.json`` and ``CASE.md`` and return their paths."""
    out_dir.mkdir(parents=True, exist_ok=True)
    payload = {
        "case": case,
        "quick": quick,
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "git_commit": _git_commit(),
        "versions": _versions(),
        "wall_s": wall_s,
        "notes": notes,
        "rows": [r.to_dict() for r in rows],
    }
    json_path = out_dir / f"{case}.json"
    json_path.write_text(json.dumps(_jsonable(payload), indent=1) + "\n")

    extra_keys: list[str] = []
    for r in rows:
        extra_keys += [k for k in r.extra if k not in extra_keys]
    header = ["quantity", "ours", "reference", "source", "rel_error", "wall_s", *extra_keys]
    lines = [
        f"# {case}{' (quick)' if quick else ''}",
        "",
        f"commit `{payload['git_commit'][:12]}`, {payload['date']}, total {wall_s:.2f} s",
        "",
    ]
    if notes:
        lines += [notes, ""]
    lines += ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        cells = [r.quantity, r.ours, r.reference, r.source, r.rel_error, r.wall_s]
        cells += [r.extra.get(k) for k in extra_keys]
        lines.append("| " + " | ".join(_fmt(c) for c in cells) + " |")
    md_path = out_dir / f"{case}.md"
    md_path.write_text("\n".join(lines) + "\n")
    return json_path, md_path
