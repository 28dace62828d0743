#include "io/xdmf_writer.hpp"

#include "core/errors.hpp"
#include "io/files.hpp"
#include "io/h5_attributes.hpp"
#include "core/h5_blocks.hpp"

#include <hdf5.h>

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace aries::io {

namespace {

// The step file of step k, relative to the output directory.
std::string stepFileName(const std::string &name, PetscInt step) {
  std::ostringstream f;
  f << name << ".steps/" << name << "_" << std::setw(6) << std::setfill('0') << step << ".h5";
  return f.str();
}

}  // namespace

PetscErrorCode XdmfWriter::open(MPI_Comm comm, const std::string &base, const core::NaturalBlocks &vertices,
                                const core::NaturalBlocks &cells, const std::vector<PetscInt> &topology,
                                int verticesPerCell, const char *topologyType, const std::vector<double> &rest,
                                PetscInt resumeAfterStep) {
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
  vertices_ = &vertices;
  cells_ = &cells;
  numVertices_ = vertices.total();
  numCells_ = cells.total();
  verticesPerCell_ = verticesPerCell;
  topologyType_ = topologyType;
  std::vector<double> topologyOwned(topology.begin(), topology.end()), topologyBlock;  // ids exact as doubles
  PetscCall(cells.toBlocks(topologyOwned, verticesPerCell, &topologyBlock));
  PetscCall(vertices.toBlocks(rest, 3, &restBlock_));
  const std::vector<long long> topologyIds(topologyBlock.begin(), topologyBlock.end());
  std::string err;
  if (rank == 0 && !makeDirectories(dir_ + "/" + name_ + ".steps"))
    err = "cannot create output directory '" + dir_ + "/" + name_ + ".steps' (-output)";
  PetscCall(core::collectiveCheck(comm, !err.empty(), err));
  const std::string tmp = base + ".h5.tmp";
  hid_t f = core::createParallelFile(comm, tmp);
  bool ok = f >= 0 && core::writeBlockIntDataset(f, "/mesh/topology", cells, topologyIds, verticesPerCell) &&
            core::writeBlockDataset(f, "/mesh/rest", vertices, restBlock_, 3) && writeVersionAttributes(f);
  if (f >= 0) ok = H5Fclose(f) >= 0 && ok;
  int good = ok, allGood = 0;
  PetscCallMPI(MPI_Allreduce(&good, &allGood, 1, MPI_INT, MPI_MIN, comm));
  if (rank == 0) {
    if (!allGood || std::rename(tmp.c_str(), (base + ".h5").c_str()) != 0) err = "cannot write '" + base + ".h5' (-output)";
    // Restart: keep the complete step files of the steps before the restart point in the index.
    for (PetscInt k = 0; err.empty() && k <= resumeAfterStep; ++k) {
      const std::string fname = stepFileName(name_, k), p = dir_ + "/" + fname;
      std::FILE *probe = std::fopen(p.c_str(), "rb");
      if (!probe) continue;
      std::fclose(probe);
      double time = 0.0;
      hid_t sf = H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
      if (sf >= 0) {
        readScalarAttribute(sf, "time", H5T_NATIVE_DOUBLE, &time);
        H5Fclose(sf);
        steps_.push_back({k, time, fname});
      }
    }
  }
  PetscCall(core::collectiveCheck(comm, !err.empty(), err));
  PetscFunctionReturn(0);
}

PetscErrorCode XdmfWriter::beginStep(PetscInt step, double time, const std::vector<double> &positions) {
  PetscFunctionBeginUser;
  open_ = OpenStep{-1, false, step, time, stepFileName(name_, step)};
  std::vector<double> block, disp;
  PetscCall(vertices_->toBlocks(positions, 3, &block));
  disp.resize(block.size());
  for (size_t i = 0; i < block.size(); ++i) disp[i] = block[i] - restBlock_[i];
  open_.file = core::createParallelFile(comm_, dir_ + "/" + open_.name + ".tmp");
  open_.ok = open_.file >= 0 && core::writeBlockDataset(open_.file, "/positions", *vertices_, block, 3) &&
             core::writeBlockDataset(open_.file, "/displacement", *vertices_, disp, 3) && writeVersionAttributes(open_.file);
  // the step's time, for restarts (the index is rebuilt from the step files)
  open_.ok = open_.ok && writeScalarAttribute(open_.file, "time", H5T_NATIVE_DOUBLE, time);
  cellFieldLayout_.clear();
  vertexFieldLayout_.clear();
  PetscFunctionReturn(0);
}

PetscErrorCode XdmfWriter::writeField(const CellField &field, bool perCell) {
  PetscFunctionBeginUser;
  const core::NaturalBlocks &layout = perCell ? *cells_ : *vertices_;
  std::vector<double> block;
  PetscCall(layout.toBlocks(field.values, field.components, &block));
  open_.ok = open_.ok && core::writeBlockDataset(open_.file, (perCell ? "/cell/" : "/vertex/") + field.name, layout, block,
                                           field.components);
  (perCell ? cellFieldLayout_ : vertexFieldLayout_).emplace_back(field.name, field.components);
  PetscFunctionReturn(0);
}

PetscErrorCode XdmfWriter::endStep() {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm_, &rank));
  if (open_.file >= 0) open_.ok = H5Fclose(open_.file) >= 0 && open_.ok;
  open_.file = -1;
  int good = open_.ok, allGood = 0;
  PetscCallMPI(MPI_Allreduce(&good, &allGood, 1, MPI_INT, MPI_MIN, comm_));
  const std::string path = dir_ + "/" + open_.name, tmp = path + ".tmp";
  std::string err;
  if (rank == 0) {
    if (!allGood || std::rename(tmp.c_str(), path.c_str()) != 0) err = "cannot write output step file '" + path + "'";
    if (err.empty()) {
      steps_.push_back({open_.step, open_.time, open_.name});
      PetscCall(writeXmf());
    }
  }
  PetscCall(core::collectiveCheck(comm_, !err.empty(), err));
  PetscFunctionReturn(0);
}

PetscErrorCode XdmfWriter::writeXmf() {
  PetscFunctionBeginUser;
  const char *topo = topologyType_.c_str();
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
