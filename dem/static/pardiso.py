r"""MKL PARDISO (Intel oneMKL's supernodal sparse LU) through ctypes, for the static Newton.

The bordered tangent ``[[K_t, -F_L], [w^T, 0]]`` keeps its pattern from one Newton iteration
to the next (the interfaces and the constraint weights of a step do not change), so the
analysis (METIS nested dissection and the symbolic factorisation) is kept and only the
numeric factorisation is redone while the pattern is the same.

Settings (``iparm``, zero-based as in C): real non-symmetric matrix, METIS ordering, no
weighted matching and no scaling (the diagonal of ``K_t`` dominates and the border's zero
pivot comes last in the elimination; the matching also makes the analysis depend on the
values, which defeats its reuse), pivots below ``1e-13 |A|`` perturbed. A factorisation
that perturbed any pivot is numerically singular at double precision: it is reported as a
failure (:class:`PardisoError`) and the caller decides (``dem.static.newton`` falls back to
SuperLU, which declares the matrix singular or factors it with its own pivoting).

The threads are MKL's (``threadpoolctl``'s "blas" API limits them, as ``solve_collapse``
does); the library is loaded at import so that such a limit finds it.

Notes
-----
The CSC arrays of ``A`` are the CSR arrays of ``A^T``; PARDISO solves with the transpose of
what it factored (``iparm[11] = 2``), which is ``A``.
"""

from __future__ import annotations

import ctypes
import glob
import sys
import weakref
from ctypes.util import find_library
from pathlib import Path

import numpy as np
import scipy.sparse as sp

REAL_NONSYMMETRIC = 11
ANALYSE, FACTOR, SOLVE, RELEASE = 11, 22, 33, -1
PERTURBED = 13  # iparm index: number of perturbed pivots after the numeric factorisation
FACTOR_ENTRIES = 17  # iparm index: entries in the factors L and U


class PardisoError(RuntimeError):
    """A PARDISO phase that failed (its error code) or a numerically singular matrix."""


def _library():
    """oneMKL's single dynamic library (the ``mkl`` wheel's in ``sys.prefix/lib``, or the
    system's), or None."""
    candidates = [find_library("mkl_rt")]
    candidates += sorted(glob.glob(str(Path(sys.prefix) / "lib" / "libmkl_rt.so*")), key=len)
    for path in filter(None, candidates):
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        fn = lib.pardiso
        int_p = ctypes.POINTER(ctypes.c_int32)
        fn.argtypes = [ctypes.c_void_p] + [int_p] * 5 + [ctypes.c_void_p, int_p, int_p, int_p,
                                                         int_p, int_p, int_p] + \
            [ctypes.c_void_p, ctypes.c_void_p, int_p]  # fmt: skip
        fn.restype = None
        return fn
    return None


_PARDISO = _library()
AVAILABLE = _PARDISO is not None


def _iparm() -> np.ndarray:
    iparm = np.zeros(64, dtype=np.int32)
    iparm[0] = 1  # these settings, not the defaults
    iparm[1] = 2  # METIS nested dissection
    iparm[9] = 13  # perturb pivots below 1e-13 |A|
    iparm[10] = 0  # no scaling
    iparm[11] = 2  # solve with the transpose of the factored (CSR) arrays
    iparm[12] = 0  # no weighted matching
    iparm[34] = 1  # zero-based indices
    return iparm


def _pointer(array: np.ndarray | None, ctype=None):
    if array is None:
        return None
    return array.ctypes.data if ctype is None else array.ctypes.data_as(ctypes.POINTER(ctype))


def _call(pt, iparm, phase: int, A: sp.csc_matrix | None, n: int, b=None) -> np.ndarray | None:
    """One PARDISO ``phase`` on the handle ``pt`` with ``A`` (CSC read as the CSR of
    ``A^T``) and, for a solve, the right-hand side ``b`` (n,); the solution, or None."""
    c_int = ctypes.c_int32
    one, error = c_int(1), c_int(0)
    x = None if b is None else np.zeros_like(b)
    arrays = (None, None, None) if A is None else (A.data, A.indptr, A.indices)
    _PARDISO(
        _pointer(pt), ctypes.byref(one), ctypes.byref(one), ctypes.byref(c_int(REAL_NONSYMMETRIC)),
        ctypes.byref(c_int(phase)), ctypes.byref(c_int(n)), _pointer(arrays[0]),
        _pointer(arrays[1], c_int), _pointer(arrays[2], c_int), None, ctypes.byref(one),
        _pointer(iparm, c_int), ctypes.byref(c_int(0)), _pointer(b), _pointer(x),
        ctypes.byref(error),
    )  # fmt: skip
    if error.value != 0:
        raise PardisoError(f"PARDISO phase {phase} failed with error {error.value}")
    return x


def _release(pt: np.ndarray, iparm: np.ndarray, n: int) -> None:
    """Free PARDISO's memory of the handle ``pt`` (the factorisation's finaliser)."""
    if pt.any():
        _call(pt, iparm, RELEASE, None, n)


class PardisoLU:
    """One PARDISO factorisation of a square CSC matrix, refactored in place.

    ``factor(A)`` redoes only the numeric factorisation when ``A`` has the pattern of the
    last analysis, else the analysis too; ``solve(b)`` solves with the last factorisation.
    After a failed ``factor`` the object holds no factorisation and ``solve`` raises.
    """

    def __init__(self):
        if not AVAILABLE:
            raise PardisoError("oneMKL's library (mkl_rt) was not found")
        self.pt = np.zeros(64, dtype=np.int64)  # PARDISO's opaque handle
        self.iparm = _iparm()
        self.shape = (0, 0)
        self._pattern = None  # (indptr, indices) of the last analysis
        self._valid = False
        self._finaliser = weakref.finalize(self, _release, self.pt, self.iparm, 0)

    def _same_pattern(self, A: sp.csc_matrix) -> bool:
        if self._pattern is None or A.shape != self.shape:
            return False
        indptr, indices = self._pattern
        return np.array_equal(indptr, A.indptr) and np.array_equal(indices, A.indices)

    def _analyse(self, A: sp.csc_matrix) -> None:
        """Release the last factorisation and analyse the pattern of ``A`` (ordering and
        symbolic factorisation)."""
        _release(self.pt, self.iparm, self.shape[0])
        self.pt[:] = 0
        self._pattern = None
        self.shape = A.shape
        self._finaliser.detach()
        self._finaliser = weakref.finalize(self, _release, self.pt, self.iparm, A.shape[0])
        self.iparm[FACTOR_ENTRIES] = -1  # the analysis reports the entries of the factors
        _call(self.pt, self.iparm, ANALYSE, A, A.shape[0])
        self._pattern = (A.indptr.copy(), A.indices.copy())

    def factor(self, A: sp.csc_matrix) -> PardisoLU:
        """Factor ``A`` (square CSC, sorted 32-bit indices, finite values) in place; raise
        :class:`PardisoError` if PARDISO fails or perturbs a pivot."""
        self._valid = False
        A = _checked(A)
        if not self._same_pattern(A):
            self._analyse(A)
        _call(self.pt, self.iparm, FACTOR, A, A.shape[0])
        self._A = A
        if self.iparm[PERTURBED] > 0:
            raise PardisoError(f"{self.iparm[PERTURBED]} pivots perturbed: numerically singular")
        self._valid = True
        return self

    @property
    def fill(self) -> int:
        """Entries in the factors L and U of the last analysis."""
        return int(self.iparm[FACTOR_ENTRIES])

    def solve(self, b: np.ndarray) -> np.ndarray:
        """``A^{-1} b`` for ``b`` of shape (n,) with the last factorisation."""
        if not self._valid:
            raise PardisoError("no valid factorisation to solve with")
        rhs = np.ascontiguousarray(b, dtype=np.float64)
        if rhs.shape != (self.shape[0],):
            raise ValueError(f"b must have shape ({self.shape[0]},), got {rhs.shape}")
        return _call(self.pt, self.iparm, SOLVE, self._A, self.shape[0], rhs)


def _checked(A: sp.csc_matrix) -> sp.csc_matrix:
    """``A`` as PARDISO reads it: CSC with sorted int32 indices and float64 values."""
    if not sp.issparse(A) or A.shape[0] != A.shape[1]:
        raise ValueError(f"A must be a square sparse matrix, got {type(A).__name__} {A.shape}")
    A = sp.csc_matrix(A, dtype=np.float64)
    if not np.all(np.diff(A.indptr)):  # PARDISO may crash on an empty column
        raise PardisoError("A has an empty column: singular")
    if not np.all(np.isfinite(A.data)):
        raise PardisoError("A has NaN or inf entries")
    if not A.has_sorted_indices:
        A = A.sorted_indices()
    if A.indptr.dtype != np.int32:
        A = sp.csc_matrix((A.data, A.indices.astype(np.int32), A.indptr.astype(np.int32)),
                          shape=A.shape)  # fmt: skip
    return A
