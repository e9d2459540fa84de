"""Several arms of one robot in one MuJoCo world (atd/sim/two_arms.py says what is shared).

Each arm is rendered to MJCF alone (`atd.sim.models.mjcf`). The world of several arms is
the first arm's world with each further arm's body tree, actuators, couplings and sensors
added, every name of theirs given a prefix (`left/`), and the home key extended with their
joints; robot geoms never collide with one another, so the trunks only overlap.
"""

from __future__ import annotations

from lxml import etree

from atd.sim.models import mjcf
from atd.sim.scene import Scene
from factories.description import RobotDescription

# Attributes that name an element of the robot's own (prefixed with it); classes are shared.
_NAMES = ("name", "joint", "joint1", "joint2", "site", "geom1", "body", "mesh")


def arm_prefix(arm: str) -> str:
    """The prefix of the names of an added arm's elements."""
    return f"{arm}/"


def _renamed(node: etree._Element, prefix: str) -> etree._Element:
    for element in node.iter():
        for attribute in _NAMES:
            if element.get(attribute) is not None:
                element.set(attribute, prefix + element.get(attribute))
    return node


def _section(root: etree._Element, tag: str) -> etree._Element:
    found = root.find(tag)
    return found if found is not None else etree.SubElement(root, tag)


def arms_mjcf(first: RobotDescription, others: tuple[RobotDescription, ...], scene: Scene) -> str:
    """The MuJoCo world of `scene` with the arm of `first` and each arm of `others`, whose
    names take `arm_prefix(arm)`. Joints lead qpos in the order of the arms, the scene's free
    objects follow; actuators come arm by arm, each arm's arm joints before its hand's."""
    root = etree.fromstring(mjcf(first, scene).encode())
    world = root.find("worldbody")
    body = world.find(f"body[@name='world_{first.name}']")
    key = root.find("keyframe/key")
    qpos, ctrl = key.get("qpos").split(), key.get("ctrl").split()
    robot_qpos = sum(1 for _ in body.iter("joint"))
    for other in others:
        prefix = arm_prefix(other.arm)
        added = etree.fromstring(mjcf(other, Scene(objects=(), table=scene.table)).encode())
        arm_body = _renamed(added.find(f"worldbody/body[@name='world_{other.name}']"), prefix)
        body.addnext(arm_body)
        body = arm_body
        joints = sum(1 for _ in arm_body.iter("joint"))
        other_key = added.find("keyframe/key")
        qpos[robot_qpos:robot_qpos] = other_key.get("qpos").split()[:joints]
        robot_qpos += joints
        ctrl += other_key.get("ctrl").split()
        for tag in ("actuator", "equality", "sensor", "asset"):
            section = added.find(tag)
            if section is None:
                continue
            elements = [e for e in section if tag != "asset" or e.tag == "mesh"]
            for element in elements:
                _section(root, tag).append(_renamed(element, prefix))
    key.set("qpos", " ".join(qpos))
    key.set("ctrl", " ".join(ctrl))
    return etree.tostring(root, encoding="unicode")
