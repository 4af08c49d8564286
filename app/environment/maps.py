"""Procedural environments (nothing downloaded): radiance L(ω) in RGB for world
directions ω (camera frame: x right, y up, z toward the viewer), each placed by the
light direction ``key`` (the point light's direction on the sphere view).

* uniform  — L = colour everywhere: the white furnace.
* studio   — a dim grey room, a key soft box (a disc of radius 12°) at ``key`` and a
             weaker, larger fill box opposite it in azimuth (radius 20°); soft edges.
* overcast — the CIE standard overcast sky, L = L_z (1 + 2 cos θ)/3 about the zenith
             ``key`` (Moon & Spencer 1942), over a dim ground.
* sunset   — a vertical gradient (deep blue zenith to orange horizon, about +y) and a
             warm sun disc of radius 2.5° at ``key``; a dark ground below the horizon.

Radiances are in arbitrary linear units; the exposure maps them to the display.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np


def _smooth_disc(w, centre, radius_deg: float, edge_deg: float) -> np.ndarray:
    """1 inside the cone of ``radius_deg`` about ``centre``, 0 outside, smoothstep over
    ``edge_deg`` (a soft box's diffuser edge; no hard edge to alias on the sphere). The
    ramp is linear in cos of the angle between the two cones (no arccos per sample)."""
    cos_in = np.cos(np.radians(radius_deg - edge_deg / 2))
    cos_out = np.cos(np.radians(radius_deg + edge_deg / 2))
    t = np.clip((w @ centre - cos_out) / (cos_in - cos_out), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def _opposite_azimuth(key) -> np.ndarray:
    """The fill light's direction: the key mirrored in x (left ↔ right), raised a bit."""
    fill = np.array([-key[0], 0.5 * abs(key[1]) + 0.3, max(key[2], 0.3)])
    return fill / np.linalg.norm(fill)


def uniform(w, key, colour):
    return np.broadcast_to(colour, w.shape[:-1] + (3,)).copy()


STUDIO_KEY, STUDIO_FILL, STUDIO_ROOM = 16.0, 1.2, 0.02


def studio(w, key, colour):
    key_box = STUDIO_KEY * _smooth_disc(w, key, 12.0, 5.0)
    fill_box = STUDIO_FILL * _smooth_disc(w, _opposite_azimuth(key), 20.0, 8.0)
    return (STUDIO_ROOM + key_box + fill_box)[..., None] * colour


OVERCAST_GROUND = 0.15


def overcast(w, key, colour):
    c = w @ key
    sky = np.where(c >= 0.0, (1.0 + 2.0 * np.clip(c, 0.0, 1.0)) / 3.0, OVERCAST_GROUND)
    return sky[..., None] * colour


SUN_RADIANCE = 60.0
ZENITH = np.array([0.08, 0.16, 0.45])
HORIZON = np.array([1.0, 0.45, 0.15])
GROUND = np.array([0.04, 0.03, 0.025])
SUN_COLOUR = np.array([1.0, 0.75, 0.45])


def sunset(w, key, colour):
    """mix(horizon, zenith, t), t = max(y, 0)^0.4, over the ground; the sun added only
    where its disc is > 0 (a few samples in a thousand)."""
    up = np.clip(w[..., 1], -1.0, 1.0)
    t = np.maximum(up, 0.0) ** 0.4
    sky = np.where((up >= 0)[..., None], HORIZON + t[..., None] * (ZENITH - HORIZON), GROUND)
    sun = _smooth_disc(w, key, 2.5, 1.0)
    flat, lit = sky.reshape(-1, 3), np.flatnonzero(sun)
    flat[lit] += (SUN_RADIANCE * sun.ravel()[lit])[:, None] * SUN_COLOUR
    sky *= colour
    return sky


@dataclass(frozen=True)
class Environment:
    name: str
    label: str
    description: str
    radiance_fn: Callable
    #: Worth sampling by its own radiance (bright small sources); uniform is not.
    sampled: bool = True

    def radiance(self, w, key, colour) -> np.ndarray:
        return self.radiance_fn(np.asarray(w, dtype=float), np.asarray(key, dtype=float),
                                np.asarray(colour, dtype=float))


ENVIRONMENTS = {e.name: e for e in [
    Environment("uniform", "Uniform (white furnace)", "L = colour in every direction.", uniform, False),
    Environment("studio", "Studio (two soft boxes)", "A key soft box at the light direction and a "
                "fill box opposite, in a dim room.", studio),
    Environment("overcast", "Overcast sky", "CIE standard overcast sky about the light direction, "
                "dim ground.", overcast),
    Environment("sunset", "Sunset", "Blue-to-orange gradient sky with a small bright sun at the light "
                "direction.", sunset),
]}
