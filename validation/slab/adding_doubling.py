"""Radiance leaving a homogeneous plane-parallel slab, by adding-doubling.

An independent solution of the azimuth-averaged (m = 0) radiative transfer equation, to check
shvol's renders against (README.md here). The slab has optical thickness tau, single-scattering
albedo `albedo` and an isotropic or Henyey-Greenstein phase function, and is lit by a sky of
radiance 1 from above, and optionally from below. Directions are Gauss-Legendre nodes in
mu in (0, 1), plus the view cosines asked for with weight 0 (they see the field, but carry none
of it).

A layer of thickness d = tau / 2^n, thin enough for single scattering (d ~ 1e-7), is doubled n
times (van de Hulst 1980, "Multiple Light Scattering", ch. 5): R' = R + T R (1 - R R)^-1 T,
T' = T (1 - R R)^-1 T. The azimuthal average of HG is a complete elliptic integral of the
second kind (by the arithmetic-geometric mean, numpy alone: scipy's ellipe to 3e-15); the phase
matrices are renormalised so that the discrete scattering conserves energy (white furnace to
1e-5 at every tau).
"""
import numpy as np


def ellipe(m):
    """Complete elliptic integral of the second kind E(m) = ∫_0^{π/2} √(1 − m sin²θ) dθ, m < 1,
    by the arithmetic-geometric mean (Abramowitz & Stegun 17.6): K = π / (2 AGM(1, √(1 − m))),
    E = K (1 − Σ_n 2^{n−1} c_n²) with c_0² = m, c_{n+1} = (a_n − b_n) / 2."""
    m = np.asarray(m, float)
    a, b = np.ones_like(m), np.sqrt(1 - m)
    total, power = 0.5 * m, 0.5
    for _ in range(40):
        c = 0.5 * (a - b)
        a, b = 0.5 * (a + b), np.sqrt(a * b)
        power *= 2
        total = total + power * c * c
        if np.all(c * c <= 1e-34 * a * a):
            break
    return np.pi / (2 * a) * (1 - total)


def _nodes(n, views):
    x, w = np.polynomial.legendre.leggauss(n)
    mu = np.concatenate([0.5 * (x + 1), np.asarray(views, float)])
    return mu, np.concatenate([0.5 * w, np.zeros(len(views))])


def _hg_azimuthal(g, a, b):
    """(1/2π) ∫ 4π·HG(a + b cos φ) dφ over φ in [0, 2π), as (1/2) ∫ P dμ' = 1 normalises it."""
    if g == 0:
        return np.ones_like(a)
    A, B = 1 + g * g - 2 * g * a, 2 * g * b
    m = np.where(A + B > 0, 2 * B / (A + B), 0.0)
    # ∫_0^π dφ / (A − B cos φ)^{3/2} = 2 E(m) / ((A − B) √(A + B)), m = 2B / (A + B)
    return (1 - g * g) * 2 * ellipe(m) / ((A - B) * np.sqrt(A + B)) / np.pi


def _phase_matrices(mu, w, g):
    """P(μ_i → μ_j) forward (same hemisphere) and backward, energy-conserving on the nodes."""
    s = np.sqrt(np.clip(1 - mu**2, 0, None))
    a, b = np.outer(mu, mu), np.outer(s, s)
    forward, backward = _hg_azimuthal(g, a, b), _hg_azimuthal(g, -a, b)
    real = w > 0
    d = np.ones(len(mu))
    for _ in range(200):  # symmetric scaling: (1/2) Σ_j w_j (P⁺ + P⁻)_ij = 1 on the real nodes
        S = 0.5 * ((forward + backward) * np.outer(d, d) * w[None, :]).sum(1)
        d[real] *= np.sqrt(1.0 / S[real])
    forward, backward = forward * np.outer(d, d), backward * np.outer(d, d)
    S = 0.5 * ((forward + backward) * w[None, :]).sum(1)
    forward[~real] /= S[~real, None]  # the views' rows: normalised alone
    backward[~real] /= S[~real, None]
    return forward, backward


def slab(tau, albedo, g=0.0, views=(1.0,), n=96, thin=1e-7):
    """Radiance leaving the top at each view cosine: (sky above only, sky above and below)."""
    mu, w = _nodes(n, views)
    forward, backward = _phase_matrices(mu, w, g)
    doublings = max(0, int(np.ceil(np.log2(tau / thin))))
    d = tau / 2.0**doublings
    mi, mj = mu[:, None], mu[None, :]
    R = 0.5 * albedo * w[None, :] * backward * mj / (mi + mj) * -np.expm1(-d * (1 / mi + 1 / mj))
    T = 0.5 * albedo * w[None, :] * forward * (d / mi) * np.exp(-0.5 * d * (1 / mi + 1 / mj))
    T += np.diag(np.exp(-d / mu))
    identity = np.eye(len(mu))
    for _ in range(doublings):
        M = np.linalg.solve(identity - R @ R, T)
        R, T = R + T @ (R @ M), T @ M
    one, k = np.ones(len(mu)), len(views)
    return (R @ one)[-k:], (R @ one + T @ one)[-k:]


if __name__ == "__main__":
    # Its own limits: no scattering is Beer-Lambert, albedo 1 lit from both sides is 1.
    for tau in (0.1, 1, 10):
        above, both = slab(tau, 0.0, views=(1.0, 0.5))
        beer = np.exp(-tau / np.array([1.0, 0.5]))
        print(f"albedo 0, tau {tau}: {both - above} against Beer-Lambert {beer}")
        for g in (0, 0.5, 0.9):
            print(f"  albedo 1, g {g}: {slab(tau, 1.0, g, views=(1.0, 0.5))[1]} (1)")
