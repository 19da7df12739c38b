"""A second implementation of FLIR's raw → temperature conversion, for the tests: Thermimage's
raw2temp (Tattersall 2017), term by term, one value at a time (math, not numpy)."""
import math


def planck_by_hand(raw, r1, r2, b, f, o, e, dist, t_refl, t_atm, rh, t_win=20.0, tau_win=1.0):
    """The second implementation: Thermimage's raw2temp (Tattersall 2017), term by term, one
    value at a time, with FLIR's default atmospheric constants."""
    a1, a2, b1, b2, x = 0.006569, 0.01262, -0.002276, -0.00667, 1.9
    h2o = rh * math.exp(1.5587 + 0.06939 * t_atm - 0.00027816 * t_atm ** 2
                        + 0.00000068455 * t_atm ** 3)
    tau1 = x * math.exp(-math.sqrt(dist / 2) * (a1 + b1 * math.sqrt(h2o))) + \
        (1 - x) * math.exp(-math.sqrt(dist / 2) * (a2 + b2 * math.sqrt(h2o)))
    tau2 = tau1

    def bb(tc):
        return r1 / (r2 * (math.exp(b / (tc + 273.15)) - f)) - o

    raw_refl1_attn = (1 - e) / e * bb(t_refl)
    raw_atm1_attn = (1 - tau1) / e / tau1 * bb(t_atm)
    raw_wind_attn = (1 - tau_win) / e / tau1 / tau_win * bb(t_win)
    raw_refl2_attn = 0.0
    raw_atm2_attn = (1 - tau2) / e / tau1 / tau_win / tau2 * bb(t_atm)
    raw_obj = (raw / e / tau1 / tau_win / tau2 - raw_atm1_attn - raw_atm2_attn - raw_wind_attn
               - raw_refl1_attn - raw_refl2_attn)
    return b / math.log(r1 / (r2 * (raw_obj + o)) + f) - 273.15
