#include "core/parallel.hpp"

#include <petscdmplex.h>
#include <petscsf.h>

#include <algorithm>

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

// MPI_Alltoallv of `comps` doubles per entry (counts in entries).
PetscErrorCode exchange(MPI_Comm comm, const std::vector<double> &send, const std::vector<int> &sendCounts,
                        const std::vector<int> &sendDispl, std::vector<double> *recv, const std::vector<int> &recvCounts,
                        const std::vector<int> &recvDispl, int comps) {
  PetscFunctionBeginUser;
  const size_t n = sendCounts.size();
  std::vector<int> sc(n), sd(n), rc(n), rd(n);
  for (size_t p = 0; p < n; ++p) {
    sc[p] = sendCounts[p] * comps;
    sd[p] = sendDispl[p] * comps;
    rc[p] = recvCounts[p] * comps;
    rd[p] = recvDispl[p] * comps;
  }
  PetscCallMPI(MPI_Alltoallv(send.data(), sc.data(), sd.data(), MPI_DOUBLE, recv->data(), rc.data(), rd.data(),
                             MPI_DOUBLE, comm));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode fetchFromBlocks(MPI_Comm comm, PetscInt total, const std::vector<double> &block, int comps,
                               const std::vector<PetscInt> &ids, std::vector<double> *values) {
  PetscMPIInt rank, size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  const PetscInt start = blockBegin(rank, total, size), rows = blockBegin(rank + 1, total, size) - start;
  PetscCheck(block.size() == static_cast<size_t>(rows) * comps, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "fetchFromBlocks: %d values for a block of %d x %d", (int)block.size(), (int)rows, comps);
  // requests grouped by the rank holding them
  std::vector<int> dest(ids.size()), sendCounts(size, 0), sendDispl(size, 0), recvCounts(size), recvDispl(size, 0);
  for (size_t i = 0; i < ids.size(); ++i) {
    PetscCheck(ids[i] >= 0 && ids[i] < total, PETSC_COMM_SELF, PETSC_ERR_PLIB, "natural id %d outside [0, %d)",
               (int)ids[i], (int)total);
    dest[i] = blockOwner(ids[i], total, size);
    ++sendCounts[dest[i]];
  }
  for (int p = 1; p < size; ++p) sendDispl[p] = sendDispl[p - 1] + sendCounts[p - 1];
  std::vector<size_t> order(ids.size());
  std::vector<double> request(ids.size());  // ids travel as doubles (exact below 2^53)
  std::vector<int> next(sendDispl);
  for (size_t i = 0; i < ids.size(); ++i) {
    order[next[dest[i]]] = i;
    request[next[dest[i]]++] = static_cast<double>(ids[i]);
  }
  PetscCallMPI(MPI_Alltoall(sendCounts.data(), 1, MPI_INT, recvCounts.data(), 1, MPI_INT, comm));
  for (int p = 1; p < size; ++p) recvDispl[p] = recvDispl[p - 1] + recvCounts[p - 1];
  std::vector<double> asked(static_cast<size_t>(recvDispl[size - 1]) + recvCounts[size - 1]);
  PetscCall(exchange(comm, request, sendCounts, sendDispl, &asked, recvCounts, recvDispl, 1));
  std::vector<double> answer(asked.size() * comps), received(ids.size() * comps);
  for (size_t k = 0; k < asked.size(); ++k)
    std::copy_n(block.begin() + (static_cast<size_t>(asked[k]) - start) * comps, comps, answer.begin() + k * comps);
  PetscCall(exchange(comm, answer, recvCounts, recvDispl, &received, sendCounts, sendDispl, comps));
  values->assign(ids.size() * comps, 0.0);
  for (size_t k = 0; k < ids.size(); ++k)
    std::copy_n(received.begin() + k * comps, comps, values->begin() + order[k] * comps);
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalBlocks::setupBlocks(MPI_Comm comm, PetscInt total) {
  PetscMPIInt rank, size;
  PetscFunctionBeginUser;
  comm_ = comm;
  total_ = total;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  blockStart_ = blockBegin(rank, total, size);
  blockSize_ = blockBegin(rank + 1, total, size) - blockStart_;
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalBlocks::setup(MPI_Comm comm, PetscInt total, const std::vector<PetscInt> &owned) {
  PetscMPIInt size;
  PetscFunctionBeginUser;
  PetscCall(setupBlocks(comm, total));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  std::vector<int> dest(owned.size());
  sendCounts_.assign(size, 0);
  for (size_t i = 0; i < owned.size(); ++i) {
    PetscCheck(owned[i] >= 0 && owned[i] < total, PETSC_COMM_SELF, PETSC_ERR_PLIB, "natural id %d outside [0, %d)",
               (int)owned[i], (int)total);
    dest[i] = blockOwner(owned[i], total, size);
    ++sendCounts_[dest[i]];
  }
  sendDispl_.assign(size, 0);
  for (int p = 1; p < size; ++p) sendDispl_[p] = sendDispl_[p - 1] + sendCounts_[p - 1];
  sendOrder_.resize(owned.size());
  std::vector<int> next(sendDispl_);
  for (size_t i = 0; i < owned.size(); ++i) sendOrder_[next[dest[i]]++] = i;
  recvCounts_.assign(size, 0);
  PetscCallMPI(MPI_Alltoall(sendCounts_.data(), 1, MPI_INT, recvCounts_.data(), 1, MPI_INT, comm));
  recvDispl_.assign(size, 0);
  for (int p = 1; p < size; ++p) recvDispl_[p] = recvDispl_[p - 1] + recvCounts_[p - 1];
  const size_t numRecv = size ? static_cast<size_t>(recvDispl_[size - 1]) + recvCounts_[size - 1] : 0;
  std::vector<double> ids(owned.size()), recvIds(numRecv);  // ids travel as doubles (exact below 2^53)
  for (size_t k = 0; k < sendOrder_.size(); ++k) ids[k] = static_cast<double>(owned[sendOrder_[k]]);
  PetscCall(exchange(comm, ids, sendCounts_, sendDispl_, &recvIds, recvCounts_, recvDispl_, 1));
  recvRow_.resize(numRecv);
  std::vector<char> seen(blockSize_, 0);
  for (size_t k = 0; k < numRecv; ++k) {
    recvRow_[k] = static_cast<PetscInt>(recvIds[k]) - blockStart_;
    PetscCheck(!seen[recvRow_[k]], PETSC_COMM_SELF, PETSC_ERR_PLIB, "natural id %d is owned by two ranks",
               (int)(recvRow_[k] + blockStart_));
    seen[recvRow_[k]] = 1;
  }
  int complete = numRecv == static_cast<size_t>(blockSize_), all = 0;
  PetscCallMPI(MPI_Allreduce(&complete, &all, 1, MPI_INT, MPI_MIN, comm));
  PetscCheck(all, comm, PETSC_ERR_PLIB, "the owned natural ids do not cover [0, %d) exactly once", (int)total);
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalBlocks::toBlocks(const std::vector<double> &owned, int comps, std::vector<double> *block) const {
  PetscFunctionBeginUser;
  PetscCheck(!sendCounts_.empty(), PETSC_COMM_SELF, PETSC_ERR_PLIB, "toBlocks: blocks set up without an exchange");
  PetscCheck(owned.size() == sendOrder_.size() * comps, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "toBlocks: %d values for %d entries x %d", (int)owned.size(), (int)sendOrder_.size(), comps);
  std::vector<double> send(owned.size()), recv(recvRow_.size() * comps);
  for (size_t k = 0; k < sendOrder_.size(); ++k)
    std::copy_n(owned.begin() + sendOrder_[k] * comps, comps, send.begin() + k * comps);
  PetscCall(exchange(comm_, send, sendCounts_, sendDispl_, &recv, recvCounts_, recvDispl_, comps));
  block->assign(static_cast<size_t>(blockSize_) * comps, 0.0);
  for (size_t k = 0; k < recvRow_.size(); ++k)
    std::copy_n(recv.begin() + k * comps, comps, block->begin() + static_cast<size_t>(recvRow_[k]) * comps);
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalBlocks::fromBlocks(const std::vector<double> &block, int comps, std::vector<double> *owned) const {
  PetscFunctionBeginUser;
  PetscCheck(!sendCounts_.empty(), PETSC_COMM_SELF, PETSC_ERR_PLIB, "fromBlocks: blocks set up without an exchange");
  PetscCheck(block.size() == static_cast<size_t>(blockSize_) * comps, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "fromBlocks: %d values for a block of %d x %d", (int)block.size(), (int)blockSize_, comps);
  std::vector<double> send(recvRow_.size() * comps), recv(sendOrder_.size() * comps);
  for (size_t k = 0; k < recvRow_.size(); ++k)
    std::copy_n(block.begin() + static_cast<size_t>(recvRow_[k]) * comps, comps, send.begin() + k * comps);
  PetscCall(exchange(comm_, send, recvCounts_, recvDispl_, &recv, sendCounts_, sendDispl_, comps));
  owned->assign(sendOrder_.size() * comps, 0.0);
  for (size_t k = 0; k < sendOrder_.size(); ++k)
    std::copy_n(recv.begin() + k * comps, comps, owned->begin() + sendOrder_[k] * comps);
  PetscFunctionReturn(0);
}

}  // namespace aries::core
