"""What back-projection needs to know of a sensor: how far its frame reaches in the normalised
plane, where its lens model stops being valid, the cone that holds its frame, and how long an
image segment may be before a straight edge visibly bends (ARCHITECTURE.md, "Backward
projection", densification)."""
import math

import numpy as np

from ..reconstruction import border_pixels

MAX_SUBDIVISIONS = 4096
"""Most pieces one edge is cut into (an edge seen from a few metres by a fisheye)."""


class SensorGeometry:
    """Per sensor: the largest normalised radius of the frame (``r_frame``), the valid radius,
    the cone that holds the frame, and the longest image segment ``segment_px`` whose chord
    stays within ``tol`` px of the true image of a straight edge."""

    def __init__(self, sensor, distortion: bool, tol: float):
        cal = sensor.calibration
        self.sensor = sensor
        self.cal = cal
        self.distortion = distortion
        b = border_pixels(sensor.width, sensor.height, 64)
        x, y = cal.pixel_to_normalised(b[:, 0], b[:, 1], distortion)
        self.r_frame = float(np.sqrt(np.max(x * x + y * y)))
        self.r_valid = float(np.sqrt(sensor.r2_limit)) if distortion else 4.0 * self.r_frame
        self.cos_cone = 1.0 / math.sqrt(1.0 + (self.r_frame * 1.01) ** 2)
        self.sin_cone = (self.r_frame * 1.01) * self.cos_cone
        self.segment_px = self._segment(tol)
        self._ngon = None

    def _segment(self, tol: float) -> float:
        """sqrt(8·tol/κ) px for the largest line curvature κ inside the frame (inf: none)."""
        if not (self.distortion and self.cal.has_distortion):
            return math.inf
        s = self.sensor
        u, v = np.meshgrid(np.linspace(0, s.width, 13), np.linspace(0, s.height, 11))
        x, y = self.cal.pixel_to_normalised(u.ravel(), v.ravel(), True)
        h = 8.0 / self.cal.f                                 # ±8 px steps, normalised
        kappa = 0.0
        for ang in np.radians([0.0, 45.0, 90.0, 135.0]):
            dx, dy = h * math.cos(ang), h * math.sin(ang)
            pa = np.column_stack(self.cal.project_normalised(x - dx, y - dy))
            pm = np.column_stack(self.cal.project_normalised(x, y))
            pb = np.column_stack(self.cal.project_normalised(x + dx, y + dy))
            dev = np.linalg.norm(pm - (pa + pb) / 2, axis=1)
            length = np.linalg.norm(pb - pa, axis=1)
            kappa = max(kappa, float(np.max(8.0 * dev / length ** 2)))
        return math.inf if kappa <= 0 else max(1.0, math.sqrt(8.0 * tol / kappa))

    def ngon(self):
        """(inradius ρ, circumradius, n) of the polygonal cone used for the valid radius."""
        if self._ngon is None:
            rf, rv = self.r_frame, self.r_valid
            if rv > rf * 1.0005:
                rho = rf + 0.5 * (rv - rf)
                n = int(np.clip(math.ceil(math.pi / math.acos(rho / rv)), 8, 1440))
            else:                                  # lens model barely covers the frame
                n = 1440
                rho = rv * math.cos(math.pi / n)
            self._ngon = (rho, rho / math.cos(math.pi / n), n)
        return self._ngon
