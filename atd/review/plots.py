"""The pictures of a recording that do not zoom: `atd compare`'s differences per state, and
the depth camera's pictures (the report's time plots zoom: atd/review/zoomable.py).
"""

from __future__ import annotations

import io
import numpy as np

from atd.review.load import Recording
from atd.runtime.report import ends

DPI = 150  # of what is drawn as pixels: sharp at the page's width
LABEL = 60  # characters of a state's name in a label
PICTURES = 8  # depth pictures drawn at most (the first and last four), ACROSS a row
ACROSS = 4


def label(name: str) -> str:
    """A state's name as a label: a long one cut, so that it cannot stretch a plot."""
    return name if len(name) <= LABEL else name[:LABEL - 3] + "..."


def _figure(rows: int, across: int = 1):
    """A figure 10 inches wide and its axes, row by row: one column of plots sharing their
    time axis, or a grid of pictures."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot

    figure, axes = pyplot.subplots(rows, across, figsize=(10, 2.1 * rows), sharex=across == 1, squeeze=False)
    return figure, list(axes.ravel())


def _svg(figure) -> str:
    from matplotlib import pyplot

    out = io.StringIO()
    # No metadata block: it names matplotlib's web site, and the page must name no URL.
    figure.savefig(out, format="svg", bbox_inches="tight", dpi=DPI,
                   metadata={"Creator": None, "Date": None, "Format": None, "Type": None})
    pyplot.close(figure)
    text = out.getvalue()
    return text[text.index("<svg"):]  # inline: no XML prolog, no DOCTYPE


def difference(a: Recording, b: Recording, rows: list[tuple[str, str, float, float]]) -> str:
    """Per state, the mean difference of each compared signal (B - A), one bar chart; of
    many states, the first and last SECTION_LINES // 2 of A's."""
    first, left_out, last = ends(list(dict.fromkeys(state for state, _, _, _ in rows)))
    states = first + last
    signals_ = list(dict.fromkeys(signal for _, signal, _, _ in rows))
    diff = {(state, signal): d for state, signal, d, _ in rows}
    figure, axes = _figure(len(signals_))
    for axis, signal in zip(axes, signals_):
        axis.bar(range(len(states)), [diff[state, signal] for state in states], color="#4a78b5")
        axis.axhline(0, color="black", linewidth=0.6)
        axis.set_ylabel(signal, fontsize=8)
    axes[-1].set_xticks(range(len(states)), [label(s) for s in states], rotation=30, fontsize=8, ha="right")
    between = f"; {left_out} states between the first and last {len(first)} not drawn" if left_out else ""
    figure.suptitle(f"mean difference per state: {b.path.name} - {a.path.name}{between}", fontsize=9)
    return _svg(figure)


def pictures(recording: Recording) -> tuple[str, int]:
    """The depth camera's pictures: what each perceive state saw when it chose, nearest dark,
    nothing seen blank; of a long run the first and last PICTURES // 2. Inline SVG (empty
    for a run that took none) and how many were left out between."""
    if not recording.pictures:
        return "", 0
    first, left_out, last = ends(recording.pictures, PICTURES)
    shown = first + last
    figure, axes = _figure(-(-len(shown) // ACROSS), ACROSS)
    for axis in axes:
        axis.set_axis_off()
    for axis, picture in zip(axes, shown):
        depth = picture.depth.astype(float)
        seen = depth > 0
        axis.imshow(np.where(seen, depth, np.nan), cmap="viridis", interpolation="nearest")
        near, far = (float(depth[seen].min()), float(depth[seen].max())) if seen.any() else (0.0, 0.0)
        axis.set_title(f"{label(picture.camera)} at {picture.t:.2f} s: {near:.2f}-{far:.2f} m", fontsize=8)
    return _svg(figure), left_out
