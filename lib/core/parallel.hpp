// Parallel helpers shared by every layer above: point-SF leaves, centroids and gathers onto rank 0.
#pragma once

#include <petscdm.h>

#include <Eigen/Core>

#include <vector>

namespace aries::core {

// Flags (indexed p - pStart over the chart) of the points this rank holds as copies of another rank's points
// (leaves of the point SF). Not collective.
PetscErrorCode sharedLeafPoints(DM dm, std::vector<char> *leaf);

// The mean of points spread over the ranks (each point added on one rank only): add() locally, then reduce().
struct CentroidAccumulator {
  double sum[4] = {0.0, 0.0, 0.0, 0.0};  // x, y, z, count
  void add(const Eigen::Vector3d &X) {
    for (int i = 0; i < 3; ++i) sum[i] += X[i];
    sum[3] += 1.0;
  }
  // Collective. `count` (optional) receives the global number of points; with none the centroid is 0.
  PetscErrorCode reduce(MPI_Comm comm, Eigen::Vector3d *centroid, double *count = nullptr) const;
};

// Concatenates every rank's `mine` on rank 0, in rank order (`all` is empty elsewhere). Collective.
PetscErrorCode gatherOnRoot(MPI_Comm comm, const std::vector<double> &mine, std::vector<double> *all);

// Gathers (natural id, values) pairs onto rank 0 into a dense array of `total * comps` values (sum: add duplicates).
PetscErrorCode gatherNatural(MPI_Comm comm, const std::vector<PetscInt> &ids, const std::vector<double> &vals,
                             int comps, PetscInt total, std::vector<double> *out, bool sum = false);

}  // namespace aries::core
