"""The signals of a recording drawn against time, the task's states shaded behind them and
each transition marked where it fired: what a roboticist looks at to see why a grasp failed.

A long run stays a page of bounded size, drawn in bounded time: past DENSE samples a line is
reduced to what the page's pixels can show (each bucket's lowest and highest value) and drawn
as pixels; past SECTION_LINES stays or events their marks are drawn as pixels and the stays
are not named (the timeline names them), and past MARKS they are not marked at all; the
timeline shows at most SECTION_LINES states, as `atd run`'s summary does, and joins a
state's stays that lie closer than a pixel.
"""

from __future__ import annotations

import io
from typing import Sequence

import numpy as np

from atd.review.load import Recording
from atd.runtime.report import SECTION_LINES, ends

DENSE = 5000  # samples past which a line is reduced to its envelope: 50 s at 100 Hz
BUCKETS = 1000  # of an envelope: two points each, as many as the picture has pixels across
MARKS = 1000  # stays or events past which the signals are not marked: closer than a pixel apart
DPI = 150  # of what is drawn as pixels: sharp at the page's width
PIXELS = 10 * DPI  # across a plot, 10 inches wide
SHADES = ("#eef3fb", "#fbf3e6")  # a state's stays, alternately
EVENT = "#c0392b"
LABEL = 60  # characters of a state's name in a label
PICTURES = 8  # depth pictures drawn at most (the first and last four), ACROSS a row
ACROSS = 4


def _label(name: str) -> str:
    """A state's name as a label: a long one cut, so that it cannot stretch a plot."""
    return name if len(name) <= LABEL else name[:LABEL - 3] + "..."


def _legend(name: str) -> str:
    """A recorded name as a legend entry, shown as written: cut like a label, a `$` not read as
    maths, a leading `_` not read as 'leave out of the legend'."""
    text = _label(name).replace("$", r"\$")
    return " " + text if text.startswith("_") else text


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


def _marks(axis, xs: np.ndarray, ys: tuple[float, ...], rasterized: bool, **style) -> None:
    """Shapes over the axis' full height, corner k of each at (xs[:, k], ys[k]), drawn as one
    path: thousands cost what one does. Closed and filled when `style` gives a face colour."""
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path

    if not len(xs):
        return
    corners = np.stack([xs, np.broadcast_to(ys, xs.shape)], axis=-1)
    filled = "facecolor" in style
    if filled:
        path = Path.make_compound_path_from_polys(np.concatenate([corners, corners[:, :1]], axis=1))
    else:
        path = Path(corners.reshape(-1, 2), np.tile([Path.MOVETO] + [Path.LINETO] * (len(ys) - 1), len(xs)))
    axis.add_artist(PathPatch(path, transform=axis.get_xaxis_transform(), rasterized=rasterized, fill=filled,
                             **style))


def _envelope(t: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A long line as the page can show it: of each of BUCKETS runs of samples, the lowest
    and the highest, in time order (a bucket of NaN keeps its gap); a short line whole."""
    if len(t) <= DENSE:
        return t, values
    size = -(-len(t) // BUCKETS)
    padded = np.full(BUCKETS * size, np.nan)
    padded[:len(values)] = values
    runs = padded.reshape(BUCKETS, size)
    gaps = np.isnan(runs)
    low, high = np.where(gaps, np.inf, runs).argmin(axis=1), np.where(gaps, -np.inf, runs).argmax(axis=1)
    kept = np.unique(np.arange(BUCKETS)[:, None] * size + np.column_stack([low, high]))  # sorted, each once
    kept = kept[kept < len(t)]
    return t[kept], values[kept]


def _mark_states(axes, recording: Recording) -> None:
    """Each stay shaded and each event's time marked on every panel; of many, none."""
    stays, fired = recording.visits, np.array([r.t for r in recording.events()])
    if max(len(stays), len(fired)) > MARKS:
        axes[0].set_title(f"{len(stays)} stays and {len(fired)} events are too many to mark here "
                          f"(the timeline above shows the stays)", fontsize=8)
        return
    many = len(stays) > SECTION_LINES
    starts = np.array([start for _, start, _ in stays])
    stops = np.array([recording.end_time if end is None else end for _, _, end in stays])
    boxes = np.column_stack([starts, starts, stops, stops])
    for axis in axes:
        for k, colour in enumerate(SHADES):
            _marks(axis, boxes[k::2], (0, 1, 1, 0), many, facecolor=colour, edgecolor="none", zorder=0)
        _marks(axis, np.column_stack([fired, fired]), (0, 1), len(fired) > SECTION_LINES, edgecolor=EVENT,
               linewidth=0.8, linestyle="--", zorder=1)
    if not many:  # a name per stay; past that, the timeline names them
        for state, start, _ in stays:
            axes[0].text(start, 1.02, _label(state.rsplit("/", 1)[-1]), transform=axes[0].get_xaxis_transform(),
                         fontsize=7, rotation=30, ha="left", va="bottom")


def signals(recording: Recording) -> str:
    """One SVG of the main signals: pad forces, wrist force, hand joints, arm joint speeds,
    the object's true height."""
    s = recording.signals
    panels: list[tuple[str, Sequence[tuple[str, np.ndarray]]]] = [
        ("pad force (N)", [(pad, force) for pad, force in sorted(s.pad_force.items())]),
        ("wrist force (N), hand frame", [(f"F{a}", s.wrist_force[:, i]) for i, a in enumerate("xyz")]),
        ("hand DOFs", [(name, s.hand_q[:, k]) for k, name in enumerate(recording.hand_dofs)]),
        ("arm joint speed (rad/s)", [(name, s.arm_dq[:, k]) for k, name in enumerate(recording.arm_joints)])]
    figure, axes = _figure(len(panels) + 1)
    for axis, (label, lines) in zip(axes, panels):
        for name, values in lines:
            axis.plot(*_envelope(s.t, values), linewidth=1, label=_legend(name), rasterized=len(s.t) > DENSE)
        axis.set_ylabel(label, fontsize=8)
        if lines:
            # Beside the panel, not on it: inside, a legend hid the lines that ran under it
            # (the SDH2's swivel DOF, for one).
            axis.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.005, 1.0), borderaxespad=0)
    axes[-1].plot(*_envelope(s.truth_t, s.object_z), color="black", linewidth=1.2, rasterized=len(s.truth_t) > DENSE)
    axes[-1].set_ylabel("object z (m)\nground truth", fontsize=8)
    axes[-1].set_xlabel("simulated time (s)")
    _mark_states(axes, recording)
    return _svg(figure)


def _bars(stays: list[tuple[float, float]], gap: float) -> list[tuple[float, float]]:
    """(start, width) of a state's stays, sorted by start, those closer than `gap` joined."""
    joined: list[list[float]] = []
    for start, stop in sorted(stays):
        if joined and start - joined[-1][1] < gap:
            joined[-1][1] = max(joined[-1][1], stop)
        else:
            joined.append([start, stop])
    return [(start, max(stop - start, gap)) for start, stop in joined]


def timeline(recording: Recording) -> str:
    """The states the run went through, a row each with a bar per stay; of many states, the
    first and last SECTION_LINES // 2 entered."""
    stays = recording.visits
    first, left_out, last = ends(list(dict.fromkeys(state for state, _, _ in stays)))
    names = first + last
    spans: dict[str, list[tuple[float, float]]] = {name: [] for name in names}
    for state, start, end in stays:
        if state in spans:
            spans[state].append((start, recording.end_time if end is None else end))
    pixel = max(recording.end_time, 1.0) / PIXELS
    figure, (axis,) = _figure(1)
    figure.set_size_inches(10, 0.35 * len(names) + 1)
    for row, name in enumerate(names):
        axis.broken_barh(_bars(spans[name], pixel), (row - 0.4, 0.8), color="#4a78b5",
                         rasterized=len(stays) > SECTION_LINES)
    axis.set_yticks(range(len(names)), [_label(n) for n in names], fontsize=8)
    axis.invert_yaxis()
    axis.set_xlabel("simulated time (s)")
    if left_out:
        axis.set_title(f"the first and last {len(first)} states entered; {left_out} more between are not drawn",
                       fontsize=8)
    return _svg(figure)


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
    axes[-1].set_xticks(range(len(states)), [_label(s) for s in states], rotation=30, fontsize=8, ha="right")
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
        axis.set_title(f"{_label(picture.camera)} at {picture.t:.2f} s: {near:.2f}-{far:.2f} m", fontsize=8)
    return _svg(figure), left_out
