#include "preprocess/tutte.hpp"

#include "core/errors.hpp"
#include "fem/harmonic.hpp"

#include <petscsf.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace aries::fem {

using core::collectiveCheck;
using core::sharedLeafPoints;
using core::gatherOnRoot;

namespace {

// Boundary edges (owned, one triangle) as (natural v0, natural v1, length) triples.
PetscErrorCode boundaryEdges(const Mesh &mesh, std::vector<double> *mine) {
  DM dm = mesh.dm;
  PetscInt pStart, eStart, eEnd;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetChart(dm, &pStart, nullptr));
  PetscCall(DMPlexGetDepthStratum(dm, 1, &eStart, &eEnd));
  std::vector<char> leaf;
  PetscCall(sharedLeafPoints(dm, &leaf));
  std::vector<Eigen::Vector3d> rest;
  PetscCall(vertexRestPositions(mesh, &rest));
  for (PetscInt e = eStart; e < eEnd; ++e) {
    if (leaf[e - pStart]) continue;
    PetscInt nsupp;
    PetscCall(DMPlexGetSupportSize(dm, e, &nsupp));
    if (nsupp != 1) continue;
    const PetscInt *cone, *supp;
    PetscCall(DMPlexGetCone(dm, e, &cone));
    PetscCall(DMPlexGetSupport(dm, e, &supp));
    // Direct the edge as it runs in its triangle's vertex cycle, so the loop follows the mesh orientation and the
    // circle is traversed counterclockwise in the elements' frames (no mirrored map).
    PetscInt ncl, *closure = nullptr, cv[3], k = 0;
    PetscCall(DMPlexGetTransitiveClosure(dm, supp[0], PETSC_TRUE, &ncl, &closure));
    for (PetscInt i = 0; i < ncl && k < 3; ++i)
      if (closure[2 * i] >= mesh.vStart && closure[2 * i] < mesh.vEnd) cv[k++] = closure[2 * i];
    PetscCall(DMPlexRestoreTransitiveClosure(dm, supp[0], PETSC_TRUE, &ncl, &closure));
    PetscInt from = cone[0], to = cone[1];
    for (int i = 0; i < 3; ++i)
      if (cv[i] == cone[1] && cv[(i + 1) % 3] == cone[0]) std::swap(from, to);
    const PetscInt a = mesh.naturalVertex[from - mesh.vStart], b = mesh.naturalVertex[to - mesh.vStart];
    mine->insert(mine->end(), {(double)a, (double)b, (rest[from - mesh.vStart] - rest[to - mesh.vStart]).norm()});
  }
  PetscFunctionReturn(0);
}

// Rank 0: walks the boundary loop and places it on a circle by arc length (or says why the mesh is not a disk).
void placeBoundaryLoop(const Mesh &mesh, const std::vector<double> &all, std::vector<double> *placedOut,
                       std::string *errorOut) {
  std::vector<double> &placed = *placedOut;
  std::string &error = *errorOut;
  std::map<PetscInt, std::pair<PetscInt, double>> next;  // directed boundary edge a -> (b, length)
  std::map<PetscInt, int> outDeg, inDeg;
  for (size_t i = 0; i < all.size(); i += 3) {
    const auto a = static_cast<PetscInt>(all[i]), b = static_cast<PetscInt>(all[i + 1]);
    next[a] = {b, all[i + 2]};
    outDeg[a]++;
    inDeg[b]++;
  }
  for (const auto &kv : outDeg)
    if ((kv.second != 1 || inDeg[kv.first] != 1) && error.empty()) {
      std::ostringstream o;
      o << "mesh '" << mesh.filename << "' is not a disk: boundary vertex " << kv.first
        << " starts or ends more than one boundary edge (-initial tutte and -uv_map need one simple boundary loop)";
      error = o.str();
    }
  if (next.empty() && error.empty())
    error = "mesh '" + mesh.filename + "' has no boundary: -initial tutte needs a disk-topology surface";
  if (error.empty()) {
    std::vector<std::pair<PetscInt, double>> loop;  // (vertex, arc length at it)
    PetscInt cur = next.begin()->first;
    double s = 0.0;
    do {
      loop.push_back({cur, s});
      s += next[cur].second;
      cur = next[cur].first;
    } while (cur != loop.front().first && loop.size() <= next.size() && next.count(cur));
    if (loop.size() != next.size() || cur != loop.front().first) {
      std::ostringstream o;
      o << "mesh '" << mesh.filename << "' has " << next.size() << " boundary vertices but its first boundary loop "
        << "has " << loop.size() << ": more than one loop (holes); -initial tutte needs a disk";
      error = o.str();
    }
    const double radius = s / (2.0 * M_PI);
    for (const auto &[v, sv] : loop) {
      const double t = 2.0 * M_PI * sv / s;
      placed.insert(placed.end(), {(double)v, radius * std::cos(t), radius * std::sin(t)});
    }
  }
}

}  // namespace

PetscErrorCode tutteEmbedding(const Mesh &mesh, std::vector<Eigen::Vector2d> *uv) {
  MPI_Comm comm;
  PetscMPIInt rank;
  DM dm = mesh.dm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)dm, &comm));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (mesh.topoDim != 2)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "-initial tutte needs a triangle surface mesh ('%s' has %d-dimensional cells)",
            mesh.filename.c_str(), (int)mesh.topoDim);
  std::vector<double> mine, all;
  PetscCall(boundaryEdges(mesh, &mine));
  PetscCall(gatherOnRoot(comm, mine, &all));

  std::vector<double> placed;  // (natural id, u, v) triples
  std::string error;
  if (rank == 0) placeBoundaryLoop(mesh, all, &placed, &error);
  PetscCall(collectiveCheck(comm, !error.empty(), error));
  int np = static_cast<int>(placed.size());
  PetscCallMPI(MPI_Bcast(&np, 1, MPI_INT, 0, comm));
  placed.resize(np);
  PetscCallMPI(MPI_Bcast(placed.data(), np, MPI_DOUBLE, 0, comm));
  std::map<PetscInt, Eigen::Vector2d> boundaryUV;
  for (int i = 0; i < np; i += 3) boundaryUV[static_cast<PetscInt>(placed[i])] = {placed[i + 1], placed[i + 2]};

  // Interior vertices: the average of their neighbours (every triangle edge weight 1), boundary on the circle.
  HarmonicProblem h;
  h.verticesPerCell = 3;
  h.cellStiffness = [](PetscInt, const PetscInt *, double *Ke) {
    const double K[9] = {2, -1, -1, -1, 2, -1, -1, -1, 2};
    std::copy(K, K + 9, Ke);
  };
  h.components = 2;
  h.constrained.assign(mesh.vEnd - mesh.vStart, 0);
  h.values.assign(2 * static_cast<size_t>(mesh.vEnd - mesh.vStart), 0.0);
  for (PetscInt v = 0; v < mesh.vEnd - mesh.vStart; ++v) {
    const auto it = boundaryUV.find(mesh.naturalVertex[v]);
    if (it == boundaryUV.end()) continue;
    h.constrained[v] = 1;
    h.values[2 * v] = it->second[0];
    h.values[2 * v + 1] = it->second[1];
  }
  h.prefix = "tutte_";
  h.what = "Tutte embedding";
  PetscCall(harmonicExtension(mesh, &h));
  uv->resize(mesh.vEnd - mesh.vStart);
  for (PetscInt v = 0; v < mesh.vEnd - mesh.vStart; ++v) (*uv)[v] = Eigen::Vector2d(h.values[2 * v], h.values[2 * v + 1]);
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
