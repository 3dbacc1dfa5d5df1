#!/usr/bin/python3
"""GetFEM reference trajectories for dyncontact's cross-code tests (see README.md beside this file).

Every run uses GetFEM's own model: its Newmark scheme (`add_Newmark_scheme`, beta = gamma = 1/2),
consistent mass, linear elasticity and one of its contact bricks with a rigid obstacle, solved by
its Newton method on the Alart-Curnier augmented Lagrangian. The initial state is dyncontact's:
U0, V0 and the Galerkin acceleration M A0 = -K U0 (no contact force).

Output (one CSV per run): t, u_contact, sigma_contact, energy, with
  u_contact      the normal displacement of the probe (bar: x = 0; block: centre of the bottom face),
  sigma_contact  the normal contact stress there, compression negative (nodal brick: the nodal force
                 over the tributary length; integral brick: the P1 multiplier at the probe),
  energy         1/2 V.M.V + 1/2 U.K.U.

Usage: /usr/bin/python3 golden/peers/generate.py [OUTDIR]   (default: the directory of this file)
"""

import os
import sys

import numpy as np
import getfem as gf

gf.util_trace_level(0)
gf.util_warning_level(0)

CONTACT, CLAMPED = 1, 2
# Semismooth Newton on the Alart-Curnier formulation with full steps (GetFEM's default line search
# cycles on the standard-mass block at dt = 1e-4), relative residual 1e-10 (1e-12 is below
# round-off there). A step that does not converge stops the generator.
NEWTON = ("max_res", 1e-10, "max_iter", 100, "lsearch", "simplest")


def regions(m, axis, clamp):
    """Gamma_C: faces with outward normal n[axis] < -0.01 (GetFEM's rule); clamped: n[axis] > 0.01."""
    faces = m.outer_faces()
    normals = m.normal_of_faces(faces)
    m.set_region(CONTACT, faces[:, np.nonzero(normals[axis] < -0.01)[0]])
    if clamp:
        m.set_region(CLAMPED, faces[:, np.nonzero(normals[axis] > 0.01)[0]])


def forms(mim, mfu, stiffness, rho):
    """Mass and stiffness matrices (dense: these problems have at most a few hundred dofs)."""
    z = np.zeros(mfu.nbdof())
    asm = lambda expr: gf.asm_generic(mim, 2, expr, -1, "u", 1, mfu, z).full()
    return asm("%r*u.Test_u" % rho), asm(stiffness)


def contact_brick(md, m, mim, mfu, brick, obstacle, r):
    """The contact brick and a function giving sigma_N at the probe from the multiplier."""
    md.add_initialized_data("r", [r])
    if brick == "nodal":
        n_c = len(mfu.basic_dof_on_region(CONTACT)) // mfu.qdim()
        md.add_variable("lambda_n", n_c)
        md.add_nodal_contact_with_rigid_obstacle_brick(mim, "u", "lambda_n", "r", CONTACT, obstacle, 1)
    else:
        mfl = gf.MeshFem(m, 1)
        mfl.set_classical_fem(1)
        md.add_filtered_fem_variable("lambda_n", mfl, CONTACT)
        mfo = gf.MeshFem(m, 1)
        mfo.set_classical_fem(1)
        md.add_initialized_fem_data("obstacle", mfo, mfo.eval(obstacle))
        md.add_integral_contact_with_rigid_obstacle_brick(mim, "u", "lambda_n", "obstacle", "r", CONTACT, 1)
        return mfl
    return None


def probe_index(mf, point):
    """Position of the node `point` among the (first-component) dofs of mf on Gamma_C."""
    dofs = [d for d in sorted(mf.basic_dof_on_region(CONTACT)) if d % mf.qdim() == 0]
    nodes = mf.basic_dof_nodes()
    dist = [np.linalg.norm(nodes[:, d] - point) for d in dofs]
    return int(np.argmin(dist)), dofs[int(np.argmin(dist))]


def run(md, mfu, M, K, u0, v0, fixed, dt, t_end, every, probe, stress, path):
    """Newmark steps of GetFEM's model; writes the probe trajectory to `path`."""
    free = [i for i in range(len(u0)) if i not in fixed]
    a0 = np.zeros_like(u0)
    a0[free] = np.linalg.solve(M[np.ix_(free, free)], -(K @ u0)[free])
    for name, value in (("u", u0), ("Previous_u", u0), ("Previous_Dot_u", v0), ("Previous_Dot2_u", a0)):
        md.set_variable(name, value)
    md.set_time_step(dt)
    rows = [(0.0, u0[probe], 0.0, 0.5 * v0 @ M @ v0 + 0.5 * u0 @ K @ u0)]
    steps = int(round(t_end / dt))
    for s in range(1, steps + 1):
        md.set_time(s * dt)
        iterations, converged = md.solve(*NEWTON)
        if not converged:
            sys.exit("%s: Newton did not converge at step %d (%d iterations)" % (path, s, iterations))
        if s % every == 0:
            u, v = md.variable("u"), md.variable("Dot_u")
            rows.append((s * dt, u[probe], stress(md.variable("lambda_n")), 0.5 * v @ M @ v + 0.5 * u @ K @ u))
        md.shift_variables_for_time_integration()
    with open(path, "w") as f:
        f.write("t,u_contact,sigma_contact,energy\n")
        for row in rows:
            f.write(",".join("%.12e" % x for x in row) + "\n")
    print("wrote", path, len(rows), "rows")


def bar1d(n, out):
    """Doyen-Ern-Piperno bar: (0, 1), E = rho = 1, clamped at x = 1, u0 = (1 - x)/2, contact at
    x = 0 (integral brick, P1 multiplier: one value at the end point), dt = h/2, T = 3."""
    m = gf.Mesh("cartesian", np.linspace(0.0, 1.0, n + 1))
    regions(m, 0, clamp=True)
    mfu = gf.MeshFem(m, 1)
    mfu.set_classical_fem(1)
    mim = gf.MeshIm(m, gf.Integ("IM_GAUSS1D(4)"))
    md = gf.Model("real")
    md.add_fem_variable("u", mfu)
    md.add_linear_term(mim, "Grad_u.Grad_Test_u")
    md.add_Newmark_scheme("u", 0.5, 0.5)
    md.add_linear_term(mim, "Dot2_u.Test_u")
    md.add_Dirichlet_condition_with_simplification("u", CLAMPED)
    contact_brick(md, m, mim, mfu, "integral", "x", float(n))
    M, K = forms(mim, mfu, "Grad_u.Grad_Test_u", 1.0)
    x = mfu.basic_dof_nodes()[0]
    h = 1.0 / n
    run(md, mfu, M, K, 0.5 * (1.0 - x), 0.0 * x, [int(np.argmax(x))], h / 2, 3.0, 1,
        int(np.argmin(x)), lambda lam: lam[0], os.path.join(out, "bar1d_p1_n%d_integral.csv" % n))


def block_mesh(cells, n):
    """The unit square, n x n quadrilaterals or each split along its (0,0)-(1,1) diagonal."""
    x = np.linspace(0.0, 1.0, n + 1)
    if cells == "q1":
        return gf.Mesh("cartesian", x, x)
    m = gf.Mesh("empty", 2)
    gt = gf.GeoTrans("GT_PK(2,1)")
    for j in range(n):
        for i in range(n):
            p = lambda a, b: [x[i + a], x[j + b]]
            for tri in ((p(0, 0), p(1, 0), p(1, 1)), (p(0, 0), p(1, 1), p(0, 1))):
                m.add_convex(gt, np.array(tri).T)
    return m


def block2d(cells, dt, brick, out, n=10, t_end=2.0):
    """Block drop (shared/reference/block_drop.md): unit square, plane strain, E = 1, nu = 0.3,
    rho = 1, v0 = (0, -0.1), touching the plane y = 0; probe at the centre of the bottom face."""
    E, nu, rho = 1.0, 0.3, 1.0
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    m = block_mesh(cells, n)
    regions(m, 1, clamp=False)
    mfu = gf.MeshFem(m, 2)
    mfu.set_classical_fem(1)
    mim = gf.MeshIm(m, 4)
    stiffness = "%r*Div_u*Div_Test_u + 2*%r*Sym(Grad_u):Grad_Test_u" % (lam, mu)
    md = gf.Model("real")
    md.add_fem_variable("u", mfu)
    md.add_linear_term(mim, stiffness)
    md.add_Newmark_scheme("u", 0.5, 0.5)
    md.add_linear_term(mim, "%r*Dot2_u.Test_u" % rho)
    h = 1.0 / n
    mfl = contact_brick(md, m, mim, mfu, brick, "y", E / h)
    M, K = forms(mim, mfu, stiffness, rho)
    centre = np.array([0.5, 0.0])
    k, dof = probe_index(mfu, centre)
    if mfl is None:
        stress = lambda l: l[k] / h  # nodal force over the tributary length of an interior vertex
    else:
        kl, _ = probe_index(mfl, centre)
        stress = lambda l: l[kl]
    v0 = np.zeros(mfu.nbdof())
    v0[1::2] = -0.1
    name = "block2d_%s_dt%s_%s.csv" % (cells, "%.0e" % dt, brick)
    run(md, mfu, M, K, 0.0 * v0, v0, [], dt, t_end, max(1, int(round(1e-3 / dt))), dof + 1, stress,
        os.path.join(out, name))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    os.makedirs(out, exist_ok=True)
    for n in (20, 40, 80, 160):
        bar1d(n, out)
    for cells in ("q1", "p1"):
        for dt in (1e-3, 1e-4):
            for brick in ("nodal", "integral"):
                block2d(cells, dt, brick, out)


if __name__ == "__main__":
    main()
