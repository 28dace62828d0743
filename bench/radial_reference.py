"""Radial reference solutions at large strain: the spherically symmetric equilibrium of a thick sphere (inner radius
a, outer b) under a pressure p on its cavity, for an isotropic material with principal-stretch energy

    psi = mu sum_i (l_i - 1)^2 + lam / 2 (J - 1)^2 + gamma / 2 (l_1 - 1)^2

(iarap = mu |F - R|^2 + lam/2 (J - 1)^2 written in the principal stretches, docs/energies.md; gamma > 0 adds the fiber
term gamma/2 (I4 - 1)^2 of a radial fiber, I4 = a . S a = l_1, which keeps the spherical symmetry). The motion
r = f(R) has stretches l_1 = f', l_2 = l_3 = f / R; the nominal stresses P_1 = dpsi/dl_1, P_2 = dpsi/dl_2 satisfy
dP_1/dR + 2 (P_1 - P_2) / R = 0 with P_1(a) = -p (f(a)/a)^2 (a follower pressure: sigma_rr = -p on the deformed
cavity; -p for a dead one) and P_1(b) = 0 (free outer surface). Solved by shooting on f(a): from R = a with l_1 from the
inner condition, DOP853 at rtol 1e-12 to R = b, and the outer condition brought to 1e-10 p by Brent's method (so f is
accurate to about 1e-8 relative, far below the finite-element errors it judges).

    /usr/bin/python3 bench/radial_reference.py   # prints f(a)/a for the verification's cases
"""
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq


def lame_parameters(E, nu):
    return E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))


class RadialInflation:
    def __init__(self, a, b, p, E, nu, gamma=0.0, follower=True):
        self.a, self.b, self.p, self.gamma, self.follower = a, b, p, gamma, follower
        self.mu, self.lam = lame_parameters(E, nu)
        self.solution = None
        # The first sign change of the outer residual on a grid of cavity stretches (the residual is not monotone
        # beyond the pressure's limit point), then Brent's method inside it.
        grid = 1.0 + np.geomspace(1e-9, 3.0, 200)
        res = [self._outer_residual(t) for t in grid]
        k = next((k for k in range(len(grid) - 1) if (res[k] > 0) != (res[k + 1] > 0)), None)
        if k is None:
            raise ValueError("no equilibrium with a cavity stretch in (1, 4] at p = %g" % p)
        ta = brentq(lambda t: self._outer_residual(t), grid[k], grid[k + 1], xtol=1e-14, rtol=1e-14)
        self._outer_residual(ta)  # keeps the solution of the root

    def stresses(self, l1, t):
        J = l1 * t * t
        P1 = 2 * self.mu * (l1 - 1) + self.gamma * (l1 - 1) + self.lam * (J - 1) * t * t
        P2 = 2 * self.mu * (t - 1) + self.lam * (J - 1) * l1 * t
        return P1, P2

    def _rhs(self, R, y):
        f, l1 = y
        t = f / R
        P1, P2 = self.stresses(l1, t)
        dP1_dl1 = 2 * self.mu + self.gamma + self.lam * t ** 4
        dP1_dt = self.lam * (2 * l1 * t ** 3 + 2 * t * (l1 * t * t - 1))
        dl1 = (-2 * (P1 - P2) / R - dP1_dt * (l1 - t) / R) / dP1_dl1
        return [l1, dl1]

    def _outer_residual(self, ta):
        a, p = self.a, self.p
        target = -p * ta * ta if self.follower else -p
        l1a = brentq(lambda l1: self.stresses(l1, ta)[0] - target, 1e-6, 50.0, xtol=1e-15, rtol=1e-15)
        sol = solve_ivp(self._rhs, (a, self.b), [ta * a, l1a], method="DOP853", rtol=1e-12, atol=1e-14,
                        dense_output=True)
        self.solution = sol
        f, l1 = sol.y[:, -1]
        return self.stresses(l1, f / self.b)[0] / p

    def displacement(self, R):
        """u_r(R) = f(R) - R, R in [a, b] (array)."""
        R = np.clip(np.asarray(R, float), self.a, self.b)
        return self.solution.sol(R)[0] - R


if __name__ == "__main__":
    for gamma in (0.0, 2e4):
        s = RadialInflation(0.5, 1.0, 2000.0, 1e4, 0.3, gamma)
        print("gamma %g: cavity radius 0.5 -> %.8f (%.1f%%)" % (gamma, 0.5 + s.displacement(0.5),
                                                                100 * s.displacement(0.5) / 0.5))
    # small strain: Lame's u_r(a) = p a^3 / (E (b^3 - a^3)) ((1 - 2 nu) a + (1 + nu) b^3 / (2 a^2))
    s = RadialInflation(0.5, 1.0, 1e-3, 1e4, 0.3, follower=False)
    lame = 1e-3 * 0.125 / (1e4 * 0.875) * (0.4 * 0.5 + 1.3 / (2 * 0.25))
    print("small strain: u_r(a) %.10e, Lame %.10e, relative difference %.2e" % (s.displacement(0.5), lame,
                                                                              s.displacement(0.5) / lame - 1))
