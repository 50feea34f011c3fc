"""numba kernels: flat arrays in, flat arrays out (numpy, numba and math only).

Compiled kernels are cached on disk. numba refreshes a cached function when its own file changes,
not when a kernel it calls from another file does, so a stale caller would silently run the old
callee. Every version of the kernel sources therefore gets its own cache directory, named by a
hash of their text, unless the user chose one with ``NUMBA_CACHE_DIR``.
"""

import hashlib
import os
from pathlib import Path

import numba


def source_keyed_cache_dir(package: Path) -> Path:
    """``package/__pycache__/numba/<hash>``: the hash covers the text of every ``*.py`` in
    ``package``, so any edit to any kernel moves every cached kernel to a fresh directory."""
    digest = hashlib.sha256()
    for source in sorted(package.glob("*.py")):
        digest.update(source.name.encode())
        digest.update(source.read_bytes())
    return package / "__pycache__" / "numba" / digest.hexdigest()[:16]


if not os.environ.get("NUMBA_CACHE_DIR"):
    numba.config.CACHE_DIR = str(source_keyed_cache_dir(Path(__file__).parent))
