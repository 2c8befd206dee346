#!/usr/bin/python3
"""Writes lv_pressure_typeA.csv: a left-ventricle pressure over one 0.8 s beat whose valve timing is the
reference study's (Zhu et al. 2021, set up after Griffith 2012): the aortic valve starts to open near
t = 0.08 s and ejection ends near 0.35 s, against the study's Windkessel (the "Type A" preset).

Why a model and not a curve: the LV pressure that opens a valve early and ejects a physiological stroke
volume depends on the aortic pressure it works against. So the table is the periodic beat of a
time-varying elastance ventricle (Suga & Sagawa 1974, Circ Res 35:117) ejecting into the same
three-element Windkessel the runs use; its pressure rises isovolumically, meets the aortic pressure,
ejects, relaxes isovolumically and fills, each phase from the model rather than drawn by hand.

  P_LV(t) = E(t) (V_LV - V_0),   E(t) = E_min + (E_max - E_min) e(t / t_max) / max e
  e(tn)   = [(tn/0.7)^1.9 / (1 + (tn/0.7)^1.9)] [1 / (1 + (tn/1.17)^21.9)]

* e: the normalised "double Hill" elastance of Stergiopulos, Meister & Westerhof (1996), Am J Physiol
  270:H2050 (its shape constants 0.7, 1.9, 1.17, 21.9, as in make_lv_pressure.py).
* Outlet: the Windkessel preset stergiopulos-typeA (Stergiopulos, Westerhof, Westerhof 1999, Am J
  Physiol 276:H81, fitted to the Type A beat of Murgo, Westerhof, Giolma & Altobelli 1980, Circulation
  62:105: late systolic pressure above early systolic): R_c = 0.033 and R_p = 0.79 mmHg s/mL,
  C = 1.75 mL/mmHg, P_d = 0 (docs/reference.md, "Boundary conditions").
* Aortic valve: a diode with the Bernoulli loss rho Q^2 / (2 A^2), A = 3.19 cm^2 (the lumped example's
  open orifice, 0.6 pi 1.3^2), so P_LV exceeds P_Ao by the few mmHg a normal valve takes.
* Filling: a mitral diode with resistance R_mv from a left-atrial pressure P_LA plus an atrial kick
  (a periodic Gaussian before the next contraction).
* Chosen, not taken from a paper, to meet the study's timing and a normal human beat (docs/reference.md,
  "Boundary conditions": 0.8 s cycle, systolic LV peak about 120 mmHg, diastolic a few mmHg): t_max =
  0.34 s (ejection ends near t_max; the opening comes at about 0.23 t_max), E_max = 3.0 mmHg/mL (with
  the volumes, the stroke and so the aortic pressure; 3.3 gives a 132 mmHg peak), E_min = 0.07 mmHg/mL,
  V_0 = 10 mL, P_LA = 7 mmHg, R_mv = 0.005 mmHg s/mL, kick 4 mmHg at 0.73 s (width 0.025 s). They give
  (--summary) the aortic valve open 0.079-0.353 s, end-diastolic 8.9 mmHg, peak 126.9 mmHg at 0.161 s,
  minimum 4.6 mmHg, P_Ao 115/71 mmHg, a stroke volume of 91 mL from 136 mL (ejection fraction 0.67).

t = 0 is the onset of contraction (end-diastole): the elastance starts to rise there with zero slope,
and the mitral valve has closed just before, so the pressure is flat across the period end (C^1). The
beat is integrated by classical Runge-Kutta 4 (dt = 5e-5 s) from P_Wk = 80 mmHg, V_LV = 130 mL until a
beat ends where it started (1e-6 in mL and mmHg); the table holds its pressure every 1 ms, the last
row being the first one a period later. Plain Python 3, no packages:
    /usr/bin/python3 examples/waveforms/make_lv_pressure_typeA.py > examples/waveforms/lv_pressure_typeA.csv
With --summary it prints the model beat's own figures instead (docs/windkessel.md quotes them).
"""
import math
import sys

PERIOD = 0.8  # s
MMHG = 1333.22  # dyn/cm^2
# Windkessel preset stergiopulos-typeA.
R_C, R_P, COMPLIANCE = 0.033, 0.79, 1.75  # mmHg s/mL, mmHg s/mL, mL/mmHg
VALVE_AREA = 0.6 * math.pi * 1.3**2  # cm^2
DENSITY = 1.0  # g/mL
# Chosen for the timing (see above).
T_MAX, E_MAX, E_MIN, V_0 = 0.34, 3.0, 0.07, 10.0  # s, mmHg/mL, mmHg/mL, mL
P_LA, R_MV = 7.0, 0.005  # mmHg, mmHg s/mL
KICK_AMPLITUDE, KICK_CENTRE, KICK_WIDTH = 4.0, 0.73, 0.025  # mmHg, s, s
STEP, SAMPLE = 5.0e-5, 1.0e-3  # s


def hill(tn):
    rise = (tn / 0.7) ** 1.9
    return rise / (1.0 + rise) / (1.0 + (tn / 1.17) ** 21.9)


HILL_MAX = max(hill(i / 100000 * PERIOD / T_MAX) for i in range(100001))
BERNOULLI = DENSITY / (2.0 * VALVE_AREA**2) / MMHG  # mmHg / (mL/s)^2


def elastance(t):
    return E_MIN + (E_MAX - E_MIN) * hill((t % PERIOD) / T_MAX) / HILL_MAX


def atrial_pressure(t):
    # Summed over neighbouring periods so the kick is exactly periodic.
    tt = t % PERIOD
    return P_LA + sum(KICK_AMPLITUDE * math.exp(-0.5 * ((tt - KICK_CENTRE + k * PERIOD) / KICK_WIDTH) ** 2)
                      for k in (-1, 0, 1))


def aortic_flow(p_lv, p_wk):
    """Q >= 0 with p_lv - p_wk = R_c Q + B Q^2 (the valve's loss, then the Windkessel's R_c)."""
    dp = p_lv - p_wk
    if dp <= 0.0:
        return 0.0
    return 2.0 * dp / (R_C + math.sqrt(R_C * R_C + 4.0 * BERNOULLI * dp))


def state(t, volume, p_wk):
    """(P_LV, aortic flow, mitral flow) at time t."""
    p_lv = elastance(t) * (volume - V_0)
    return p_lv, aortic_flow(p_lv, p_wk), max(0.0, (atrial_pressure(t) - p_lv) / R_MV)


def rate(t, volume, p_wk):
    _, q_ao, q_mv = state(t, volume, p_wk)
    return q_mv - q_ao, (q_ao - p_wk / R_P) / COMPLIANCE


def beat(volume, p_wk):
    """One period from (V_LV, P_Wk): the samples (t, P_LV, P_Wk, Q_Ao, Q_MV, V_LV) and the end state."""
    steps, every = round(PERIOD / STEP), round(SAMPLE / STEP)
    samples = []
    for i in range(steps):
        t = i * STEP
        if i % every == 0:
            p_lv, q_ao, q_mv = state(t, volume, p_wk)
            samples.append((t, p_lv, p_wk, q_ao, q_mv, volume))
        k1 = rate(t, volume, p_wk)
        k2 = rate(t + STEP / 2, volume + STEP / 2 * k1[0], p_wk + STEP / 2 * k1[1])
        k3 = rate(t + STEP / 2, volume + STEP / 2 * k2[0], p_wk + STEP / 2 * k2[1])
        k4 = rate(t + STEP, volume + STEP * k3[0], p_wk + STEP * k3[1])
        volume += STEP / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        p_wk += STEP / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
    return samples, volume, p_wk


def periodic_beat():
    volume, p_wk = 130.0, 80.0
    for _ in range(200):
        samples, end_volume, end_p_wk = beat(volume, p_wk)
        if abs(end_volume - volume) < 1e-6 and abs(end_p_wk - p_wk) < 1e-6:
            return samples
        volume, p_wk = end_volume, end_p_wk
    raise RuntimeError("the model beat did not become periodic in 200 cycles")


def print_summary(samples):
    t, p_lv, p_wk, q_ao, q_mv, volume = zip(*samples)
    p_ao = [w + R_C * q for w, q in zip(p_wk, q_ao)]
    ejecting = [i for i, q in enumerate(q_ao) if q > 0.0]
    peak = max(range(len(t)), key=lambda i: p_lv[i])
    print(f"aortic valve open {t[ejecting[0]]:.3f}-{t[ejecting[-1]] + SAMPLE:.3f} s; "
          f"P_LV end-diastolic {p_lv[0]:.1f}, peak {p_lv[peak]:.1f} mmHg at {t[peak]:.3f} s, "
          f"minimum {min(p_lv):.1f}; P_Ao {max(p_ao):.1f}/{min(p_ao):.1f} mmHg; P_Wk(0) {p_wk[0]:.1f} mmHg; "
          f"stroke volume {sum(q_ao) * SAMPLE:.1f} mL, peak flow {max(q_ao):.0f} mL/s; "
          f"V_LV {min(volume):.0f}-{max(volume):.0f} mL")


def main():
    samples = periodic_beat()
    if "--summary" in sys.argv[1:]:
        print_summary(samples)
        return
    print("# LV pressure of a time-varying elastance ventricle ejecting into the stergiopulos-typeA")
    print("# Windkessel (make_lv_pressure_typeA.py says how). time in s, pressure in mmHg; one period,")
    print("# last row = first row one period later.")
    print("time,pressure")
    values = [s[1] for s in samples] + [samples[0][1]]
    for i, p in enumerate(values):
        print(f"{i * SAMPLE:.3f},{p:.6f}")


if __name__ == "__main__":
    main()
