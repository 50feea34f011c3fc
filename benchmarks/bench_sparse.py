"""Sparse direct solvers on the static DEM's real tangents (in-plane running-bond walls).

Run ``python benchmarks/bench_sparse.py dump SIZE DIR [--every K] [--steps N]`` to write
every K-th Newton matrix and right-hand side of the wall of about SIZE blocks
(``bench_static.IN_PLANE_SIZES``) as ``DIR/A_SIZE_I.npz``, ``DIR/b_SIZE_I.npy``;
then ``python benchmarks/bench_sparse.py bench FILES... [--solvers a,b]`` factors each matrix
with each solver in a fresh subprocess and prints factor (analysis + numeric) and numeric-only
ms, solve ms, fill (entries of the factors), the residual ``|A x - b| / |b|`` and the
subprocess's peak resident memory above the loaded matrix.

Solvers: SuperLU as ``dem.static.newton.factor`` calls it (MMD on A + A^T, symmetric mode,
diagonal pivot threshold 0.01); SuperLU with COLAMD and partial pivoting; SuperLU on the
matrix permuted symmetrically by METIS nested dissection (pymetis); UMFPACK and KLU
(kvxopt's SuiteSparse); MKL PARDISO (``dem.static.pardiso``), its numeric factorisation
repeated on the kept analysis. A solver whose package is missing prints as such.

``--numba`` runs the factorisations while numba's threads evaluate the resultant law in a
background thread (coexistence: no deadlock, the same solution); ``--threads`` sets the
BLAS (MKL) threads (default 1, as ``solve_collapse`` pins them).

Times are wall-clock on a shared machine: compare ratios within one run.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from threadpoolctl import threadpool_limits

from dem.static.pardiso import PardisoLU  # loads oneMKL now, so that the thread limit finds it

REPEATS = 3


def _peak_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def _best(fn, repeats: int = REPEATS):
    """Smallest wall time of ``repeats`` calls [s] and the last call's value."""
    best, out = float("inf"), None
    for _ in range(repeats):
        start = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - start)
    return best, out


class SuperLU:
    """scipy's SuperLU with ``options``; ``order`` (a callable giving a symmetric
    permutation) is applied before SuperLU, which then keeps the natural column order."""

    def __init__(self, order=None, **options):
        self.order, self.options = order, options

    def run(self, A, b):
        perm = None if self.order is None else self.order(A)
        if perm is not None:
            A = A[perm][:, perm].tocsc()
            b = b[perm]
        t_fac, lu = _best(lambda: spla.splu(A, **self.options))
        t_sol, x = _best(lambda: lu.solve(b))
        if perm is not None:
            x_out = np.empty_like(x)
            x_out[perm] = x
            x = x_out
        return {"factor_s": t_fac, "numeric_s": t_fac, "solve_s": t_sol,
                "fill": int(lu.L.nnz + lu.U.nnz), "x": x}  # fmt: skip


def metis_order(A) -> np.ndarray:
    """Nested dissection of the graph of A + A^T (pymetis)."""
    import pymetis

    G = (abs(A) + abs(A.T)).tocsr()
    G.setdiag(0)
    G.eliminate_zeros()
    perm, _ = pymetis.nested_dissection(xadj=G.indptr, adjncy=G.indices)
    return np.asarray(perm)


class Kvx:
    """kvxopt's UMFPACK or KLU: symbolic analysis, then numeric factorisation (repeated)."""

    def __init__(self, module: str):
        self.module = module

    def run(self, A, b):
        import kvxopt
        from kvxopt import klu, umfpack

        mod = umfpack if self.module == "umfpack" else klu
        Ac = A.tocoo()

        def convert():
            return kvxopt.spmatrix(Ac.data, Ac.row.astype(int), Ac.col.astype(int), A.shape)

        def factor():
            K = convert()
            return K, mod.numeric(K, mod.symbolic(K))

        t_fac, (K, Fn) = _best(factor)
        Fs = mod.symbolic(K)
        t_num, Fn = _best(lambda: mod.numeric(K, Fs))

        def solve():
            B = kvxopt.matrix(b)
            mod.solve(K, Fn, B) if self.module == "umfpack" else mod.solve(K, Fs, Fn, B)
            return np.array(B).ravel()

        t_sol, x = _best(solve)
        parts = mod.get_numeric(K, Fs, Fn) if self.module == "klu" else mod.get_numeric(K, Fn)
        fill = len(parts[0].V) + len(parts[1].V)
        return {"factor_s": t_fac, "numeric_s": t_num, "solve_s": t_sol, "fill": fill, "x": x}


class Pardiso:
    """MKL PARDISO as ``dem.static.pardiso`` sets it: analysis with numeric factorisation,
    then the numeric factorisation repeated on the kept analysis."""

    def run(self, A, b):
        def fresh():
            return PardisoLU().factor(A)

        t_fac, _ = _best(fresh)
        lu = fresh()
        t_num, _ = _best(lambda: lu.factor(A))
        t_sol, x = _best(lambda: lu.solve(b))
        return {"factor_s": t_fac, "numeric_s": t_num, "solve_s": t_sol, "fill": lu.fill, "x": x}


SOLVERS = {
    "superlu": SuperLU(permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.01,
                       options={"SymmetricMode": True}),
    "superlu-colamd": SuperLU(permc_spec="COLAMD"),
    "superlu-metis": SuperLU(order=metis_order, permc_spec="NATURAL", diag_pivot_thresh=0.01,
                             options={"SymmetricMode": True}),
    "umfpack": Kvx("umfpack"),
    "klu": Kvx("klu"),
    "pardiso": Pardiso(),
}  # fmt: skip


def _law_load(stop: threading.Event) -> int:
    """Evaluate the resultant law of a small wall in numba's threads until ``stop``."""
    sys.path.insert(0, str(Path(__file__).parent))
    from bench_static import in_plane_wall

    from dem.static import StaticSettings
    from dem.static.model import Model

    model = Model(in_plane_wall(24, 40), StaticSettings(interface_model="resultant"))
    u = np.zeros(model.n_free)
    n = 0
    while not stop.is_set():
        model.evaluate(u, 1e-6)
        n += 1
    return n


def run_one(path: str, name: str, with_numba: bool, threads: int = 1) -> dict:
    """One matrix by one solver in this process, with ``threads`` BLAS (MKL) threads: times,
    fill, residual, peak memory."""
    A = sp.load_npz(path).tocsc()
    b = np.load(path.replace("/A_", "/b_").replace(".npz", ".npy"))
    stop, thread = threading.Event(), None
    if with_numba:
        thread = threading.Thread(target=_law_load, args=(stop,), daemon=True)
        thread.start()
        time.sleep(5.0)  # the law compiled or loaded and running
    base = _peak_mib()
    try:
        with threadpool_limits(limits=threads, user_api="blas"):  # as solve_collapse pins them
            row = SOLVERS[name].run(A, b)
    except ImportError as exc:
        return {"solver": name, "error": f"missing: {exc}"}
    except Exception as exc:  # a solver's failure is a row of the table, not a crash
        return {"solver": name, "error": f"{type(exc).__name__}: {exc}"}
    finally:
        stop.set()
    x = row.pop("x")
    row["residual"] = float(np.linalg.norm(A @ x - b) / np.linalg.norm(b))
    row["solution_norm"] = float(np.linalg.norm(x))
    row["peak_mib"] = _peak_mib() - base
    return {"solver": name, "n": A.shape[0], "nnz": int(A.nnz), **row}


def bench(files, names, with_numba: bool, threads: int = 1) -> None:
    print(f"{'matrix':>16s} {'n':>6s} {'nnz':>8s} {'solver':>15s} {'factor ms':>10s} "
          f"{'numeric ms':>10s} {'solve ms':>9s} {'fill':>10s} {'residual':>9s} "
          f"{'MiB':>6s}")  # fmt: skip
    for path in files:
        for name in names:
            cmd = [sys.executable, __file__, "one", path, name]
            cmd += ["--threads", str(threads)] + (["--numba"] if with_numba else [])
            out = subprocess.run(cmd, capture_output=True, text=True)
            lines = out.stdout.strip().splitlines()
            if out.returncode or not lines:
                err = (out.stderr.strip().splitlines() or ["?"])[-1]
                print(f"{Path(path).stem:>16s} {'':>6s} {'':>8s} {name:>15s} crashed: {err}")
                continue
            r = json.loads(lines[-1])
            if "error" in r:
                print(f"{Path(path).stem:>16s} {'':>6s} {'':>8s} {name:>15s} {r['error']}")
                continue
            print(f"{Path(path).stem:>16s} {r['n']:6d} {r['nnz']:8d} {name:>15s} "
                  f"{1e3 * r['factor_s']:10.1f} {1e3 * r['numeric_s']:10.1f} "
                  f"{1e3 * r['solve_s']:9.2f} {r['fill']:10d} {r['residual']:9.1e} "
                  f"{r['peak_mib']:6.0f}", flush=True)  # fmt: skip


def dump(size: int, out: Path, every: int, steps: int | None) -> None:
    """Write every ``every``-th Newton matrix of the in-plane wall of about ``size`` blocks."""
    sys.path.insert(0, str(Path(__file__).parent))
    from bench_static import IN_PLANE_SIZES, in_plane_wall

    import dem.static.newton as newton
    from dem.static import StaticSettings, solve_collapse

    out.mkdir(parents=True, exist_ok=True)
    count = [0]
    solve = newton.LinearSolver.solve

    def recording(self, A, rhs):
        if count[0] % every == 0:
            sp.save_npz(out / f"A_{size}_{count[0]}.npz", A)
            np.save(out / f"b_{size}_{count[0]}.npy", rhs)
        count[0] += 1
        return solve(self, A, rhs)

    newton.LinearSolver.solve = recording
    extra = {} if steps is None else {"max_steps": steps}
    settings = StaticSettings(interface_model="resultant", on_failure="return", **extra)
    res = solve_collapse(in_plane_wall(*IN_PLANE_SIZES[size]), settings)
    print(f"{count[0]} solves, lambda {res.lambda_max!r} ({res.termination})")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="cmd", required=True)
    d = sub.add_parser("dump")
    d.add_argument("size", type=int)
    d.add_argument("out", type=Path)
    d.add_argument("--every", type=int, default=10)
    d.add_argument("--steps", type=int)
    b = sub.add_parser("bench")
    b.add_argument("files", nargs="+")
    b.add_argument("--solvers", default=",".join(SOLVERS))
    b.add_argument("--numba", action="store_true")
    b.add_argument("--threads", type=int, default=1, help="BLAS (MKL) threads")
    o = sub.add_parser("one")
    o.add_argument("file")
    o.add_argument("solver")
    o.add_argument("--numba", action="store_true")
    o.add_argument("--threads", type=int, default=1)
    args = parser.parse_args(argv)
    if args.cmd == "dump":
        dump(args.size, args.out, args.every, args.steps)
    elif args.cmd == "bench":
        bench(args.files, args.solvers.split(","), args.numba, args.threads)
    else:
        print(json.dumps(run_one(args.file, args.solver, args.numba, args.threads)))


if __name__ == "__main__":
    main()
