// Element matrices added straight into an assembled matrix's value arrays, at positions found once per matrix pattern.
//
// MatSetValues locates every entry on every assembly: for AIJ (GAMG's matrix) each of an element's (NV R)^2 entries
// goes through MPIAIJ's ownership test, its off-diagonal column map and a search of its row, which made the insertion
// about half of a Jacobian evaluation on the compressed box (bench/peer.py's, 125k tets, one rank: two evaluations took
// 0.82 s, 0.30 s with this scatter; BAIJ, whose search is per 3x3 block, 0.40 s and 0.33 s). The pattern is fixed once
// the matrix is preallocated (Discretization::preallocateHessian fills and assembles it), so the position of each
// element block is found once: per element and vertex pair (v, w),
// where block (v, w) starts in the value array of the diagonal or the off-diagonal part (MatMPIAIJGetSeqAIJ,
// MatMPIBAIJGetSeqBAIJ) of v's rows. An assembly then adds each block with no search. Rows another rank owns still go
// through MatSetValues (PETSc's stash), as before.
//
// Supported: SEQAIJ, MPIAIJ, and SEQBAIJ / MPIBAIJ with block size R, where every vertex of the rank's table is wholly
// free or wholly held (a partly held vertex's rows and columns are not R wide). Anything else, or a pattern that does
// not look as expected (checked entry by entry when the positions are found), keeps the MatSetValues path (prepare()
// says so). The choice is each rank's own: every rank writes only its own rows, so ranks that go direct and ranks that
// do not assemble one matrix together. The positions are kept for one matrix (PetscObjectId) and nonzero pattern
// (MatGetNonzeroState) and found again when either changes. The values are summed in the same order as MatSetValues
// sums them (element by element; another rank's rows at assembly), so the matrix is the same bit for bit
// (tests/fem/test_element_scatter.cpp).
#pragma once

#include "fem/vertex_layout.hpp"

#include <petscmat.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace aries::fem {

// A vertex's block row / column (R x R blocks, BAIJ): -1 where it is held (PETSc's Mat*SetValues* skip negative
// indices); its scalar rows are VertexInfo::row.
template <int R>
inline PetscInt blockIndex(const VertexInfo &vi) {
  return vi.numFree == 0 ? -1 : vi.global / R;
}

// Adds element matrix K (row-major, (NV R) x (NV R)) into J through MatSetValuesBlocked (R x R blocks, BAIJ) or
// MatSetValues (AIJ), prescribed dofs skipped: every element matrix's path where the scatter below does not apply.
template <int NV, int R, class Vertices>
inline PetscErrorCode setElementMatrix(const VertexTable &verts, const Vertices &vertex, const double *K, bool blocked,
                                       Mat J) {
  PetscFunctionBeginUser;
  if (blocked) {  // every vertex all free or all held (a partly held vertex makes the matrix AIJ)
    PetscInt rows[NV];
    for (int v = 0; v < NV; ++v) rows[v] = blockIndex<R>(verts[vertex[v]]);
    PetscCall(MatSetValuesBlocked(J, NV, rows, NV, rows, K, ADD_VALUES));
  } else {
    PetscInt rows[NV * R];
    for (int v = 0; v < NV; ++v)
      for (int i = 0; i < R; ++i) rows[v * R + i] = verts[vertex[v]].row(i);
    PetscCall(MatSetValues(J, NV * R, rows, NV * R, rows, K, ADD_VALUES));
  }
  PetscFunctionReturn(0);
}

template <int NV, int R>
class ElementScatter {
 public:
  ElementScatter() = default;
  // A copy starts empty: its owner may have another vertex table, which the cache key does not see.
  ElementScatter(const ElementScatter &) {}
  ElementScatter &operator=(const ElementScatter &other) {
    if (this != &other) *this = ElementScatter();
    return *this;
  }
  ElementScatter(ElementScatter &&) = default;
  ElementScatter &operator=(ElementScatter &&) = default;
  // Finds (or keeps) the positions for J of the elements vertexOf(e), e < count (local vertex indices; only those
  // with owned(e) are added later). *direct says whether add() may be used for this assembly.
  template <class VertexOf, class Owned>
  PetscErrorCode prepare(Mat J, const VertexTable &verts, size_t count, VertexOf vertexOf, Owned owned, bool *direct);
  // Between begin() and end() (after prepare() said direct): adds element e's matrix K (row-major, (NV R)^2) into J,
  // the rows of vertices another rank owns through MatSetValues.
  PetscErrorCode begin();
  template <class Vertices>
  PetscErrorCode add(Mat J, const VertexTable &verts, size_t e, const Vertices &vertex, const double *K);
  PetscErrorCode end();
  // How many times the positions were found (once per matrix and pattern; tests/fem/test_element_scatter.cpp).
  std::size_t positionsFound() const { return finds_; }

 private:
  static constexpr std::int32_t kSkip = -1;  // block not added here: row held or owned by another rank, column held
  struct Part {                              // the diagonal (local columns) or off-diagonal part of this rank's rows
    Mat mat = nullptr;
    PetscScalar *values = nullptr;
  };
  // cellVertex: the elements' local vertices side by side (NV per element, -1 for one not owned), read row by row
  // below (read in place from the terms' element records, each element was a cache miss).
  PetscErrorCode find(Mat J, const VertexTable &verts, const std::vector<PetscInt> &cellVertex,
                      const std::vector<char> &ownedCells, bool *ok);
  // Per local vertex: its (unit) row where owned and free, else -1; its column in part 0 or 1 where free, else -1
  // (-2: a free vertex the off-diagonal part does not list).
  struct VertexColumns {
    std::vector<PetscInt> rowOf, columnOf;
    std::vector<char> partOf;
  };
  static void vertexColumns(const VertexTable &verts, PetscInt unit, PetscInt rowStart, PetscInt colStart,
                            PetscInt colEnd, const PetscInt *garray, PetscInt garrayLength, VertexColumns *vc);
  // The (element, corner) places of every row's vertex (firstPlace[v] .. firstPlace[v + 1] in places), so find()
  // searches each row's column indices while they are in cache and each of its column blocks once. Element by
  // element, every search was a miss: 1.9% of the 1M-tet peer box's samples, 1.15% this way.
  struct RowPlaces {
    std::vector<PetscInt> firstPlace, places;
  };
  static void placesByRow(const std::vector<PetscInt> &cellVertex, const std::vector<char> &ownedCells,
                          const std::vector<PetscInt> &rowOf, RowPlaces *rp);

  PetscInt64 matId_ = -1;
  PetscObjectState pattern_ = -1;
  bool usable_ = false;
  std::size_t finds_ = 0;
  bool blocked_ = false;
  Part parts_[2];
  // Per (element, v, w): 2 * (index of the block's first value in its part's array) + part, or kSkip.
  std::vector<std::int32_t> position_;
  // Per local vertex and part (AIJ): the length of each of its R rows (the rows of a vertex share their pattern).
  std::vector<std::int32_t> rowLength_[2];
};

// ---------------------------------------------------------------------------------------------------------------------

template <int NV, int R>
template <class VertexOf, class Owned>
PetscErrorCode ElementScatter<NV, R>::prepare(Mat J, const VertexTable &verts, size_t count, VertexOf vertexOf,
                                              Owned owned, bool *direct) {
  PetscObjectId id;
  PetscObjectState pattern;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetId((PetscObject)J, &id));
  PetscCall(MatGetNonzeroState(J, &pattern));
  if ((PetscInt64)id != matId_ || pattern != pattern_) {
    matId_ = (PetscInt64)id;
    pattern_ = pattern;
    std::vector<PetscInt> cellVertex(count * NV, -1);
    std::vector<char> ownedCells(count);
    for (size_t e = 0; e < count; ++e) {
      ownedCells[e] = owned(e);
      if (ownedCells[e]) std::copy_n(vertexOf(e), NV, cellVertex.begin() + e * NV);
    }
    PetscCall(find(J, verts, cellVertex, ownedCells, &usable_));
  }
  *direct = usable_;
  PetscFunctionReturn(0);
}

template <int NV, int R>
void ElementScatter<NV, R>::vertexColumns(const VertexTable &verts, PetscInt unit, PetscInt rowStart,
                                          PetscInt colStart, PetscInt colEnd, const PetscInt *garray,
                                          PetscInt garrayLength, VertexColumns *vc) {
  const size_t nv = verts.size();
  vc->rowOf.assign(nv, -1);
  vc->columnOf.assign(nv, -1);
  vc->partOf.assign(nv, 0);
  for (size_t v = 0; v < nv; ++v) {
    const VertexInfo &vi = verts[v];
    if (vi.numFree == 0) continue;
    if (vi.ownedFree()) vc->rowOf[v] = (vi.global - rowStart) / unit;
    if (vi.global >= colStart && vi.global < colEnd) {
      vc->columnOf[v] = (vi.global - colStart) / unit;
      continue;
    }
    vc->partOf[v] = 1;  // the off-diagonal part's compressed column: garray is sorted (the global columns in order)
    const PetscInt *at = garray ? std::lower_bound(garray, garray + garrayLength, vi.global / unit) : nullptr;
    vc->columnOf[v] = at && at != garray + garrayLength && *at == vi.global / unit ? at - garray : -2;
  }
}

template <int NV, int R>
void ElementScatter<NV, R>::placesByRow(const std::vector<PetscInt> &cellVertex, const std::vector<char> &ownedCells,
                                        const std::vector<PetscInt> &rowOf, RowPlaces *rp) {
  const size_t nv = rowOf.size(), count = ownedCells.size();
  rp->firstPlace.assign(nv + 1, 0);
  for (size_t e = 0; e < count; ++e)
    if (ownedCells[e])
      for (int a = 0; a < NV; ++a)
        if (rowOf[cellVertex[e * NV + a]] >= 0) ++rp->firstPlace[cellVertex[e * NV + a] + 1];
  for (size_t v = 0; v < nv; ++v) rp->firstPlace[v + 1] += rp->firstPlace[v];
  rp->places.resize(rp->firstPlace[nv]);
  std::vector<PetscInt> next(rp->firstPlace.begin(), rp->firstPlace.end() - 1);
  for (size_t e = 0; e < count; ++e)
    if (ownedCells[e])
      for (int a = 0; a < NV; ++a) {
        const PetscInt v = cellVertex[e * NV + a];
        if (rowOf[v] >= 0) rp->places[next[v]++] = static_cast<PetscInt>(e * NV + a);
      }
}

template <int NV, int R>
PetscErrorCode ElementScatter<NV, R>::find(Mat J, const VertexTable &verts, const std::vector<PetscInt> &cellVertex,
                                           const std::vector<char> &ownedCells, bool *ok) {
  PetscBool seqAij, mpiAij, seqBaij, mpiBaij;
  PetscInt bs, rowStart, rowEnd, colStart, colEnd;
  const PetscInt *garray = nullptr;
  PetscFunctionBeginUser;
  *ok = false;
  ++finds_;
  position_.clear();
  for (auto &l : rowLength_) l.clear();
  parts_[0] = parts_[1] = Part{};
  PetscCall(PetscObjectTypeCompare((PetscObject)J, MATSEQAIJ, &seqAij));
  PetscCall(PetscObjectTypeCompare((PetscObject)J, MATMPIAIJ, &mpiAij));
  PetscCall(PetscObjectTypeCompare((PetscObject)J, MATSEQBAIJ, &seqBaij));
  PetscCall(PetscObjectTypeCompare((PetscObject)J, MATMPIBAIJ, &mpiBaij));
  PetscCall(MatGetBlockSize(J, &bs));
  blocked_ = seqBaij || mpiBaij;
  if (!(seqAij || mpiAij || ((seqBaij || mpiBaij) && bs == R))) PetscFunctionReturn(0);
  for (const VertexInfo &vi : verts)
    if (vi.numFree != 0 && vi.numFree != R) PetscFunctionReturn(0);  // a partly held vertex: rows not R wide
  if (mpiAij) PetscCall(MatMPIAIJGetSeqAIJ(J, &parts_[0].mat, &parts_[1].mat, &garray));
  else if (mpiBaij) PetscCall(MatMPIBAIJGetSeqBAIJ(J, &parts_[0].mat, &parts_[1].mat, &garray));
  else parts_[0].mat = J;
  PetscCall(MatGetOwnershipRange(J, &rowStart, &rowEnd));
  PetscCall(MatGetOwnershipRangeColumn(J, &colStart, &colEnd));
  const PetscInt unit = blocked_ ? R : 1;  // the row/column unit of the parts' index arrays
  PetscInt rows[2] = {0, 0}, garrayLength = 0;
  const PetscInt *ia[2] = {nullptr, nullptr}, *ja[2] = {nullptr, nullptr};
  PetscBool done[2] = {PETSC_FALSE, PETSC_FALSE};
  for (int p = 0; p < 2; ++p) {
    if (!parts_[p].mat) continue;
    PetscCall(MatGetRowIJ(parts_[p].mat, 0, PETSC_FALSE, blocked_ ? PETSC_TRUE : PETSC_FALSE, &rows[p], &ia[p], &ja[p],
                          &done[p]));
    if (!done[p]) break;
  }
  if (parts_[1].mat) PetscCall(MatGetLocalSize(parts_[1].mat, nullptr, &garrayLength));
  garrayLength /= unit;
  // every position, 2 * (value index) + part, must fit the 32-bit table
  const PetscInt64 valuesPerEntry = blocked_ ? R * R : 1, limit = std::numeric_limits<std::int32_t>::max() / 2;
  bool good = done[0] && (!parts_[1].mat || done[1]);
  for (int p = 0; good && p < 2; ++p) good = !parts_[p].mat || (PetscInt64)ia[p][rows[p]] * valuesPerEntry < limit;
  if (good) {
    for (auto &l : rowLength_) l.assign(verts.size(), 0);
    position_.assign(ownedCells.size() * NV * NV, kSkip);
  }
  // The position in part p of the column block of global (unit) column c in local (unit) row r; -1 if absent.
  auto locate = [&](int p, PetscInt r, PetscInt c) -> PetscInt {
    const PetscInt *first = ja[p] + ia[p][r], *last = ja[p] + ia[p][r + 1];
    const PetscInt *at = std::lower_bound(first, last, c);
    return at != last && *at == c ? at - ja[p] : -1;
  };
  VertexColumns vc;
  RowPlaces rp;
  if (good) {
    vertexColumns(verts, unit, rowStart, colStart, colEnd, garray, garrayLength, &vc);
    placesByRow(cellVertex, ownedCells, vc.rowOf, &rp);
  }
  const size_t nv = verts.size();
  struct Found {  // a column block of the current row: its part, column and position
    int part;
    PetscInt column, at;
  };
  std::vector<Found> found;  // of the current row: each block searched and checked once, not once per element
  for (size_t v = 0; good && v < nv; ++v) {
    const PetscInt row = vc.rowOf[v];  // local (unit) row of the vertex's first dof
    found.clear();
    for (PetscInt k0 = rp.firstPlace[v]; good && k0 < rp.firstPlace[v + 1]; ++k0) {  // none where row < 0
      const size_t place = static_cast<size_t>(rp.places[k0]), e = place / NV;
      const PetscInt *vertex = &cellVertex[e * NV];
      for (int b = 0; b < NV; ++b) {
        const PetscInt w = vertex[b];
        const PetscInt col = vc.columnOf[w];
        if (col == -1) continue;  // held
        const int p = vc.partOf[w];
        PetscInt k = -1;
        for (const Found &f : found)
          if (f.column == col && f.part == p) {
            k = f.at;
            break;
          }
        if (k < 0) {
          k = col < 0 ? -1 : locate(p, row, col);
          if (k < 0) { good = false; break; }
          if (!blocked_) {  // AIJ: the vertex's R rows have the same length and hold the R columns of w side by side
            const PetscInt length = ia[p][row + 1] - ia[p][row];
            for (int i = 0; good && i < R; ++i) {
              good = ia[p][row + i + 1] - ia[p][row + i] == length;
              for (int j = 0; good && j < R; ++j)  // off-diagonal columns are compressed: global ids via garray
                good = ja[p][k + i * length + j] == col + j && (p == 0 || garray[col + j] == verts[w].global + j);
            }
            if (!good) break;
            rowLength_[p][v] = static_cast<std::int32_t>(length);
          }
          found.push_back(Found{p, col, k});
        }
        position_[place * NV + b] = static_cast<std::int32_t>(blocked_ ? 2 * (k * R * R) + p : 2 * k + p);
      }
    }
  }
  for (int p = 0; p < 2; ++p)
    if (parts_[p].mat && done[p])
      PetscCall(MatRestoreRowIJ(parts_[p].mat, 0, PETSC_FALSE, blocked_ ? PETSC_TRUE : PETSC_FALSE, &rows[p], &ia[p],
                                &ja[p], &done[p]));
  if (!good) {
    position_.clear();
    for (auto &l : rowLength_) l.clear();
    PetscCall(PetscInfo(J, "aries: the element matrices go through MatSetValues (the pattern is not as expected)\n"));
  }
  *ok = good;
  PetscFunctionReturn(0);
}

template <int NV, int R>
PetscErrorCode ElementScatter<NV, R>::begin() {
  PetscFunctionBeginUser;
  for (Part &part : parts_) {
    if (!part.mat) continue;
    if (blocked_) PetscCall(MatSeqBAIJGetArray(part.mat, &part.values));
    else PetscCall(MatSeqAIJGetArray(part.mat, &part.values));
  }
  PetscFunctionReturn(0);
}

template <int NV, int R>
PetscErrorCode ElementScatter<NV, R>::end() {
  PetscFunctionBeginUser;
  for (Part &part : parts_) {  // restoring the arrays marks the parts (and so the matrix's assembly) as changed
    if (!part.mat || !part.values) continue;
    if (blocked_) PetscCall(MatSeqBAIJRestoreArray(part.mat, &part.values));
    else PetscCall(MatSeqAIJRestoreArray(part.mat, &part.values));
    part.values = nullptr;
  }
  PetscFunctionReturn(0);
}

template <int NV, int R>
template <class Vertices>
PetscErrorCode ElementScatter<NV, R>::add(Mat J, const VertexTable &verts, size_t e, const Vertices &vertex,
                                          const double *K) {
  constexpr int N = NV * R;
  PetscFunctionBeginUser;
  const std::int32_t *position = position_.data() + e * NV * NV;
  for (int a = 0; a < NV; ++a) {
    const VertexInfo &vi = verts[vertex[a]];
    if (vi.numFree == 0) continue;
    if (!vi.owned) {  // another rank's rows: through the stash, as setElementMatrix adds them
      if (blocked_) {
        PetscInt row = blockIndex<R>(vi), cols[NV];
        for (int b = 0; b < NV; ++b) cols[b] = blockIndex<R>(verts[vertex[b]]);
        PetscCall(MatSetValuesBlocked(J, 1, &row, NV, cols, K + a * R * N, ADD_VALUES));
      } else {
        PetscInt rows[R], cols[N];
        for (int i = 0; i < R; ++i) rows[i] = vi.row(i);
        for (int b = 0; b < NV; ++b)
          for (int j = 0; j < R; ++j) cols[b * R + j] = verts[vertex[b]].row(j);
        PetscCall(MatSetValues(J, R, rows, N, cols, K + a * R * N, ADD_VALUES));
      }
      continue;
    }
    for (int b = 0; b < NV; ++b) {
      const std::int32_t at = position[a * NV + b];
      if (at == kSkip) continue;
      PetscScalar *block = parts_[at & 1].values + (at >> 1);
      const double *k = K + (a * R) * N + b * R;  // row a*R, column b*R of the element matrix
      if (blocked_) {  // BAIJ blocks are stored column by column
        for (int j = 0; j < R; ++j)
          for (int i = 0; i < R; ++i) block[j * R + i] += k[i * N + j];
      } else {
        const std::int32_t length = rowLength_[at & 1][vertex[a]];
        for (int i = 0; i < R; ++i)
          for (int j = 0; j < R; ++j) block[i * length + j] += k[i * N + j];
      }
    }
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
