"""Sensor models shared by both engines: noise, bias, filtering and quantisation of a
reading, and the taxel grid that turns contact points on a pad into a pressure image."""

from __future__ import annotations

import numpy as np

from factories.description import FingerPad, SensorModel


class NoisySensor:
    """Turns a true reading into what the sensor reports, reproducibly from the run's seed.

    The bias is drawn once per run (per axis, scale `bias`); the filter is first order
    with the model's cutoff, sampled at the control rate.
    """

    def __init__(self, model: SensorModel, rng: np.random.Generator, size: int, period: float):
        self._rng = rng
        self._std = np.asarray(model.noise_std, float) if np.any(model.noise_std) else None
        self._size = size
        self._bias = np.asarray(model.bias, float) * rng.standard_normal(size) if np.any(model.bias) else None
        self._alpha = 1.0 - np.exp(-2 * np.pi * model.cutoff_hz * period) if model.cutoff_hz else None
        self._state: np.ndarray | None = None
        self._resolution = model.resolution

    def __call__(self, true: np.ndarray) -> np.ndarray:
        """The reported reading, worked out in place: `true` must be a fresh array."""
        x = true
        if self._std is not None:
            x += self._std * self._rng.standard_normal(self._size)
        if self._bias is not None:
            x += self._bias
        if self._alpha is not None:
            if self._state is None:
                self._state = x.copy()
            else:
                self._state += self._alpha * (x - self._state)
            x[:] = self._state
        if self._resolution:
            np.rint(x / self._resolution, out=x)
            x *= self._resolution
        return x


class TaxelImages:
    """The pads' sensor arrays, all at once: each contact's normal force goes to the taxel
    under it. Contact points come in their pad's frame (x across, y along the finger);
    points past the edge count on the edge taxel, as a real pad's rim still loads its
    outer cells. One pass over all contacts keeps this cheap enough for every tick."""

    def __init__(self, pads: tuple[FingerPad, ...]):
        self._names = [p.name for p in pads]
        self._arrays = [p.taxels is not None for p in pads]
        rows = np.array([(p.taxels or (1, 1))[0] for p in pads])
        cols = np.array([(p.taxels or (1, 1))[1] for p in pads])
        half = np.array([p.half_size for p in pads], float).reshape(-1, 2)
        cells = np.stack([cols, rows], axis=1)
        self._scale = cells / (2 * half)  # pad coordinates to (column, row) cell coordinates
        self._centre = cells / 2
        self._cols, self._last_col, self._last_row = cols, cols - 1, rows - 1
        self._offset = np.concatenate([[0], np.cumsum(rows * cols)[:-1]]).astype(int)
        self._layout = list(zip(self._offset, rows, cols))
        self._size = int((rows * cols).sum())

    def __call__(self, pad: np.ndarray, xy: np.ndarray, force: np.ndarray) -> tuple[dict[str, np.ndarray | None], np.ndarray]:
        """Images by pad name (None for a pad without an array) and the force on each pad."""
        n = len(self._names)
        if len(pad) == 0:
            flat, total = np.zeros(self._size), np.zeros(n)
        else:
            u = (xy * self._scale[pad] + self._centre[pad]).astype(int)
            col = np.minimum(np.maximum(u[:, 0], 0), self._last_col[pad])
            row = np.minimum(np.maximum(u[:, 1], 0), self._last_row[pad])
            flat = np.bincount(self._offset[pad] + row * self._cols[pad] + col, weights=force, minlength=self._size)
            total = np.bincount(pad, weights=force, minlength=n)
        images = {
            name: flat[o : o + r * c].reshape(r, c) if array else None
            for name, array, (o, r, c) in zip(self._names, self._arrays, self._layout)
        }
        return images, total
