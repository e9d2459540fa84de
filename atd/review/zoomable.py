"""The report's time plots as Bokeh figures a reader pans and zooms: the timeline of the
states and the main signals, their time axes linked, the states shaded behind the signals
and each transition marked where it fired.

The page embeds BokehJS inline (`bokeh.resources.INLINE`, only the bundle these figures
need: its core, 1.27 MB) and the figures' data beside it, so it works offline and loads
nothing from the network. A long run stays a page of bounded size: past DENSE samples a
line is reduced to what a screen's pixels can show (each bucket's lowest and highest
value); past SECTION_LINES stays the stays are not named (the timeline names them), and
past MARKS they and the events are not marked at all; the timeline shows at most
SECTION_LINES states, as `atd run`'s summary does, and joins a state's stays that lie
closer than a pixel.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from atd.review.load import Recording
from atd.review.plots import label
from atd.runtime.report import SECTION_LINES, ends

DENSE = 5000  # samples past which a line is reduced to its envelope: 50 s at 100 Hz
BUCKETS = 1000  # of an envelope: two points each, as many as a plot has pixels across
MARKS = 1000  # stays or events past which the signals are not marked: closer than a pixel apart
PIXELS = 1500  # across a plot at most: stays closer than one apart are joined on the timeline
SHADES = ("#eef3fb", "#fbf3e6")  # a state's stays, alternately
EVENT = "#c0392b"
BAR = "#4a78b5"
PANEL_HEIGHT = 150  # px of a signal panel's plotting area
ROW_HEIGHT = 22  # px of a timeline row
LINES = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22",
         "#17becf")  # matplotlib's tab10, as the campaign plots colour their lines
LEFT_BORDER = 110  # px left of every plotting area: its axis label and a state name of the timeline
TOOLS = "xpan,xwheel_zoom,xbox_zoom,reset,save"  # x only: every panel shares the time axis


@dataclass(frozen=True)
class Figures:
    """What the page embeds: the BokehJS bundle (inline scripts), the script that draws the
    figures from their data, and the element each figure is drawn into."""

    library: str
    script: str
    timeline: str
    signals: str


def envelope(t: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A long line as a screen can show it: of each of BUCKETS runs of samples, the lowest
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


def _axis(title: str, x_range, height: int, legend: bool, **y_range):
    """A figure sharing `x_range`, as wide as the page, zooming and panning in time only;
    its plotting area starts and ends where its neighbours' do (a fixed left border, the
    legend above), so that one time is one column of pixels on every figure."""
    from bokeh.plotting import figure

    plot = figure(x_range=x_range, frame_height=height, sizing_mode="stretch_width", tools=TOOLS,
                  active_drag="xbox_zoom", toolbar_location="right", min_border_left=LEFT_BORDER,
                  **y_range)
    plot.yaxis.axis_label = title
    plot.yaxis.axis_label_text_font_size = "8pt"
    plot.toolbar.logo = None
    if legend:  # above the panel, not on it: inside, a legend hid the lines that ran under it
        from bokeh.models import Legend

        plot.add_layout(Legend(click_policy="hide", label_text_font_size="8pt", orientation="horizontal",
                               padding=2, margin=0, border_line_color=None), "above")
    return plot


def _lines(plot, t: np.ndarray, lines: Sequence[tuple[str, np.ndarray]]) -> None:
    """Each line of a panel, named in its legend (a click hides it); float32: a page's
    worth of precision at half the bytes."""
    from bokeh.models import ColumnDataSource

    for k, (name, values) in enumerate(lines):
        shown_t, shown = envelope(t, values)
        source = ColumnDataSource({"t": shown_t.astype(np.float32), "v": shown.astype(np.float32)})
        plot.line("t", "v", source=source, color=LINES[k % len(LINES)], line_width=1.2, legend_label=name)


def _mark_states(plots: list, recording: Recording) -> None:
    """Each stay shaded and each event's time marked on every panel, each stay named on the
    first; of many, none."""
    from bokeh.models import ColumnDataSource, LabelSet

    stays, fired = recording.visits, [r.t for r in recording.events()]
    if max(len(stays), len(fired)) > MARKS:
        plots[0].title.text = (f"{len(stays)} stays and {len(fired)} events are too many to mark here "
                               f"(the timeline above shows the stays)")
        return
    starts = np.array([start for _, start, _ in stays], float)
    stops = np.array([recording.end_time if end is None else end for _, _, end in stays], float)
    shaded = [ColumnDataSource({"x0": starts[k::2], "x1": stops[k::2]}) for k in range(len(SHADES))]
    events = ColumnDataSource({"x": np.array(fired, float)})
    for plot in plots:
        for source, colour in zip(shaded, SHADES):
            plot.vstrip(x0="x0", x1="x1", source=source, fill_color=colour, line_color=None, level="underlay")
        plot.vspan(x="x", source=events, line_color=EVENT, line_width=0.8, line_dash="dashed", level="underlay")
    if len(stays) <= SECTION_LINES:  # a name per stay; past that, the timeline names them
        names = ColumnDataSource({"x": starts, "name": [label(state.rsplit("/", 1)[-1]) for state, _, _ in stays]})
        plots[0].add_layout(LabelSet(x="x", y=PANEL_HEIGHT - 4, y_units="screen", text="name", source=names,
                                     text_font_size="7pt", text_baseline="top", x_offset=2))


def _signals(recording: Recording, x_range) -> list:
    """A panel each of pad forces, wrist force, hand DOFs, arm joint speeds and the object's
    true height."""
    s = recording.signals
    panels: list[tuple[str, Sequence[tuple[str, np.ndarray]]]] = [
        ("pad force (N)", [(label(pad), force) for pad, force in sorted(s.pad_force.items())]),
        ("wrist force (N), hand frame", [(f"F{a}", s.wrist_force[:, i]) for i, a in enumerate("xyz")]),
        ("hand DOFs", [(label(name), s.hand_q[:, k]) for k, name in enumerate(recording.hand_dofs)]),
        ("arm joint speed (rad/s)", [(label(name), s.arm_dq[:, k]) for k, name in enumerate(recording.arm_joints)])]
    plots = []
    for title, lines in panels:
        plot = _axis(title, x_range, PANEL_HEIGHT, legend=bool(lines))
        _lines(plot, s.t, lines)
        plots.append(plot)
    truth = _axis("object z (m), ground truth", x_range, PANEL_HEIGHT, legend=True)
    _lines(truth, s.truth_t, [("object z", s.object_z)])
    plots.append(truth)
    _mark_states(plots, recording)
    truth.xaxis.axis_label = "simulated time (s)"
    return plots


def _bars(stays: list[tuple[float, float]], gap: float) -> list[tuple[float, float]]:
    """(start, stop) of a state's stays, sorted by start, those closer than `gap` joined,
    none narrower than `gap`."""
    joined: list[list[float]] = []
    for start, stop in sorted(stays):
        if joined and start - joined[-1][1] < gap:
            joined[-1][1] = max(joined[-1][1], stop)
        else:
            joined.append([start, stop])
    return [(start, max(stop, start + gap)) for start, stop in joined]


def _timeline(recording: Recording, x_range):
    """The states the run went through, a row each with a bar per stay; of many states, the
    first and last SECTION_LINES // 2 entered."""
    from bokeh.models import ColumnDataSource, FactorRange

    first, left_out, last = ends(list(dict.fromkeys(state for state, _, _ in recording.visits)))
    names = first + last
    rows = {name: label(name) for name in names}
    spans: dict[str, list[tuple[float, float]]] = {name: [] for name in names}
    for state, start, end in recording.visits:
        if state in spans:
            spans[state].append((start, recording.end_time if end is None else end))
    pixel = max(recording.end_time, 1.0) / PIXELS
    bars = [(rows[name], start, stop) for name in names for start, stop in _bars(spans[name], pixel)]
    row_names = list(dict.fromkeys(rows.values()))
    plot = _axis("", x_range, ROW_HEIGHT * len(row_names) + 10, legend=False,
                 y_range=FactorRange(*reversed(row_names)))
    plot.yaxis.major_label_text_font_size = "8pt"
    source = ColumnDataSource({"state": [b[0] for b in bars], "left": [b[1] for b in bars],
                               "right": [b[2] for b in bars]})
    plot.xaxis.axis_label = "simulated time (s)"
    plot.hbar(y="state", left="left", right="right", height=0.8, source=source, color=BAR)
    if left_out:
        plot.title.text = f"the first and last {len(first)} states entered; {left_out} more between are not drawn"
    return plot


def figures(recording: Recording) -> Figures:
    """The timeline and the signals, sharing one time axis, with what it takes to draw them
    offline."""
    from bokeh.embed import components
    from bokeh.embed.bundle import bundle_for_objs_and_resources
    from bokeh.layouts import column
    from bokeh.models import Range1d
    from bokeh.resources import INLINE

    end = max(recording.end_time, 1e-3)
    x_range = Range1d(0.0, end, bounds=(0.0, end))
    timeline = _timeline(recording, x_range)
    signals = column(_signals(recording, x_range), sizing_mode="stretch_width")
    script, (timeline_div, signals_div) = components((timeline, signals))
    return Figures(bundle_for_objs_and_resources([timeline, signals], INLINE).scripts(), script, timeline_div,
                   signals_div)
