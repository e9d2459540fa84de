"""A hand taken from an installed robot and hung on another arm: a new robot's first hand,
until its own is described."""

from __future__ import annotations

from dataclasses import replace

from factories.description import Hand, Link, Origin, Site
from factories.registry import create


def installed_hand(robot: str, arm: str | None, parent: str, mount: Origin) -> tuple[tuple[Link, ...], Hand, Site]:
    """The hand of an installed robot's arm: its links, the first hung on the link `parent`
    at `mount`; its hand model (DOFs, pads, postures); its TCP site (on a hand link, so it
    comes along)."""
    donor = create(robot, arm).robot
    links = [donor.links_by_name[name] for name in donor.hand_links]
    links[0] = replace(links[0], parent=parent, origin=mount)
    return tuple(links), donor.hand, donor.tcp
