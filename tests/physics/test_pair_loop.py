"""The pair loop (:func:`sph.engine.fluid.interact`) against a brute-force evaluation of the
same sums.

``interact`` finds each fluid particle's neighbours through the cell list. The reference
here visits, for every fluid particle, every other particle of the set (no cells), and sums
Eqs. 2, 3 and 5 of Cao et al. (2019) with the wall rules, the delta-SPH terms and the
particle shift (Sun et al. 2017: gate, anti-clumping term, surface projection, cap) pair by
pair. The state is a patch of a damaged ship around its open side
opening (sea, cabin, hull walls with their extrapolated pressures), with random velocities,
pressures (some negative: fluid in tension against a wall) and density gradients, so that
every branch of the pair rules is taken: fluid pairs of one compartment, sea-cabin pairs
through the opening and blocked elsewhere, fluid-wall pairs on either side of the plating.
The two must agree to round-off. Pressure and viscous forces between fluid particles are
equal and opposite, so they leave the fluid's momentum unchanged.
"""

import numpy as np
import pytest
from physics_helpers import NO_EXTRAS, verlet_lists

from sph.cases import builtin
from sph.driver import Simulation
from sph.engine.fluid import interact, pair_work
from sph.engine.kernels import f_r2, w_given_f, w_r2
from sph.engine.neighbours import CellGrid
from sph.engine.opening import passable, wall_hidden
from sph.engine.shifting import PACKED, PACKED_RAMP, R_ANTI, SURFACE_DIVR, shift_params

RTOL = 1e-10


@pytest.fixture(scope="module")
def patch():
    """Particles of the damaged ship within 5 m of the open opening's centre, with the sea
    next to the opening mirrored into the cabin (as if it had begun to flood) and the fluid
    within 2 m of the highest particle drawn towards it (packed at the surface),
    re-sorted."""
    cfg = builtin("damaged_ship", [
        ("numerics.dx", 0.8), ("numerics.threads", 2),
        ("geometry.damage.time_periods", 0.001)])
    sim = Simulation(cfg)
    sim.evaluate()
    for _ in range(20):
        sim.advance()
        if sim.op[0] == 1.0:
            break
    op, kin = sim.op.copy(), sim.kin.copy()
    assert op[0] == 1.0, "the opening should be open"
    p = sim.parts
    keep = np.hypot(p.x - op[18], p.z - op[19]) < 5.0
    st = {name: getattr(p, name)[keep].copy() for name in
          ("x", "z", "vx", "vz", "rho", "p", "m", "kind", "body", "comp")}
    sea = (st["kind"] == 0) & (op[4] * (st["x"] - op[18]) > 0.1)
    cabin = {k: v[sea].copy() for k, v in st.items()}
    cabin["x"] = 2 * op[18] - cabin["x"]
    cabin["comp"][:] = int(op[2]) if int(op[1]) == st["comp"][sea][0] else int(op[1])
    st = {k: np.concatenate([v, cabin[k]]) for k, v in st.items()}
    rng = np.random.default_rng(7)
    n = len(st["x"])
    st["x"] += rng.normal(0, 0.02, n) * (st["kind"] == 0)
    st["vx"] += rng.normal(0, 0.5, n)
    st["vz"] += rng.normal(0, 0.5, n)
    st["rho"] *= 1.0 + rng.normal(0, 0.003, n)
    # a packed cluster at the free surface (the shift's surface projection and cap)
    fluid = np.nonzero(st["kind"] == 0)[0]
    top = fluid[np.argmax(st["z"][fluid])]
    near = fluid[np.hypot(st["x"][fluid] - st["x"][top], st["z"][fluid] - st["z"][top]) < 2.0]
    for key in ("x", "z"):
        st[key][near] = st[key][top] + 0.4 * (st[key][near] - st[key][top])
    st["p"] = rng.normal(1.0e4, 1.5e4, n)
    st["grx"] = rng.normal(0, 20.0, n)
    st["grz"] = rng.normal(0, 20.0, n)
    r = sim.grid.cell
    g = CellGrid(st["x"].min() - 1, st["x"].max() + 1, st["z"].min() - 1, st["z"].max() + 1, r)
    assert g.sort(st["x"], st["z"]) == 0
    st = {k: v[g.order].copy() for k, v in st.items()}
    kinds = set(np.unique(st["kind"]))
    comps = set(np.unique(st["comp"][st["kind"] == 0]))
    assert 0 in kinds and len(kinds) > 1 and len(comps) > 1, "patch lacks walls or cabin"
    return dict(st=st, grid=g, kp=sim.kp, op=op, kin=kin, dx=cfg.numerics.dx)


def _reference(st, grid, kp, op, kin, visc, gx, gz, delta, ddt_rho, shift):
    """Gather over all particles for each fluid particle (no cells), pair by pair."""
    x, z, vx, vz, rho, p, m = (st[k] for k in ("x", "z", "vx", "vz", "rho", "p", "m"))
    kind, body, comp, grx, grz = (st[k] for k in ("kind", "body", "comp", "grx", "grz"))
    n = len(x)
    eps2 = 1.0e-4 * kp[1] ** 2
    out = {k: np.zeros(n) for k in ("ax", "az", "drho", "sx", "sz")}
    seen = {"through the opening": 0, "blocked": 0, "wall hidden": 0, "fluid-wall": 0,
            "shifted": 0, "capped": 0, "at the surface": 0}
    for i in np.nonzero(kind == 0)[0]:
        ddx, ddz = x[i] - x, z[i] - z
        r2 = ddx * ddx + ddz * ddz
        accx = accz = div = diff = 0.0
        shep = m[i] / rho[i] * w_r2(0.0, kp)
        cgx = cgz = divr = 0.0  # concentration gradient and divergence of the position
        for j in np.nonzero(r2 < kp[3])[0]:
            if j == i:
                continue
            if kind[j] == 0:
                if comp[j] != comp[i]:
                    if not passable(x[i], z[i], x[j], z[j], comp[i], comp[j], op, kin):
                        seen["blocked"] += 1
                        continue
                    seen["through the opening"] += 1
            elif comp[j] != comp[i]:
                continue
            elif wall_hidden(x[i], z[i], x[j], z[j], body[j], op, kin):
                seen["wall hidden"] += 1
                continue
            else:
                seen["fluid-wall"] += 1
            dx, dz = ddx[j], ddz[j]
            fw = f_r2(r2[j], kp)
            vj = m[j] / rho[j]
            vr = (vx[i] - vx[j]) * dx + (vz[i] - vz[j]) * dz
            div += vj * vr * fw
            if kind[j] == 0:
                coef = -m[j] * (p[i] + p[j]) / (rho[i] * rho[j])
                coef += visc * m[j] / (rho[i] + rho[j]) * vr / (r2[j] + eps2)
                if ddt_rho:
                    rho_h = -ddt_rho * (gx * dx + gz * dz)
                    diff -= 2.0 * vj * fw * (rho[j] - rho[i] - rho_h)
                elif delta:
                    diff += vj * fw * (-2.0 * (rho[j] - rho[i]) - ((grx[i] + grx[j]) * dx
                                                                   + (grz[i] + grz[j]) * dz))
            else:
                coef = -m[j] * (max(p[i], 0.0) + p[j]) / (rho[i] * rho[j])
            accx += coef * fw * dx
            accz += coef * fw * dz
            wij = w_given_f(r2[j], fw, kp)
            shep += vj * wij
            anti = 1.0 + R_ANTI * (wij / shift[1]) ** 4
            cgx += vj * fw * anti * dx
            cgz += vj * fw * anti * dz
            divr -= vj * fw * r2[j]
        out["ax"][i] = accx + gx
        out["az"][i] = accz + gz
        out["drho"][i] = rho[i] * div + delta * diff
        gate = min(max((shep - PACKED) / PACKED_RAMP, 0.0), 1.0)
        if shift[0] and gate > 0.0:  # Sun et al. (2017), surface projection, cap
            sh = -shift[0] * gate * np.array([cgx, cgz])
            g = np.array([cgx, cgz])
            if divr < SURFACE_DIVR and g @ g > 0.0:
                sh -= (sh @ g) / (g @ g) * g
            size = np.hypot(*sh)
            if size > shift[2]:
                sh *= shift[2] / size
            out["sx"][i], out["sz"][i] = sh
            seen["shifted"] += 1
            seen["capped"] += size > shift[2]
            seen["at the surface"] += divr < SURFACE_DIVR
    return out, seen


def _interact(st, grid, kp, op, kin, visc, gx, gz, delta, ddt_rho, shift):
    n = len(st["x"])
    out = {k: np.zeros(n) for k in ("ax", "az", "drho", "sx", "sz")}
    interact(st["x"], st["z"], st["vx"], st["vz"], st["rho"], st["p"], st["m"], st["kind"],
             st["body"], st["comp"], np.ones(n), grid.cell_of, grid.cell_start, grid.ncx, kp,
             visc, gx, gz, delta, ddt_rho, st["grx"], st["grz"], out["ax"], out["az"],
             out["drho"], op, kin, shift, out["sx"], out["sz"], pair_work(n),
             *verlet_lists(st["x"], st["z"], st["kind"], grid), False, *NO_EXTRAS)
    return out


@pytest.mark.parametrize("diffusion", ["delta", "ddt", "none"])
def test_pair_loop_matches_the_gather_over_all_particles(patch, diffusion):
    kp, dx = patch["kp"], patch["dx"]
    visc = 2 * 0.02 * kp[1] * 170.0
    delta = 0.0 if diffusion == "none" else 0.1 * kp[1] * 170.0
    ddt_rho = 1000.0 / 170.0**2 if diffusion == "ddt" else 0.0
    shift = shift_params(4.0, 0.2, 10.0, kp, dx)  # C = 4: some shifts reach the cap
    args = (patch["st"], patch["grid"], kp, patch["op"], patch["kin"], visc, 0.0, -9.81, delta,
            ddt_rho, shift)
    got, (want, seen) = _interact(*args), _reference(*args)
    print(seen)
    assert min(seen.values()) > 0, seen  # every pair rule and shifting branch is exercised
    for name in ("ax", "az", "drho", "sx", "sz"):
        scale = np.abs(want[name]).max()
        assert scale > 0, name
        np.testing.assert_allclose(got[name], want[name], rtol=0, atol=RTOL * max(scale, 1e-30),
                                   err_msg=name)


def test_fluid_pairs_conserve_momentum(patch):
    """Without gravity and walls, the pressure and viscous forces of all pairs cancel:
    sum m a = 0 to round-off."""
    st = dict(patch["st"])
    fluid = st["kind"] == 0
    st = {k: v[fluid].copy() for k, v in st.items()}
    g = patch["grid"]
    grid = CellGrid(*g.bounds, g.cell)
    assert grid.sort(st["x"], st["z"]) == 0
    st = {k: v[grid.order].copy() for k, v in st.items()}
    st["comp"][:] = 0
    kp = patch["kp"]
    out = _interact(st, grid, kp, patch["op"], patch["kin"], 2 * 0.02 * kp[1] * 170.0, 0.0, 0.0,
                    0.0, 0.0, np.zeros(3))
    for a in (out["ax"], out["az"]):
        assert abs((st["m"] * a).sum()) < 1e-12 * (st["m"] * np.abs(a)).sum()

