"""The porous aluminium of the P-alpha verification (decks/porous_aluminium_hugoniot_1d.toml and
tests/verification/element/porous.toml): spall's Mie-Gruneisen matrix (materials/Eos.hpp: 6061
aluminium, Steinberg's C0 5350 m/s, S 1.34, Gamma0 2.0, with Gamma rho = Gamma0 rho0 in
compression) re-implemented, and the one-stage crush curve (materials/Porosity.hpp)."""

RHO_S, C0, S, GAMMA0 = 2703.0, 5350.0, 1.34, 2.0
ALPHA0, PE, PS, N = 1.4, 2.0e6, 1.0e9, 2.0
A0 = RHO_S * C0**2
B0 = A0 * (1 + 2 * (S - 1))
C0H = A0 * (2 * (S - 1) + 3 * (S - 1) ** 2)


def p_eos(rho, e):
    """The matrix's pressure at density rho and specific internal energy e."""
    eta = rho / RHO_S - 1
    if eta > 0:
        pH = eta * (A0 + eta * (B0 + eta * C0H))
        return (1 - 0.5 * GAMMA0 * eta / (1 + eta)) * pH + GAMMA0 * RHO_S * e
    return (1 - 0.5 * GAMMA0 * eta) * A0 * eta + GAMMA0 * RHO_S * (1 + eta) * e


def curve(P):
    """alpha_c(P): alpha0 to Pe, 1 + (alpha0 - 1) ((Ps - P)/(Ps - Pe))^n, 1 from Ps."""
    if P <= PE:
        return ALPHA0
    if P >= PS:
        return 1.0
    return 1 + (ALPHA0 - 1) * ((PS - P) / (PS - PE)) ** N
