#include "core/parallel.hpp"

#include <petscdmplex.h>
#include <petscsf.h>

#include <algorithm>
#include <type_traits>

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

int blockOwner(PetscInt id, PetscInt total, int size) {
  const PetscInt base = total / size, extra = total % size;
  const PetscInt split = extra * (base + 1);
  return id < split ? static_cast<int>(id / (base + 1)) : static_cast<int>(extra + (id - split) / base);
}

PetscInt blockBegin(int rank, PetscInt total, int size) {
  const PetscInt base = total / size, extra = total % size;
  return rank * base + std::min<PetscInt>(rank, extra);
}

namespace {

// MPI_Alltoallv of `comps` values of T per row (counts in rows).
template <class T>
PetscErrorCode exchange(MPI_Comm comm, const std::vector<T> &send, const std::vector<int> &sendCounts,
                        const std::vector<int> &sendDispl, std::vector<T> *recv, const std::vector<int> &recvCounts,
                        const std::vector<int> &recvDispl, int comps) {
  static_assert(std::is_same_v<T, double> || std::is_same_v<T, long long>, "RowRoute moves doubles or long longs");
  const MPI_Datatype type = std::is_same_v<T, double> ? MPI_DOUBLE : MPI_LONG_LONG;
  PetscFunctionBeginUser;
  const size_t n = sendCounts.size();
  std::vector<int> sc(n), sd(n), rc(n), rd(n);
  for (size_t p = 0; p < n; ++p) {
    sc[p] = sendCounts[p] * comps;
    sd[p] = sendDispl[p] * comps;
    rc[p] = recvCounts[p] * comps;
    rd[p] = recvDispl[p] * comps;
  }
  PetscCallMPI(MPI_Alltoallv(send.data(), sc.data(), sd.data(), type, recv->data(), rc.data(), rd.data(), type, comm));
  PetscFunctionReturn(0);
}

// Collective: the route of natural ids to the ranks whose blocks hold them.
PetscErrorCode routeToBlocks(MPI_Comm comm, PetscInt total, const std::vector<PetscInt> &ids, RowRoute *route) {
  PetscMPIInt size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  std::vector<int> dest(ids.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    PetscCheck(ids[i] >= 0 && ids[i] < total, PETSC_COMM_SELF, PETSC_ERR_PLIB, "natural id %d outside [0, %d)",
               (int)ids[i], (int)total);
    dest[i] = blockOwner(ids[i], total, size);
  }
  PetscCall(route->setup(comm, dest));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode RowRoute::setup(MPI_Comm comm, const std::vector<int> &dest) {
  PetscMPIInt size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  comm_ = comm;
  sendCounts_.assign(size, 0);
  for (const int d : dest) ++sendCounts_[d];
  sendDispl_.assign(size, 0);
  for (int p = 1; p < size; ++p) sendDispl_[p] = sendDispl_[p - 1] + sendCounts_[p - 1];
  order_.resize(dest.size());
  std::vector<int> next(sendDispl_);
  for (size_t i = 0; i < dest.size(); ++i) order_[next[dest[i]]++] = i;
  recvCounts_.assign(size, 0);
  PetscCallMPI(MPI_Alltoall(sendCounts_.data(), 1, MPI_INT, recvCounts_.data(), 1, MPI_INT, comm));
  recvDispl_.assign(size, 0);
  for (int p = 1; p < size; ++p) recvDispl_[p] = recvDispl_[p - 1] + recvCounts_[p - 1];
  numReceived_ = size ? static_cast<size_t>(recvDispl_[size - 1]) + recvCounts_[size - 1] : 0;
  PetscFunctionReturn(0);
}

template <class T>
PetscErrorCode RowRoute::forward(const std::vector<T> &rows, int comps, std::vector<T> *received) const {
  PetscFunctionBeginUser;
  PetscCheck(rows.size() == order_.size() * comps, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "RowRoute::forward: %d values for %d rows x %d", (int)rows.size(), (int)order_.size(), comps);
  std::vector<T> send(rows.size());
  for (size_t k = 0; k < order_.size(); ++k)
    std::copy_n(rows.begin() + order_[k] * comps, comps, send.begin() + k * comps);
  received->assign(numReceived_ * comps, T());
  PetscCall(exchange(comm_, send, sendCounts_, sendDispl_, received, recvCounts_, recvDispl_, comps));
  PetscFunctionReturn(0);
}

template <class T>
PetscErrorCode RowRoute::backward(const std::vector<T> &replies, int comps, std::vector<T> *rows) const {
  PetscFunctionBeginUser;
  PetscCheck(replies.size() == numReceived_ * comps, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "RowRoute::backward: %d values for %d rows x %d", (int)replies.size(), (int)numReceived_, comps);
  std::vector<T> recv(order_.size() * comps);
  PetscCall(exchange(comm_, replies, recvCounts_, recvDispl_, &recv, sendCounts_, sendDispl_, comps));
  rows->assign(order_.size() * comps, T());
  for (size_t k = 0; k < order_.size(); ++k)
    std::copy_n(recv.begin() + k * comps, comps, rows->begin() + order_[k] * comps);
  PetscFunctionReturn(0);
}

template PetscErrorCode RowRoute::forward(const std::vector<double> &, int, std::vector<double> *) const;
template PetscErrorCode RowRoute::forward(const std::vector<long long> &, int, std::vector<long long> *) const;
template PetscErrorCode RowRoute::backward(const std::vector<double> &, int, std::vector<double> *) const;
template PetscErrorCode RowRoute::backward(const std::vector<long long> &, int, std::vector<long long> *) const;

PetscErrorCode fetchFromBlocks(MPI_Comm comm, PetscInt total, const std::vector<double> &block, int comps,
                               const std::vector<PetscInt> &ids, std::vector<double> *values) {
  PetscMPIInt rank, size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  const PetscInt start = blockBegin(rank, total, size), rows = blockBegin(rank + 1, total, size) - start;
  PetscCheck(block.size() == static_cast<size_t>(rows) * comps, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "fetchFromBlocks: %d values for a block of %d x %d", (int)block.size(), (int)rows, comps);
  RowRoute route;
  PetscCall(routeToBlocks(comm, total, ids, &route));
  const std::vector<long long> request(ids.begin(), ids.end());
  std::vector<long long> asked;
  PetscCall(route.forward(request, 1, &asked));
  std::vector<double> answer(asked.size() * comps);
  for (size_t k = 0; k < asked.size(); ++k)
    std::copy_n(block.begin() + static_cast<size_t>(asked[k] - start) * comps, comps, answer.begin() + k * comps);
  PetscCall(route.backward(answer, comps, values));
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalBlocks::setupBlocks(MPI_Comm comm, PetscInt total) {
  PetscMPIInt rank, size;
  PetscFunctionBeginUser;
  total_ = total;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  blockStart_ = blockBegin(rank, total, size);
  blockSize_ = blockBegin(rank + 1, total, size) - blockStart_;
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalBlocks::setup(MPI_Comm comm, PetscInt total, const std::vector<PetscInt> &owned) {
  PetscFunctionBeginUser;
  PetscCall(setupBlocks(comm, total));
  PetscCall(routeToBlocks(comm, total, owned, &route_));
  const std::vector<long long> ids(owned.begin(), owned.end());
  std::vector<long long> recvIds;
  PetscCall(route_.forward(ids, 1, &recvIds));
  recvRow_.resize(recvIds.size());
  std::vector<char> seen(blockSize_, 0);
  for (size_t k = 0; k < recvIds.size(); ++k) {
    recvRow_[k] = static_cast<PetscInt>(recvIds[k]) - blockStart_;
    PetscCheck(!seen[recvRow_[k]], PETSC_COMM_SELF, PETSC_ERR_PLIB, "natural id %d is owned by two ranks",
               (int)(recvRow_[k] + blockStart_));
    seen[recvRow_[k]] = 1;
  }
  int complete = recvIds.size() == static_cast<size_t>(blockSize_), all = 0;
  PetscCallMPI(MPI_Allreduce(&complete, &all, 1, MPI_INT, MPI_MIN, comm));
  PetscCheck(all, comm, PETSC_ERR_PLIB, "the owned natural ids do not cover [0, %d) exactly once", (int)total);
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalBlocks::toBlocks(const std::vector<double> &owned, int comps, std::vector<double> *block) const {
  PetscFunctionBeginUser;
  PetscCheck(route_.ready(), PETSC_COMM_SELF, PETSC_ERR_PLIB, "toBlocks: blocks set up without an exchange");
  std::vector<double> recv;
  PetscCall(route_.forward(owned, comps, &recv));
  block->assign(static_cast<size_t>(blockSize_) * comps, 0.0);
  for (size_t k = 0; k < recvRow_.size(); ++k)
    std::copy_n(recv.begin() + k * comps, comps, block->begin() + static_cast<size_t>(recvRow_[k]) * comps);
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalBlocks::fromBlocks(const std::vector<double> &block, int comps, std::vector<double> *owned) const {
  PetscFunctionBeginUser;
  PetscCheck(route_.ready(), PETSC_COMM_SELF, PETSC_ERR_PLIB, "fromBlocks: blocks set up without an exchange");
  PetscCheck(block.size() == static_cast<size_t>(blockSize_) * comps, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "fromBlocks: %d values for a block of %d x %d", (int)block.size(), (int)blockSize_, comps);
  std::vector<double> send(recvRow_.size() * comps);
  for (size_t k = 0; k < recvRow_.size(); ++k)
    std::copy_n(block.begin() + static_cast<size_t>(recvRow_[k]) * comps, comps, send.begin() + k * comps);
  PetscCall(route_.backward(send, comps, owned));
  PetscFunctionReturn(0);
}

}  // namespace aries::core
