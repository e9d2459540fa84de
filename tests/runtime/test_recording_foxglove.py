"""`atd run --record`: what Foxglove's 3D panel needs to draw the robot, the object and the
table (its own schema names, JSON Schemas, one tree of frames rooted at "world")."""

from __future__ import annotations

import base64
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader

from atd.model import load_task
from atd.runtime.recording_format import CLOCK
from atd.runtime.recording_scene import SCENE_RATE, Arm, frames_of
from atd.runtime.session import Run
from atd.sim.scene import Body, Scene
from factories.description import Shape
from factories.registry import create
from tests.conftest import REPO
from translator import translate

FOXGLOVE = {"/truth/tf": "foxglove.FrameTransforms", "/truth/scene": "foxglove.SceneUpdate",
            "/tcp": "foxglove.PoseInFrame"}


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """A simple move's recording: its channels with their schemas, messages by topic, run time."""
    path = tmp_path_factory.mktemp("fox") / "run.mcap"
    task, _ = load_task(REPO / "examples" / "simple_move.xml")
    factory = create("melfa")
    before = time.time_ns()
    outcome = Run(translate(task, factory).estd, factory, record=path).execute()
    found: dict[str, list[tuple[int, dict]]] = {}
    with path.open("rb") as f:
        reader = make_reader(f)
        channels = {c.topic: (c, reader.get_summary().schemas[c.schema_id])
                    for c in reader.get_summary().channels.values()}
        zero = int({m.name: m.metadata for m in reader.iter_metadata()}[CLOCK]["value"])
        for _, channel, message in reader.iter_messages():
            found.setdefault(channel.topic, []).append((message.log_time - zero, json.loads(message.data)))
    return {"channels": channels, "messages": found, "end": outcome.sim_time, "zero": zero, "before": before}


def test_the_3d_channels_carry_foxglove_schemas_by_name_in_json(recording: dict) -> None:
    for topic, name in FOXGLOVE.items():
        channel, schema = recording["channels"][topic]
        assert schema.name == name and schema.encoding == "jsonschema" and channel.message_encoding == "json"
        assert json.loads(schema.data)["type"] == "object", f"{name}'s schema is a JSON Schema of an object"
    assert recording["channels"]["/truth/tf"][0].metadata["ground_truth"] == "true"
    assert recording["channels"]["/tcp"][0].metadata["ground_truth"] == "false", "the believed TCP is no truth"


def _foxglove_rejects(schema: dict, where: str) -> list[str]:
    """Where Foxglove's JSON Schema reader (Studio 1.48, mcap-support parseJsonSchema) gives up
    on a channel: every property needs one type (or number-valued oneOf), objects their
    properties, arrays items of one type other than array."""
    if schema.get("type") != "object" or not isinstance(schema.get("properties"), dict):
        return [f"{where}: an object needs its properties"]
    found = []
    for name, field in schema["properties"].items():
        kind, at = field.get("type"), f"{where}.{name}"
        if "oneOf" in field:
            found += [] if all(isinstance(a.get("const"), (int, float)) for a in field["oneOf"]) else [at]
        elif kind == "object":
            found += _foxglove_rejects(field, at)
        elif kind == "array":
            item = field.get("items", {})
            found += _foxglove_rejects(item, at) if item.get("type") == "object" else \
                [] if item.get("type") in ("boolean", "string", "number", "integer") else [at]
        elif kind not in ("boolean", "string", "number", "integer"):
            found.append(at)
    return found


def test_foxglove_reads_every_channel_and_finds_each_field_the_layout_plots(recording: dict) -> None:
    declared = {topic: json.loads(schema.data) for topic, (_, schema) in recording["channels"].items()}
    for topic, schema in declared.items():
        assert _foxglove_rejects(schema, topic) == []
    panels = json.loads((REPO / "docs" / "foxglove-layout.json").read_text())["configById"]
    plotted = [p["value"] for panel in panels.values() for p in panel.get("paths", ())]
    assert "/sensors.pads.tactile_left.force" in plotted and "/truth.object.position.z" in plotted
    for path in plotted:
        topic, *fields = path.split(".")
        schema = declared[topic]
        for field in fields:
            schema = schema["properties"][field.split("[")[0]]  # a KeyError: Foxglove plots nothing there


def test_log_times_and_timestamps_are_the_wall_clock_of_the_run(recording: dict) -> None:
    """So a viewer shows when the run happened, not 1970: simulated 0 is the moment it started."""
    assert recording["before"] <= recording["zero"] <= time.time_ns()
    tfs = recording["messages"]["/truth/tf"]
    assert 0 <= tfs[0][0] < 1e8 and tfs[-1][0] == pytest.approx(recording["end"] * 1e9, abs=1e8)


def test_every_frame_reaches_world_and_each_transform_lies_within_the_run(recording: dict) -> None:
    tfs = recording["messages"]["/truth/tf"]
    end_ns = recording["end"] * 1e9 + 1
    assert len(tfs) == pytest.approx(recording["end"] * SCENE_RATE, abs=2), "transforms at the scene's rate"
    for log_time, message in tfs:
        parents = {t["child_frame_id"]: t["parent_frame_id"] for t in message["transforms"]}
        assert len(parents) == len(message["transforms"]), "each frame has one parent"
        for frame in parents:
            seen = {frame}
            while frame != "world":
                frame = parents[frame]  # a KeyError: a frame whose chain breaks off
                assert frame not in seen, f"a cycle through {frame}"
                seen.add(frame)
        for t in message["transforms"]:
            ns = t["timestamp"]["sec"] * 1_000_000_000 + t["timestamp"]["nsec"] - recording["zero"]
            assert ns == log_time and 0 <= ns <= end_ns
            q = t["rotation"]
            assert q["x"] ** 2 + q["y"] ** 2 + q["z"] ** 2 + q["w"] ** 2 == pytest.approx(1.0, abs=1e-5)
    frames = set(parents)
    assert {"base", "tcp", "object/object", "link/base"} <= frames
    assert len([f for f in frames if f.startswith("link/")]) > 8, "a frame per link of the Melfa and its hand"


def test_the_scene_draws_table_object_and_links_on_frames_that_exist(recording: dict) -> None:
    frames = {"world"} | {t["child_frame_id"] for t in recording["messages"]["/truth/tf"][0][1]["transforms"]}
    scenes = recording["messages"]["/truth/scene"]
    assert len(scenes) == pytest.approx(recording["end"], abs=1.5), "the scene again every second"
    entities = {e["id"]: e for e in scenes[0][1]["entities"]}
    assert {e["frame_id"] for e in entities.values()} <= frames
    assert entities["table"]["cubes"] and entities["object object"]["frame_id"] == "object/object"
    links = [e for e in entities.values() if e["id"].startswith("link ")]
    assert sum(len(e["cubes"]) + len(e["cylinders"]) + len(e["spheres"]) + len(e["models"]) for e in links) > 5
    tfs = [{t["child_frame_id"]: t for t in m["transforms"]} for _, m in recording["messages"]["/truth/tf"]]
    assert tfs[0]["link/link1"]["rotation"] != tfs[-1]["link/link1"]["rotation"], "the first joint turned"
    assert tfs[0]["tcp"]["translation"] == tfs[-1]["tcp"]["translation"], "the TCP sits fixed on its link"
    tcp = [m["pose"]["position"] for _, m in recording["messages"]["/tcp"]]
    assert tcp[0] != tcp[-1], "the believed TCP moves with the arm"


def test_the_shipped_layout_shows_channels_a_recording_has(recording: dict) -> None:
    layout = json.loads((REPO / "docs" / "foxglove-layout.json").read_text())
    panels = layout["configById"]
    shown = set(panels["3D!atd"]["topics"]) | {panels["RawMessages!trace"]["topicPath"]}
    shown |= {p["value"].split(".")[0] for name, panel in panels.items() for p in panel.get("paths", ())}
    assert panels["3D!atd"]["followTf"] == "world" and "/truth/scene" in shown
    assert shown <= set(recording["channels"])
    placed = json.dumps(layout["layout"])
    assert all(f'"{name}"' in placed for name in panels), "every configured panel is in the layout"


def test_a_mesh_object_is_drawn_from_its_own_file_and_a_capsule_link_with_round_ends(tmp_path: Path) -> None:
    mesh = tmp_path / "wedge.obj"
    mesh.write_text("v 0 0 0\nv 0.04 0 0\nv 0 0.04 0\nv 0 0 0.04\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n")
    wedge = Body("wedge", "mesh", (0.04, 0.04, 0.04), np.eye(4), 0.1, 1.0, mesh, mesh_scale=(2.0, 2.0, 2.0))
    d = create("melfa").robot
    arm = replace(d.links[1], shapes=(Shape("capsule", (0.03, 0.1)),), visuals=())
    d = replace(d, links=(d.links[0], arm, *d.links[2:]))
    frames = frames_of((Arm("", d, d.arm_joints),), Scene(objects=(wedge,), table=False))
    entities = {e["id"]: e for e in frames.entities}
    model = entities["object wedge"]["models"][0]
    assert base64.b64decode(model["data"]) == mesh.read_bytes() and model["media_type"] == "model/obj"
    assert model["scale"] == {"x": 2.0, "y": 2.0, "z": 2.0} and "table" not in entities
    capsule = entities[f"link {arm.name}"]
    assert capsule["cylinders"][0]["size"] == {"x": 0.06, "y": 0.06, "z": 0.2}
    assert sorted(s["pose"]["position"]["z"] for s in capsule["spheres"]) == [-0.1, 0.1]
