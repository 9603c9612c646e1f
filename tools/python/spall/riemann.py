"""The exact Riemann solution of the ideal-gas shock tube (Toro, "Riemann Solvers and Numerical
Methods for Fluid Dynamics", 3rd ed., sections 4.2-4.5): tools/work_precision's Sod answer.

A state is (rho, u, p, gamma); each side keeps its own gamma, which costs nothing and covers
two-gas tubes.

    from spall.riemann import riemann_profile
    rho, u, p = riemann_profile((1.0, 0.0, 1.0, 1.4), (0.125, 0.0, 0.1, 1.4), 0.0, 0.2, x)
"""
import math

import numpy as np

def _pressure_function(p, state):
    """Toro's f_K(p) and its derivative: the velocity jump across the K wave (shock or fan)."""
    rho, _, pk, g = state
    if p > pk:  # shock (Rankine-Hugoniot)
        a, b = 2.0 / ((g + 1.0) * rho), (g - 1.0) / (g + 1.0) * pk
        q = math.sqrt(a / (p + b))
        return (p - pk) * q, q * (1.0 - 0.5 * (p - pk) / (b + p))
    c = math.sqrt(g * pk / rho)  # rarefaction (isentropic)
    return (2.0 * c / (g - 1.0) * ((p / pk) ** ((g - 1.0) / (2.0 * g)) - 1.0),
            (p / pk) ** (-(g + 1.0) / (2.0 * g)) / (rho * c))


def star_state(left, right):
    """Pressure and velocity between the two nonlinear waves, by Newton iteration on
    f_L(p) + f_R(p) + (u_R - u_L) = 0 (Toro Eq. 4.5)."""
    (rl, ul, pl, gl), (rr, ur, pr, gr) = left, right
    cl, cr = math.sqrt(gl * pl / rl), math.sqrt(gr * pr / rr)
    if 2.0 * cl / (gl - 1.0) + 2.0 * cr / (gr - 1.0) <= ur - ul:
        raise ValueError("the initial states generate vacuum; no star state exists")
    floor = 1e-10 * min(pl, pr)  # Newton may overshoot below zero from a poor guess
    # Primitive-variable (linearised) guess, Toro Eq. 4.47: close for weak and moderate waves.
    p = max(floor, 0.5 * (pl + pr) - 0.125 * (ur - ul) * (rl + rr) * (cl + cr))
    for _ in range(100):
        (fl, dl), (fr, dr) = _pressure_function(p, left), _pressure_function(p, right)
        p_new = max(floor, p - (fl + fr + ur - ul) / (dl + dr))
        converged = abs(p_new - p) <= 1e-14 * (p_new + p)
        p = p_new
        if converged:
            break
    else:
        raise RuntimeError("star pressure iteration did not converge")
    fl, fr = _pressure_function(p, left)[0], _pressure_function(p, right)[0]
    return p, 0.5 * (ul + ur) + 0.5 * (fr - fl)


def _sample_left(state, p_star, u_star, s):
    """(rho, u, p) at similarity coordinate s = x/t, for s left of the contact (Toro 4.5)."""
    rho, u, p, g = state
    c = math.sqrt(g * p / rho)
    if p_star > p:  # left shock
        if s <= u - c * math.sqrt((g + 1.0) / (2.0 * g) * p_star / p + (g - 1.0) / (2.0 * g)):
            return rho, u, p
        k = (g - 1.0) / (g + 1.0)
        return rho * (p_star / p + k) / (k * p_star / p + 1.0), u_star, p_star
    if s <= u - c:  # ahead of the rarefaction head
        return rho, u, p
    if s >= u_star - c * (p_star / p) ** ((g - 1.0) / (2.0 * g)):  # behind its tail
        return rho * (p_star / p) ** (1.0 / g), u_star, p_star
    k = 2.0 / (g + 1.0) + (g - 1.0) / ((g + 1.0) * c) * (u - s)  # inside the fan
    return rho * k ** (2.0 / (g - 1.0)), 2.0 / (g + 1.0) * (c + 0.5 * (g - 1.0) * u + s), \
        p * k ** (2.0 * g / (g - 1.0))


def riemann_sample(left, right, p_star, u_star, s):
    """(rho, u, p) at s = (x - x0)/t. Right of the contact, sample the mirrored problem
    (x -> -x swaps the sides and flips velocities) so one routine covers both sides."""
    if s <= u_star:
        return _sample_left(left, p_star, u_star, s)
    rho, u, p, g = right
    r, v, q = _sample_left((rho, -u, p, g), p_star, -u_star, -s)
    return r, -v, q


def riemann_profile(left, right, x0, t, x):
    """Exact (rho, u, p) arrays at positions x and time t > 0."""
    p_star, u_star = star_state(left, right)
    return np.array([riemann_sample(left, right, p_star, u_star, (xi - x0) / t) for xi in x]).T
