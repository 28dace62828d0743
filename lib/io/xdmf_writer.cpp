#include "io/xdmf_writer.hpp"

#include "core/errors.hpp"
#include "io/files.hpp"
#include "io/h5_attributes.hpp"

#include <hdf5.h>

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace aries::io {

namespace {

bool writeDataset(hid_t file, const char *path, const double *data, hsize_t rows, hsize_t cols) {
  const hsize_t dims[2] = {rows, cols};
  hid_t space = H5Screate_simple(cols > 1 ? 2 : 1, dims, nullptr);
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  hid_t dset = H5Dcreate2(file, path, H5T_NATIVE_DOUBLE, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  bool ok = dset >= 0 && H5Dwrite(dset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
  if (dset >= 0) H5Dclose(dset);
  H5Pclose(lcpl);
  H5Sclose(space);
  return ok;
}

bool writeIntDataset(hid_t file, const char *path, const std::vector<PetscInt> &data, hsize_t rows, hsize_t cols) {
  std::vector<long long> v(data.begin(), data.end());
  const hsize_t dims[2] = {rows, cols};
  hid_t space = H5Screate_simple(2, dims, nullptr);
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  hid_t dset = H5Dcreate2(file, path, H5T_NATIVE_LLONG, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  bool ok = dset >= 0 && H5Dwrite(dset, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) >= 0;
  if (dset >= 0) H5Dclose(dset);
  H5Pclose(lcpl);
  H5Sclose(space);
  return ok;
}

}  // namespace

PetscErrorCode XdmfWriter::open(MPI_Comm comm, const std::string &base, const std::vector<PetscInt> &cells,
                                int verticesPerCell, const std::vector<double> &rest, PetscInt resumeAfterStep) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  comm_ = comm;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  base_ = base;
  dir_ = directoryOf(base);
  name_ = fileNameOf(base);
  if (name_.empty())
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -output '%s' needs a file name: -output DIR/NAME", base.c_str());
  meshFile_ = name_ + ".h5";
  xmf_ = base + ".xmf";
  verticesPerCell_ = verticesPerCell;
  std::string err;
  if (rank == 0) {
    numCells_ = static_cast<PetscInt>(cells.size() / verticesPerCell);
    numVertices_ = static_cast<PetscInt>(rest.size() / 3);
    rest_ = rest;
    if (!makeDirectories(dir_ + "/" + name_ + ".steps")) {
      err = "cannot create output directory '" + dir_ + "/" + name_ + ".steps' (-output)";
    } else {
      const std::string tmp = base + ".h5.tmp";
      hid_t f = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
      bool ok = f >= 0 && writeIntDataset(f, "/mesh/topology", cells, numCells_, verticesPerCell) &&
                writeDataset(f, "/mesh/rest", rest.data(), numVertices_, 3) && writeVersionAttributes(f);
      if (f >= 0) ok = H5Fclose(f) >= 0 && ok;
      if (!ok || std::rename(tmp.c_str(), (base + ".h5").c_str()) != 0)
        err = "cannot write '" + base + ".h5' (-output)";
    }
    // Restart: keep the complete step files of the steps before the restart point in the index.
    for (PetscInt k = 0; err.empty() && k <= resumeAfterStep; ++k) {
      std::ostringstream fname;
      fname << name_ << ".steps/" << name_ << "_" << std::setw(6) << std::setfill('0') << k << ".h5";
      const std::string p = dir_ + "/" + fname.str();
      std::FILE *probe = std::fopen(p.c_str(), "rb");
      if (!probe) continue;
      std::fclose(probe);
      double time = 0.0;
      hid_t f = H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
      if (f >= 0) {
        readScalarAttribute(f, "time", H5T_NATIVE_DOUBLE, &time);
        H5Fclose(f);
        steps_.push_back({k, time, fname.str()});
      }
    }
  }
  PetscCall(core::collectiveCheck(comm, !err.empty(), err));
  PetscFunctionReturn(0);
}

PetscErrorCode XdmfWriter::writeStep(PetscInt step, double time, const std::vector<double> &positions,
                                     const std::vector<CellField> &cellFields,
                                     const std::vector<CellField> &vertexFields) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm_, &rank));
  std::string err;
  if (rank == 0) {
    std::ostringstream fname;
    fname << name_ << ".steps/" << name_ << "_" << std::setw(6) << std::setfill('0') << step << ".h5";
    const std::string path = dir_ + "/" + fname.str(), tmp = path + ".tmp";
    std::vector<double> disp(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) disp[i] = positions[i] - rest_[i];
    hid_t f = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    bool ok = f >= 0 && writeDataset(f, "/positions", positions.data(), numVertices_, 3) &&
              writeDataset(f, "/displacement", disp.data(), numVertices_, 3) && writeVersionAttributes(f);
    // the step's time, for restarts (the index is rebuilt from the step files)
    ok = ok && writeScalarAttribute(f, "time", H5T_NATIVE_DOUBLE, time);
    cellFieldLayout_.clear();
    for (const auto &cf : cellFields) {
      ok = ok && writeDataset(f, ("/cell/" + cf.name).c_str(), cf.values.data(), numCells_, cf.components);
      cellFieldLayout_.emplace_back(cf.name, cf.components);
    }
    vertexFieldLayout_.clear();
    for (const auto &vf : vertexFields) {
      ok = ok && writeDataset(f, ("/vertex/" + vf.name).c_str(), vf.values.data(), numVertices_, vf.components);
      vertexFieldLayout_.emplace_back(vf.name, vf.components);
    }
    if (f >= 0) ok = H5Fclose(f) >= 0 && ok;
    if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) err = "cannot write output step file '" + path + "'";
    if (err.empty()) {
      steps_.push_back({step, time, fname.str()});
      PetscCall(writeXmf());
    }
  }
  PetscCall(core::collectiveCheck(comm_, !err.empty(), err));
  PetscFunctionReturn(0);
}

PetscErrorCode XdmfWriter::writeXmf() {
  PetscFunctionBeginUser;
  const char *topo = verticesPerCell_ == 4 ? "Tetrahedron" : "Triangle";
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
    << "<Grid Name=\"aries\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  x << std::setprecision(15);  // times shown as ParaView users expect: 0.3, not 0.30000000000000004
  for (const auto &s : steps_) {
    x << "  <Grid Name=\"step " << s.step << "\" GridType=\"Uniform\">\n"
      << "    <Time Value=\"" << s.time << "\"/>\n"
      << "    <Topology TopologyType=\"" << topo << "\" NumberOfElements=\"" << numCells_ << "\">\n"
      << "      <DataItem Dimensions=\"" << numCells_ << " " << verticesPerCell_
      << "\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">" << meshFile_ << ":/mesh/topology</DataItem>\n"
      << "    </Topology>\n"
      // Geometry = the rest shape, plus the step's displacement: WarpByVector (scale 1) shows the deformed body and
      // meshio's TimeSeriesReader gets one mesh and per-step data (the positions stay in the step file).
      << "    <Geometry GeometryType=\"XYZ\">\n"
      << "      <DataItem Dimensions=\"" << numVertices_ << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
      << meshFile_ << ":/mesh/rest</DataItem>\n    </Geometry>\n";
    // one field of the step file: name, components (1, 3, 9), on cells or vertices, its dataset
    const auto attribute = [&](const std::string &name, int comps, bool cell, const std::string &dataset) {
      const char *type = comps == 1 ? "Scalar" : comps == 9 ? "Tensor" : "Vector";
      x << "    <Attribute Name=\"" << name << "\" AttributeType=\"" << type << "\" Center=\""
        << (cell ? "Cell" : "Node") << "\">\n"
        << "      <DataItem Dimensions=\"" << (cell ? numCells_ : numVertices_);
      if (comps > 1) x << " " << comps;
      x << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << s.file << ":" << dataset
        << "</DataItem>\n    </Attribute>\n";
    };
    attribute("displacement", 3, false, "/displacement");
    for (const auto &vf : vertexFieldLayout_) attribute(vf.first, vf.second, false, "/vertex/" + vf.first);
    for (const auto &cf : cellFieldLayout_) attribute(cf.first, cf.second, true, "/cell/" + cf.first);
    x << "  </Grid>\n";
  }
  x << "</Grid>\n</Domain>\n</Xdmf>\n";
  const std::string tmp = xmf_ + ".tmp";
  {
    std::ofstream out(tmp);
    out << x.str();
    if (!out) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write '%s'", tmp.c_str());
  }
  if (std::rename(tmp.c_str(), xmf_.c_str()) != 0)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot rename '%s' to '%s'", tmp.c_str(), xmf_.c_str());
  PetscFunctionReturn(0);
}

}  // namespace aries::io
