#!/usr/bin/python3
"""GetFEM's static sphere: the finite-body coefficient c of dyncontact's `study::finite_body`,
computed by another code on another discretisation (see README.md beside this file).

The ball of radius R = 1 centred at (0, 0, 1) (E = 1, nu = 0.3) touches the rigid plane z = 0 at the
origin. Under a uniform body force of total F towards the plane (the quasi-static impact's inertia)
it comes to rest on the plane, and its centre of mass approaches the plane by

    delta(F) = (F/k)^(2/3) - c F / (E* R),   k = (4/3) E* sqrt(R),   E* = E / (1 - nu^2),

Hertz's half-space approach less a finite-body term. This script measures c at F = F_max / 2 and
F_max of hertz3d (v = 0.01) on Gmsh meshes of 10-node tetrahedra graded towards the pole (size hp
within 0.3 of it, 0.25 beyond 1.2), P2 displacement, GetFEM's nodal contact brick on the lower cap
(every P2 node of the faces with n_z < -0.5), solved by its Newton method.

Equilibrium: K U = F_body + contact has the rigid modes of a free ball, so every solve adds the
proximal term eps (U - U_prev) (eps = 1e-3, then 1e-7) and repeats from the last solution until
the approach changes by less than 1e-11 of itself: the fixed point is the static solution, which
does not depend on eps.

Output: sphere_static.csv with hp, dofs, volume, force, approach, approach_hertz, coefficient.

Needs Gmsh (apt-get install -y gmsh) and GetFEM (apt-get install -y python3-getfem).
Usage: /usr/bin/python3 golden/peers/finite_body.py [OUTDIR]   (default: the directory of this file)
"""

import os
import subprocess
import sys
import tempfile

import numpy as np
import getfem as gf

gf.util_trace_level(0)
gf.util_warning_level(0)

E, NU = 1.0, 0.3
LAM, MU = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
E_STAR = E / (1 - NU * NU)
K = 4.0 / 3.0 * E_STAR
F_MAX = 1.2524e-2  # hertz3d's Hertz peak force (shared/reference/hertz_impact.md)
LOADS = (0.5 * F_MAX, F_MAX)
POLE_SIZES = (0.04, 0.03, 0.025)
CONTACT = 1

GEO = """SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 1, 1};
Point(100) = {0, 0, 0};
Field[1] = Distance;
Field[1].PointsList = {100};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = %r;
Field[2].SizeMax = 0.25;
Field[2].DistMin = 0.3;
Field[2].DistMax = 1.2;
Background Field = 2;
Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.ElementOrder = 2;
Physical Volume("body") = {1};
"""


def mesh(hp, work):
    """The graded ball of 10-node tetrahedra (MSH 2.2, which GetFEM 5.4 reads)."""
    geo, msh = os.path.join(work, "ball.geo"), os.path.join(work, "ball.msh")
    with open(geo, "w") as f:
        f.write(GEO % hp)
    subprocess.run(["gmsh", "-3", geo, "-format", "msh22", "-o", msh], check=True,
                   stdout=subprocess.DEVNULL)
    return gf.Mesh("import", "gmsh", msh)


def static_points(m):
    """(dofs, volume, [(F, delta)]) of the ball at rest under each load."""
    faces = m.outer_faces()
    normals = m.normal_of_faces(faces)
    m.set_region(CONTACT, faces[:, np.nonzero(normals[2] < -0.5)[0]])
    mfu = gf.MeshFem(m, 3)
    mfu.set_classical_fem(2)
    mim = gf.MeshIm(m, 4)
    volume = gf.asm_generic(mim, 0, "1", -1)
    md = gf.Model("real")
    md.add_fem_variable("u", mfu)
    md.add_linear_term(mim, "%r*Div_u*Div_Test_u + 2*%r*Sym(Grad_u):Grad_Test_u" % (LAM, MU))
    md.add_initialized_fem_data("u_prev", mfu, np.zeros(mfu.nbdof()))
    md.add_initialized_data("eps", [1e-3])
    md.add_linear_term(mim, "eps*u.Test_u")
    md.add_source_term(mim, "eps*u_prev.Test_u")
    md.add_initialized_data("b", [0.0, 0.0, 0.0])
    md.add_source_term_brick(mim, "u", "b")
    md.add_variable("lambda_n", len(mfu.basic_dof_on_region(CONTACT)) // 3)
    md.add_initialized_data("r", [E / 0.02])
    md.add_nodal_contact_with_rigid_obstacle_brick(mim, "u", "lambda_n", "r", CONTACT, "z", 1)
    points = []
    for force in LOADS:
        md.set_variable("b", [0.0, 0.0, -force / volume])
        last = 0.0
        for outer in range(60):
            md.set_variable("eps", [1e-3 if outer < 2 else 1e-7])
            iterations, converged = md.solve("max_res", 1e-11, "max_iter", 100, "lsearch", "simplest")
            if not converged:
                sys.exit("Newton did not converge (F = %g, outer iteration %d)" % (force, outer))
            md.set_variable("u_prev", md.variable("u"))
            delta = -gf.asm_generic(mim, 0, "u(3)", -1, md) / volume
            if abs(delta - last) <= 1e-11 * abs(delta):
                break
            last = delta
        else:
            sys.exit("no static equilibrium (F = %g)" % force)
        points.append((force, delta))
    return mfu.nbdof(), volume, points


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    os.makedirs(out, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for hp in POLE_SIZES:
            dofs, volume, points = static_points(mesh(hp, work))
            for force, delta in points:
                hertz = (force / K) ** (2.0 / 3.0)
                c = (hertz - delta) * E_STAR / force
                rows.append((hp, dofs, volume, force, delta, hertz, c))
                print("hp %g, %d dofs: F %.4e, delta %.6e, Hertz %.6e, c %.4f"
                      % (hp, dofs, force, delta, hertz, c), flush=True)
    path = os.path.join(out, "sphere_static.csv")
    with open(path, "w") as f:
        f.write("hp,dofs,volume,force,approach,approach_hertz,coefficient\n")
        for r in rows:
            f.write("%g,%d,%s\n" % (r[0], r[1], ",".join("%.12e" % x for x in r[2:])))
    print("wrote", path)


if __name__ == "__main__":
    main()
