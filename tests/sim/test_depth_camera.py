"""The depth camera (the thesis's Kinect over the table), headless in both engines: a
picture on demand, its point cloud where the world truly is, seen from where the robot
believes the camera stands."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from atd.sim import make_robot
from atd.sim.scene import box_scene
from factories.description import KINECT, Origin
from primitives.robot import point_cloud

BOX = 0.05  # m, a cube on the table
WHERE = (0.25, -0.1)  # in view, and not under the parked hand


def _top_of_box(points: np.ndarray, xy: tuple[float, float] = WHERE) -> np.ndarray:
    """The points over the middle of the box's top face (clear of its edges)."""
    near = (np.abs(points[:, 0] - xy[0]) < BOX / 2 - 0.01) & (np.abs(points[:, 1] - xy[1]) < BOX / 2 - 0.01)
    return points[near]


def test_the_point_cloud_puts_a_known_box_s_top_where_it_is(melfa, robot_of, engine) -> None:
    robot = robot_of(melfa, engine, box_scene(BOX, WHERE))
    robot.hold_still(0.1)
    image = robot.capture("kinect")
    assert image.depth.shape == (KINECT.height, KINECT.width) and image.depth.dtype == np.float32
    assert image.sensor == "kinect" and image.time == pytest.approx(0.1)
    np.testing.assert_array_equal(image.pose, KINECT.origin.matrix())
    top = _top_of_box(point_cloud(image))
    assert len(top) >= 10
    assert abs(float(np.median(top[:, 2])) - BOX) < 0.01  # the box's top, within 1 cm
    table = point_cloud(image)
    beside = (np.abs(table[:, 0] - 0.25) < 0.05) & (np.abs(table[:, 1] - 0.15) < 0.05)
    assert abs(float(np.median(table[beside, 2]))) < 0.01  # and the table top at z = 0


def test_the_picture_shows_the_truth_and_reports_the_believed_pose(melfa, robot_of, engine) -> None:
    # The camera truly stands 6 cm further along world y than its calibration says.
    shifted = np.array(KINECT.origin.xyz) + (0.0, 0.06, 0.0)
    truth = dataclasses.replace(melfa, cameras=(dataclasses.replace(KINECT, origin=Origin(tuple(shifted), KINECT.origin.rpy)),))
    robot = make_robot(truth, box_scene(BOX, WHERE), engine, belief=melfa)
    try:
        seen = robot.capture("kinect")
    finally:
        robot.close()
    np.testing.assert_array_equal(seen.pose, KINECT.origin.matrix())  # the belief, wherever the camera stands
    cloud = point_cloud(seen)
    moved = _top_of_box(cloud, (WHERE[0], WHERE[1] - 0.06))
    assert len(moved) >= 10 and abs(float(np.median(moved[:, 2])) - BOX) < 0.01  # seen 6 cm off, as a miscalibration makes it
    assert abs(float(np.median(_top_of_box(cloud)[:, 2]))) < 0.01  # and the table where the box truly is


def test_the_camera_is_rendered_only_when_captured(melfa, robot_of, engine, monkeypatch) -> None:
    robot = robot_of(melfa, engine, box_scene(BOX, WHERE))
    rendered = []
    render = robot._render_depth
    monkeypatch.setattr(robot, "_render_depth", lambda camera: rendered.append(camera.name) or render(camera))
    robot.hold_still(0.2)
    assert rendered == []  # 40 ticks, no picture: a picture costs what hundreds of ticks do
    robot.capture("kinect")
    assert rendered == ["kinect"]


def test_a_camera_the_robot_lacks_is_refused_with_the_ones_it_has(melfa, robot_of, engine) -> None:
    robot = robot_of(melfa, engine, box_scene(BOX, WHERE))
    with pytest.raises(LookupError, match="melfa has no depth camera 'realsense'; its cameras: kinect"):
        robot.capture("realsense")
    blind = robot_of(dataclasses.replace(melfa, cameras=()), engine, box_scene(BOX, WHERE))
    with pytest.raises(LookupError, match="its cameras: none"):
        blind.capture("kinect")


def test_depth_noise_grows_with_the_depth_and_follows_the_seed(melfa, robot_of, engine) -> None:
    images = [robot_of(melfa, engine, box_scene(BOX, WHERE), seed).capture("kinect").depth for seed in (1, 1, 2)]
    np.testing.assert_array_equal(images[0], images[1])
    seen = images[0] > 0
    # Two draws of the noise about the same picture, scaled by what the model says at each depth.
    scaled = (images[0][seen] - images[2][seen]) / (np.sqrt(2) * KINECT.noise * images[0][seen] ** 2)
    assert float(np.std(scaled)) == pytest.approx(1.0, abs=0.1)
