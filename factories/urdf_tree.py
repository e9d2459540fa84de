"""A URDF's link tree, found in time linear in its links: one root, every other link hung
from it by exactly one joint, no loops, plain names, and not more links than atd imports.

A link left out of the tree would be silently missing from the robot, so every way of
leaving one out (a second root, a loop of joints) is an error at the URDF's line.
"""

from __future__ import annotations

import re
from collections import deque
from dataclasses import dataclass
from typing import Callable

from lxml import etree

MAX_LINKS = 1000  # an arm with a hand has tens; more is a whole scene, or a generated file gone wrong
# Link and joint names are written into simulator models and Python sources: plain names only.
NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]{0,127}")

Fail = Callable[[etree._Element, str, str], Exception]
"""(element, what is wrong, how to fix) -> the error to raise, located at the element's line."""


@dataclass(frozen=True)
class Tree:
    """The <link>s and <joint>s of a URDF, ordered root first."""

    order: tuple[str, ...]
    """Link names, parents before children: breadth first, children in document order."""
    links: dict[str, etree._Element]
    """Each <link> by its name."""
    joints: dict[str, etree._Element]
    """The <joint> that hangs each link (but the root) from its parent, by the link's name."""


def link_tree(robot: etree._Element, fail: Fail) -> Tree:
    """The tree of the <robot> `robot`; `fail(...)` is raised for the first thing wrong."""
    links = _named(robot.findall("link"), "link", fail)
    joints = _joints(robot.findall("joint"), links, fail)
    roots = [name for name in links if name not in joints]
    if len(roots) > 1:
        raise fail(links[roots[1]], f"link '{roots[1]}' is a second root: no joint hangs it from another link, "
                   f"as none hangs '{roots[0]}' (line {links[roots[0]].sourceline})",
                   "a URDF is one tree: join it to the others by a joint, or remove it")
    children: dict[str, list[str]] = {}
    for child, joint in joints.items():
        children.setdefault(joint.find("parent").get("link"), []).append(child)
    order, pending = [], deque(roots)
    while pending:
        name = pending.popleft()
        order.append(name)
        pending.extend(children.get(name, ()))
    if len(order) < len(links):
        reached = set(order)
        _raise_loop(next(name for name in links if name not in reached), joints, roots, fail)
    return Tree(tuple(order), links, joints)


def _named(elements: list[etree._Element], kind: str, fail: Fail) -> dict[str, etree._Element]:
    """The elements by their names: each plain, each once, at most MAX_LINKS of them."""
    if len(elements) > MAX_LINKS:
        raise fail(elements[MAX_LINKS], f"the URDF has {len(elements)} <{kind}>s, more than the {MAX_LINKS} "
                   "atd imports", f"give the robot alone (an arm and its hand), in at most {MAX_LINKS} links")
    named: dict[str, etree._Element] = {}
    for element in elements:
        name = element.get("name")
        if not name:
            raise fail(element, f"a <{kind}> has no name", "add name=\"...\"")
        if not NAME.fullmatch(name):
            raise fail(element, f"the {kind} name {name[:80]!r} is not a plain name",
                       "use letters, digits, '_', '.' and '-' (up to 128, not starting with '.' or '-')")
        if name in named:
            raise fail(element, f"a second {kind} '{name}' (the first at line {named[name].sourceline})",
                       f"give every {kind} its own name")
        named[name] = element
    return named


def _joints(elements: list[etree._Element], links: dict[str, etree._Element], fail: Fail) -> dict[str, etree._Element]:
    """Each joint by the name of its child link, once both its links are known."""
    by_child: dict[str, etree._Element] = {}
    for name, element in _named(elements, "joint", fail).items():
        for end in ("parent", "child"):
            tag = element.find(end)
            if tag is None or tag.get("link") not in links:
                raise fail(element, f"joint '{name}' has no <{end} link=...> naming a link",
                           "name one of the URDF's links")
        child = element.find("child").get("link")
        if child in by_child:
            raise fail(element, f"link '{child}' is the child of two joints, '{by_child[child].get('name')}' "
                       f"and '{name}'", "a URDF is a tree: give each link one parent")
        by_child[child] = element
    return by_child


def _raise_loop(start: str, joints: dict[str, etree._Element], roots: list[str], fail: Fail) -> None:
    """Raise for the loop of joints above the link `start`, which the root does not reach."""
    seen: dict[str, int] = {}
    path = [start]
    while path[-1] not in seen:
        seen[path[-1]] = len(path) - 1
        path.append(joints[path[-1]].find("parent").get("link"))
    loop = path[seen[path[-1]]:]
    where = f"the root '{roots[0]}' does not reach it" if roots else "the URDF has no root link"
    names = " <- ".join(loop)
    raise fail(joints[loop[0]], f"link '{start}' hangs from a loop of joints ({names}): {where}",
               "a URDF is a tree: remove a joint of the loop and hang its links from the root")
