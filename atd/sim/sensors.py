"""Sensor models shared by both engines: noise, bias, filtering and quantisation of the
readings, and the taxel grid that turns contact points on a pad into a pressure image."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from factories.description import FingerPad, SensorModel


def _positions(mask: np.ndarray) -> slice | np.ndarray:
    """Where `mask` holds, as a slice when that is one run (a view: cheaper each tick)."""
    where = np.flatnonzero(mask)
    if len(where) and where[-1] - where[0] + 1 == len(where):
        return slice(int(where[0]), int(where[-1]) + 1)
    return where


class NoisySensors:
    """Turns true readings into what the sensors report, reproducibly from the run's seed.

    All streams (joints, wrench, pads, range) are modelled at once over one vector that
    holds them end to end: one noise draw, one filter update and one quantisation per
    tick, each element with its own stream's noise, bias, cutoff and resolution. Noise
    is drawn in stream order, so a seed gives the numbers a draw per stream would.
    The bias is drawn once per run (per element, scale `bias`); the filter is first
    order with the stream's cutoff, sampled at the control rate.
    """

    def __init__(self, streams: Sequence[tuple[SensorModel, int]], rng: np.random.Generator, period: float):
        self._rng = rng
        std, noisy, bias, alpha, resolution = [], [], [], [], []
        for model, size in streams:
            std.append(np.broadcast_to(np.asarray(model.noise_std, float), size))
            noisy.append(np.full(size, bool(np.any(model.noise_std))))
            drawn = np.any(model.bias)
            bias.append(np.asarray(model.bias, float) * rng.standard_normal(size) if drawn else np.zeros(size))
            cutoff = model.cutoff_hz
            alpha.append(np.full(size, 1.0 - np.exp(-2 * np.pi * cutoff * period) if cutoff else 0.0))
            resolution.append(np.full(size, model.resolution))
        self.size = sum(size for _, size in streams)
        noisy_mask, bias_all = np.concatenate(noisy), np.concatenate(bias)
        alpha_all, resolution_all = np.concatenate(alpha), np.concatenate(resolution)
        self._noisy, self._n_noisy = _positions(noisy_mask), int(noisy_mask.sum())
        self._std = np.concatenate(std)[noisy_mask]
        self._biased = _positions(bias_all != 0)
        self._bias = bias_all[bias_all != 0]
        self._filtered = _positions(alpha_all > 0)
        self._alpha = alpha_all[alpha_all > 0]
        self._state: np.ndarray | None = None
        self._quantised = _positions(resolution_all > 0)
        self._resolution = resolution_all[resolution_all > 0]

    def __call__(self, x: np.ndarray) -> None:
        """Work the reported readings out in place; `x` starts with the `size` modelled values."""
        if self._n_noisy:
            x[self._noisy] += self._std * self._rng.standard_normal(self._n_noisy)
        if len(self._bias):
            x[self._biased] += self._bias
        if len(self._alpha):
            if self._state is None:
                self._state = x[self._filtered].copy()
            else:
                self._state += self._alpha * (x[self._filtered] - self._state)
            x[self._filtered] = self._state
        if len(self._resolution):
            x[self._quantised] = np.rint(x[self._quantised] / self._resolution) * self._resolution


class TaxelImages:
    """The pads' sensor arrays, all at once: each contact's normal force goes to the taxel
    under it. Contact points come in their pad's frame (x across, y along the finger);
    points past the edge count on the edge taxel, as a real pad's rim still loads its
    outer cells. One pass over all contacts keeps this cheap enough for every tick."""

    def __init__(self, pads: tuple[FingerPad, ...]):
        rows = np.array([(p.taxels or (1, 1))[0] for p in pads])
        cols = np.array([(p.taxels or (1, 1))[1] for p in pads])
        half = np.array([p.half_size for p in pads], float).reshape(-1, 2)
        cells = np.stack([cols, rows], axis=1)
        offset = np.concatenate([[0], np.cumsum(rows * cols)[:-1]])
        # Per pad: pad coordinates to (column, row) cell coordinates (scale, centre), the
        # last column and row, the row length and the first cell in the flat image.
        self._pads = (cells / (2 * half), cells / 2, (cells - 1).astype(float), cols.astype(float), offset.astype(float))
        self._size = int((rows * cols).sum())
        self._n = len(pads)
        self._images = [
            (p.name, slice(o, o + r * c), (r, c)) if p.taxels is not None else (p.name, None, None)
            for p, o, r, c in zip(pads, offset, rows, cols)
        ]
        self._contacts_of = b""  # the pads of the contacts last seen, and their constants
        self._per_contact: tuple[np.ndarray, ...] = ()
        # What a hand touching nothing reads, most of a run: made once, read-only, shared by the ticks.
        nothing, self._no_force = np.zeros(self._size), np.zeros(self._n)
        nothing.flags.writeable = self._no_force.flags.writeable = False
        self._untouched, _ = self._read(nothing, self._no_force)

    def __call__(self, pad: np.ndarray, xy: np.ndarray, force: np.ndarray) -> tuple[dict[str, np.ndarray | None], np.ndarray]:
        """Images by pad name (None for a pad without an array) and the force on each pad."""
        if len(pad) == 0 or not np.count_nonzero(force):
            return self._untouched, self._no_force
        # MuJoCo reports the same contact slots every tick: their constants are gathered once.
        if pad.tobytes() != self._contacts_of:
            self._contacts_of = pad.tobytes()
            self._per_contact = (*(column[pad] for column in self._pads), np.zeros((len(pad), 2)))
        scale, centre, last, row_length, first, zero = self._per_contact
        cell = np.minimum(np.maximum(np.floor(xy * scale + centre), zero), last)
        index = (first + cell[:, 1] * row_length + cell[:, 0]).astype(np.intp)
        return self._read(np.bincount(index, weights=force, minlength=self._size),
                          np.bincount(pad, weights=force, minlength=self._n))

    def _read(self, flat: np.ndarray, total: np.ndarray) -> tuple[dict[str, np.ndarray | None], np.ndarray]:
        """The images by pad name, cut from all the pads' cells end to end, and the pad forces."""
        return {name: None if cells is None else flat[cells].reshape(shape) for name, cells, shape in self._images}, total
