"""Sensor models shared by both engines: noise, bias, filtering and quantisation of the
readings, and the taxel grid that turns contact points on a pad into a pressure image."""

from __future__ import annotations

from typing import Iterator, Mapping, Sequence

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
        # Scratch arrays the tick's steps work in, made once (the same operations, no new arrays).
        self._noise = np.empty(self._n_noisy)
        self._change = np.empty(len(self._alpha))
        self._steps = np.empty(len(self._resolution))

    def __call__(self, x: np.ndarray) -> None:
        """Work the reported readings out in place; `x` starts with the `size` modelled values."""
        if self._n_noisy:
            noise = self._rng.standard_normal(out=self._noise)
            x[self._noisy] += np.multiply(self._std, noise, out=noise)
        if len(self._bias):
            x[self._biased] += self._bias
        if len(self._alpha):
            if self._state is None:
                self._state = x[self._filtered].copy()
            else:
                change = np.subtract(x[self._filtered], self._state, out=self._change)
                self._state += np.multiply(self._alpha, change, out=change)
            x[self._filtered] = self._state
        if len(self._resolution):
            steps = np.rint(np.divide(x[self._quantised], self._resolution, out=self._steps), out=self._steps)
            x[self._quantised] = np.multiply(steps, self._resolution, out=steps)


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
        self._untouched = self._read(nothing)

    @property
    def untouched(self) -> tuple[Mapping[str, np.ndarray | None], np.ndarray]:
        """What the pads read when nothing presses on them, as `__call__` gives it."""
        return self._untouched, self._no_force

    def __call__(self, pad: np.ndarray, xy: np.ndarray, force: np.ndarray) -> tuple[Mapping[str, np.ndarray | None], np.ndarray]:
        """Images by pad name (None for a pad without an array) and the force on each pad.
        The images are worked out when first looked at (`PadImages`): the pad forces are read
        every tick, the images by a few controllers on a few ticks."""
        if len(pad) == 0 or not np.count_nonzero(force):
            return self.untouched
        # MuJoCo reports the same contact slots every tick: their constants are gathered once.
        if pad.tobytes() != self._contacts_of:
            self._contacts_of = pad.tobytes()
            self._per_contact = (*(column[pad] for column in self._pads), np.zeros((len(pad), 2)))
        return PadImages(self, self._per_contact, xy, force), np.bincount(pad, weights=force, minlength=self._n)

    def images(self, per_contact: tuple[np.ndarray, ...], xy: np.ndarray, force: np.ndarray) -> dict[str, np.ndarray | None]:
        """The images of contacts at `xy` (pad frames) pressing with `force`; `per_contact`:
        their pads' constants, as `__call__` gathered them."""
        scale, centre, last, row_length, first, zero = per_contact
        cell = np.minimum(np.maximum(np.floor(xy * scale + centre), zero), last)
        index = (first + cell[:, 1] * row_length + cell[:, 0]).astype(np.intp)
        return self._read(np.bincount(index, weights=force, minlength=self._size))

    def _read(self, flat: np.ndarray) -> dict[str, np.ndarray | None]:
        """The images by pad name, cut from all the pads' cells end to end."""
        return {name: None if cells is None else flat[cells].reshape(shape) for name, cells, shape in self._images}


class PadImages(Mapping[str, "np.ndarray | None"]):
    """One tick's taxel images by pad name, worked out from its contacts when first read."""

    def __init__(self, taxels: TaxelImages, per_contact: tuple[np.ndarray, ...], xy: np.ndarray, force: np.ndarray) -> None:
        self._taxels, self._contacts = taxels, (per_contact, xy, force)
        self._images: dict[str, np.ndarray | None] | None = None

    def _worked_out(self) -> dict[str, np.ndarray | None]:
        if self._images is None:
            self._images = self._taxels.images(*self._contacts)
        return self._images

    def __getitem__(self, name: str) -> np.ndarray | None:
        return self._worked_out()[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._worked_out())

    def __len__(self) -> int:
        return len(self._worked_out())
