#!/usr/bin/python3
"""The peer side of bench/peer.py: the compressed box in DOLFINx 0.5.2 (Debian's python3-dolfinx-real, on the same
PETSc 3.18 and Open MPI as aries), run under mpiexec by bench/peer.py. Not a test: a measurement.

    mpiexec -n 2 /usr/bin/python3 bench/peer_dolfinx.py MESH.msh OUT.json [--pc gamg|jacobi] [--disp 0.2]
        [--E 1e4] [--nu 0.3] [--ksp-rtol 1e-8] [--snes-rtol 1e-8] [--npz OUT.npz]

The problem is aries' (bench/peer.py): the gmsh mesh's physical surface 1 (bottom) held, surface 2 (top) moved by
(0, 0, -disp), every component of both prescribed, one static load step. The material is the compressible
neo-Hookean solid psi = mu/2 (I_C - 3) - mu ln J + lambda/2 (ln J)^2 with aries' E and nu (at small strain the same
linear elasticity as aries' iarap, mu |F - R|^2 + lambda/2 (J - 1)^2; at finite strain they differ, and bench/peer.py
reports by how much). The Newton solver is PETSc's SNES newtonls (its default bt line search on the residual norm,
PETSc's default tolerances unless given) with the Dirichlet increment lifted into the first solve, as every DOLFINx
solver does: the residual is assembled with apply_lifting(b, [J], [bcs], x0=[u], scale=-1) and set_bc(b, bcs, u, -1).
The linear solver is CG with GAMG (smoothed aggregation, the rigid-body near-nullspace, aries' rule's settings:
threshold 0, one Chebyshev/Jacobi smoothing step per level) or with Jacobi, at -ksp_rtol.

Writes OUT.json: Newton iterations, linear solves and Krylov iterations, the SNES reason, the nonlinear solve's wall
time (timed apart from the mesh input and the forms' JIT compile, which is cached in ~/.cache/fenics), the setup time,
the last Newton step's inf-norm and the final residual; with --npz the rest coordinates and displacements of every
vertex (gathered on rank 0) for the distance to aries' solution.
"""

import argparse
import json
import sys
import time

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import gmsh
import ufl
from dolfinx import fem
from dolfinx.fem import petsc as fem_petsc
from dolfinx.io import gmshio

BOTTOM, TOP = 1, 2  # physical surface tags of meshes/tools/build.py's box


def parse():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("mesh")
    ap.add_argument("out")
    ap.add_argument("--pc", choices=("gamg", "jacobi"), default="gamg")
    ap.add_argument("--disp", type=float, default=0.2)
    ap.add_argument("--E", type=float, default=1e4)
    ap.add_argument("--nu", type=float, default=0.3)
    ap.add_argument("--ksp-rtol", type=float, default=1e-8)
    ap.add_argument("--snes-rtol", type=float, default=1e-8)
    ap.add_argument("--npz", default=None)
    return ap.parse_args()


def read_mesh(path, comm):
    # DOLFINx 0.5.2's gmshio.read_from_msh is broken; read with the gmsh module on rank 0 and hand the model over.
    if comm.rank == 0:
        gmsh.initialize()
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(path)
    mesh, _, facets = gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=3)
    if comm.rank == 0:
        gmsh.finalize()
    return mesh, facets


def rigid_body_modes(V):
    """The six rigid-body modes of the owned dofs' coordinates (PETSc orthonormalizes them)."""
    owned = V.dofmap.index_map.size_local
    x = V.tabulate_dof_coordinates()[:owned]
    coords = PETSc.Vec().createMPI((3 * owned, PETSc.DECIDE), bsize=3, comm=V.mesh.comm)
    coords.setArray(x.reshape(-1))
    return PETSc.NullSpace().createRigidBody(coords)


class Problem:
    """SNES callbacks: the residual with the Dirichlet increment lifted, the Jacobian with identity rows at the
    Dirichlet dofs."""

    def __init__(self, residual, jacobian, u, bcs):
        self.L, self.a, self.u, self.bcs = fem.form(residual), fem.form(jacobian), u, bcs
        self.assembly = 0.0

    def F(self, snes, x, b):
        t = time.perf_counter()
        x.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        x.copy(self.u.vector)
        self.u.vector.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        with b.localForm() as bl:
            bl.set(0.0)
        fem_petsc.assemble_vector(b, self.L)
        fem_petsc.apply_lifting(b, [self.a], bcs=[self.bcs], x0=[x], scale=-1.0)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fem_petsc.set_bc(b, self.bcs, x, -1.0)
        self.assembly += time.perf_counter() - t

    def J(self, snes, x, A, P):
        t = time.perf_counter()
        A.zeroEntries()
        fem_petsc.assemble_matrix(A, self.a, bcs=self.bcs)
        A.assemble()
        self.assembly += time.perf_counter() - t


def main():
    args = parse()
    comm = MPI.COMM_WORLD
    t_start = MPI.Wtime()
    mesh, facets = read_mesh(args.mesh, comm)
    t_mesh = MPI.Wtime() - t_start
    V = fem.VectorFunctionSpace(mesh, ("Lagrange", 1))
    u, v, du = fem.Function(V), ufl.TestFunction(V), ufl.TrialFunction(V)

    fdim = mesh.topology.dim - 1
    held = fem.locate_dofs_topological(V, fdim, facets.indices[facets.values == BOTTOM])
    moved = fem.locate_dofs_topological(V, fdim, facets.indices[facets.values == TOP])
    bcs = [fem.dirichletbc(np.zeros(3, dtype=PETSc.ScalarType), held, V),
           fem.dirichletbc(np.array([0.0, 0.0, -args.disp], dtype=PETSc.ScalarType), moved, V)]

    mu = args.E / (2.0 * (1.0 + args.nu))
    lmbda = args.E * args.nu / ((1.0 + args.nu) * (1.0 - 2.0 * args.nu))
    F = ufl.variable(ufl.Identity(3) + ufl.grad(u))
    J = ufl.det(F)
    psi = mu / 2 * (ufl.tr(F.T * F) - 3) - mu * ufl.ln(J) + lmbda / 2 * ufl.ln(J) ** 2
    energy = psi * ufl.dx
    residual = ufl.derivative(energy, u, v)
    jacobian = ufl.derivative(residual, u, du)
    problem = Problem(residual, jacobian, u, bcs)  # fem.form JIT-compiles (cached after the first run)

    b = fem_petsc.create_vector(problem.L)
    A = fem_petsc.create_matrix(problem.a)
    A.setNearNullSpace(rigid_body_modes(V))
    x = u.vector.copy()
    x.set(0.0)

    snes = PETSc.SNES().create(comm)
    snes.setType("newtonls")
    snes.setFunction(problem.F, b)
    snes.setJacobian(problem.J, A, A)
    snes.setTolerances(rtol=args.snes_rtol, max_it=50)
    ksp = snes.getKSP()
    ksp.setType("cg")
    ksp.setTolerances(rtol=args.ksp_rtol, max_it=10000)
    pc = ksp.getPC()
    opts = PETSc.Options()
    if args.pc == "gamg":  # aries' rule (lib/solver/newton.cpp): threshold 0, one smoothing step per level
        pc.setType("gamg")
        opts["pc_gamg_type"] = "agg"
        opts["pc_gamg_agg_nsmooths"] = 1
        opts["pc_gamg_threshold"] = 0.0
        opts["pc_gamg_reuse_interpolation"] = "true"
        opts["pc_gamg_use_sa_esteig"] = "false"
        opts["mg_levels_ksp_type"] = "chebyshev"
        opts["mg_levels_pc_type"] = "jacobi"
        opts["mg_levels_ksp_max_it"] = 1
    else:
        pc.setType("jacobi")
    snes.setFromOptions()
    ksp.setFromOptions()

    steps = []  # |dx|_inf of each Newton update

    def monitor(s, it, fnorm):
        if it > 0:
            steps.append(s.getSolutionUpdate().norm(PETSc.NormType.INFINITY))

    snes.setMonitor(monitor)
    comm.Barrier()
    t_setup = MPI.Wtime() - t_start
    t0 = MPI.Wtime()
    snes.solve(None, x)
    comm.Barrier()
    t_solve = MPI.Wtime() - t0

    x.copy(u.vector)
    u.x.scatter_forward()
    b_final = b.copy()
    problem.F(snes, x, b_final)
    # the force the moved support exerts: the internal force summed over its dofs (the residual without the bcs)
    internal = fem_petsc.assemble_vector(problem.L)
    internal.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    owned_moved = moved[moved < V.dofmap.index_map.size_local]
    local_force = internal.array_r.reshape(-1, 3)[owned_moved].sum(axis=0)
    force = comm.allreduce(local_force, op=MPI.SUM)
    result = {
        "code": "DOLFINx %s (ufl %s, petsc4py %s)" % (dolfinx.__version__, ufl.__version__, PETSc.Sys.getVersion()),
        "ranks": comm.size, "pc": args.pc, "ksp_rtol": args.ksp_rtol, "snes_rtol": args.snes_rtol,
        "material": "compressible neo-Hookean", "E": args.E, "nu": args.nu, "disp": args.disp,
        "vertices": mesh.geometry.index_map().size_global,
        "cells": mesh.topology.index_map(3).size_global,
        "dofs": V.dofmap.index_map.size_global * 3,
        "reason": int(snes.getConvergedReason()),
        "newton": snes.getIterationNumber(),
        "linear_solves": snes.getIterationNumber(),  # newtonls: one linear solve per update
        "krylov": snes.getLinearSolveIterations(),
        "step_inf": steps,
        "residual": b_final.norm(),
        "top_force": [float(f) for f in force],
        "mesh_s": t_mesh, "setup_s": t_setup, "solve_s": t_solve, "assembly_s": problem.assembly,
        "total_s": MPI.Wtime() - t_start,
    }

    # every vertex's rest position and displacement, gathered on rank 0
    owned = V.dofmap.index_map.size_local
    X = V.tabulate_dof_coordinates()[:owned]
    U = u.x.array[:3 * owned].reshape(-1, 3)
    Xs, Us = comm.gather(X, root=0), comm.gather(U, root=0)
    if comm.rank == 0:
        if args.npz:
            np.savez(args.npz, rest=np.vstack(Xs), disp=np.vstack(Us))
        with open(args.out, "w") as f:
            json.dump(result, f, indent=1)
            f.write("\n")
        print(json.dumps(result))
    return 0 if result["reason"] > 0 else 3


if __name__ == "__main__":
    sys.exit(main())
