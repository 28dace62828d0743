#include "mesh/mesh_transfer.hpp"

#include "core/errors.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

namespace aries::fem {

namespace {

constexpr double kInsideTol = 1e-10;   // barycentric coordinates >= -kInsideTol count as inside
constexpr double kNotFound = 1e300;    // the distance of "no candidate cell on this rank"

// One local source cell, its corners ordered by natural vertex id, so that its barycentric coordinates are computed
// with the same operations on every rank that holds it.
struct SourceCell {
  std::array<PetscInt, 4> corner;  // local vertex indices
  Eigen::Vector3d origin;          // rest position of corner 0
  Eigen::Matrix3d inverse;         // of [X1 - X0, X2 - X0, X3 - X0]
  Eigen::Vector3d lo, hi;          // bounding box
  PetscInt natural;
  PetscInt local;                  // c - cStart
};

struct Located {
  double distance = kNotFound;  // 0 inside; else from the point to the cell's clamped barycentric point
  PetscInt natural = -1, cell = -1;
  bool better(const Located &o) const {
    return distance < o.distance || (distance == o.distance && natural < o.natural);
  }
};

std::array<double, 4> barycentric(const SourceCell &c, const Eigen::Vector3d &p) {
  const Eigen::Vector3d l = c.inverse * (p - c.origin);
  return {1.0 - l[0] - l[1] - l[2], l[0], l[1], l[2]};
}

// The cells of one rank in a uniform grid of bins (each cell in every bin its box overlaps).
class CellGrid {
 public:
  CellGrid(const std::vector<SourceCell> &cells, const std::vector<Eigen::Vector3d> &rest, double pad)
      : cells_(cells), rest_(rest) {
    lo_.setConstant(std::numeric_limits<double>::max());
    hi_.setConstant(-std::numeric_limits<double>::max());
    for (const auto &c : cells) {
      lo_ = lo_.cwiseMin(c.lo);
      hi_ = hi_.cwiseMax(c.hi);
    }
    const int n = std::max(1, static_cast<int>(std::cbrt(cells.size() / 2.0)));
    for (int d = 0; d < 3; ++d) {
      dims_[d] = cells.empty() ? 1 : n;
      width_[d] = cells.empty() ? 1.0 : std::max((hi_[d] - lo_[d]) / n, 1e-300);
    }
    bins_.assign(static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2], {});
    for (size_t k = 0; k < cells.size(); ++k) {
      std::array<int, 3> a, b;
      range(cells[k].lo.array() - pad, cells[k].hi.array() + pad, &a, &b);  // (always inside the grid)
      for (int i = a[0]; i <= b[0]; ++i)
        for (int j = a[1]; j <= b[1]; ++j)
          for (int l = a[2]; l <= b[2]; ++l) bins_[index(i, j, l)].push_back(static_cast<PetscInt>(k));
    }
    seen_.assign(cells.size(), -1);
  }

  // The best cell for p: among the cells containing it the one of smallest natural id; else, among the cells whose box
  // is within `margin` of p, the nearest (by the distance to its clamped barycentric point), ties by natural id.
  Located locate(const Eigen::Vector3d &p, double margin, long query) {
    Located best;
    if (cells_.empty()) return best;
    for (int pass = 0; pass < 2 && best.distance > 0.0; ++pass) {
      const double r = pass == 0 ? 0.0 : margin;
      std::array<int, 3> a, b;
      if (!range(p.array() - r, p.array() + r, &a, &b)) continue;
      for (int i = a[0]; i <= b[0]; ++i)
        for (int j = a[1]; j <= b[1]; ++j)
          for (int l = a[2]; l <= b[2]; ++l)
            for (PetscInt k : bins_[index(i, j, l)]) {
              if (seen_[k] == 2 * query + pass) continue;
              seen_[k] = 2 * query + pass;
              const SourceCell &c = cells_[k];
              if (pass == 1 && boxDistance(c, p) > margin) continue;
              const Located cand = judge(c, k, p);
              if (pass == 0 && cand.distance > 0.0) continue;
              if (cand.better(best)) best = cand;
            }
    }
    return best;
  }

 private:
  Located judge(const SourceCell &c, PetscInt k, const Eigen::Vector3d &p) const {
    Located r;
    r.natural = c.natural;
    r.cell = k;
    const auto l = barycentric(c, p);
    if (*std::min_element(l.begin(), l.end()) >= -kInsideTol) {
      r.distance = 0.0;
      return r;
    }
    double sum = 0.0;
    std::array<double, 4> clamped;
    for (int i = 0; i < 4; ++i) sum += clamped[i] = std::max(l[i], 0.0);
    Eigen::Vector3d q = Eigen::Vector3d::Zero();
    for (int i = 0; i < 4; ++i) q += clamped[i] / sum * rest_[c.corner[i]];
    r.distance = (p - q).norm();
    return r;
  }
  static double boxDistance(const SourceCell &c, const Eigen::Vector3d &p) {
    return (p.cwiseMax(c.lo).cwiseMin(c.hi) - p).norm();
  }
  // The bins overlapped by [lo, hi]; false if none.
  bool range(const Eigen::Vector3d &lo, const Eigen::Vector3d &hi, std::array<int, 3> *a, std::array<int, 3> *b) const {
    for (int d = 0; d < 3; ++d) {
      if (hi[d] < lo_[d] || lo[d] > hi_[d]) return false;
      (*a)[d] = std::clamp(static_cast<int>(std::floor((lo[d] - lo_[d]) / width_[d])), 0, dims_[d] - 1);
      (*b)[d] = std::clamp(static_cast<int>(std::floor((hi[d] - lo_[d]) / width_[d])), 0, dims_[d] - 1);
    }
    return true;
  }
  size_t index(int i, int j, int l) const {
    return (static_cast<size_t>(i) * dims_[1] + j) * dims_[2] + l;
  }

  const std::vector<SourceCell> &cells_;
  const std::vector<Eigen::Vector3d> &rest_;
  Eigen::Vector3d lo_, hi_, width_;
  std::array<int, 3> dims_;
  std::vector<std::vector<PetscInt>> bins_;
  std::vector<long> seen_;
};

PetscErrorCode sourceCells(const Mesh &mesh, const std::vector<Eigen::Vector3d> &rest, std::vector<SourceCell> *cells,
                           double *diameter) {
  PetscFunctionBeginUser;
  // One entry per DM cell below: a quadratic mesh's DM cells are not its elements (nested iteration refuses them).
  PetscCheck(!mesh.quadratic, PETSC_COMM_SELF, PETSC_ERR_SUP, "locating points in a quadratic mesh is not supported");
  std::vector<PetscInt> verts;
  *diameter = 0.0;
  for (PetscInt c = mesh.cStart; c < mesh.cEnd; ++c) {
    if (!mesh.cellOwned[c - mesh.cStart]) continue;
    PetscCall(closureVertices(mesh, c, &verts));
    PetscCheck(verts.size() == 4, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "nested iteration: mesh '%s' is not a tetrahedral mesh (a cell has %d vertices)", mesh.filename.c_str(),
               (int)verts.size());
    std::sort(verts.begin(), verts.end(),
              [&](PetscInt a, PetscInt b) { return mesh.naturalVertex[a] < mesh.naturalVertex[b]; });
    SourceCell s;
    std::copy(verts.begin(), verts.end(), s.corner.begin());
    s.origin = rest[s.corner[0]];
    Eigen::Matrix3d D;
    for (int i = 0; i < 3; ++i) D.col(i) = rest[s.corner[i + 1]] - s.origin;
    s.inverse = D.inverse();
    s.lo = s.hi = s.origin;
    for (int i = 1; i < 4; ++i) {
      s.lo = s.lo.cwiseMin(rest[s.corner[i]]);
      s.hi = s.hi.cwiseMax(rest[s.corner[i]]);
    }
    s.natural = mesh.naturalCell[c - mesh.cStart];
    s.local = c - mesh.cStart;
    *diameter = std::max(*diameter, (s.hi - s.lo).norm());
    cells->push_back(s);
  }
  PetscFunctionReturn(0);
}

// Where points lie in a source mesh: for each point (any rank's list) the rank whose cell was chosen, that cell's index
// in the rank's SourceCell list, and its distance (0 inside). Collective.
struct CellSearch {
  std::vector<Eigen::Vector3d> rest;  // the source's local vertices
  std::vector<SourceCell> cells;      // its owned cells
  double margin = 0.0;                // the largest source cell's diameter (global)
  std::vector<int> winner;            // per point
  std::vector<double> cell, distance;

  PetscErrorCode setup(const Mesh &source) {
    PetscFunctionBeginUser;
    PetscCall(vertexRestPositions(source, &rest));
    PetscCall(sourceCells(source, rest, &cells, &margin));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &margin, 1, MPI_DOUBLE, MPI_MAX, comm(source)));
    PetscFunctionReturn(0);
  }
  // `uncovered`: the position in `points` of a point farther than the margin from every cell, or -1.
  PetscErrorCode find(const Mesh &source, const std::vector<Eigen::Vector3d> &points, long *uncovered) {
    MPI_Comm c = comm(source);
    PetscMPIInt size;
    PetscFunctionBeginUser;
    PetscCallMPI(MPI_Comm_size(c, &size));
    // Every rank's box of cells, enlarged by the margin: where the points it may hold a candidate for lie.
    double box[6] = {kNotFound, kNotFound, kNotFound, -kNotFound, -kNotFound, -kNotFound};
    for (const auto &sc : cells)
      for (int d = 0; d < 3; ++d) {
        box[d] = std::min(box[d], sc.lo[d] - margin);
        box[3 + d] = std::max(box[3 + d], sc.hi[d] + margin);
      }
    std::vector<double> boxes(6 * static_cast<size_t>(size));
    PetscCallMPI(MPI_Allgather(box, 6, MPI_DOUBLE, boxes.data(), 6, MPI_DOUBLE, c));
    // Each point to every rank whose box holds it (a point's rows are consecutive).
    std::vector<int> dest;
    std::vector<size_t> rowPoint;
    std::vector<double> rows;
    for (size_t k = 0; k < points.size(); ++k) {
      const Eigen::Vector3d &p = points[k];
      for (int r = 0; r < size; ++r) {
        const double *b = &boxes[6 * static_cast<size_t>(r)];
        if (p[0] < b[0] || p[1] < b[1] || p[2] < b[2] || p[0] > b[3] || p[1] > b[4] || p[2] > b[5]) continue;
        dest.push_back(r);
        rowPoint.push_back(k);
        rows.insert(rows.end(), {p[0], p[1], p[2]});
      }
    }
    core::RowRoute ask;
    PetscCall(ask.setup(c, dest));
    std::vector<double> received, replies, answers;
    PetscCall(ask.forward(rows, 3, &received));
    CellGrid grid(cells, rest, 1e-8 * margin);
    for (size_t k = 0; 3 * k < received.size(); ++k) {
      const Located best = grid.locate(Eigen::Vector3d(received[3 * k], received[3 * k + 1], received[3 * k + 2]),
                                       margin, static_cast<long>(k));
      replies.insert(replies.end(), {best.distance, static_cast<double>(best.natural), static_cast<double>(best.cell)});
    }
    PetscCall(ask.backward(replies, 3, &answers));
    // Per point the best answer over the ranks asked.
    winner.assign(points.size(), -1);
    cell.assign(points.size(), -1.0);
    distance.assign(points.size(), kNotFound);
    std::vector<PetscInt> natural(points.size(), -1);
    for (size_t e = 0; e < rowPoint.size(); ++e) {
      const size_t k = rowPoint[e];
      const Located cand{answers[3 * e], static_cast<PetscInt>(answers[3 * e + 1]), 0};
      if (cand.distance < kNotFound && (winner[k] < 0 || cand.better(Located{distance[k], natural[k], 0}))) {
        winner[k] = dest[e];
        cell[k] = answers[3 * e + 2];
        distance[k] = cand.distance;
        natural[k] = cand.natural;
      }
    }
    *uncovered = -1;
    for (size_t k = 0; k < points.size() && *uncovered < 0; ++k)
      if (winner[k] < 0) *uncovered = static_cast<long>(k);
    PetscFunctionReturn(0);
  }
  static MPI_Comm comm(const Mesh &m) {
    MPI_Comm c;
    PetscObjectGetComm((PetscObject)m.dm, &c);
    return c;
  }
};

std::string uncoveredMessage(const std::string &what, const std::string &point, const Mesh &target,
                             const Mesh &source, double margin) {
  return what + ": " + point + " of '" + target.filename + "' is farther than the largest cell (" +
         std::to_string(margin) + ") from every cell of '" + source.filename +
         "': the two meshes are not of the same body (same surface, same units)";
}

}  // namespace

PetscErrorCode VertexInterpolation::setup(const Mesh &source, const Mesh &target, const std::string &what) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)source.dm, &comm));
  CellSearch search;
  PetscCall(search.setup(source));
  std::vector<Eigen::Vector3d> points;
  PetscCall(vertexRestPositions(target, &points));
  long uncovered = -1;
  PetscCall(search.find(source, points, &uncovered));
  PetscCall(core::collectiveCheck(
      comm, uncovered >= 0,
      uncoveredMessage(what, "vertex " + std::to_string(uncovered >= 0 ? target.naturalVertex[uncovered] : -1), target,
                       source, search.margin)));
  std::vector<double> chosen;  // per point: the cell on its winner and the point
  double outside = 0.0;
  for (size_t k = 0; k < points.size(); ++k) {
    chosen.insert(chosen.end(), {search.cell[k], points[k][0], points[k][1], points[k][2]});
    outside = std::max(outside, search.distance[k]);
  }
  PetscCallMPI(MPI_Allreduce(&outside, &outside_, 1, MPI_DOUBLE, MPI_MAX, comm));
  PetscCall(route_.setup(comm, search.winner));
  std::vector<double> mine;
  PetscCall(route_.forward(chosen, 4, &mine));
  corner_.resize(mine.size() / 4);
  weight_.resize(mine.size() / 4);
  for (size_t k = 0; k < corner_.size(); ++k) {
    const SourceCell &c = search.cells[static_cast<size_t>(mine[4 * k])];
    corner_[k] = c.corner;
    weight_[k] = barycentric(c, Eigen::Vector3d(mine[4 * k + 1], mine[4 * k + 2], mine[4 * k + 3]));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode valuesOfCellsAt(const Mesh &source, const std::vector<PetscInt> &cellValues, const Mesh &target,
                               const std::vector<Eigen::Vector3d> &points, const std::string &what,
                               std::vector<PetscInt> *values) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)source.dm, &comm));
  CellSearch search;
  PetscCall(search.setup(source));
  long uncovered = -1;
  PetscCall(search.find(source, points, &uncovered));
  PetscCall(core::collectiveCheck(comm, uncovered >= 0,
                                  uncoveredMessage(what, "a point", target, source, search.margin)));
  core::RowRoute route;
  PetscCall(route.setup(comm, search.winner));
  std::vector<long long> asked, answers, got;
  PetscCall(route.forward(std::vector<long long>(search.cell.begin(), search.cell.end()), 1, &asked));
  for (long long k : asked) answers.push_back(cellValues[search.cells[static_cast<size_t>(k)].local]);
  PetscCall(route.backward(answers, 1, &got));
  values->assign(got.begin(), got.end());
  PetscFunctionReturn(0);
}

PetscErrorCode VertexInterpolation::interpolate(const std::vector<double> &sourceValues,
                                                std::vector<double> *targetValues) const {
  PetscFunctionBeginUser;
  std::vector<double> replies(3 * corner_.size(), 0.0);
  for (size_t k = 0; k < corner_.size(); ++k)
    for (int i = 0; i < 4; ++i)
      for (int d = 0; d < 3; ++d) replies[3 * k + d] += weight_[k][i] * sourceValues[3 * corner_[k][i] + d];
  PetscCall(route_.backward(replies, 3, targetValues));  // (one row per local target vertex, in their order)
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
