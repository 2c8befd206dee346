#!/usr/bin/env python3
"""Writes lv_pressure.csv, ibvalve's default left-ventricle pressure over one 0.8 s cycle.

The reference study (Zhu et al. 2021) drives its valve with an LV pressure curve it does not publish as
data, so ibvalve ships this stand-in. It is built, not measured:

  P_LV(t) = P_base + (P_peak - P_base) * E(t) / max(E) + P_kick(t)

* E(t): the normalised time-varying elastance "double Hill" curve of Stergiopulos, Meister & Westerhof
  (1996), Am J Physiol 270:H2050,
      E(tn) = [(tn/0.7)^1.9 / (1 + (tn/0.7)^1.9)] * [1 / (1 + (tn/1.17)^21.9)],  tn = t / t_max,
  with t_max = 0.28 s (our choice: it puts the systolic peak near 0.28 s and the end of
  relaxation near 0.42 s).
  Using the elastance shape for the pressure is an approximation (it ignores the volume change during
  ejection); it gives a smooth, physiological-looking systolic wave.
* P_base = 5 mmHg, P_peak = 120 mmHg (docs/reference.md, "Boundary conditions": systolic peak about
  120 mmHg, diastolic a few mmHg).
* P_kick(t): the atrial contraction at the end of diastole, a periodic Gaussian of 3 mmHg centred at
  0.72 s with a 0.03 s standard deviation.

The cycle starts at the onset of ventricular contraction (end-diastole). Samples every 5 ms; the last
row is t = 0.8 s with the value at t = 0, so the table is periodic. Run it with any Python 3:
    python3 examples/waveforms/make_lv_pressure.py > examples/waveforms/lv_pressure.csv
"""
import math

PERIOD = 0.8
T_MAX = 0.28
P_BASE = 5.0
P_PEAK = 120.0
KICK_AMPLITUDE, KICK_CENTRE, KICK_WIDTH = 3.0, 0.72, 0.03
STEP = 0.005


def elastance(t):
    tn = (t % PERIOD) / T_MAX
    rise = (tn / 0.7) ** 1.9
    return rise / (1.0 + rise) / (1.0 + (tn / 1.17) ** 21.9)


def kick(t):
    # Sum over neighbouring periods so the Gaussian is exactly periodic.
    return sum(KICK_AMPLITUDE * math.exp(-0.5 * ((t - KICK_CENTRE + k * PERIOD) / KICK_WIDTH) ** 2)
               for k in (-2, -1, 0, 1, 2))


def main():
    fine = [i * PERIOD / 80000 for i in range(80000)]
    e_max = max(elastance(t) for t in fine)
    n = round(PERIOD / STEP)
    print("# Default LV pressure for ibvalve (see make_lv_pressure.py for how it is made).")
    print("# time in s, pressure in mmHg; one period, last row = first row one period later.")
    print("time,pressure")
    values = []
    for i in range(n + 1):
        t = i * STEP
        p = P_BASE + (P_PEAK - P_BASE) * elastance(t) / e_max + kick(t)
        values.append(p)
    values[-1] = values[0]
    for i, p in enumerate(values):
        print(f"{i * STEP:.3f},{p:.6f}")


if __name__ == "__main__":
    main()
