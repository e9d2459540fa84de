"""The signals of a recording drawn against time, the task's states shaded behind them and
each transition marked where it fired: what a roboticist looks at to see why a grasp failed."""

from __future__ import annotations

import io
from typing import Sequence

import numpy as np

from atd.review.load import Recording


def _figure(rows: int):
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot

    figure, axes = pyplot.subplots(rows, 1, figsize=(10, 2.1 * rows), sharex=True, squeeze=False)
    return figure, [a[0] for a in axes]


def _svg(figure) -> str:
    from matplotlib import pyplot

    out = io.StringIO()
    # No metadata block: it names matplotlib's web site, and the page must name no URL.
    figure.savefig(out, format="svg", bbox_inches="tight",
                   metadata={"Creator": None, "Date": None, "Format": None, "Type": None})
    pyplot.close(figure)
    text = out.getvalue()
    return text[text.index("<svg"):]  # inline: no XML prolog, no DOCTYPE


def _mark_states(axes, recording: Recording) -> None:
    colours = ("#eef3fb", "#fbf3e6")
    for i, (state, start, end) in enumerate(recording.visits()):
        for axis in axes:
            axis.axvspan(start, recording.end_time if end is None else end, color=colours[i % 2], zorder=0)
        axes[0].text(start, 1.02, state.rsplit("/", 1)[-1], transform=axes[0].get_xaxis_transform(),
                     fontsize=7, rotation=30, ha="left", va="bottom")
    for record in recording.trace:
        if record["type"] == "event":
            for axis in axes:
                axis.axvline(record["t"], color="#c0392b", linewidth=0.8, linestyle="--", zorder=1)


def signals(recording: Recording) -> str:
    """One SVG of the main signals: pad forces, wrist force, hand joints, arm joint speeds,
    the object's true height."""
    t = recording.times("/sensors")
    panels: list[tuple[str, Sequence[tuple[str, np.ndarray]]]] = []
    first = recording.messages["/sensors"][0][1] if recording.messages.get("/sensors") else {}
    pads = sorted(first.get("pads", {}))
    panels.append(("pad force (N)", [(pad, recording.series("/sensors", "pads", pad, "force")) for pad in pads]))
    force = np.column_stack([recording.series("/sensors", "wrench", "force", a) for a in "xyz"]) if len(t) else \
        np.zeros((0, 3))
    panels.append(("wrist force (N), hand frame", [(f"F{a}", force[:, i]) for i, a in enumerate("xyz")]))
    hand_q = np.array([m["hand_q"] for _, m in recording.messages.get("/sensors", [])], float).reshape(len(t), -1)
    panels.append(("hand DOFs", [(f"dof {k}", hand_q[:, k]) for k in range(hand_q.shape[1])]))
    arm_dq = np.array([m["arm_dq"] for _, m in recording.messages.get("/sensors", [])], float).reshape(len(t), -1)
    panels.append(("arm joint speed (rad/s)", [(f"q{k + 1}", arm_dq[:, k]) for k in range(arm_dq.shape[1])]))
    truth_t = recording.times("/truth")
    height = recording.series("/truth", "object", "position", "z")
    figure, axes = _figure(len(panels) + 1)
    for axis, (label, lines) in zip(axes, panels):
        for name, values in lines:
            axis.plot(t, values, linewidth=1, label=name)
        axis.set_ylabel(label, fontsize=8)
        if lines:
            # Beside the panel, not on it: inside, a legend hid the lines that ran under it
            # (the SDH2's swivel DOF, for one).
            axis.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.005, 1.0), borderaxespad=0)
    axes[-1].plot(truth_t, height, color="black", linewidth=1.2)
    axes[-1].set_ylabel("object z (m)\nground truth", fontsize=8)
    axes[-1].set_xlabel("simulated time (s)")
    _mark_states(axes, recording)
    return _svg(figure)


def timeline(recording: Recording) -> str:
    """The states the run went through, one bar each."""
    stays = recording.visits()
    names = list(dict.fromkeys(state for state, _, _ in stays))
    figure, (axis,) = _figure(1)
    figure.set_size_inches(10, 0.35 * len(names) + 1)
    for state, start, end in stays:
        stop = recording.end_time if end is None else end
        axis.barh(names.index(state), max(stop - start, 0.02), left=start, color="#4a78b5")
    axis.set_yticks(range(len(names)), names, fontsize=8)
    axis.invert_yaxis()
    axis.set_xlabel("simulated time (s)")
    return _svg(figure)


def difference(a: Recording, b: Recording, rows: list[tuple[str, str, float, float]]) -> str:
    """Per state, the mean difference of each compared signal (B - A), one bar chart."""
    signals_ = list(dict.fromkeys(signal for _, signal, _, _ in rows))
    states = list(dict.fromkeys(state for state, _, _, _ in rows))
    figure, axes = _figure(len(signals_))
    for axis, signal in zip(axes, signals_):
        values = [next((d for s, g, d, _ in rows if s == state and g == signal), np.nan) for state in states]
        axis.bar(range(len(states)), values, color="#4a78b5")
        axis.axhline(0, color="black", linewidth=0.6)
        axis.set_ylabel(signal, fontsize=8)
    axes[-1].set_xticks(range(len(states)), states, rotation=30, fontsize=8, ha="right")
    figure.suptitle(f"mean difference per state: {b.path.name} - {a.path.name}", fontsize=9)
    return _svg(figure)
