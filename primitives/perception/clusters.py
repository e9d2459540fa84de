"""Euclidean clustering of a point cloud on a voxel grid, in numpy alone (the project has no
scipy): points fall in cubic voxels; occupied voxels that touch, faces, edges or corners,
belong to one cluster; a cluster is every point of its voxels.

Two points of one cluster may be a voxel's diagonal apart or more; points further apart
than about two voxels with nothing between them are never joined. So objects that stand
apart by more than two voxels come out apart; objects that touch come out as one.
"""

from __future__ import annotations

import itertools

import numpy as np

# The 13 of a voxel's 26 neighbours that come after it in lexicographic order: each touching
# pair of voxels is looked at once.
_FORWARD = np.array([d for d in itertools.product((-1, 0, 1), repeat=3) if d > (0, 0, 0)], dtype=np.int64)
_SPAN = 1 << 20  # voxel indices per axis a key holds: 10 km of 1 cm voxels


def _keys(cells: np.ndarray) -> np.ndarray:
    """One int64 per voxel index triple (indices shifted to be non-negative, below _SPAN)."""
    return (cells[:, 0] * _SPAN + cells[:, 1]) * _SPAN + cells[:, 2]


def _components(count: int, pairs: np.ndarray) -> np.ndarray:
    """Connected components of `count` nodes joined by `pairs` (m, 2): a label per node,
    the smallest node index of its component (labels propagated until nothing changes)."""
    labels = np.arange(count)
    if len(pairs) == 0:
        return labels
    a, b = pairs[:, 0], pairs[:, 1]
    while True:
        low = np.minimum(labels[a], labels[b])
        new = labels.copy()
        np.minimum.at(new, a, low)
        np.minimum.at(new, b, low)
        new = new[new]  # a label points at a node; follow it to that node's label
        if np.array_equal(new, labels):
            return labels
        labels = new


def euclidean_clusters(points: np.ndarray, voxel: float, min_points: int = 1) -> list[np.ndarray]:
    """The clusters of `points` (n, 3) on a grid of `voxel` (m): index arrays into `points`,
    largest first, those of fewer than `min_points` points left out."""
    points = np.asarray(points, float)
    if len(points) == 0:
        return []
    cells = np.floor(points / voxel).astype(np.int64)
    cells -= cells.min(axis=0) - 1  # >= 1: a neighbour one below is still >= 0
    occupied, of_point = np.unique(_keys(cells), return_inverse=True)
    of_point = of_point.reshape(-1)
    corner = np.zeros((len(occupied), 3), dtype=np.int64)
    corner[of_point] = cells
    pairs = []
    for step in _FORWARD:
        wanted = _keys(corner + step)
        at = np.searchsorted(occupied, wanted)
        hit = (at < len(occupied)) & (occupied[np.minimum(at, len(occupied) - 1)] == wanted)
        pairs.append(np.column_stack([np.flatnonzero(hit), at[hit]]))
    labels = _components(len(occupied), np.concatenate(pairs))[of_point]
    members = [np.flatnonzero(labels == label) for label in np.unique(labels)]
    return sorted((m for m in members if len(m) >= min_points), key=len, reverse=True)
