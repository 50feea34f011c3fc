"""Shared reading and drawing helpers of the TIS figures (results npz of the tis-* cases)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from validation.report import reading_dir

RESULTS = reading_dir()  # validation/results, or BLOCKMECH_RESULTS (quick or a path)
OUT = Path(__file__).resolve().parent / "out"
MM = 1e-3


def load_npz(name: str, case: str) -> dict:
    """``validation/results/<name>``, or an error naming the case to run."""
    path = RESULTS / name
    if not path.exists():
        raise FileNotFoundError(f"{path} is missing: run 'python -m validation run {case} --quick'")
    with np.load(path) as data:
        return {k: data[k] for k in data.files}


def keys(store: dict) -> list[str]:
    """Run keys (``<key>/delta`` present) in file order."""
    return [k[: -len("/delta")] for k in store if k.endswith("/delta")]


def quat_to_rot(q: np.ndarray) -> np.ndarray:
    """(..., 4) scalar-first unit quaternions -> (..., 3, 3) rotations."""
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


def posed_blocks(store: dict, key: str, k: int) -> list[np.ndarray]:
    """Vertices of every block at pose record ``k`` of run ``key`` [m]."""
    verts, ptr = store[f"{key}/vertices"], store[f"{key}/vert_ptr"]
    c0 = store[f"{key}/ref_centroid"]
    pos, rot = store[f"{key}/pose_pos"][k], quat_to_rot(store[f"{key}/pose_quat"][k])
    return [(verts[ptr[i] : ptr[i + 1]] - c0[i]) @ rot[i].T + pos[i] for i in range(len(ptr) - 1)]


def hull_faces(points: np.ndarray) -> list[np.ndarray]:
    """Triangles (as (3, 3) arrays) of the convex hull of a block's vertices, for drawing."""
    from scipy.spatial import ConvexHull

    hull = ConvexHull(points)
    return [points[s] for s in hull.simplices]
