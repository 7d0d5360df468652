"""Granular media: the Li 2013 catalogue, the generic profile, 3D-RFT media and plate calibration.

A :class:`Medium` is a small immutable record in SI units. Li's Fourier coefficients (supplement
table S2, published in N/cm^3) are stored in N/m^3 (x 1e6), in the order

    A00, A10, B11, B01, B_11, C11, C01, C_11, D10

The generic profile ``generic`` is the dimensionless M0 fit times 1 N/cm^3 (so its scaling factor
``zeta`` is 1e6 N/m^3 and alpha_z(0, pi/2) = 1 N/cm^3); ``generic.scaled(zeta)`` is the generic
profile of a medium with scaling factor ``zeta`` (N/m^3).

Measured plate stress: ``alpha_z_measured`` is alpha_z(0, pi/2) as measured with a horizontal plate
pushed straight down (the slope of stress against depth), which is larger than the Fourier fit's
value at the same angles (the fit smooths the sharp maximum). For the five Li media it is supplement
table S3 (N/cm^3: poppy seeds LP 0.35, CP 0.56; 0.3 mm glass LP 0.24, CP 0.40; 3 mm glass CP 0.29,
against fitted 0.26, 0.47, 0.19, 0.38, 0.22); :func:`calibrate` stores the slope it fitted. The
depth-only law (supplement eqs. S3-S7) is built from it; a medium without one (``generic`` and its
scaled copies, 3D-RFT media, saturated sand) falls back to the fit's alpha_z(0, pi/2). The paper
prints no numbers for the other two depth-only constants, alpha_z(0, -pi/2) (plate pulled up) and
alpha_x(pi/2, 0) (vertical plate dragged): they are read off its Fig. 2 C-D (figure and data table
S5 not in the text), so every medium takes those two from its fit (:meth:`Medium.own_params`).

3D-RFT (Agarwal et al. 2023) describes a medium by its bulk density, internal friction coefficient
``mu_int`` and surface (leg) friction ``mu_surface``; its stress scale is
``xi_n = g rho_bulk (894 mu^3 - 386 mu^2 + 89 mu)``. For the Li media the paper gives no internal
friction, so we *choose* the ``mu_int`` that makes 3D-RFT's plate-pushed-down stress (0.875 xi_n)
equal the medium's fitted alpha_z(0, pi/2) (what the ``rft`` law gives): the two laws then agree on
vertical penetration, and the angle of repose is kept only as a reported property. Likewise a medium made by
:func:`medium_3d` gets the Li generic profile with the same vertical stress.
"""

from __future__ import annotations

import csv
import dataclasses
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from .errors import check_finite, check_positive, unknown
from .params import P_AX_DRAG, P_AZ_DOWN, P_AZ_UP, P_COEFF, P_MU_S, P_XI, P_ZETA

G = 9.81
N_CM3 = 1e6  # N/cm^3 -> N/m^3
COEFF_NAMES = ("A00", "A10", "B11", "B01", "B_11", "C11", "C01", "C_11", "D10")
RFT3D_DOWN = 0.875  # 3D-RFT generic response of a horizontal plate pushed straight down (up, per xi_n)
CHI = 1.26  # Li supplement: zeta = alpha_z(0, pi/2)_measured / chi



def xi_n(rho_bulk: float, mu_int: float) -> float:
    """3D-RFT material constant (N/m^3) from bulk density (kg/m^3) and internal friction."""
    return G * rho_bulk * (894 * mu_int**3 - 386 * mu_int**2 + 89 * mu_int)


def _mu_for_xi(xi: float, rho_bulk: float) -> float:
    """Invert :func:`xi_n` for mu_int (the cubic is strictly increasing, so bisection is exact)."""
    lo, hi = 0.0, 3.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if xi_n(rho_bulk, mid) < xi:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def fourier_alpha(coeffs, beta, gamma):
    """Li 2013 Fourier fit (supplement eq. S8): returns (alpha_z, alpha_x) in the units of ``coeffs``.

    ``beta`` (attack angle) and ``gamma`` (intrusion angle, positive downward) in radians;
    numpy arrays broadcast. alpha_z > 0 pushes up, alpha_x > 0 resists motion along +x.
    """
    a00, a10, b11, b01, bm11, c11, c01, cm11, d10 = coeffs
    b2 = 2 * np.asarray(beta, dtype=float)
    g = np.asarray(gamma, dtype=float)
    az = a00 + a10 * np.cos(b2) + b11 * np.sin(b2 + g) + b01 * np.sin(g) + bm11 * np.sin(-b2 + g)
    ax = c11 * np.cos(b2 + g) + c01 * np.cos(g) + cm11 * np.cos(-b2 + g) + d10 * np.sin(b2)
    return az, ax


@dataclass(frozen=True)
class Medium:
    """One granular medium. All values SI (stresses per depth in N/m^3, lengths in m, densities kg/m^3).

    Attributes:
        name: catalogue name.
        coeffs: Li Fourier coefficients (N/m^3), order :data:`COEFF_NAMES`.
        zeta: scaling factor of the generic profile (N/m^3); 1 N/cm^3 = 1e6.
        grain_diameter: mean grain diameter (m), or None if unknown.
        grain_density: grain material density (kg/m^3), or None.
        volume_fraction: packing fraction, or None.
        repose_angle: angle of repose (deg), or None.
        mu_surface: friction coefficient between leg material and grains.
        mu_int: internal friction coefficient used by 3D-RFT (see module docstring), or None.
        description: where the numbers come from.
        extra: constants of laws beyond Li / 3D-RFT (e.g. wet-sand speed calibration), by name.
        alpha_z_measured: measured alpha_z(0, pi/2) of a horizontal plate pushed down (N/m^3; Li
            table S3, or the slope :func:`calibrate` fitted), or None; read by the depth-only law.
    """

    name: str
    coeffs: tuple
    zeta: float
    grain_diameter: float | None = None
    grain_density: float | None = None
    volume_fraction: float | None = None
    repose_angle: float | None = None
    mu_surface: float = 0.4
    mu_int: float | None = None
    description: str = ""
    extra: tuple = field(default_factory=tuple)
    alpha_z_measured: float | None = None

    def __post_init__(self):
        coeffs = tuple(float(c) for c in self.coeffs)
        if len(coeffs) != 9:
            raise ValueError(f"medium {self.name!r}: coeffs needs 9 values ({', '.join(COEFF_NAMES)}), got {len(coeffs)}")
        for n, c in zip(COEFF_NAMES, coeffs):
            check_finite(f"medium {self.name!r} coefficient {n}", c)
        object.__setattr__(self, "coeffs", coeffs)
        check_positive(f"medium {self.name!r} zeta", self.zeta)
        check_positive(f"medium {self.name!r} mu_surface", self.mu_surface, allow_zero=True)
        for attr in ("grain_diameter", "grain_density", "volume_fraction", "mu_int", "alpha_z_measured"):
            v = getattr(self, attr)
            if v is not None:
                check_positive(f"medium {self.name!r} {attr}", v)
        if self.volume_fraction is not None and self.volume_fraction > 1:
            raise ValueError(f"medium {self.name!r} volume_fraction must be <= 1, got {self.volume_fraction!r}")
        if self.alpha_z_down <= 0:
            raise ValueError(f"medium {self.name!r}: alpha_z(0, pi/2) must be > 0, got {self.alpha_z_down!r}")
        object.__setattr__(self, "extra", tuple(self.extra))

    # --- derived quantities -------------------------------------------------------------------
    def alpha(self, beta, gamma):
        """(alpha_z, alpha_x) in N/m^3 from the medium's own Fourier fit."""
        return fourier_alpha(self.coeffs, beta, gamma)

    @property
    def alpha_z_down(self) -> float:
        """alpha_z(0, pi/2): stress per depth under a horizontal plate pushed straight down (N/m^3)."""
        return float(fourier_alpha(self.coeffs, 0.0, math.pi / 2)[0])

    @property
    def depth_only_alphas(self) -> tuple[float, float, float]:
        """The depth-only law's constants (N/m^3, Li supplement eqs. S3-S4, S7), all magnitudes:
        alpha_z(0, pi/2) (measured when known, else the fit), |alpha_z(0, -pi/2)| and
        |alpha_x(pi/2, 0)| (the fit; the paper prints no measured numbers for these two)."""
        az_down = self.alpha_z_down if self.alpha_z_measured is None else float(self.alpha_z_measured)
        az_up = float(fourier_alpha(self.coeffs, 0.0, -math.pi / 2)[0])
        ax_drag = float(fourier_alpha(self.coeffs, math.pi / 2, 0.0)[1])
        return az_down, abs(az_up), abs(ax_drag)

    @property
    def rho_bulk(self) -> float | None:
        """Bulk density grain_density x volume_fraction (kg/m^3), or None if unknown."""
        if self.grain_density is None or self.volume_fraction is None:
            return None
        return self.grain_density * self.volume_fraction

    @property
    def critical_speed(self) -> float | None:
        """v_c = sqrt(2 g d) (m/s) from the grain diameter (mean, else ``grain_diameter_max``), or None when
        unknown: the intrusion speed above which grain inertia matters (Zhang et al., DynaRoACH paper,
        sec. 3.2: 25 cm/s for 3 mm glass); see :mod:`mjrft.laws.inertial`."""
        d = self.grain_diameter if self.grain_diameter is not None else self.get("grain_diameter_max")
        return None if d is None else math.sqrt(2.0 * G * float(d))

    @property
    def xi_n(self) -> float:
        """3D-RFT stress scale (N/m^3): from rho_bulk and mu_int when known, else matched to alpha_z_down."""
        if self.mu_int is not None and self.rho_bulk is not None:
            return xi_n(self.rho_bulk, self.mu_int)
        return self.alpha_z_down / RFT3D_DOWN

    def get(self, key: str, default=None):
        """A constant from :attr:`extra` by name."""
        return dict(self.extra).get(key, default)

    # --- constructors ---------------------------------------------------------------------------
    def scaled(self, zeta: float, name: str | None = None) -> "Medium":
        """The generic profile scaled to ``zeta`` (N/m^3): coefficients = M0 x zeta.

        Only meaningful on the generic profile; other media keep their own fit shape and are
        rescaled so that their scaling factor becomes ``zeta``. The result has no measured
        ``alpha_z_measured`` (it is a fit, not a measured medium).
        """
        zeta = check_positive("zeta", zeta)
        k = zeta / self.zeta
        return dataclasses.replace(
            self,
            name=name or f"{self.name}*{zeta:g}",
            coeffs=tuple(c * k for c in self.coeffs),
            zeta=zeta,
            mu_int=None,
            alpha_z_measured=None,
            description=f"{self.description} scaled to zeta = {zeta:g} N/m^3".strip(),
        )

    def with_extra(self, **values) -> "Medium":
        """A copy with constants added to :attr:`extra` (used by laws beyond Li and 3D-RFT)."""
        d = dict(self.extra)
        d.update(values)
        return dataclasses.replace(self, extra=tuple(sorted(d.items())))

    def own_params(self, p: np.ndarray) -> np.ndarray:
        """Write the medium's own constants into the parameter vector ``p`` (layout :mod:`mjrft.params`): Li's
        coefficients, xi_n, the surface friction, zeta and the depth-only law's three stresses; returns ``p``. The
        whole vector, with each law's constants, is :func:`mjrft.laws.registry.parameter_vector`."""
        p[P_COEFF:P_COEFF + 9] = self.coeffs
        p[P_XI] = self.xi_n
        p[P_MU_S] = self.mu_surface
        p[P_ZETA] = self.zeta
        p[P_AZ_DOWN], p[P_AZ_UP], p[P_AX_DRAG] = self.depth_only_alphas
        return p

    def params(self) -> np.ndarray:
        """Deprecated: :func:`mjrft.laws.parameter_vector` (``mjrft.laws.parameter_vector(medium)``) gives the same
        vector; the laws' constants are theirs, not the medium's."""
        warnings.warn("Medium.params() is deprecated; use mjrft.laws.parameter_vector(medium)", DeprecationWarning,
                      stacklevel=2)
        import importlib

        return importlib.import_module("mjrft.laws.registry").parameter_vector(self)


def _li(name, coeffs_ncm3, zeta_ncm3, d, rho_g, phi, repose, mu_s, az_measured_ncm3, description):
    coeffs = tuple(c * N_CM3 for c in coeffs_ncm3)
    az = float(fourier_alpha(coeffs, 0.0, math.pi / 2)[0])
    rho_bulk = rho_g * phi
    mu_int = _mu_for_xi(az / RFT3D_DOWN, rho_bulk)
    return Medium(name, coeffs, zeta_ncm3 * N_CM3, d, rho_g, phi, repose, mu_s, mu_int,
                  f"{description}; measured alpha_z(0, pi/2) {az_measured_ncm3:g} N/cm^3 (table S3)",
                  alpha_z_measured=az_measured_ncm3 * N_CM3)


_SRC = "Li, Zhang & Goldman, Science 2013, tables S1-S2"
# The argument before each description is the measured alpha_z(0, pi/2) in N/cm^3 (table S3, first row).
# Leg friction with poppy seeds is 0.36 (ABS) to 0.40 (aluminium); we use 0.40 for poppy seeds.
# The paper gives none for glass; 0.3 is our documented assumption (smooth glass on aluminium).
MEDIA: dict[str, Medium] = {
    m.name: m
    for m in (
        _li("poppy_lp", (0.051, 0.047, 0.053, 0.083, 0.020, -0.026, 0.057, 0.0, 0.025), 0.248,
            0.7e-3, 1100.0, 0.58, 36.0, 0.40, 0.35, f"poppy seeds, loosely packed ({_SRC})"),
        _li("poppy_cp", (0.094, 0.092, 0.092, 0.151, 0.035, -0.039, 0.086, 0.018, 0.046), 0.488,
            0.7e-3, 1100.0, 0.62, 47.0, 0.40, 0.56, f"poppy seeds, closely packed ({_SRC})"),
        _li("glass03_lp", (0.040, 0.030, 0.045, 0.077, 0.0, -0.031, 0.066, 0.0, 0.017), 0.194,
            0.27e-3, 2500.0, 0.58, 25.0, 0.30, 0.24, f"0.3 mm glass beads, loosely packed ({_SRC})"),
        _li("glass03_cp", (0.081, 0.063, 0.078, 0.133, 0.024, -0.050, 0.087, 0.0, 0.033), 0.371,
            0.27e-3, 2500.0, 0.62, 35.0, 0.30, 0.40, f"0.3 mm glass beads, closely packed ({_SRC})"),
        _li("glass3_cp", (0.045, 0.031, 0.046, 0.084, 0.012, -0.031, 0.060, 0.0, 0.015), 0.214,
            3.2e-3, 2600.0, 0.63, 21.0, 0.30, 0.29, f"3 mm glass beads, closely packed ({_SRC})"),
        Medium("generic", tuple(c * N_CM3 for c in (0.206, 0.169, 0.212, 0.358, 0.055, -0.124, 0.253, 0.007, 0.088)),
               1.0 * N_CM3, description=f"generic profile M0 x 1 N/cm^3 ({_SRC})"),
    )
}

generic = MEDIA["generic"]

# Saturated sea sand (SGRFT, "Granular Resistive Force Theory Extension for Saturated Wet Sand Ground",
# MDPI 2022): grains <= 1 mm, volume fraction 0.73, about 21.4 % water by mass. Table 3's alpha^30 = 0.47
# is read as zeta in N/cm^3 at the 30 mm/s base case, and wet_* is its speed factor (eps_v = 0.16 per
# 10 mm/s, measured 10-50 mm/s); see mjrft.laws.wet for both choices.
MEDIA["sea_sand_saturated"] = dataclasses.replace(
    generic.scaled(0.47 * N_CM3, name="sea_sand_saturated"), volume_fraction=0.73,
    description="saturated sea sand: generic profile x 0.47 N/cm^3 at 30 mm/s (SGRFT, MDPI 2022, table 3)",
).with_extra(wet_eps_v=0.16, wet_v_base=0.030, wet_dv=0.010, wet_v_min=0.010, wet_v_max=0.050,
             grain_diameter_max=1e-3, water_mass_fraction=0.214)


def fluidized(medium, air_flow: float) -> Medium:
    """``medium`` on an air-fluidised bed: an upward air flow whose pressure drop per unit height is ``air_flow``
    times the grains' weight per unit volume (0 <= air_flow < 1; 1 is the onset of fluidisation, where "the force
    of the air exceeded the weight of the grains": the thesis "A robophysics approach to bipedal walking in granular
    media", sec. 1.3.3; its fluidised-bed experiments weaken the bed up to that onset, sec. 1.4.3 and fig. 4).

    The air carries ``air_flow`` of the grains' weight, so the effective weight of the grains above any depth, and
    with it every frictional (hydrostatic-like) stress, is ``1 - air_flow`` times the still bed's (the effective
    stress principle): Li's coefficients, zeta, the measured plate stress and the hybrid law's unit weight scale by
    it; 3D-RFT's xi_n follows the coefficients (``mu_int`` is dropped: the still medium's internal friction no longer
    gives its stress). The grains' density, and with it the inertial regime's ``C rho_bulk`` (grain inertia), the
    packing and the angle of repose stay. ``air_flow = 0`` returns ``medium`` itself. A medium fluidised twice
    carries the combined flow ``1 - (1 - a)(1 - b)``; its name is ``<base>@air<flow>``."""
    m = get_medium(medium)
    q = check_finite("air_flow", air_flow)
    if not 0.0 <= q < 1.0:
        raise ValueError(f"air_flow must be in [0, 1) (a fraction of the onset of fluidisation, where the bed no longer "
                         f"carries any load), got {air_flow!r}")
    if q == 0.0:
        return m
    base = m.get("fluidized_from", m.name)
    total = 1.0 - (1.0 - float(m.get("air_flow", 0.0))) * (1.0 - q)
    k = 1.0 - q
    extra = dict(m.extra)
    if "hybrid_unit_weight" in extra or m.rho_bulk is None:
        if "hybrid_unit_weight" not in extra:
            from .laws.hybrid import GAMMA_S  # the hybrid law's default unit weight

            extra["hybrid_unit_weight"] = GAMMA_S
        extra["hybrid_unit_weight"] = extra["hybrid_unit_weight"] * k
    else:
        extra["hybrid_unit_weight"] = G * m.rho_bulk * k
    extra.update(fluidized_from=base, air_flow=total)
    return dataclasses.replace(
        m, name=f"{base}@air{total:g}", coeffs=tuple(c * k for c in m.coeffs), zeta=m.zeta * k, mu_int=None,
        alpha_z_measured=None if m.alpha_z_measured is None else m.alpha_z_measured * k,
        extra=tuple(sorted(extra.items())),
        description=f"{m.description}; air-fluidised bed at {total:g} of the onset (frictional stresses x {k:g})")


def register_medium(medium: Medium) -> Medium:
    """Add a medium to the catalogue so that it can be looked up by name."""
    if not isinstance(medium, Medium):
        raise TypeError(f"register_medium expects a Medium, got {type(medium).__name__}")
    MEDIA[medium.name] = medium
    return medium


def get_medium(medium) -> Medium:
    """A :class:`Medium` by catalogue name (or the medium itself). Unknown names list the choices."""
    if isinstance(medium, Medium):
        return medium
    if isinstance(medium, str) and medium in MEDIA:
        return MEDIA[medium]
    raise unknown("medium", medium, MEDIA)


def medium_3d(name: str, rho_bulk: float, mu_int: float, mu_surface: float, description: str = "") -> Medium:
    """A 3D-RFT medium from bulk density (kg/m^3), internal and surface friction.

    Its Li coefficients are the generic profile with alpha_z(0, pi/2) = 0.875 xi_n, so that the
    ``rft`` and ``rft3d`` laws agree on vertical penetration.
    """
    rho_bulk = check_positive("rho_bulk", rho_bulk)
    mu_int = check_positive("mu_int", mu_int)
    mu_surface = check_positive("mu_surface", mu_surface, allow_zero=True)
    zeta = RFT3D_DOWN * xi_n(rho_bulk, mu_int)
    base = generic.scaled(zeta, name=name)
    return dataclasses.replace(base, grain_density=rho_bulk, volume_fraction=1.0, mu_int=mu_int,
                               mu_surface=mu_surface, description=description or "3D-RFT medium")


def calibrate(depth, stress, *, name: str = "calibrated", max_depth: float | None = None, chi: float = CHI,
              mu_surface: float = 0.4) -> Medium:
    """Li's scaling routine: a medium from plate-penetration samples.

    ``depth`` (m, positive below the surface) and ``stress`` (Pa, vertical force / plate area) of a
    horizontal plate pushed straight down. A zero-intercept line is fitted over depths up to
    ``max_depth`` (the shallow linear range; default all samples); its slope is the measured
    alpha_z(0, pi/2) and ``zeta = slope / chi`` (chi = 1.26). Returns ``generic.scaled(zeta)`` with
    ``alpha_z_measured`` = the slope (what the depth-only law uses for a plate pushed down).
    """
    d = np.asarray(depth, dtype=float).ravel()
    s = np.asarray(stress, dtype=float).ravel()
    if d.shape != s.shape:
        raise ValueError(f"depth and stress must have the same length, got {d.size} and {s.size}")
    if not (np.all(np.isfinite(d)) and np.all(np.isfinite(s))):
        raise ValueError("depth and stress must be finite (found NaN or inf)")
    if np.any(d < 0):
        raise ValueError(f"depth must be >= 0 (positive below the surface), got min {d.min()!r}")
    if max_depth is not None:
        max_depth = check_positive("max_depth", max_depth)
        keep = d <= max_depth
        d, s = d[keep], s[keep]
    if np.count_nonzero(d > 0) < 2:
        raise ValueError("calibrate needs at least 2 samples below the surface in the fitted depth range")
    chi = check_positive("chi", chi)
    slope = float(np.dot(d, s) / np.dot(d, d))
    if slope <= 0:
        raise ValueError(f"fitted stress-per-depth slope must be > 0, got {slope!r} N/m^3")
    return dataclasses.replace(generic.scaled(slope / chi, name=name), mu_surface=mu_surface, alpha_z_measured=slope,
                               description=f"calibrated from {d.size} plate samples: slope {slope:.4g} N/m^3, chi {chi}")


def read_plate_csv(path) -> tuple[np.ndarray, np.ndarray]:
    """Read ``depth,stress`` columns (header required; SI) from a CSV file for :func:`calibrate`."""
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    if not rows or not {"depth", "stress"} <= set(rows[0]):
        raise ValueError(f"{path}: expected a CSV with header columns 'depth' and 'stress'")
    try:
        return (np.array([float(r["depth"]) for r in rows]), np.array([float(r["stress"]) for r in rows]))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{path}: non-numeric value ({exc})") from None
