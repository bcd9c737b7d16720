#!/usr/bin/env python3
"""The centroid speed that `tearflow verify pulse` would measure on the continuum; prints JSON.

A linear model of the pulse tube, no mesh: the inlet pulse's spectrum (the same smoothed
10 mmHg, 3 ms pulse) is carried down an infinite tube (no reflection) with the wavenumber
  k(w) = w / (c0 sqrt(1 - F10(alpha))) * sqrt((ka/2) I0(ka)/I1(ka) + rho_s h a k^2 / (2 rho))
(Womersley's viscous factor F10 = 2 J1(L) / (L J0(L)), L = i^(3/2) alpha, alpha = a sqrt(w/nu);
the radial inertia of the fluid and the inertia of the wall as in fsi_pulse.cpp, solved for
k by bisection; this membrane model has a cut-off near 480 Hz, above which the spectrum is
dropped: the JSON gives that part's share of the pulse's energy). The station signals, their three-section averages,
the cut at the outlet reflection's arrival and the least-squares speed are those of
src/verify/fsi_pulse.cpp. Without viscosity and dispersion the script returns c0 exactly.

usage: bench/pulse_continuum.py [--c0 5.25] [--no-viscosity] [--no-dispersion] [--h 0.00105]
  --c0: the long-wave speed [m/s] (5.25 plane-strain thick wall, 5.07 axially free wall)
  --h:  element size [m], only for the section slab (0.6 h) of the measurement's cut
Standard library only; about a minute.
"""
import argparse, cmath, json, math

a, wall_h, L = 0.005, 0.001, 0.05  # radius, wall thickness, length [m]
rho, mu, rho_s = 1000.0, 0.003, 1200.0  # [kg/m^3], [Pa s], [kg/m^3]
P0, t_pulse, t_edge, t_end = 1333.2, 0.003, 1.25e-3, 0.015  # [Pa], [s]
c_cut = 5.25  # fsi_pulse.cpp cuts at the thick-wall estimate's reflection time
stations, spacing, dt = [0.0125, 0.015, 0.0175, 0.02, 0.0225, 0.025], 0.0025, 1.75e-5


def smoothstep(s):
    s = min(max(s, 0.0), 1.0)
    return s * s * (3.0 - 2.0 * s)


def bessel_j(n, z, terms=80):
    """J_n(z) by its power series (complex z, |z| <= 30: relative error ~1e-13)."""
    term = (z / 2) ** n / math.factorial(n)
    total = term
    for k in range(1, terms):
        term *= -(z / 2) ** 2 / (k * (k + n))
        total += term
    return total


def bessel_i_ratio(x):
    """I0(x) / I1(x) for real x > 0 (power series, no cancellation; asymptotics above 50)."""
    if x > 50.0:
        return 1.0 + 1.0 / (2.0 * x) + 3.0 / (8.0 * x * x)
    i0 = i1 = 0.0
    t0, t1 = 1.0, x / 2
    for k in range(200):
        i0 += t0
        i1 += t1
        t0 *= (x / 2) ** 2 / ((k + 1) ** 2)
        t1 *= (x / 2) ** 2 / ((k + 1) * (k + 2))
    return i0 / i1


def womersley_f10(alpha):
    lam = (1j ** 1.5) * alpha
    if alpha <= 30.0:
        return 2.0 * bessel_j(1, lam) / (lam * bessel_j(0, lam))
    return 2.0 / lam * (1j + 1.0 / (2.0 * lam))  # Hankel asymptotics, Im(lam) > 0


def wavenumber(w, c0, viscous, dispersive):
    """k(w) [1/m]; None above the dispersion's cut-off (no propagating wave: dropped)."""
    if w == 0.0:
        return 0j
    k = w / c0
    if dispersive:
        # w^2 = c0^2 k^2 / (F(ka) + beta k^2), F = (ka/2) I0/I1: increasing in k towards
        # c0^2 / beta, so one root below the cut-off w = c0 / sqrt(beta) (~480 Hz here).
        beta = rho_s * wall_h * a / (2.0 * rho)
        def omega2(k):
            return c0 * c0 * k * k / (0.5 * k * a * bessel_i_ratio(k * a) + beta * k * k)
        lo, hi = w / c0, 2e4
        if omega2(hi) <= w * w:
            return None
        for _ in range(100):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if omega2(mid) < w * w else (lo, mid)
        k = 0.5 * (lo + hi)
    k = k + 0j
    if viscous:
        k /= cmath.sqrt(1.0 - womersley_f10(a * math.sqrt(w * rho / mu)))
    return k


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--c0", type=float, default=5.25)
    ap.add_argument("--no-viscosity", action="store_true")
    ap.add_argument("--no-dispersion", action="store_true")
    ap.add_argument("--h", type=float, default=0.00105)
    args = ap.parse_args()

    # Spectrum of the inlet pulse over a long window (no wrap-around), up to 4 kHz.
    T, N, f_max = 0.12, 4096, 4000.0
    dts = T / N
    p0 = [P0 * smoothstep(i * dts / t_edge) * (1 - smoothstep((i * dts - t_pulse) / t_edge))
          for i in range(N)]
    nonzero = [(i * dts, p) for i, p in enumerate(p0) if p != 0.0]
    freqs = [2 * math.pi * n / T for n in range(int(f_max * T) + 1)]
    spectrum = [sum(p * cmath.exp(-1j * w * t) for t, p in nonzero) * dts for w in freqs]
    ks = [wavenumber(w, args.c0, not args.no_viscosity, not args.no_dispersion) for w in freqs]
    dropped = sum(abs(s) ** 2 for s, k in zip(spectrum, ks) if k is None) / sum(
        abs(s) ** 2 for s in spectrum)
    spectrum = [s if k is not None else 0j for s, k in zip(spectrum, ks)]
    ks = [k if k is not None else 0j for k in ks]

    times = [dt * (i + 1) for i in range(int(round(t_end / dt)))]

    def pressure(z):
        rot = [cmath.exp(-1j * k * z) * s for k, s in zip(ks, spectrum)]
        out = []
        for t in times:
            v = spectrum[0].real
            for w, r in zip(freqs[1:], rot[1:]):
                v += 2.0 * (r * cmath.exp(1j * w * t)).real
            out.append(v / T)
        return out

    slab = 0.6 * args.h
    centroids = []
    for z in stations:
        sig = [sum(v) / 3 for v in zip(pressure(z - spacing), pressure(z), pressure(z + spacing))]
        cut = (2 * L - (z + spacing + slab)) / c_cut
        window = [(t, p) for t, p in zip(times, sig) if t <= cut]
        centroids.append(sum(t * p for t, p in window) / sum(p for _, p in window))
    tm, zm = sum(centroids) / len(centroids), sum(stations) / len(stations)
    speed = sum((t - tm) * (z - zm) for t, z in zip(centroids, stations)) / sum(
        (t - tm) ** 2 for t in centroids)
    print(json.dumps({"c0_m_per_s": args.c0, "viscosity": not args.no_viscosity,
                      "dispersion": not args.no_dispersion, "element_size_m": args.h,
                      "energy_above_cutoff": round(dropped, 6),
                      "centroid_speed_m_per_s": round(speed, 4),
                      "relative_to_5.25": round(speed / 5.25 - 1.0, 4)}))


if __name__ == "__main__":
    main()
