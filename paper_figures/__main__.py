"""Command line: ``python -m paper_figures list | all | NAME``: redraw figures from results.

Every module ``paper_figures/fig*.py`` exposes ``main()``, which reads only
``validation/results/`` and writes PNGs to ``paper_figures/out/``. A figure whose results are
missing fails with a message naming the validation case to run first.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys

import matplotlib

import paper_figures

matplotlib.use("Agg")


def figure_modules() -> list[str]:
    return sorted(
        m.name for m in pkgutil.iter_modules(paper_figures.__path__) if m.name.startswith("fig")
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m paper_figures")
    parser.add_argument("target", help="'list', 'all' or a figure module name")
    args = parser.parse_args(argv)
    names = figure_modules()
    if args.target == "list":
        print("\n".join(names))
        return 0
    chosen = names if args.target == "all" else [args.target]
    failed = []
    for name in chosen:
        if name not in names:
            print(
                f"unknown figure module {name!r}; see 'python -m paper_figures list'",
                file=sys.stderr,
            )
            return 2
        try:
            written = importlib.import_module(f"paper_figures.{name}").main()
            print(f"{name}: {', '.join(str(p) for p in written or [])}")
        except Exception as exc:  # report every figure, fail at the end
            print(f"{name}: FAILED: {type(exc).__name__}: {exc}", file=sys.stderr)
            failed.append(name)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
