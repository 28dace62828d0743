#include "core/h5_blocks.hpp"

namespace aries::core {

namespace {

// MPI-IO on several ranks; one rank keeps HDF5's default POSIX driver (no MPI-IO layer to pay for).
hid_t mpioAccess(MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  if (size > 1) H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL);
  return fapl;
}

// The file and memory dataspaces of this rank's block of a total x comps dataset.
struct BlockSpaces {
  hid_t file = -1, memory = -1;
  BlockSpaces(hid_t fileSpace, const NaturalBlocks &layout, int comps) : file(H5Scopy(fileSpace)) {
    const hsize_t start[2] = {static_cast<hsize_t>(layout.blockStart()), 0};
    const hsize_t count[2] = {static_cast<hsize_t>(layout.blockSize()), static_cast<hsize_t>(comps)};
    const int rank = comps > 1 ? 2 : 1;
    memory = H5Screate_simple(rank, count, nullptr);
    if (layout.blockSize() == 0) {
      H5Sselect_none(file);
      H5Sselect_none(memory);
    } else {
      H5Sselect_hyperslab(file, H5S_SELECT_SET, start, nullptr, count, nullptr);
    }
  }
  ~BlockSpaces() {
    H5Sclose(memory);
    H5Sclose(file);
  }
};

// Collective transfers where the file is open with MPI-IO.
hid_t collectiveTransfer(hid_t file) {
  hid_t dxpl = H5Pcreate(H5P_DATASET_XFER);
  hid_t fapl = H5Fget_access_plist(file);
  if (H5Pget_driver(fapl) == H5FD_MPIO) H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE);
  H5Pclose(fapl);
  return dxpl;
}

bool writeBlock(hid_t file, const std::string &name, const NaturalBlocks &layout, const void *block, int comps,
                hid_t memType, hid_t fileType) {
  const hsize_t dims[2] = {static_cast<hsize_t>(layout.total()), static_cast<hsize_t>(comps)};
  hid_t space = H5Screate_simple(comps > 1 ? 2 : 1, dims, nullptr);
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  hid_t dset = H5Dcreate2(file, name.c_str(), fileType, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  bool ok = dset >= 0;
  if (ok && layout.total() > 0) {  // an empty dataset has nothing to write (HDF5 refuses empty transfers)
    BlockSpaces spaces(space, layout, comps);
    hid_t dxpl = collectiveTransfer(file);
    ok = H5Dwrite(dset, memType, spaces.memory, spaces.file, dxpl, block) >= 0;
    H5Pclose(dxpl);
    H5Dclose(dset);
  }
  if (dset >= 0 && layout.total() == 0) H5Dclose(dset);
  H5Pclose(lcpl);
  H5Sclose(space);
  return ok;
}

}  // namespace

hid_t createParallelFile(MPI_Comm comm, const std::string &path) {
  hid_t fapl = mpioAccess(comm);
  hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  H5Pclose(fapl);
  return f;
}

hid_t openParallelFile(MPI_Comm comm, const std::string &path) {
  hid_t fapl = mpioAccess(comm);
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
  H5Pclose(fapl);
  return f;
}

bool writeBlockDataset(hid_t file, const std::string &name, const NaturalBlocks &layout,
                       const std::vector<double> &block, int comps) {
  return block.size() == static_cast<size_t>(layout.blockSize()) * comps &&
         writeBlock(file, name, layout, block.data(), comps, H5T_NATIVE_DOUBLE, H5T_NATIVE_DOUBLE);
}

bool writeBlockIntDataset(hid_t file, const std::string &name, const NaturalBlocks &layout,
                          const std::vector<long long> &block, int comps) {
  return block.size() == static_cast<size_t>(layout.blockSize()) * comps &&
         writeBlock(file, name, layout, block.data(), comps, H5T_NATIVE_LLONG, H5T_NATIVE_LLONG);
}

namespace {

bool readBlock(hid_t file, const std::string &name, const NaturalBlocks &layout, int comps, void *block,
               hid_t memType) {
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0) return false;
  hid_t dset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (dset < 0) return false;
  hid_t space = H5Dget_space(dset);
  hsize_t dims[2] = {0, 0};
  const int nd = H5Sget_simple_extent_dims(space, dims, nullptr);
  bool ok = nd == (comps > 1 ? 2 : 1) && dims[0] == static_cast<hsize_t>(layout.total()) &&
            (comps == 1 || dims[1] == static_cast<hsize_t>(comps));
  if (ok && layout.total() > 0) {
    BlockSpaces spaces(space, layout, comps);
    hid_t dxpl = collectiveTransfer(file);
    ok = H5Dread(dset, memType, spaces.memory, spaces.file, dxpl, block) >= 0;
    H5Pclose(dxpl);
  }
  H5Sclose(space);
  H5Dclose(dset);
  return ok;
}

}  // namespace

bool readBlockDataset(hid_t file, const std::string &name, const NaturalBlocks &layout, int comps,
                      std::vector<double> *block) {
  block->assign(static_cast<size_t>(layout.blockSize()) * comps, 0.0);
  return readBlock(file, name, layout, comps, block->data(), H5T_NATIVE_DOUBLE);
}

bool readBlockIntDataset(hid_t file, const std::string &name, const NaturalBlocks &layout, int comps,
                         std::vector<long long> *block) {
  block->assign(static_cast<size_t>(layout.blockSize()) * comps, 0);
  return readBlock(file, name, layout, comps, block->data(), H5T_NATIVE_LLONG);
}

long long datasetRows(hid_t file, const std::string &name) {
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0) return -1;
  hid_t dset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (dset < 0) return -1;
  hid_t space = H5Dget_space(dset);
  hsize_t dims[2] = {0, 0};
  const int nd = H5Sget_simple_extent_dims(space, dims, nullptr);
  H5Sclose(space);
  H5Dclose(dset);
  return nd >= 1 ? static_cast<long long>(dims[0]) : -1;
}

}  // namespace aries::core
