"""Console progress of a sweep: ``[#####.....] 32/64 ok 31 failed 1 | 2m10s, ~2m10s left``."""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field
from typing import TextIO


def _clock(seconds: float) -> str:
    seconds = int(round(seconds))
    h, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{h}h{m:02d}m" if h else (f"{m}m{s:02d}s" if m else f"{s}s")


@dataclass
class ConsoleProgress:
    """A one-line bar redrawn in place on a terminal, a line per ~10 % otherwise.

    Parameters
    ----------
    total : int or None
        Number of tasks to run (None if the task generator has no length).
    label : str
    stream : text file
        Default ``sys.stderr``.
    width : int
        Characters of the bar.
    """

    total: int | None
    label: str = "sweep"
    stream: TextIO | None = None
    width: int = 30
    done: int = 0
    failed: int = 0
    skipped: int = 0
    _start: float = field(default_factory=time.perf_counter)
    _last_decile: int = -1

    def __post_init__(self):
        self.stream = self.stream or sys.stderr

    def update(self, record: dict) -> None:
        self.done += 1
        self.failed += record["status"] != "ok"
        self._draw(final=False)

    def close(self) -> None:
        self._draw(final=True)

    def line(self) -> str:
        elapsed = time.perf_counter() - self._start
        skipped = f", {self.skipped} done before" if self.skipped else ""
        ok = self.done - self.failed
        if self.total:
            frac = min(1.0, self.done / self.total)
            bar = "#" * int(frac * self.width) + "." * (self.width - int(frac * self.width))
            left = elapsed / self.done * (self.total - self.done) if self.done else float("nan")
            eta = f", ~{_clock(left)} left" if self.done and self.done < self.total else ""
            return (
                f"{self.label} [{bar}] {self.done}/{self.total} ok {ok} failed {self.failed}"
                f"{skipped} | {_clock(elapsed)}{eta}"
            )
        return f"{self.label} {self.done} ok {ok} failed {self.failed}{skipped} | {_clock(elapsed)}"

    def _draw(self, final: bool) -> None:
        interactive = hasattr(self.stream, "isatty") and self.stream.isatty()
        if interactive:
            self.stream.write("\r" + self.line() + ("\n" if final else ""))
        else:
            decile = int(10 * self.done / self.total) if self.total else self.done // 10
            if decile != self._last_decile or (final and self.done == 0):
                self._last_decile = decile
                self.stream.write(self.line() + "\n")
        self.stream.flush()


@dataclass
class NoProgress:
    """Silence."""

    total: int | None = None
    skipped: int = 0

    def update(self, record: dict) -> None:
        pass

    def close(self) -> None:
        pass
