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
        x = true + self._std * self._rng.standard_normal(self._size) if self._std is not None else true.copy()
        if self._bias is not None:
            x += self._bias
        if self._alpha is not None:
            if self._state is None:
                self._state = x
            else:
                self._state = self._state + self._alpha * (x - self._state)
            x = self._state.copy()
        if self._resolution:
            x = np.round(x / self._resolution) * self._resolution
        return x


class TaxelGrid:
    """A pad's sensor array: each contact's normal force goes to the taxel under it.

    Contact points come in the pad frame (x across, y along the finger); points past the
    edge count on the edge taxel, as a real pad's rim still loads its outer cells.
    """

    def __init__(self, pad: FingerPad):
        self.shape = pad.taxels or (1, 1)
        self._half = np.array(pad.half_size)

    def image(self, xy: np.ndarray, forces: np.ndarray) -> np.ndarray:
        rows, cols = self.shape
        grid = np.zeros(self.shape)
        u = (xy / (2 * self._half) + 0.5) * (cols, rows)
        c = np.clip(u[:, 0].astype(int), 0, cols - 1)
        r = np.clip(u[:, 1].astype(int), 0, rows - 1)
        np.add.at(grid, (r, c), forces)
        return grid
