#include "fem/caricature_field.hpp"

#include "core/errors.hpp"
#include "fem/harmonic.hpp"

#include <petscsf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace aries::fem {

using core::collectiveCheck;
using core::sharedLeafPoints;

namespace {

// Per local vertex, from the boundary faces around it: the cotangent Laplacian sum (3), the area-weighted outward
// normal (3) and the barycentric area (1), summed over the ranks sharing the vertex.
constexpr int kFaceSums = 7;

// `X`: the rest positions of the local vertices. The boundary faces (mesh/mesh.hpp's bodyBoundaryFacets; without
// overlap each lies on one rank) add their terms to their vertices; sumOverSharedVertices then totals every vertex.
PetscErrorCode accumulateBoundaryFaces(const Mesh &mesh, const std::vector<Eigen::Vector3d> &X,
                                       std::vector<double> *accOut) {
  PetscFunctionBeginUser;
  std::vector<PetscInt> faces;
  PetscCall(bodyBoundaryFacets(mesh, &faces));
  constexpr int K = kFaceSums;
  std::vector<double> &acc = *accOut;
  acc.assign(static_cast<size_t>(mesh.vEnd - mesh.vStart) * K, 0.0);
  std::vector<PetscInt> cv, fv;
  for (PetscInt f : faces) {
    const PetscInt *supp;
    PetscCall(DMPlexGetSupport(mesh.dm, f, &supp));
    PetscCall(closureVertices(mesh, supp[0], &cv));
    PetscCall(closureVertices(mesh, f, &fv));
    PetscInt apex = -1;
    for (PetscInt v : cv)
      if (std::find(fv.begin(), fv.end(), v) == fv.end()) apex = v;
    const std::array<PetscInt, 3> t = {fv[0], fv[1], fv[2]};
    Eigen::Vector3d n = (X[t[1]] - X[t[0]]).cross(X[t[2]] - X[t[0]]);
    const double area = 0.5 * n.norm();
    if (!(area > 0.0)) continue;
    n /= 2.0 * area;
    if (n.dot(X[t[0]] - X[apex]) < 0.0) n = -n;  // outward: away from the tet's fourth vertex
    for (int k = 0; k < 3; ++k) {
      const PetscInt i = t[(k + 1) % 3], j = t[(k + 2) % 3], o = t[k];  // corner o opposite edge (i, j)
      const Eigen::Vector3d ei = X[i] - X[o], ej = X[j] - X[o];
      const double cot = ei.dot(ej) / ei.cross(ej).norm();
      const Eigen::Vector3d d = 0.5 * cot * (X[j] - X[i]);
      for (int c = 0; c < 3; ++c) {
        acc[i * K + c] += d[c];
        acc[j * K + c] -= d[c];
      }
      for (int c = 0; c < 3; ++c) acc[o * K + 3 + c] += area * n[c];
      acc[o * K + 6] += area / 3.0;
    }
  }
  PetscCall(sumOverSharedVertices(mesh, K, &acc));

  PetscFunctionReturn(0);
}

// Per cell: the mean of its vertices' extended curvature and normal; the ratio c = -H / (mean curvature).
PetscErrorCode cellValues(const Mesh &mesh, const std::vector<double> &values, CaricatureField *field) {
  const MPI_Comm comm = PetscObjectComm((PetscObject)mesh.dm);
  const PetscInt nc = mesh.cEnd - mesh.cStart;
  std::vector<PetscInt> cv;
  PetscFunctionBeginUser;
  field->ratio.assign(nc, 0.0);
  field->normal.assign(nc, Eigen::Vector3d::UnitX());
  double lo = 1e300, hi = -1e300;
  PetscInt degenerate = 0;
  for (PetscInt c = 0; c < nc; ++c) {
    PetscCall(closureVertices(mesh, c + mesh.cStart, &cv));
    double H = 0.0;
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (PetscInt v : cv) {
      H += 0.25 * values[v * 4];
      n += 0.25 * Eigen::Vector3d(values[v * 4 + 1], values[v * 4 + 2], values[v * 4 + 3]);
    }
    if (n.norm() < 1e-8) {  // opposite normals cancel deep inside a thin part: no preferred direction
      if (mesh.cellOwned[c]) ++degenerate;
      continue;
    }
    field->normal[c] = n.normalized();
    field->ratio[c] = -H / field->meanCurvature;  // sign: see caricature_field.hpp
    lo = std::min(lo, field->ratio[c]);
    hi = std::max(hi, field->ratio[c]);
  }
  PetscCallMPI(MPI_Allreduce(&lo, &field->minRatio, 1, MPI_DOUBLE, MPI_MIN, comm));
  PetscCallMPI(MPI_Allreduce(&hi, &field->maxRatio, 1, MPI_DOUBLE, MPI_MAX, comm));
  PetscCallMPI(MPI_Allreduce(&degenerate, &field->degenerateNormals, 1, MPIU_INT, MPI_SUM, comm));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode computeCaricatureField(const Mesh &mesh, CaricatureField *field) {
  MPI_Comm comm;
  DM dm = mesh.dm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)dm, &comm));
  if (mesh.topoDim != 3)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "energy 'caricature' needs a tetrahedral mesh ('%s' has %d-dimensional cells)",
            mesh.filename.c_str(), (int)mesh.topoDim);
  const PetscInt nv = mesh.vEnd - mesh.vStart;

  std::vector<Eigen::Vector3d> X;  // rest positions of the local vertices
  PetscCall(vertexRestPositions(mesh, &X));

  std::vector<char> leaf;
  PetscInt pStart;
  PetscCall(sharedLeafPoints(dm, &leaf));
  PetscCall(DMPlexGetChart(dm, &pStart, nullptr));
  constexpr int K = kFaceSums;
  std::vector<double> acc;
  PetscCall(accumulateBoundaryFaces(mesh, X, &acc));

  // Surface vertex values; the object's mean curvature over owned surface vertices.
  HarmonicProblem h;
  h.verticesPerCell = 4;
  h.components = 4;  // H, n
  h.constrained.assign(nv, 0);
  h.values.assign(static_cast<size_t>(nv) * 4, 0.0);
  double loc[3] = {0, 0, 0}, glob[3];
  for (PetscInt v = 0; v < nv; ++v) {
    const double A = acc[v * K + 6];
    if (!(A > 0.0)) continue;
    Eigen::Vector3d n(acc[v * K + 3], acc[v * K + 4], acc[v * K + 5]);
    n.normalize();
    const Eigen::Vector3d lap = Eigen::Vector3d(acc[v * K], acc[v * K + 1], acc[v * K + 2]) / A;  // Delta x
    const double H = -0.5 * lap.dot(n);
    h.constrained[v] = 1;
    h.values[v * 4] = H;
    for (int c = 0; c < 3; ++c) h.values[v * 4 + 1 + c] = n[c];
    if (!leaf[v + mesh.vStart - pStart]) {
      loc[0] += H * A;
      loc[1] += A;
      loc[2] += 1.0;
    }
  }
  PetscCallMPI(MPI_Allreduce(loc, glob, 3, MPI_DOUBLE, MPI_SUM, comm));
  field->surfaceVertices = static_cast<PetscInt>(glob[2]);
  field->meanCurvature = glob[1] > 0.0 ? glob[0] / glob[1] : 0.0;
  if (!(field->meanCurvature > 0.0)) {
    std::ostringstream o;
    o << "energy 'caricature': the boundary surface of '" << mesh.filename << "' has mean curvature "
      << field->meanCurvature << " (area " << glob[1] << "); the curvature ratio c needs a closed surface with "
      << "positive mean curvature";
    PetscCall(collectiveCheck(comm, true, o.str()));
  }

  // Interior: harmonic extension with the P1 (cotangent) Laplacian of the tets, Ke = V G G^T.
  h.cellStiffness = [&](PetscInt, const PetscInt *verts, double *Ke) {
    Eigen::Matrix3d Dm;
    for (int k = 0; k < 3; ++k) Dm.col(k) = X[verts[k + 1]] - X[verts[0]];
    const double vol = std::abs(Dm.determinant()) / 6.0;
    const Eigen::Matrix3d B = Dm.inverse();  // rows: gradients of the barycentric functions 1..3
    Eigen::Matrix<double, 4, 3> G;
    G.row(0) = -B.colwise().sum();
    G.bottomRows<3>() = B;
    Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> K(Ke);
    K = vol * G * G.transpose();
  };
  h.prefix = "caricature_";
  h.what = "caricature curvature propagation";
  PetscCall(harmonicExtension(mesh, &h));

  PetscCall(cellValues(mesh, h.values, field));
  PetscFunctionReturn(0);
}

namespace {

template <int C>
class CaricatureSource final : public CellFieldSource<C> {
 public:
  PetscErrorCode setup(const Mesh &mesh, const std::vector<char> &applies,
                       std::vector<energies::CellData<C>> *data) override {
    PetscFunctionBeginUser;
    if constexpr (C == 3) {
      for (const char *opt : {"-curvature", "-fiber", "-fiber_file"}) {
        PetscBool given = PETSC_FALSE;
        PetscCall(PetscOptionsHasName(nullptr, nullptr, opt, &given));
        if (given)
          SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                  "option %s does not apply to energy 'caricature' in the solver: each element's curvature ratio c and "
                  "normal n come from the mesh surface (paper Sec. 6); %s is for aries-matpoint",
                  opt, std::string(opt) == "-fiber_file" ? "a uniform -fiber" : opt);
      }
      CaricatureField f;
      PetscCall(computeCaricatureField(mesh, &f));
      for (size_t c = 0; c < applies.size(); ++c) {
        if (!applies[c]) continue;
        (*data)[c].a = f.normal[c];
        (*data)[c].curvature = f.ratio[c];
      }
      PetscCall(PetscPrintf(PetscObjectComm((PetscObject)mesh.dm),
                            "aries: caricature field: %d surface vertices, mean curvature %.6g, curvature ratio c in "
                            "[%.4g, %.4g]%s\n",
                            (int)f.surfaceVertices, f.meanCurvature, f.minRatio, f.maxRatio,
                            f.degenerateNormals ? " (some cells without a normal: c = 0)" : ""));
    } else {
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "energy 'caricature' needs a tetrahedral mesh");
    }
    PetscFunctionReturn(0);
  }
  std::unique_ptr<CellFieldSource<C>> clone() const override { return std::make_unique<CaricatureSource<C>>(*this); }
};

}  // namespace

template <int C>
std::unique_ptr<CellFieldSource<C>> makeCaricatureSource() {
  return std::make_unique<CaricatureSource<C>>();
}
template std::unique_ptr<CellFieldSource<2>> makeCaricatureSource<2>();
template std::unique_ptr<CellFieldSource<3>> makeCaricatureSource<3>();

}  // namespace aries::fem
