"""A mesh object as the campaign's library builds it: scaled and placed in its body, and,
when concave, several convex parts, the same in both engines; the parts are computed once
and kept in the user's cache, never in the repository."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pybullet as pb
import pybullet_data
import pytest

from atd.model.meshcheck import MeshError
from atd.model.meshcheck import mesh_points
from atd.sim.convex import convex_parts
from atd.sim.scene import Body, Scene
from tests.conftest import REPO

TORUS = Path(pybullet_data.getDataPath()) / "torus" / "torus_textured.obj"

# A 2 x 2 x 2 cube whose centre is at (1, 1, 1) in its own file.
OFF_CENTRE_CUBE = "\n".join(
    [f"v {x} {y} {z}" for x in (0, 2) for y in (0, 2) for z in (0, 2)]
    + ["f 1 2 4 3", "f 5 7 8 6", "f 1 5 6 2", "f 3 4 8 7", "f 1 3 7 5", "f 2 6 8 4"]
) + "\n"


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "cache"
    monkeypatch.setenv("ATD_CACHE_DIR", str(folder))
    return folder


def _resting(z: float) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, 3] = (0.1, 0.0, z)
    return pose


def test_a_scaled_mesh_placed_off_its_file_origin_rests_where_its_box_says(melfa, robot_of, run, engine,
                                                                          tmp_path) -> None:
    # Scaled to 4 x 5 x 6 cm and shifted so its centre is the body's: it must rest 3 cm up.
    mesh = tmp_path / "cube.obj"
    mesh.write_text(OFF_CENTRE_CUBE)
    frame = np.eye(4)
    frame[:3, 3] = (-0.02, -0.025, -0.03)
    body = Body("object", "mesh", (0.04, 0.05, 0.06), _resting(0.04), 0.2, 1.0, mesh,
                mesh_scale=(0.02, 0.025, 0.03), mesh_frame=frame)
    robot = robot_of(melfa, engine, Scene(body))
    run(robot, 0.5)
    np.testing.assert_allclose(robot.object_pose()[:3, 3], (0.1, 0.0, 0.03), atol=2.5e-3)


def test_a_concave_mesh_collides_as_several_convex_parts_in_both_engines(melfa, robot_of, engine, cache) -> None:
    parts = convex_parts(TORUS)
    body = Body("object", "mesh", (0.057, 0.057, 0.019), _resting(0.0095), 0.05, 0.7, TORUS,
                mesh_scale=(0.038, 0.038, 0.038), mesh_parts=parts)
    robot = robot_of(melfa, engine, Scene(body))
    if engine == "mujoco":
        m = robot.model
        collided = [g for g in range(m.ngeom) if m.geom_bodyid[g] == robot._object_bodies[0] and m.geom_contype[g]]
        assert [m.geom_type[g] for g in collided] == [mujoco.mjtGeom.mjGEOM_MESH] * len(parts)
    else:
        assert len(pb.getCollisionShapeData(robot.object, -1, physicsClientId=robot.client)) == len(parts)
    assert len(parts) > 1


def test_convex_parts_are_computed_once_and_cached_by_the_mesh_content(cache: Path, tmp_path: Path) -> None:
    parts = convex_parts(TORUS)
    assert all(cache in p.parents for p in parts)
    stamps = [p.stat().st_mtime_ns for p in parts]
    copy = tmp_path / "elsewhere.obj"
    copy.write_bytes(TORUS.read_bytes())
    assert convex_parts(copy) == parts  # same content, same parts, not computed again
    assert [p.stat().st_mtime_ns for p in parts] == stamps
    # Together the parts cover the torus (1.5 across, 0.495 thick), overreaching it by at most 3%.
    together = np.vstack([mesh_points(p) for p in parts])
    np.testing.assert_allclose(np.ptp(together, axis=0), np.ptp(mesh_points(TORUS), axis=0), rtol=0.03)
    assert not list(cache.glob("convex/.tmp-*"))  # no half-written folder left behind


def test_an_unreadable_mesh_gets_a_one_line_error_naming_the_file(tmp_path: Path, cache: Path) -> None:
    bad = tmp_path / "broken.obj"
    bad.write_text("v 1 2 three\n")
    with pytest.raises(MeshError, match=r"broken\.obj: .*'three' is not a number") as error:
        convex_parts(bad)
    assert "\n" not in str(error.value)


def test_pybullet_feels_a_held_mesh_object_pull_the_wrist_down() -> None:
    # Bullet reports a pair with the object as its body A swapped but with its friction
    # directions unturned: the mug's weight, carried by the pads' friction, read upward.
    from atd.campaign.objects import get
    from atd.model import load_task
    from atd.runtime.session import Run, belief_scene
    from factories.registry import create
    from translator import translate

    cup = get("mug")
    task, _ = load_task(REPO / "examples" / "grasp_and_lift.xml")
    factory = create("melfa")
    estd = translate(task.model_copy(update={"object": cup.object_info(0.10, 0.0)}), factory).estd
    belief = belief_scene(estd)
    run = Run(estd, factory, engine="pybullet", scene=Scene(cup.realize(belief.object), belief.obstacles, belief.table))
    empty = run.robot.read().wrench[2]
    loads: list[float] = []
    run.execute(afterwards=lambda robot: loads.append(float(robot.read().wrench[2])))
    assert run.object_position[2] > 0.10, "the cup was lifted"
    assert loads[0] - empty == pytest.approx(cup.mass * 9.81, abs=0.3), "the wrist carries the cup's weight"
