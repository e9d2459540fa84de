"""Key frames of a recorded run: the scene as it stood each time the task entered a state,
and at the end, drawn from the recording alone.

A recording of `atd run --record` holds what a picture needs: the bodies (the robot's
links, the table, the objects, as Foxglove's `/truth/scene`) and where each frame was
(`/truth/tf`, 25 times a second). The frames become MuJoCo bodies moved by hand (mocap),
the bodies' shapes their geoms, and MuJoCo's offscreen renderer draws them through the
video's camera with the video's settings and label (atd/sim/video.py), whichever engine
ran: neither the task, the world nor the robot's package is needed beside the file.
"""

from __future__ import annotations

import base64
import bisect
import io
from dataclasses import dataclass
from xml.sax.saxutils import quoteattr

import numpy as np
from mcap.records import Channel, Message

from atd.model.files import InputError, read_capped
from atd.review.load import RECORDING_CAP, Recording
from atd.review.mcap_records import Damaged, records
from atd.review.messages import (Entity, MessageProblem, SceneMessage, ScenePose, Sized, TransformsMessage,
                                 parsed)
from atd.runtime.recording_scene import ROOT
from atd.runtime.report import ends

KEY_FRAMES = 12  # drawn at most: the first and last six
SIZE = (480, 360)  # pixels of a key frame: three across the page
QUALITY = 85  # JPEG's: the scene's flat colours show no artefacts
_SCENE, _TF = "/truth/scene", "/truth/tf"
# The video's look (atd/sim/templates/scene.mjcf.j2): its headlight, sky, light and floor.
_LOOK = """<visual><global offwidth="{w}" offheight="{h}"/>
<headlight ambient="0.35 0.35 0.35" diffuse="0.45 0.45 0.45" specular="0.1 0.1 0.1"/></visual>
<asset><texture type="skybox" builtin="flat" rgb1="0.86 0.89 0.93" rgb2="0.86 0.89 0.93" width="16" height="16"/>
{meshes}</asset>
<default><geom contype="0" conaffinity="0" density="0"/></default>"""
_WORLD = """<light pos="0.2 -0.6 1.5" dir="-0.1 0.4 -1"/>
<geom type="plane" size="2 2 0.5" pos="0 0 -0.78" rgba="0.8 0.8 0.8 1"/>"""


@dataclass(frozen=True)
class KeyFrame:
    t: float
    state: str  # the state entered, or "the end"
    jpeg: bytes

    @property
    def source(self) -> str:
        """The picture as a data: URL, which the page holds itself."""
        return "data:image/jpeg;base64," + base64.b64encode(self.jpeg).decode()


@dataclass(frozen=True)
class KeyFrames:
    """The first and last key frames, how many lie between, and why there are none (else "")."""

    first: list[KeyFrame]
    left_out: int
    last: list[KeyFrame]
    problem: str = ""


def moments(recording: Recording) -> list[tuple[float, str]]:
    """(time, what) of each key frame: each entry into a state of the task's top level, and
    the end when the run ended later than it entered its last state."""
    found = [(r.t, r.state) for r in recording.trace if r.type == "enter" and "/" not in r.state]
    if not found or recording.end_time > found[-1][0] + 1e-6:
        found.append((recording.end_time, "the end"))
    return found


def key_frames(recording: Recording) -> KeyFrames:
    """The key frames of `recording` (the first and last KEY_FRAMES // 2 of a long run);
    none, with the reason, where the recording holds no scene or nothing can render it."""
    first, left_out, last = ends(moments(recording), KEY_FRAMES)
    wanted = first + last
    try:
        scene, poses = _read(recording, [t for t, _ in wanted])
        if scene is None:
            return KeyFrames([], 0, [], f"the recording holds no {_SCENE} (a run recorded by atd run --record has)")
        pictures = _render(scene, poses, [f"{t:6.2f} s  {state}" for t, state in wanted])
    except (InputError, Damaged, MessageProblem) as exc:
        return KeyFrames([], 0, [], f"{recording.path}: {exc}")
    except Exception as exc:  # noqa: BLE001 - no OpenGL, a mesh MuJoCo refuses: said on the page, not raised
        return KeyFrames([], 0, [], f"offscreen rendering failed ({type(exc).__name__}: {exc}); "
                                    f"try MUJOCO_GL=egl or MUJOCO_GL=osmesa")
    shown = [KeyFrame(t, state, jpeg) for (t, state), jpeg in zip(wanted, pictures)]
    return KeyFrames(shown[:len(first)], left_out, shown[len(first):])


def _read(recording: Recording, times: list[float]) -> tuple[SceneMessage | None, list[TransformsMessage | None]]:
    """The run's first scene, and for each of `times` (sorted) the frames' last transforms
    at or before it (the first, before the first; None without any): one more pass over the
    file, keeping only those."""
    data = read_capped(recording.path, RECORDING_CAP)
    topics: dict[int, str] = {}
    scene: tuple[float, bytes] | None = None
    latest: list[tuple[float, bytes] | None] = [None] * len(times)  # per time: the last message since the one before
    earliest: tuple[float, bytes] | None = None
    for record in records(data):
        if isinstance(record, Channel):
            topics[record.id] = record.topic
        elif isinstance(record, Message) and topics.get(record.channel_id) in (_SCENE, _TF):
            t = (record.log_time - recording.zero) / 1e9
            if topics[record.channel_id] == _SCENE:
                if scene is None or t < scene[0]:
                    scene = (t, bytes(record.data))
                continue
            if earliest is None or t < earliest[0]:
                earliest = (t, bytes(record.data))
            i = bisect.bisect_left(times, t - 1e-9)
            if i < len(times) and (latest[i] is None or t >= latest[i][0]):
                latest[i] = (t, bytes(record.data))
    for i in range(1, len(times)):  # the last at or before each time: its own, or an earlier time's
        if latest[i] is None:
            latest[i] = latest[i - 1]
    # Before the first: the first (the run's first state is entered before the first tick's pictures).
    latest = [earliest if found is None else found for found in latest]
    if scene is None:
        return None, []
    return (parsed(SceneMessage, scene[1], f"its {_SCENE} message at {scene[0]:.3f} s"),
            [None if m is None else parsed(TransformsMessage, m[1], f"its {_TF} message at {m[0]:.3f} s")
             for m in latest])


def _pos_quat(pose: ScenePose) -> tuple[np.ndarray, np.ndarray]:
    p, q = pose.position, pose.orientation
    return np.array([p.x, p.y, p.z]), np.array([q.w, q.x, q.y, q.z])


def _placed(pose: ScenePose) -> str:
    pos, quat = _pos_quat(pose)
    return f'pos="{" ".join(map(repr, pos.tolist()))}" quat="{" ".join(map(repr, quat.tolist()))}"'


def _rgba(shape: Sized) -> str:
    c = shape.color
    return f'rgba="{c.r!r} {c.g!r} {c.b!r} {c.a!r}"'


def _geoms(entity: Entity, meshes: dict[str, tuple[bytes, str]]) -> list[str]:
    """An entity's shapes as MJCF geoms in its frame; its meshes (file, scale) added to `meshes`."""
    found = [f'<geom type="box" size="{s.size.x / 2!r} {s.size.y / 2!r} {s.size.z / 2!r}" {_placed(s.pose)} '
             f'{_rgba(s)}/>' for s in entity.cubes]
    found += [f'<geom type="sphere" size="{s.size.x / 2!r}" {_placed(s.pose)} {_rgba(s)}/>' for s in entity.spheres]
    found += [f'<geom type="cylinder" size="{s.size.x / 2!r} {s.size.z / 2!r}" {_placed(s.pose)} {_rgba(s)}/>'
              for s in entity.cylinders]
    for model in entity.models:
        name = f"mesh{len(meshes)}.{model.media_type.split('/')[1]}"
        meshes[name] = (base64.b64decode(model.data), f"{model.scale.x!r} {model.scale.y!r} {model.scale.z!r}")
        found.append(f'<geom type="mesh" mesh={quoteattr(name)} {_placed(model.pose)} {_rgba(model)}/>')
    return found


def _model(scene: SceneMessage):
    """A MuJoCo model of the scene's entities: those in the world fixed, the others on a
    mocap body per frame. The model and the frames, in the order of its mocap bodies."""
    import mujoco

    meshes: dict[str, tuple[bytes, str]] = {}
    fixed: list[str] = []
    moving: dict[str, list[str]] = {}
    for entity in scene.entities:
        (fixed if entity.frame_id == ROOT else moving.setdefault(entity.frame_id, [])).extend(_geoms(entity, meshes))
    frames = list(moving)
    bodies = "".join(f'<body name="frame{k}" mocap="true">{"".join(moving[f])}</body>' for k, f in enumerate(frames))
    mesh_xml = "".join(f'<mesh name={quoteattr(name)} file={quoteattr(name)} scale="{scale}"/>'
                       for name, (_, scale) in meshes.items())
    xml = (f'<mujoco><compiler inertiafromgeom="false"/>{_LOOK.format(w=SIZE[0], h=SIZE[1], meshes=mesh_xml)}'
           f'<worldbody>{_WORLD}{"".join(fixed)}{bodies}</worldbody></mujoco>')
    return mujoco.MjModel.from_xml_string(xml, {name: data for name, (data, _) in meshes.items()}), frames


def _world_poses(message: TransformsMessage) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each frame's pose in the world, through its parents (a frame whose chain does not
    reach the world is left out)."""
    import mujoco

    parent = {t.child_frame_id: t for t in message.transforms}
    found: dict[str, tuple[np.ndarray, np.ndarray]] = {ROOT: (np.zeros(3), np.array([1.0, 0, 0, 0]))}

    def pose(frame: str, depth: int = 0) -> tuple[np.ndarray, np.ndarray] | None:
        if frame in found:
            return found[frame]
        if frame not in parent or depth > len(parent):  # no parent, or a loop
            return None
        above = pose(parent[frame].parent_frame_id, depth + 1)
        if above is None:
            return None
        t = parent[frame]
        pos, quat = np.zeros(3), np.zeros(4)
        mujoco.mju_mulPose(pos, quat, above[0], above[1], np.array([t.translation.x, t.translation.y, t.translation.z]),
                           np.array([t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z]))
        found[frame] = (pos, quat)
        return found[frame]

    for frame in parent:
        pose(frame)
    return found


def _render(scene: SceneMessage, poses: list[TransformsMessage | None], labels: list[str]) -> list[bytes]:
    """A JPEG per pose, labelled as a video's frame is: the scene with each frame where the
    transforms put it (a frame without one is drawn out of sight)."""
    import mujoco

    from atd.sim.mujoco_engine import video_renderer, workspace_view
    from atd.sim.video import draw_label

    model, frames = _model(scene)
    data = mujoco.MjData(model)
    renderer = video_renderer(model, *SIZE)
    pictures = []
    try:
        for message, label in zip(poses, labels):
            placed = {} if message is None else _world_poses(message)
            for k, frame in enumerate(frames):
                data.mocap_pos[k], data.mocap_quat[k] = placed.get(frame, (np.full(3, 1e3), np.array([1.0, 0, 0, 0])))
            mujoco.mj_kinematics(model, data)
            renderer.update_scene(data, workspace_view())
            out = io.BytesIO()
            draw_label(renderer.render(), label).save(out, format="JPEG", quality=QUALITY)
            pictures.append(out.getvalue())
    finally:
        renderer.close()
    return pictures
