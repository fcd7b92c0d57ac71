"""What a running sweep shows: a progress bar (tqdm) and a note when kernels compile.

The bar counts grid points (blocks in its postfix), with tqdm's rate and time left, on
stderr. The compile note comes from Numba's event API: the first compilation inside a sweep
says so once, so that a first run's wait for the compiler (tens of seconds) is not silent.
"""

from __future__ import annotations

import contextlib
import sys
import threading
import time

from tqdm import tqdm

__all__ = ["SweepBar", "compile_notice", "CompileClock"]


class SweepBar:
    """A tqdm bar over the points of a sweep, with ``blocks done/total`` in its postfix.

    Parameters
    ----------
    points, blocks : int
        Totals.
    desc : str
        The bar's label.
    enabled : bool
        ``False``: nothing is drawn (the counts are still kept).
    """

    def __init__(self, points: int, blocks: int, desc: str = "sweep", enabled: bool = True):
        self.blocks, self.blocks_done, self.enabled = int(blocks), 0, bool(enabled)
        self._bar = tqdm(total=int(points), desc=desc, unit="pt",
                         unit_scale=points >= 10_000,  # 2.6M; below, whole numbers
                         disable=not self.enabled, file=sys.stderr, dynamic_ncols=True)
        self._postfix()

    def _postfix(self) -> None:
        if self.enabled:
            self._bar.set_postfix_str(f"block {self.blocks_done}/{self.blocks}", refresh=False)

    def update(self, points: int, blocks: int = 1) -> None:
        """``points`` more points done, in ``blocks`` blocks."""
        self.blocks_done += blocks
        self._postfix()
        self._bar.update(int(points))

    def close(self) -> None:
        self._bar.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def say_on_stderr(text: str) -> None:
    """One line on stderr, above any running tqdm bar."""
    tqdm.write(f"agglomtool: {text}", file=sys.stderr)


class CompileClock:
    """Seconds spent compiling (Numba) while it is installed, nested compilations once."""

    def __init__(self):
        self.seconds = 0.0
        self._depth = 0
        self._t0 = 0.0
        self._lock = threading.Lock()

    def on_start(self) -> None:
        with self._lock:
            if self._depth == 0:
                self._t0 = time.perf_counter()
            self._depth += 1

    def on_end(self) -> None:
        with self._lock:
            self._depth -= 1
            if self._depth == 0:
                self.seconds += time.perf_counter() - self._t0


@contextlib.contextmanager
def listen_to_compiles(on_start=None, on_end=None):
    """Call ``on_start()`` / ``on_end()`` as Numba starts and ends each compilation
    (nested ones included) inside the ``with`` block."""
    from numba.core import event

    class _Listener(event.Listener):
        def on_start(self, ev):
            if on_start is not None:
                on_start()

        def on_end(self, ev):
            if on_end is not None:
                on_end()

    with event.install_listener("numba:compile", _Listener()):
        yield


@contextlib.contextmanager
def compile_notice(say, seconds: float):
    """Inside the ``with`` block, the first Numba compilation calls ``say(text)`` once:
    ``"compiling kernels (first run only, ~N s)..."``, ``N`` = ``seconds`` (a figure
    measured on a reference machine: :data:`agglomtool.maps.estimate.COMPILE_SECONDS`)."""
    said: list[str] = []

    def start():
        if not said:
            said.append(True)
            say(f"compiling kernels (first run only, ~{seconds:.0f} s)...")

    with listen_to_compiles(on_start=start):
        yield
