#include "core/parallel.hpp"

#include <petscdmplex.h>
#include <petscsf.h>

namespace aries::core {

PetscErrorCode sharedLeafPoints(DM dm, std::vector<char> *leaf) {
  PetscSF sf;
  PetscInt pStart, pEnd, nleaves;
  const PetscInt *ilocal;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
  PetscCall(DMGetPointSF(dm, &sf));
  PetscCall(PetscSFGetGraph(sf, nullptr, &nleaves, &ilocal, nullptr));
  leaf->assign(pEnd - pStart, 0);
  for (PetscInt i = 0; i < nleaves; ++i) (*leaf)[(ilocal ? ilocal[i] : i) - pStart] = 1;
  PetscFunctionReturn(0);
}

PetscErrorCode CentroidAccumulator::reduce(MPI_Comm comm, Eigen::Vector3d *centroid, double *count) const {
  double tot[4];
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(sum, tot, 4, MPI_DOUBLE, MPI_SUM, comm));
  *centroid = tot[3] > 0.0 ? Eigen::Vector3d(Eigen::Vector3d(tot[0], tot[1], tot[2]) / tot[3]) : Eigen::Vector3d::Zero();
  if (count) *count = tot[3];
  PetscFunctionReturn(0);
}

PetscErrorCode gatherOnRoot(MPI_Comm comm, const std::vector<double> &mine, std::vector<double> *all) {
  PetscMPIInt rank, size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  const int n = static_cast<int>(mine.size());
  std::vector<int> counts(size), displs(size);
  PetscCallMPI(MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm));
  int total = 0;
  if (rank == 0)
    for (int p = 0; p < size; ++p) {
      displs[p] = total;
      total += counts[p];
    }
  all->assign(rank == 0 ? total : 0, 0.0);
  PetscCallMPI(MPI_Gatherv(mine.data(), n, MPI_DOUBLE, all->data(), counts.data(), displs.data(), MPI_DOUBLE, 0, comm));
  PetscFunctionReturn(0);
}

PetscErrorCode gatherNatural(MPI_Comm comm, const std::vector<PetscInt> &ids, const std::vector<double> &vals,
                             int comps, PetscInt total, std::vector<double> *out, bool sum) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::vector<double> mine, all;  // per entry: id (exact as a double below 2^53), then its values
  mine.reserve(ids.size() * (comps + 1));
  for (size_t i = 0; i < ids.size(); ++i) {
    mine.push_back(static_cast<double>(ids[i]));
    mine.insert(mine.end(), vals.begin() + i * comps, vals.begin() + (i + 1) * comps);
  }
  PetscCall(gatherOnRoot(comm, mine, &all));
  out->clear();
  if (rank == 0) {
    out->assign(static_cast<size_t>(total) * comps, 0.0);
    for (size_t e = 0; e < all.size(); e += comps + 1) {
      double *dst = &(*out)[static_cast<size_t>(all[e]) * comps];
      for (int k = 0; k < comps; ++k) dst[k] = sum ? dst[k] + all[e + 1 + k] : all[e + 1 + k];
    }
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::core
