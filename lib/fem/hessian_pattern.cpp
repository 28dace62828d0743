#include "fem/hessian_pattern.hpp"

#include <algorithm>

namespace aries::fem {

HessianPattern::~HessianPattern() {
  if (shell_) (void)MatDestroy(&shell_);
}

PetscErrorCode HessianPattern::create(Mat J) {
  PetscInt m, n, M, N, rStart, rEnd;
  PetscLayout rowLayout, columnLayout;
  PetscFunctionBeginUser;
  PetscCall(MatGetLayouts(J, &rowLayout, &columnLayout));
  PetscCall(PetscLayoutSetUp(rowLayout));
  PetscCall(PetscLayoutSetUp(columnLayout));
  PetscCall(MatGetLocalSize(J, &m, &n));
  PetscCall(MatGetSize(J, &M, &N));
  PetscCall(MatGetBlockSize(J, &bs_));
  PetscCall(MatGetOwnershipRange(J, &rStart, &rEnd));
  rowStart_ = rStart / bs_;
  rowEnd_ = rEnd / bs_;
  rows_.assign(rowEnd_ - rowStart_, {});
  offRank_.clear();
  PetscCall(MatCreateShell(PetscObjectComm((PetscObject)J), m, n, M, N, this, &shell_));
  PetscCall(MatSetBlockSize(shell_, bs_));
  PetscCall(MatShellSetOperation(shell_, MATOP_SET_VALUES, (void (*)(void))setValues));
  PetscCall(MatShellSetOperation(shell_, MATOP_SET_VALUES_BLOCKED, (void (*)(void))setValuesBlocked));
  PetscCall(MatSetUp(shell_));
  PetscFunctionReturn(0);
}

void HessianPattern::record(PetscInt br, PetscInt n, const PetscInt cols[], PetscInt unit) {
  const bool owned = br >= rowStart_ && br < rowEnd_;
  std::vector<PetscInt> *list = owned ? &rows_[br - rowStart_] : nullptr;
  PetscInt last = -1;
  for (PetscInt k = 0; k < n; ++k) {
    if (cols[k] < 0) continue;
    const PetscInt bc = cols[k] / unit;
    if (bc == last) continue;  // the next scalar column of the same block
    last = bc;
    if (owned) list->push_back(bc);
    else offRank_.insert(offRank_.end(), {br, bc});
  }
}

// Scalar rows and columns (AIJ, or MatSetValuesBlocked expanded): the pairs of their blocks, as MATPREALLOCATOR keys
// them (index / bs). The rows of one call share their columns, so a block's later rows add nothing new.
PetscErrorCode HessianPattern::setValues(Mat A, PetscInt m, const PetscInt rows[], PetscInt n, const PetscInt cols[],
                                         const PetscScalar[], InsertMode) {
  HessianPattern *self;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &self));
  PetscInt last = -1;
  for (PetscInt r = 0; r < m; ++r) {
    if (rows[r] < 0 || rows[r] / self->bs_ == last) continue;
    last = rows[r] / self->bs_;
    self->record(last, n, cols, self->bs_);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode HessianPattern::setValuesBlocked(Mat A, PetscInt m, const PetscInt rows[], PetscInt n,
                                                const PetscInt cols[], const PetscScalar[], InsertMode) {
  HessianPattern *self;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &self));
  for (PetscInt r = 0; r < m; ++r)
    if (rows[r] >= 0) self->record(rows[r], n, cols, 1);
  PetscFunctionReturn(0);
}

PetscErrorCode HessianPattern::exchange(Mat J) {
  MPI_Comm comm = PetscObjectComm((PetscObject)J);
  PetscMPIInt size;
  const PetscInt *ranges;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  int none = offRank_.empty() ? 1 : 0;  // MATPREALLOCATOR's nooffproc: no rank recorded another's rows
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &none, 1, MPI_INT, MPI_LAND, comm));
  noOffRank_ = none != 0;
  if (size == 1 || noOffRank_) PetscFunctionReturn(0);
  PetscCall(MatGetOwnershipRanges(J, &ranges));
  auto ownerOf = [&](PetscInt br) {
    return static_cast<int>(std::upper_bound(ranges, ranges + size + 1, br * bs_) - ranges) - 1;
  };
  std::vector<PetscMPIInt> sendCounts(size, 0), recvCounts(size), sendAt(size + 1, 0), recvAt(size + 1, 0);
  for (size_t k = 0; k < offRank_.size(); k += 2) sendCounts[ownerOf(offRank_[k])] += 2;
  for (int p = 0; p < size; ++p) sendAt[p + 1] = sendAt[p] + sendCounts[p];
  std::vector<PetscInt> send(offRank_.size());
  {
    std::vector<PetscMPIInt> at(sendAt.begin(), sendAt.end() - 1);
    for (size_t k = 0; k < offRank_.size(); k += 2) {
      PetscMPIInt &to = at[ownerOf(offRank_[k])];
      send[to] = offRank_[k];
      send[to + 1] = offRank_[k + 1];
      to += 2;
    }
  }
  std::vector<PetscInt>().swap(offRank_);
  PetscCallMPI(MPI_Alltoall(sendCounts.data(), 1, MPI_INT, recvCounts.data(), 1, MPI_INT, comm));
  for (int p = 0; p < size; ++p) recvAt[p + 1] = recvAt[p] + recvCounts[p];
  std::vector<PetscInt> recv(recvAt[size]);
  PetscCallMPI(MPI_Alltoallv(send.data(), sendCounts.data(), sendAt.data(), MPIU_INT, recv.data(), recvCounts.data(),
                             recvAt.data(), MPIU_INT, comm));
  for (size_t k = 0; k < recv.size(); k += 2) {
    PetscCheck(recv[k] >= rowStart_ && recv[k] < rowEnd_, PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "aries: a Hessian pattern row %" PetscInt_FMT " sent to a rank that does not own it", recv[k]);
    rows_[recv[k] - rowStart_].push_back(recv[k + 1]);
  }
  PetscFunctionReturn(0);
}

// MatPreallocatorPreallocate(P, PETSC_TRUE, J) with the recorded pattern (PETSc 3.18's preallocator.c, step by step).
PetscErrorCode HessianPattern::preallocate(Mat J) {
  PetscInt cStart, cEnd;
  PetscFunctionBeginUser;
  PetscCall(exchange(J));
  PetscCall(MatGetOwnershipRangeColumn(J, &cStart, &cEnd));
  cStart /= bs_;
  cEnd /= bs_;
  const PetscInt nRows = rowEnd_ - rowStart_;
  std::vector<PetscInt> dnz(nRows, 0), onz(nRows, 0), dnzu(nRows, 0), onzu(nRows, 0);
  size_t longest = 1;
  for (PetscInt i = 0; i < nRows; ++i) {
    std::vector<PetscInt> &cols = rows_[i];
    std::sort(cols.begin(), cols.end());
    cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
    longest = std::max(longest, cols.size());
    const PetscInt row = rowStart_ + i;
    for (PetscInt c : cols) {
      const bool diagonal = c >= cStart && c < cEnd;
      ++(diagonal ? dnz : onz)[i];
      if (c >= row) ++(diagonal ? dnzu : onzu)[i];
    }
  }
  PetscCall(MatDestroy(&shell_));
  PetscCall(MatXAIJSetPreallocation(J, bs_, dnz.data(), onz.data(), dnzu.data(), onzu.data()));
  PetscCall(MatSetUp(J));
  PetscCall(MatSetOption(J, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  PetscCall(MatSetOption(J, MAT_NO_OFF_PROC_ENTRIES, noOffRank_ ? PETSC_TRUE : PETSC_FALSE));
  const std::vector<PetscScalar> zeros(longest * bs_ * bs_, 0.0);
  for (PetscInt i = 0; i < nRows; ++i) {
    const PetscInt row = rowStart_ + i;
    PetscCall(MatSetValuesBlocked(J, 1, &row, static_cast<PetscInt>(rows_[i].size()), rows_[i].data(), zeros.data(),
                                  INSERT_VALUES));
    std::vector<PetscInt>().swap(rows_[i]);
  }
  rows_.clear();
  PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatSetOption(J, MAT_NO_OFF_PROC_ENTRIES, PETSC_FALSE));
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
