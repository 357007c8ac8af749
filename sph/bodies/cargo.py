r"""The loaded ship: mass properties of the dry part and the cargo, the free-surface effect,
and the linear roll of a ship with sloshing cargo.

**What stays fixed as the fill changes.** Cao et al. (2019, Sec. IV D) fill the two end
cabins with liquid to :math:`\eta = h_w / D` and keep the draught d for every fill ("the ship
models with different loading ratios have the same draught before the damage creation"), so
the displacement :math:`\Delta = \rho A(d)` per unit length is the same at every fill. They
give the empty ship's roll natural frequency (1.06 rad/s, Sec. IV A and Table II) but no
centre of gravity, inertia or cargo density. The simulation's rigid body is the *dry part*
(hull, structure, ballast); the cargo is fluid. Key ``geometry.hull.mass_properties`` says
what the case values ``kg`` (KG) and ``gyradius`` (k) describe:

``loaded`` (the default)
    the whole loaded ship with its cargo frozen: mass :math:`\Delta`, centre of gravity KG
    and inertia :math:`\Delta k^2` about it, at every fill. The dry part is the loaded ship
    less the frozen cargo (first moments, and the parallel-axis theorem for the inertia):

    .. math::
        m_d = \Delta - m_c,\qquad m_d\,KG_d = \Delta\,KG - m_c\,KG_c,

        I_d = \Delta k^2 - \left[J_c + m_c (KG_c - KG)^2\right] - m_d (KG_d - KG)^2,

    with :math:`m_c = w \rho_c A_c` the cargo's mass, :math:`KG_c` its centroid,
    :math:`J_c = w \rho_c \int (u^2 + (z - KG_c)^2)\,dA` its inertia about the centroid and
    :math:`w` the fraction of the ship's length that carries cargo (the intact cabins, 2/3).
    The empty ship is the loaded ship; a fill changes only what is free to move, the
    cargo's liquid, which is what the paper studies, and the frozen ship keeps the paper's
    roll frequency and metacentric height at every fill.
``dry``
    the dry part alone: it keeps KG and k at every fill while its mass
    :math:`\Delta - m_c` (and with it its inertia) falls as the cargo grows; the loaded
    ship's centre of gravity moves to :math:`(m_d KG + m_c KG_c) / \Delta`. For a user who
    knows the lightship's KG and gyradius of a ship loaded to d.

Refused (:func:`check_mass_properties`): a dry part lighter than :data:`MIN_DRY_FRACTION` of
the displacement (an explicitly coupled body much lighter than the liquid it carries is
ill-conditioned, and a ship is never almost all cargo), a dry part with no roll inertia, and
a dry part whose centre of gravity lies outside the hull. With the paper's ship, water fills
25 and 50 %, but at 75 % water outweighs the displacement at d (by 0.5 %), and the densest
cargo that leaves a dry part at all (917 kg/m3) leaves it no roll inertia.

**Free-surface effect** (e.g. Biran and López-Pulido 2014, *Ship Hydrostatics and
Stability*, Sec. 6.8): when the ship heels slowly the cargo's surface stays level and its
weight moves to the low side, as if the metacentric height were

.. math:: GM_{\rm eff} = GM - w \frac{\rho_c}{\rho} \frac{i}{A(d)},\qquad i = \frac{b^3}{12},

with b the breadth of the cargo's free surface (15.8 m in the paper's cabins: a correction of
3.3 m for water against GM = 3.88 m).

**Roll with sloshing cargo** (:func:`roll_modes`). Linear potential flow in a rectangular
tank of the cargo's breadth :math:`b = 2a` and depth h (the bilges ignored) rolling by
:math:`\theta` about the loaded ship's centre of gravity O. In the tank's frame (x across,
z up from the mean free surface) the potential is
:math:`\Phi = \dot\theta\,\Omega + \sum_n R_n \varphi_n` (Faltinsen and Timokha 2009,
*Sloshing*, Ch. 5): :math:`\Omega` the Stokes-Joukowski potential, whose normal derivative is
the normal velocity of the rotating walls on the walls and on the mean free surface, and the
natural modes :math:`\varphi_n = \cos k_n(x + a)\cosh k_n(z + h)/\cosh k_n h`,
:math:`k_n = n\pi/b`, :math:`\sigma_n^2 = g\kappa_n`, :math:`\kappa_n = k_n\tanh k_n h`, with the
free surface :math:`\zeta = \sum_n \beta_n \cos k_n(x + a)`. The liquid's angular momentum
about O and the moment of its weight give, with the modal free-surface conditions, the
symmetric linear system (odd n; the even modes do not couple with roll)

.. math::
    (I_d^O + A_{44} + w\rho_c J_\Omega)\ddot\theta + C\theta
        + w\rho_c \sum_n (\lambda_n \ddot\beta_n + g\mu_n\beta_n) = 0,

    \frac{a}{\kappa_n}\ddot\beta_n + g a \beta_n + \lambda_n\ddot\theta + g\mu_n\theta = 0,

with :math:`J_\Omega = \int|\nabla\Omega|^2\,dA` (the liquid's inertia under a lid; for a
square tank 0.1565 of the frozen one, Lamb 1932, *Hydrodynamics*, Sec. 72),
:math:`\lambda_n = \int \Omega(x, 0)\cos k_n(x + a)\,dx`,
:math:`\mu_n = \int x \cos k_n(x + a)\,dx = -2/k_n^2`, :math:`C = \Delta g\,GM` of the frozen
ship, :math:`I_d^O` the dry part's inertia about O and :math:`A_{44}` the sea's added
inertia in roll about O. Slowly (:math:`\ddot\theta \to 0`) the modes keep the surface level
and the stiffness falls to :math:`C - w\rho_c g\,b^3/12`: the free-surface correction above.
Its eigenvalues are the coupled natural frequencies: a low one where the ship rolls on the
reduced GM while the cargo stays nearly level, and one above the cargo's sloshing frequency
where ship and cargo move against each other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sph.bodies.hull import HullConfig, hydrostatics, submerged_moments
from sph.schema import ConfigError

#: the dry part must keep at least this fraction of the displacement
MIN_DRY_FRACTION = 0.05


@dataclass(frozen=True)
class CargoSection:
    """The cargo's cross-section in one cabin (keel frame, upright ship)."""

    area: float  #: m2
    kg: float  #: centroid height above the keel, m
    inertia: float  #: polar second moment of area about the centroid, m4
    breadth: float  #: breadth of the free surface, m
    depth: float  #: liquid depth h_w above the cabin floor, m


def _surface_breadth(hull: HullConfig, level: float) -> float:
    """Breadth of the cabin (inside the plating) at keel-frame height ``level``."""
    t = hull.plating
    r = max(hull.bilge_radius - t, 0.0)
    half = 0.5 * hull.breadth - t
    if level >= t + r:
        return 2.0 * half
    dz = t + r - level
    return 2.0 * (half - r + math.sqrt(max(r * r - dz * dz, 0.0)))


def cargo_section(hull: HullConfig, fill: float) -> CargoSection:
    """The cargo at fill ratio ``fill`` (level ``plating + fill D`` above the keel), from the
    exact section (the rounded bilges included)."""
    if fill <= 0.0:
        return CargoSection(0.0, hull.plating, 0.0, 0.0, 0.0)
    level = hull.plating + fill * hull.depth
    area, kg, inertia = submerged_moments(hull, level, hull.plating)
    return CargoSection(area, kg, inertia, _surface_breadth(hull, level), fill * hull.depth)


def cargo_section_of_particles(hull: HullConfig, fill: float, u, w, volume) -> CargoSection:
    """The cargo as placed: particles at keel-frame ``(u, w)`` with volumes ``volume``; each
    particle's own cell (about square) adds :math:`V^2/6` to the second moment."""
    u, w, v = (np.asarray(a, dtype=float) for a in (u, w, volume))
    area = float(v.sum())
    if area <= 0.0:
        return cargo_section(hull, 0.0)
    uc, wc = float(v @ u) / area, float(v @ w) / area
    inertia = float(v @ ((u - uc) ** 2 + (w - wc) ** 2) + (v * v).sum() / 6.0)
    exact = cargo_section(hull, fill)
    return CargoSection(area, wc, inertia, exact.breadth, exact.depth)


@dataclass(frozen=True)
class MassProperties:
    """Mass properties per unit length of ship (kg/m, m, kg m2/m)."""

    reference: str  #: what kg and gyradius describe: ``loaded`` or ``dry``
    displacement: float  #: Delta = rho A(d)
    cargo: float  #: m_c = w rho_c A_c
    cargo_kg: float  #: KG_c
    cargo_inertia: float  #: J_c, the frozen cargo's inertia about its own centroid
    dry: float  #: m_d, the rigid body of the simulation
    dry_kg: float  #: KG_d
    dry_inertia: float  #: I_d about the dry part's centre of gravity
    ship_kg: float  #: KG of the loaded ship, cargo frozen
    ship_inertia: float  #: inertia of the loaded ship about its centre of gravity, frozen
    gm: float  #: GM of the loaded ship, cargo frozen
    free_surface: float  #: free-surface correction w (rho_c / rho) b^3 / 12 / A(d)

    @property
    def gm_fluid(self) -> float:
        """GM corrected for the cargo's free surface."""
        return self.gm - self.free_surface


def mass_properties(hull: HullConfig, rho0: float, gravity: float, weight: float,
                    cargo_density: float, cargo: CargoSection) -> MassProperties:
    """Dry part, cargo and loaded ship (module docstring) for the cargo ``cargo`` of density
    ``cargo_density`` in the fraction ``weight`` of the ship's length."""
    hs = hydrostatics(hull, rho0, gravity)
    delta = hs["mass"]
    mc = weight * cargo_density * cargo.area
    jc = weight * cargo_density * cargo.inertia
    md = delta - mc
    if hull.mass_properties == "loaded":
        kg_ship = hull.kg
        i_ship = delta * hull.gyradius**2
        kg_d = (delta * hull.kg - mc * cargo.kg) / md if md > 0.0 else math.nan
        i_d = i_ship - jc - mc * (cargo.kg - kg_ship) ** 2 - md * (kg_d - kg_ship) ** 2
    else:
        kg_d, i_d = hull.kg, md * hull.gyradius**2
        kg_ship = (md * hull.kg + mc * cargo.kg) / delta
        i_ship = i_d + md * (kg_d - kg_ship) ** 2 + jc + mc * (cargo.kg - kg_ship) ** 2
    gm = hs["kb"] + hs["bm"] - kg_ship
    fsc = weight * cargo_density / rho0 * cargo.breadth**3 / 12.0 / hs["area"]
    return MassProperties(hull.mass_properties, delta, mc, cargo.kg, jc, md, kg_d, i_d,
                          kg_ship, i_ship, gm, fsc)


def _fits(mp: MassProperties, hull: HullConfig) -> str:
    """Empty if the dry part is possible, else what is wrong with it."""
    if not mp.dry >= MIN_DRY_FRACTION * mp.displacement:
        return (f"leaves the dry part (hull, structure, ballast) {mp.dry:.4g} kg/m, "
                f"{100 * mp.dry / mp.displacement:.3g} % of the displacement "
                f"{mp.displacement:.4g} kg/m at draught {hull.draught:g} m (at least "
                f"{100 * MIN_DRY_FRACTION:g} % needed)")
    if not 0.0 < mp.dry_kg < hull.depth:
        return (f"puts the dry part's centre of gravity {mp.dry_kg:.4g} m above the keel, "
                f"outside the hull (0, {hull.depth:g}) m")
    if not mp.dry_inertia > 0.0:
        return (f"leaves the dry part a roll inertia of {mp.dry_inertia:.4g} kg m2/m: the "
                f"frozen cargo's inertia exceeds the loaded ship's")
    return ""


def densest_cargo(hull: HullConfig, rho0: float, gravity: float, weight: float,
                  cargo: CargoSection) -> float:
    """The densest cargo (kg/m3) that leaves a possible dry part, 0 if none does."""
    def ok(rho):
        return not _fits(mass_properties(hull, rho0, gravity, weight, rho, cargo), hull)

    lo, hi = 0.0, 1.0e5
    if not ok(lo):
        return 0.0
    if ok(hi):
        return hi
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
    return lo


def check_mass_properties(hull: HullConfig, rho0: float, gravity: float, weight: float,
                          cargo_density: float, fill: float, cargo: CargoSection,
                          key: str = "geometry") -> MassProperties:
    """The mass properties, or a :class:`~sph.schema.ConfigError` naming
    ``{key}.cargo_density`` and the densest cargo that fits when the dry part would not be
    possible."""
    mp = mass_properties(hull, rho0, gravity, weight, cargo_density, cargo)
    why = _fits(mp, hull)
    if why:
        best = densest_cargo(hull, rho0, gravity, weight, cargo)
        allowed = (f"allowed (0, {math.floor(best):g}] kg/m3 at this fill" if best > 0.0
                   else f"no cargo fits at this fill; lower {key}.fill")
        raise ConfigError(f"{key}.cargo_density",
                          f"a cargo of {cargo_density:g} kg/m3 at fill {fill:g} "
                          f"({mp.cargo:.4g} kg/m, {key}.hull.mass_properties = "
                          f"{hull.mass_properties}) {why}; {allowed}")
    return mp


# ------------------------------------------------------------------------------ roll
def _stokes_joukowski(a: float, c: float, d: float, x: np.ndarray, terms: int = 400):
    r"""The Stokes-Joukowski potential of a rectangle ``|x| < a``, ``|z'| < c`` rotating about
    a point ``d`` below its centre: ``J = int |grad Omega|^2 dA`` and ``Omega`` on the top
    side ``z' = c`` at ``x``.

    :math:`\Omega = x z' + \sum_n A_n \sinh(m_n x)\sin(m_n z') - d\,x`,
    :math:`m_n = (2n + 1)\pi / 2c`, :math:`A_n = -2 b_n / (m_n\cosh m_n a)`,
    :math:`b_n = 2(-1)^n / (c\,m_n^2)` (the sine series of :math:`z'`): the series fixes the
    side walls' condition :math:`\partial\Omega/\partial x = -z'`; the parallel-axis term
    :math:`4ac\,d^2` moves J from the centre to the rotation point.
    """
    n = np.arange(terms)
    m = (2 * n + 1) * math.pi / (2.0 * c)
    b = 2.0 * (-1.0) ** n / (c * m * m)
    a_sinh = -2.0 * b / m * np.tanh(m * a)  # A_n sinh(m_n a)
    a_cosh = -2.0 * b / m  # A_n cosh(m_n a)
    sides = -2.0 * a * c**3 / 3.0 - c * np.sum(a_sinh * b)
    tops = 2.0 * a**3 * c / 3.0 + np.sum((-1.0) ** n * 2.0 * (a * a_cosh / m - a_sinh / m**2))
    j = 2.0 * sides + 2.0 * tops + 4.0 * a * c * d * d
    ax = np.abs(x)[:, None]
    # A_n sinh(m_n x) without overflow (far terms underflow to 0, as they should)
    with np.errstate(under="ignore"):
        ratio = (np.exp(m * (ax - a)) * (1.0 - np.exp(-2.0 * m * ax))
                 / (1.0 + np.exp(-2.0 * m * a)))
        series = (np.sign(x)[:, None] * ratio * (-2.0 * b / m) * (-1.0) ** n).sum(axis=1)
    return j, x * c + series - d * x


def roll_matrices(mp: MassProperties, hull: HullConfig, cargo: CargoSection, rho0: float,
                  gravity: float, weight: float, cargo_density: float,
                  added_inertia: float, modes: int = 6) -> tuple[np.ndarray, np.ndarray]:
    r"""Mass and stiffness matrices of the linear roll-sloshing system (module docstring)
    in the coordinates :math:`(\theta, \beta_1, \beta_3, \ldots)`; arguments as
    :func:`roll_modes`."""
    g = gravity
    c_roll = mp.displacement * g * mp.gm
    i_dry = mp.dry_inertia + mp.dry * (mp.dry_kg - mp.ship_kg) ** 2
    rc = weight * cargo_density
    if rc * cargo.area <= 0.0:
        return np.array([[i_dry + added_inertia]]), np.array([[c_roll]])
    a = 0.5 * cargo.breadth
    h = cargo.depth
    d = (hull.plating + 0.5 * h) - mp.ship_kg  # the tank's centre above O
    x = np.linspace(-a, a, 4001)
    j_lid, omega_top = _stokes_joukowski(a, 0.5 * h, d, x)
    size = 1 + modes
    mass = np.zeros((size, size))
    stiff = np.zeros((size, size))
    mass[0, 0] = i_dry + added_inertia + rc * j_lid
    stiff[0, 0] = c_roll
    for i in range(modes):
        k = (2 * i + 1) * math.pi / (2.0 * a)
        kappa = k * math.tanh(k * h)
        lam = float(np.trapezoid(omega_top * np.cos(k * (x + a)), x))
        mu = -2.0 / k**2
        mass[0, 1 + i] = mass[1 + i, 0] = rc * lam
        mass[1 + i, 1 + i] = rc * a / kappa
        stiff[0, 1 + i] = stiff[1 + i, 0] = rc * g * mu
        stiff[1 + i, 1 + i] = rc * g * a
    return mass, stiff


def roll_modes(mp: MassProperties, hull: HullConfig, cargo: CargoSection, rho0: float,
               gravity: float, weight: float, cargo_density: float, added_inertia: float,
               modes: int = 6) -> dict:
    r"""Coupled roll-sloshing natural frequencies of the loaded ship (module docstring).

    Parameters
    ----------
    mp : MassProperties
        Of the loaded ship (:func:`mass_properties`).
    cargo : CargoSection
        Its breadth and depth make the rectangular tank.
    added_inertia : float
        The sea's added inertia in roll about the ship's centre of gravity, kg m2/m (e.g.
        from the empty ship's roll frequency: :math:`\Delta g GM/\omega_\phi^2 - \Delta k^2`).
    modes : int
        Antisymmetric sloshing modes kept (n = 1, 3, ...).

    Returns
    -------
    dict
        ``omega``: the coupled natural frequencies (rad/s, ascending); ``roll_share``: each
        one's part in the roll of a ship released from rest at a heel with its cargo's
        surface parallel to the deck (the roll is :math:`\theta_0\sum_j s_j\cos\omega_j t`);
        ``sloshing``: the first sloshing frequency of the tank (rad/s); ``quasi_static``:
        :math:`\sqrt{C_{\rm eff}/I}` with the free-surface correction and the liquid's
        inertia under a lid.
    """
    from scipy.linalg import eigh

    mass, stiff = roll_matrices(mp, hull, cargo, rho0, gravity, weight, cargo_density,
                                added_inertia, modes)
    eigval, vec = eigh(stiff, mass)
    q0 = np.zeros(len(mass))
    q0[0] = 1.0
    share = vec[0] * np.linalg.solve(vec, q0)
    omega = np.sqrt(np.maximum(eigval, 0.0))
    if len(mass) == 1:
        return dict(omega=omega, roll_share=share, sloshing=math.nan, quasi_static=omega[0])
    k1 = math.pi / cargo.breadth
    quasi = (stiff[0, 0] - weight * cargo_density * gravity * cargo.breadth**3 / 12.0) \
        / mass[0, 0]
    return dict(omega=omega, roll_share=share,
                sloshing=math.sqrt(gravity * k1 * math.tanh(k1 * cargo.depth)),
                quasi_static=math.sqrt(quasi) if quasi > 0.0 else math.nan)
