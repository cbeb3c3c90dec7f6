"""Adhesive line contact: a cylinder on a flat, JKR and Maugis–Dugdale.

Linear elasticity, plane strain, per unit length: an elastic cylinder of
radius R (plane-strain modulus E* = E / (1 - nu^2)) on a rigid flat, a
contact of half-width a (the gap is zero on |x| < a) and the load P (N/m,
compressive positive). The cohesive law of docs/contact_laws.md is a
Dugdale zone: a constant tension sigma_0 = sigma_c wherever the gap is
within h_0 = g_c, and the work of adhesion is w = sigma_0 h_0.

JKR (Chaudhury, Weaver, Hui & Kramer, J. Appl. Phys. 80 (1996) 30, the
cylinder; a sharp edge, sigma_0 -> infinity at fixed w):

    P(a) = pi E* a^2 / (4 R) - sqrt(2 pi E* w a)

whose load-controlled pull-off (dP/da = 0) is at
a_c = (2 w R^2 / (pi E*))^(1/3) with P_c = -3 (pi E* w^2 R / 16)^(1/3),
and whose zero-load half-width is a_0 = (32 w R^2 / (pi E*))^(1/3).

Maugis–Dugdale line contact (the cohesive zone a < |x| < c resolved;
Baney & Hui, J. Adhesion Sci. Technol. 11 (1997) 393), derived here
(docs/adhesion/README.md) from the half-plane's Green function, the
pressure bounded at x = +-a:

    P = pi E* a^2 / (4 R) - 2 sigma_0 sqrt(c^2 - a^2)
    h_0 = [c s - a^2 ln((c + s) / a)] / (2 R)
          + (4 sigma_0 s / (pi E*)) int_0^s db / (c + sqrt(a^2 + b^2))

with s = sqrt(c^2 - a^2); the second line is the gap at x = c. As
sigma_0 -> infinity at fixed w (s << a) it gives 2 sigma_0 s ->
sqrt(2 pi E* w a), the JKR line above. The same two equations, written
in Baney & Hui's dimensionless variables (their eq. 23 for c / a, and
P = a^2 - lambda a sqrt(m^2 - 1)), give the same P(a) to 1e-12
(tests/python/test_adhesion.py). Baney & Hui's parameter
lambda = 4 sigma_0 (R / (pi^2 E*^2 w))^(1/3) measures the cohesive zone
(JKR as lambda -> infinity: s / a = 4^(2/3) / lambda at a = a_c).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from scipy import integrate, optimize


@dataclass(frozen=True)
class LineContact:
    """A cylinder of radius R on a rigid flat, Dugdale adhesion."""

    radius: float          # R, m
    modulus: float         # E* = E / (1 - nu^2), Pa (plane strain)
    cohesion: float        # sigma_0, Pa
    distance: float        # h_0, m

    @property
    def work(self) -> float:
        """w = sigma_0 h_0, J/m^2."""
        return self.cohesion * self.distance

    @property
    def maugis_lambda(self) -> float:
        """Baney & Hui's 4 sigma_0 (R / (pi^2 E*^2 w))^(1/3)."""
        return 4.0 * self.cohesion * (self.radius / (
            math.pi ** 2 * self.modulus ** 2 * self.work)) ** (1.0 / 3.0)

    # ------------------------------------------------------------ JKR
    def jkr_load(self, a: float) -> float:
        """P(a), N/m."""
        e, r, w = self.modulus, self.radius, self.work
        return (math.pi * e * a * a / (4 * r)
                - math.sqrt(2 * math.pi * e * w * a))

    def jkr_pull_off(self) -> tuple:
        """(a_c, P_c): the load-controlled pull-off (P_c < 0)."""
        e, r, w = self.modulus, self.radius, self.work
        a_c = (2 * w * r * r / (math.pi * e)) ** (1 / 3)
        return a_c, -3 * (math.pi * e * w * w * r / 16) ** (1 / 3)

    def jkr_zero_load_width(self) -> float:
        """a_0, m."""
        e, r, w = self.modulus, self.radius, self.work
        return (32 * w * r * r / (math.pi * e)) ** (1 / 3)

    # ------------------------------------------------- Maugis–Dugdale
    def gap_at_zone_end(self, a: float, c: float) -> float:
        """The gap at x = c of the contact (a, c), m."""
        s = math.sqrt(max(c * c - a * a, 0.0))
        hertz = (c * s - a * a * math.log((c + s) / a)) / (2 * self.radius)
        zone, _ = integrate.quad(lambda b: 1.0 / (c + math.hypot(a, b)),
                                 0.0, s, epsabs=0.0, epsrel=1e-12)
        return hertz + 4 * self.cohesion * s * zone / (math.pi * self.modulus)

    def zone_end(self, a: float) -> float:
        """c(a): the gap at c equals h_0 (it grows with c)."""
        h0 = self.distance
        hi = a * 1.01 + 1e-12
        while self.gap_at_zone_end(a, hi) < h0:
            hi = a + 2 * (hi - a)
        return optimize.brentq(lambda c: self.gap_at_zone_end(a, c) - h0, a,
                               hi, xtol=1e-15 * a, rtol=1e-13)

    def md_load(self, a: float) -> float:
        """P(a), N/m."""
        c = self.zone_end(a)
        return (math.pi * self.modulus * a * a / (4 * self.radius)
                - 2 * self.cohesion * math.sqrt(c * c - a * a))

    def md_pull_off(self) -> tuple:
        """(a_c, P_c): the least load over a (load-controlled pull-off)."""
        a_jkr, _ = self.jkr_pull_off()
        found = optimize.minimize_scalar(
            self.md_load, bounds=(1e-3 * a_jkr, 3 * a_jkr), method="bounded",
            options={"xatol": 1e-9 * a_jkr})
        return float(found.x), float(found.fun)

    def md_zero_load_width(self) -> float:
        """a_0: P(a_0) = 0 on the branch beyond the pull-off."""
        a_c, _ = self.md_pull_off()
        hi = 2 * a_c
        while self.md_load(hi) < 0:
            hi *= 2
        return optimize.brentq(self.md_load, a_c, hi, rtol=1e-12)
