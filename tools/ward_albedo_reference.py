#!/usr/bin/python3
"""Reference albedos of Ward's original isotropic BRDF, for Bsdf.WardAlbedo.

Ward (1992), "Measuring and modeling anisotropic reflection", eq. 5, with rho_s = 1:
    f(wo, wi) = exp(-tan^2(theta_h) / a^2) / (4 pi a^2 sqrt(cos theta_i cos theta_o)),
and the directional albedo is the integral of f cos theta_i over the upper hemisphere, here
by scipy's dblquad over (cos theta_i, phi_i), independently of shvol's own quadrature.
Run with Debian's python3 (python3-scipy): /usr/bin/python3 tools/ward_albedo_reference.py
"""
import numpy as np
from scipy import integrate


def albedo(cos_o, a):
    wo = np.array([np.sqrt(1 - cos_o * cos_o), 0.0, cos_o])

    def integrand(phi, ci):
        si = np.sqrt(max(0.0, 1 - ci * ci))
        h = wo + np.array([si * np.cos(phi), si * np.sin(phi), ci])
        h /= np.linalg.norm(h)
        tan2 = (1 - h[2] ** 2) / h[2] ** 2
        return np.exp(-tan2 / (a * a)) / (4 * np.pi * a * a * np.sqrt(ci * cos_o)) * ci

    return integrate.dblquad(integrand, 0, 1, 0, 2 * np.pi, epsabs=1e-10, epsrel=1e-10)


if __name__ == "__main__":
    for cos_o in (1e-3, 0.01):
        value, error = albedo(cos_o, 0.5)
        print(f"cos_o {cos_o:g}, alpha 0.5: albedo {value:.10f} (error estimate {error:.1e})")
