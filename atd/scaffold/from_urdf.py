"""What `atd robots new --from-urdf` finds in a URDF for the generated description: the
gripper's two finger joints and the link they hang from, the arm's joints down to it,
where the robot should stand, and its home posture."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from atd.scaffold.source import IDENTIFIER
from factories.description import Origin, RobotDescription, Site
from factories.home import HOME_TCP, with_home
from factories.urdf import UrdfError, UrdfModel, read_urdf
from factories.urdf_hand import urdf_parallel_jaw

MAX_ARM_JOINTS = 32  # a redundant arm has 7 or 8: a longer chain to the hand is a mistake, or no arm
REACH_SHARE = 0.4  # of the summed joint offsets, root to TCP: the Panda's 1.43 m puts its base 45 cm back, where its home is central


class UrdfScaffoldError(ValueError):
    """The URDF cannot start a robot; the message names the file and what it lacks."""


def _fingers(model: UrdfModel) -> tuple[str, tuple[str, str]]:
    """The link with exactly two prismatic joints under it, and those joints."""
    by_parent: dict[str, list[str]] = {}
    for link in model.links:
        if link.joint is not None and link.joint.kind == "prismatic":
            by_parent.setdefault(link.parent or "", []).append(link.joint.name)
    pairs = [(parent, joints) for parent, joints in by_parent.items() if len(joints) == 2]
    if len(pairs) != 1:
        raise UrdfScaffoldError(
            f"{model.path}: found {len(pairs)} links with two prismatic finger joints; --from-urdf makes a "
            "parallel-jaw robot, whose hand link carries exactly two (describe other hands by hand: "
            "docs/writing-a-robot.md)")
    parent, joints = pairs[0]
    return parent, (joints[0], joints[1])


def _chain(model: UrdfModel, link: str) -> list[str]:
    """Link names from the root down to `link`."""
    parents = {l.name: l.parent for l in model.links}
    chain = [link]
    while parents[chain[-1]] is not None:
        chain.append(parents[chain[-1]])
    return chain[::-1]


def _import_path(urdf: Path) -> tuple[str, str] | None:
    """(package, path inside it) when the URDF ships inside an installed Python package
    whose name is a plain identifier (the generated code imports it by that name)."""
    for entry in sys.path:
        folder = Path(entry or ".").resolve()
        if folder.is_dir() and urdf.is_relative_to(folder) and len(urdf.relative_to(folder).parts) > 1:
            package = urdf.relative_to(folder).parts[0]
            if IDENTIFIER.fullmatch(package) and (folder / package / "__init__.py").is_file():
                return package, str(Path(*urdf.relative_to(folder).parts[1:]))
    return None


def urdf_values(urdf: Path, name: str) -> dict[str, object]:
    """The template values of a description read from `urdf`, as read: the templates write
    each through `atd.scaffold.source.literal` (their `py` filter)."""
    urdf = Path(urdf).resolve()
    try:
        model = read_urdf(urdf)
        hand_root, fingers = _fingers(model)
        hand, tcp = urdf_parallel_jaw(model, hand_root, fingers)
    except UrdfError as exc:
        raise UrdfScaffoldError(str(exc)) from None
    by_name = {link.name: link for link in model.links}
    chain = _chain(model, hand_root)
    arm_joints = tuple(by_name[l].joint.name for l in chain if by_name[l].joint is not None)
    if len(arm_joints) > MAX_ARM_JOINTS:
        line = model.joint_lines[arm_joints[MAX_ARM_JOINTS]]
        raise UrdfScaffoldError(f"{urdf}:{line}: the arm down to '{hand_root}' has {len(arm_joints)} moving joints, "
                                f"more than the {MAX_ARM_JOINTS} atd drives; make the extra joints fixed, or start "
                                "from a URDF of the arm and its hand alone")
    if len(arm_joints) < 6:
        raise UrdfScaffoldError(f"{urdf}: the arm down to '{hand_root}' has {len(arm_joints)} moving joints; "
                                "a hand pointing down anywhere in the work area needs at least 6")
    reach = sum(float(np.linalg.norm(by_name[l].origin.xyz)) for l in chain[1:]) + tcp.origin.xyz[2]
    base_x = round(HOME_TCP[0] - REACH_SHARE * reach, 3)
    robot = RobotDescription(name=name, arm=None, links=model.links, arm_joints=arm_joints, hand_root=hand_root,
                             hand=hand, tcp=tcp, wrist_sensor=Site("wrist_ft", hand_root),
                             base=Origin((base_x, 0.0, 0.0)), home=(0.0,) * len(arm_joints))
    try:
        home = with_home(robot).home
    except ValueError as exc:
        raise UrdfScaffoldError(f"{urdf}: {exc}") from None
    inside = _import_path(urdf)
    return {"urdf_package": inside[0] if inside else "", "urdf_inside": inside[1] if inside else "",
            "urdf_path": str(urdf), "arm_joints": arm_joints, "dof": len(arm_joints), "hand_root": hand_root,
            "fingers": fingers, "max_opening": round(2 * hand.dofs[0].open, 6), "base_x": base_x,
            "home": tuple(home)}
