"""PNG pictures of flights and evaluations, drawn off-screen (matplotlib's Agg backend)."""
from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path


@contextmanager
def png(path: Path, figsize: tuple[float, float], ncols: int = 1):
    """A figure and its axes (a row of `ncols` of them), written to `path` (its folder made) when
    the block ends without error."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, ncols, figsize=figsize)
    try:
        yield fig, ax
        fig.tight_layout()
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=110)
    finally:
        plt.close(fig)


def draw_track(ax, points, *style, **options) -> None:
    """Points (n, e, ...) in local metres on map axes: east across, north up."""
    ax.plot([p[1] for p in points], [p[0] for p in points], *style, **options)


def label_map(ax, title: str) -> None:
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_title(title)
