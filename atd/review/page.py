"""`atd report`: one self-contained HTML page for one recorded run, readable offline: the
outcome in ATD terms, the task graph with the path taken, a picture of the scene as each
state began, a timeline, the signals with
the events on them, and the readings that fired each event."""

from __future__ import annotations

import html
import json
from collections import Counter, defaultdict
from dataclasses import replace

from pathlib import Path

from jinja2 import Environment

from atd.graph.layout import MAX_ELEMENTS
from atd.graph.model import Graph, from_estd
from atd.graph.render import render
from atd.graph.trail import on_trail
from atd.review.keyframes import key_frames
from atd.review.load import Recording
from atd.review.messages import TraceRecord
from atd.review.plots import pictures
from atd.review.zoomable import figures
from atd.runtime.report import ends

_PAGE = Environment(autoescape=True).from_string("""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>{{ title }}</title>
<style>
body { font-family: sans-serif; margin: 2em auto; max-width: 70em; color: #222; }
h1 { font-size: 1.4em; } h2 { font-size: 1.1em; margin-top: 2em; border-bottom: 1px solid #ccc; }
.outcome { padding: .6em 1em; border-radius: 4px; }
.succeeded { background: #e3f4e1; } .failed { background: #fbe4e1; }
table { border-collapse: collapse; font-size: .85em; } td, th { border: 1px solid #ddd; padding: .25em .5em; text-align: left; vertical-align: top; }
figure { margin: 0; overflow-x: auto; } figure svg { max-width: 100%; height: auto; }
/* The task graph at its own size, its text as drawn (12 px), scrolled rather than shrunk to fit */
#graph { overflow: auto; max-height: 85vh; border: 1px solid #eee; } #graph svg { max-width: none; }
code { font-size: .9em; }
#keyframes { display: grid; grid-template-columns: repeat(3, 1fr); gap: .5em; } #keyframes img { width: 100%; display: block; }
</style>
{{ figures.library|safe }}
</head><body>
<h1>{{ title }}</h1>
<p class="outcome {{ 'succeeded' if succeeded else 'failed' }}">{{ outcome.summary or "no outcome recorded" }}
 &middot; {{ "%.2f"|format(end_time) }} s simulated &middot; seed {{ run.seed }}</p>
<h2>The task, and the path taken</h2>
<figure id="graph">{{ graph|safe }}</figure>
<p class="note">{{ graph_note }}</p>
<h2>The run, state by state</h2>
{% set first, left_out, last = keyframes.first, keyframes.left_out, keyframes.last %}
{% if first %}<p>The scene as it stood when the task entered each state{% if left_out %} (the first and last;
{{ left_out }} more between){% endif %}, drawn from the recording by MuJoCo through the video's camera.</p>
<figure id="keyframes">{% macro frame(f) %}<img src="{{ f.source }}" alt="{{ f.state }} at {{ "%.2f"|format(f.t) }} s"
 title="{{ f.state }} at {{ "%.2f"|format(f.t) }} s">{% endmacro %}{% for f in first %}{{ frame(f) }}{% endfor %}
{% for f in last %}{{ frame(f) }}{% endfor %}</figure>
{% else %}<p id="no-keyframes">No pictures of the run: {{ keyframes.problem }}.</p>{% endif %}
<h2>The robot in 3D</h2>
<p id="foxglove">Foxglove's 3D panel draws the robot, the table and the objects of this run, moving, from the
same recording: in Foxglove (desktop app) choose <em>Open local file</em>, <code>{{ recording_path }}</code>; then,
in the Layout menu, <em>Import from file</em>, <code>{{ layout }}</code>
(a 3D panel, the task's states over time, the forces and the trace).</p>
<h2>Timeline</h2>
<p>Drag across a plot to zoom into that time, on every plot at once; the tools beside it pan, zoom
with the wheel and reset. A click on a legend's entry hides its line.</p>
<figure id="timeline">{{ figures.timeline|safe }}</figure>
<table><tr><th>state</th><th>entered (s)</th><th>left (s)</th><th>time spent (s)</th></tr>
{% macro stay(s) %}{% set state, start, end = s %}<tr><td>{{ state }}</td><td>{{ "%.3f"|format(start) }}</td>
<td>{{ "%.3f"|format(end) if end is not none else "(the end)" }}</td>
<td>{{ "%.3f"|format((end if end is not none else end_time) - start) }}</td></tr>{% endmacro %}
{% set first, left_out, last = visits %}{% for s in first %}{{ stay(s) }}{% endfor %}
{% if left_out %}<tr><td colspan="4">... {{ left_out }} more stays (the graph counts every one)</td></tr>{% endif %}
{% for s in last %}{{ stay(s) }}{% endfor %}
</table>
<h2>Signals</h2>
<p>States are shaded; a dashed red line is an event firing. The last panel is the simulator's
ground truth, which the robot does not see.</p>
<figure id="signals">{{ figures.signals|safe }}</figure>
{% if pictures %}<h2>Depth camera</h2>
<p>What the robot's depth camera saw each time a state took a picture, nearest darkest, nothing
seen blank{% if pictures_left_out %} (the first and last; {{ pictures_left_out }} more between){% endif %}.
The recording also holds each picture's points, in the world as the robot believes it
(<code>/camera/points</code>).</p>
<figure id="pictures">{{ pictures|safe }}</figure>
{% endif %}<h2>Events, and the readings that fired them</h2>
<table id="events"><tr><th>time (s)</th><th>transition</th><th>event</th><th>conditions and readings</th></tr>
{% macro event(e) %}<tr><td>{{ "%.3f"|format(e.t) }}</td><td>{{ e.transition }}</td><td>{{ e.event }}</td>
<td>{% for c in e.conditions %}<code>{{ c }}</code><br>{% endfor %}</td></tr>{% endmacro %}
{% set first, left_out, last = events %}{% for e in first %}{{ event(e) }}{% endfor %}
{% if left_out %}<tr><td colspan="4">... {{ left_out }} more events</td></tr>{% endif %}
{% for e in last %}{{ event(e) }}{% endfor %}
</table>
{{ figures.script|safe }}
</body></html>
""")


def _graph(recording: Recording) -> tuple[str, str]:
    """The ESTD's graph as inline SVG with the path taken in colour, each state visited
    labelled with its visits and time; and a line saying what it leaves out."""
    if recording.estd is None:
        return (f"<p>(the ESTD this recording holds cannot be read: {html.escape(recording.estd_problem)})</p>"
                if recording.estd_problem else "<p>(this recording holds no ESTD)</p>"), ""
    graph: Graph = from_estd(recording.estd, recording.run.task or "task")
    if len(graph.nodes) + len(graph.edges) > MAX_ELEMENTS:
        return (f"<p>(the task's {len(graph.nodes)} states and {len(graph.edges)} transitions are more than a report "
                f"draws, {MAX_ELEMENTS} in all; draw them with atd graph)</p>"), ""
    taken = Counter(r.transition for r in recording.trace if r.type == "exit" and r.transition and "/" not in r.state)
    spent: dict[str, float] = defaultdict(float)
    count: dict[str, int] = defaultdict(int)
    for state, start, end in recording.visits:
        top = state.split("/", 1)[0]
        spent[top] += (recording.end_time if end is None else end) - start
        count[top] += 1 if "/" not in state else 0
    graph.nodes = [replace(n, lines=n.lines + (f">> visited {count[n.id]}x, {spent[n.id]:.2f} s",))
                   if n.id in spent else n for n in graph.nodes]
    graph, folded = on_trail(graph, set(spent), taken)
    svg, _ = render(graph, "svg")
    text = svg.decode()
    note = "The path taken is in colour, thick arrows the transitions taken; grey: never visited, never taken."
    if folded.arrows:
        note += (f" The {folded.transitions} failure transitions never taken are folded into {folded.arrows} grey "
                 f"arrows, each saying how many it stands for (hover it for their names).")
    return text[text.index("<svg"):], note


# In a clone of atd, beside the package; the page names it there, else as the source tree names it.
FOXGLOVE_LAYOUT = Path(__file__).resolve().parents[2] / "docs" / "foxglove-layout.json"


def _layout() -> str:
    return str(FOXGLOVE_LAYOUT) if FOXGLOVE_LAYOUT.is_file() else "docs/foxglove-layout.json of atd's source"


def _event(record: TraceRecord) -> dict:
    conditions = [f"{c.get('kind')}: " + json.dumps({k: v for k, v in c.items() if k not in ("kind", "atd", "sensors")})
                  for c in record.conditions]
    return {"t": record.t, "transition": record.transition, "event": record.event, "conditions": conditions}


def report_page(recording: Recording) -> str:
    """The page; of a long run, the first and last SECTION_LINES // 2 stays and events in its
    tables (the graph counts every visit)."""
    run = recording.run
    title = f"{html.unescape(run.task)} on {run.robot} ({run.arm} arm) in {run.engine}"
    first, left_out, last = ends(recording.events())
    drawn, pictures_left_out = pictures(recording)
    graph, graph_note = _graph(recording)
    return _PAGE.render(
        title=title, run=run, outcome=recording.outcome, succeeded=recording.outcome.get("succeeded") == "true",
        recording_path=recording.path.resolve(), layout=_layout(),
        end_time=recording.end_time, graph=graph, graph_note=graph_note, figures=figures(recording), keyframes=key_frames(recording),
        visits=ends(recording.visits), pictures=drawn,
        pictures_left_out=pictures_left_out,
        events=([_event(e) for e in first], left_out, [_event(e) for e in last]))
