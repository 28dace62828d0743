// Parallel HDF5 files whose datasets are written and read block by block (NaturalBlocks): every rank opens the
// file (MPI-IO; a single rank uses the POSIX driver), the datasets are created collectively, and each rank moves its
// block of rows (one contiguous hyperslab) in one collective transfer. No rank ever holds more than its block, and a
// file written on one rank count is read on any other. Attribute and dataset creation are collective: every rank
// calls with the same arguments.
#pragma once

#include "core/parallel.hpp"

#include <hdf5.h>

#include <string>
#include <vector>

namespace aries::core {

// Collective: creates (truncates) `path` for parallel writing, or opens it read-only; -1 on failure (on every rank).
hid_t createParallelFile(MPI_Comm comm, const std::string &path);
hid_t openParallelFile(MPI_Comm comm, const std::string &path);

// Collective: dataset `name` (intermediate groups created) of total x comps doubles (rank 1 when comps == 1), this
// rank's block written at rows [blockStart, blockStart + blockSize).
bool writeBlockDataset(hid_t file, const std::string &name, const NaturalBlocks &layout,
                       const std::vector<double> &block, int comps);
// The same for 64-bit integers (the topology).
bool writeBlockIntDataset(hid_t file, const std::string &name, const NaturalBlocks &layout,
                          const std::vector<long long> &block, int comps);
// Collective: this rank's block of `name`, which must be total x comps (false if missing or shaped otherwise).
bool readBlockDataset(hid_t file, const std::string &name, const NaturalBlocks &layout, int comps,
                      std::vector<double> *block);
// The same for 64-bit integers.
bool readBlockIntDataset(hid_t file, const std::string &name, const NaturalBlocks &layout, int comps,
                         std::vector<long long> *block);
// Rows of dataset `name` (its first dimension); -1 if there is no such dataset.
long long datasetRows(hid_t file, const std::string &name);

}  // namespace aries::core
