"""Raw FLIR sensor values ↔ temperatures: the Planck curve with the camera's constants and the
object parameters (emissivity, distance, reflected and atmospheric temperature, humidity, IR
window).

The model is FLIR's, as published by exiftool's FLIR tag notes and written out in the R
package Thermimage (``raw2temp``, Tattersall 2017): the signal the camera measured is the
object's radiance attenuated by the air (two halves of the path, around the IR window) and the
window, plus what the surroundings add: radiance reflected by the object (at the reflected
apparent temperature), emitted by the air (at the atmospheric temperature) and by the window.
The radiance of a black body at ``T`` kelvin, in raw units, is ``R1 / (R2·(exp(B/T) − F)) − O``.
The transmission of air over ``d`` metres with water content ``h2o`` (from the relative humidity
and the air temperature) is ``X·exp(−√(d/2)·(α1 + β1·√h2o)) + (1 − X)·exp(−√(d/2)·(α2 + β2·√h2o))``
with the camera's ``α1, α2, β1, β2, X`` (FLIR's usual ones when the photo has none).

Temperatures are in °C in and out; distance in metres; humidity a share 0–1.
"""
from dataclasses import asdict, dataclass, replace
from typing import Dict, Optional

import numpy as np

from ..errors import EasyIDPError

KELVIN = 273.15
# FLIR's usual atmospheric transmission constants (exiftool, Thermimage), for photos without them
ATMOSPHERE = dict(alpha1=0.006569, alpha2=0.01262, beta1=-0.002276, beta2=-0.00667, x=1.9)

# the object parameters a tool or a script may override, with their meaning
OBJECT_PARAMETERS = {
    "emissivity": "emissivity of the object, 0–1",
    "object_distance": "distance camera–object in metres",
    "reflected_temperature": "reflected apparent temperature in °C",
    "atmospheric_temperature": "air temperature in °C",
    "relative_humidity": "relative humidity, a share 0–1 (or percent above 1)",
    "ir_window_temperature": "IR window temperature in °C",
    "ir_window_transmission": "IR window transmission, 0–1",
}


@dataclass(frozen=True)
class ThermalParameters:
    """The camera's Planck constants and the object parameters of one photo."""

    r1: float
    r2: float
    b: float
    f: float
    o: float
    emissivity: float = 0.95
    object_distance: float = 1.0
    reflected_temperature: float = 20.0
    atmospheric_temperature: float = 20.0
    relative_humidity: float = 0.5
    ir_window_temperature: float = 20.0
    ir_window_transmission: float = 1.0
    alpha1: float = ATMOSPHERE["alpha1"]
    alpha2: float = ATMOSPHERE["alpha2"]
    beta1: float = ATMOSPHERE["beta1"]
    beta2: float = ATMOSPHERE["beta2"]
    x: float = ATMOSPHERE["x"]

    def overridden(self, options: Optional[Dict[str, object]], photo: str = "") -> "ThermalParameters":
        """These parameters with the object parameters of ``options`` (keys of
        :data:`OBJECT_PARAMETERS`; None or absent: the photo's) replacing the photo's,
        checked."""
        new = {}
        for key in OBJECT_PARAMETERS:
            v = (options or {}).get(key)
            if v is None:
                continue
            try:
                v = float(v)
            except (TypeError, ValueError):
                raise EasyIDPError(f"{key} must be a number, not {v!r}.") from None
            if key == "relative_humidity" and v > 1.0:
                v /= 100.0
            new[key] = v
        out = replace(self, **new)
        out.check(photo)
        return out

    def check(self, photo: str = "") -> None:
        """:class:`EasyIDPError` for parameters no conversion can use."""
        where = f" ({photo})" if photo else ""
        if not (0.0 < self.emissivity <= 1.0):
            raise EasyIDPError(f"Emissivity {self.emissivity:g}{where} must be above 0 and at "
                               "most 1 (leaves: about 0.95–0.98).")
        if not (0.0 < self.ir_window_transmission <= 1.0):
            raise EasyIDPError(f"IR window transmission {self.ir_window_transmission:g}{where} "
                               "must be above 0 and at most 1 (1: no window).")
        if self.object_distance < 0:
            raise EasyIDPError(f"Object distance {self.object_distance:g} m{where} is negative.")
        if not (0.0 <= self.relative_humidity <= 1.0):
            raise EasyIDPError(f"Relative humidity {self.relative_humidity:g}{where} must be a "
                               "share 0–1 or a percentage.")
        if not (self.r1 and self.r2 and self.b):
            raise EasyIDPError(f"The photo{where} has no Planck constants (R1, R2, B are 0): it "
                               "is not a radiometric photo.")

    def as_dict(self) -> Dict[str, float]:
        return asdict(self)


def black_body_raw(p: ThermalParameters, celsius):
    """The raw signal of a black body at ``celsius`` (the Planck curve in raw units)."""
    t = np.asarray(celsius, np.float64) + KELVIN
    return p.r1 / (p.r2 * (np.exp(p.b / t) - p.f)) - p.o


def transmissions(p: ThermalParameters):
    """(tau1, tau2): the air's transmission over each half of the path."""
    ta = p.atmospheric_temperature
    h2o = p.relative_humidity * np.exp(1.5587 + 0.06939 * ta - 0.00027816 * ta ** 2
                                        + 0.00000068455 * ta ** 3)
    half = np.sqrt(p.object_distance / 2.0)
    tau = p.x * np.exp(-half * (p.alpha1 + p.beta1 * np.sqrt(h2o))) + \
        (1.0 - p.x) * np.exp(-half * (p.alpha2 + p.beta2 * np.sqrt(h2o)))
    return float(tau), float(tau)


def _gain_and_offset(p: ThermalParameters):
    """(g, c): the raw signal the camera measures is ``g · object + c``."""
    tau1, tau2 = transmissions(p)
    e, w = p.emissivity, p.ir_window_transmission
    g = e * tau1 * w * tau2
    refl = black_body_raw(p, p.reflected_temperature)
    atm = black_body_raw(p, p.atmospheric_temperature)
    win = black_body_raw(p, p.ir_window_temperature)
    c = ((1 - e) * tau1 * w * tau2 * refl          # reflected by the object
         + (1 - tau1) * w * tau2 * atm             # air between object and window
         + (1 - w) * tau2 * win                    # the window itself (reflection 0)
         + (1 - tau2) * atm)                       # air between window and camera
    return g, float(c)


def raw_to_celsius(raw, p: ThermalParameters) -> np.ndarray:
    """Temperatures (°C, float64) of raw sensor values; NaN where the object's signal falls
    outside the Planck curve (below absolute zero's signal)."""
    g, c = _gain_and_offset(p)
    obj = (np.asarray(raw, np.float64) - c) / g
    with np.errstate(divide="ignore", invalid="ignore"):
        arg = p.r1 / (p.r2 * (obj + p.o)) + p.f
        t = p.b / np.log(arg) - KELVIN
    return np.where(np.isfinite(t) & (arg > 1.0), t, np.nan)


def celsius_to_raw(celsius, p: ThermalParameters) -> np.ndarray:
    """The raw sensor values (float64) a camera measures for objects at ``celsius``: the
    inverse of :func:`raw_to_celsius`."""
    g, c = _gain_and_offset(p)
    return g * black_body_raw(p, celsius) + c
