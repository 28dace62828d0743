// Parallel helpers shared by every layer above: point-SF leaves, centroids, gathers onto rank 0 (small data only) and
// the natural-block layout that output and restart use instead of gathering whole-mesh arrays.
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

// The rank whose block (NaturalBlocks: `size` contiguous blocks, the first total % size one entry longer) holds
// natural id `id`.
int blockOwner(PetscInt id, PetscInt total, int size);
// The first natural id of rank `rank`'s block (blockBegin(size, ...) == total).
PetscInt blockBegin(int rank, PetscInt total, int size);

// The exchange in which row i of a rank's list goes to rank dest[i] (any ranks, any number of rows per rank), set up
// once (one MPI_Alltoall of counts). forward: the list's rows -> the rows this rank receives, grouped by source rank in
// rank order (each source's rows in its list order); backward: one reply row per received row -> the replies at their
// rows' places in the list. Each move is one MPI_Alltoallv; T is double or long long.
class RowRoute {
 public:
  PetscErrorCode setup(MPI_Comm comm, const std::vector<int> &dest);  // collective
  bool ready() const { return !sendCounts_.empty(); }
  size_t numSent() const { return order_.size(); }
  size_t numReceived() const { return numReceived_; }
  template <class T>
  PetscErrorCode forward(const std::vector<T> &rows, int comps, std::vector<T> *received) const;
  template <class T>
  PetscErrorCode backward(const std::vector<T> &replies, int comps, std::vector<T> *rows) const;

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  std::vector<size_t> order_;                // list row of each send slot (slots sorted by destination rank)
  std::vector<int> sendCounts_, sendDispl_;  // rows per destination rank
  std::vector<int> recvCounts_, recvDispl_;  // rows per source rank
  size_t numReceived_ = 0;
};

// Collective: `values` receives, for each of `ids` (natural ids in [0, total), any order, repeats and ids wanted by
// several ranks allowed), its `comps` values from `block`, the rows this rank holds of the blocked array (rank r's rows
// are block r of NaturalBlocks' split of [0, total)). Two MPI_Alltoallv; no rank holds more than its block and its ids.
PetscErrorCode fetchFromBlocks(MPI_Comm comm, PetscInt total, const std::vector<double> &block, int comps,
                               const std::vector<PetscInt> &ids, std::vector<double> *values);

// The natural numbering [0, total) of vertices or cells split into one contiguous block per rank (rank r holds
// [start(r), start(r + 1)), sizes differing by at most one), and the exchange between the entries each rank owns
// (natural ids in any order, each id owned by one rank) and those blocks. Output files are written block by block
// (each rank one contiguous hyperslab, no rank ever holds the whole mesh) and restarts read them the same way, on any
// number of ranks. The exchange pattern is computed once (setup); every move is one MPI_Alltoallv.
class NaturalBlocks {
 public:
  // Collective: `owned` are the natural ids of the entries this rank will pass to toBlocks / receive from fromBlocks.
  PetscErrorCode setup(MPI_Comm comm, PetscInt total, const std::vector<PetscInt> &owned);
  // The blocks alone (no exchange: toBlocks / fromBlocks refuse), for reading a file's rows block by block.
  PetscErrorCode setupBlocks(MPI_Comm comm, PetscInt total);
  PetscInt total() const { return total_; }
  PetscInt blockStart() const { return blockStart_; }
  PetscInt blockSize() const { return blockSize_; }
  size_t numOwned() const { return route_.numSent(); }
  // Collective: `owned` holds `comps` values per owned entry (setup's order); `block` receives blockSize() * comps
  // values, row i the entry of natural id blockStart() + i. Every id of the block must be owned by some rank.
  PetscErrorCode toBlocks(const std::vector<double> &owned, int comps, std::vector<double> *block) const;
  // Collective, the reverse: each owned entry receives its row of the blocks.
  PetscErrorCode fromBlocks(const std::vector<double> &block, int comps, std::vector<double> *owned) const;

 private:
  PetscInt total_ = 0, blockStart_ = 0, blockSize_ = 0;
  RowRoute route_;                 // owned entries -> the ranks whose blocks hold them
  std::vector<PetscInt> recvRow_;  // block row of each received entry
};

}  // namespace aries::core
