"""Progress of a long command (evaluate's episodes, a mission's items) on one stream.

On a terminal: a bar redrawn in place, at most every REDRAW_S and always at the end. Elsewhere (a
pipe, a CI log): a plain line each time the caller's milestone changes, so a log gets a few lines,
not a bar's worth of carriage returns.
"""
from __future__ import annotations

import math
import sys
import time

BAR_WIDTH = 24
REDRAW_S = 0.1


class Progress:
    def __init__(self, total: int, stream=None):
        self.total = max(1, total)
        self.stream = sys.stderr if stream is None else stream  # the stderr of now, not of import time
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self._milestone = object()  # differs from any milestone a caller passes
        self._drawn_at = -math.inf
        self._bar_open = False

    def show(self, done: int, text: str, milestone=None) -> None:
        """`done` of `total`, described by `text`; off a terminal the line is written only when
        `milestone` differs from the last one written."""
        if self.tty:
            now = time.monotonic()
            if done >= self.total or now - self._drawn_at >= REDRAW_S:
                filled = int(BAR_WIDTH * min(done, self.total) / self.total)
                self.stream.write(f"\r[{'#' * filled}{'-' * (BAR_WIDTH - filled)}] {text} ")
                self.stream.flush()
                self._drawn_at, self._bar_open = now, True
        elif milestone != self._milestone:
            self._milestone = milestone
            self.stream.write(text + "\n")
            self.stream.flush()

    def close(self) -> None:
        """End the bar's line (on a terminal), so what is printed next starts on its own line."""
        if self._bar_open:
            self.stream.write("\n")
            self.stream.flush()
            self._bar_open = False
