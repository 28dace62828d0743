// HDF5 + XDMF output that ParaView opens (-output DIR/NAME):
//   DIR/NAME.h5                 the mesh: /mesh/topology (cells x vertices, natural gmsh order), /mesh/rest
//   DIR/NAME.steps/NAME_<k>.h5  one file per output step: /positions, /displacement, /vertex/<f> (vertex fields)
//                               and /cell/<f> (cell fields); 9 components are a row-major 3x3 tensor
//   DIR/NAME.xmf                temporal collection over the steps written so far
// Every file is written under a temporary name and renamed when complete, and the .xmf is rewritten after each
// step, so a run killed at any moment leaves the last complete step readable. Datasets are in natural (gmsh) order and
// written collectively, each rank its block of rows (core/h5_blocks.hpp): identical files for any number of ranks, and no
// rank holds more than its block of any of them.
#pragma once

#include "core/parallel.hpp"

#include <hdf5.h>

#include <petscsys.h>

#include <string>
#include <vector>

namespace aries::io {

struct CellField {  // a cell or vertex field
  std::string name;
  int components;              // 1, 3 or 9 (XDMF Scalar, Vector, Tensor)
  std::vector<double> values;  // this rank's owned cells or vertices, in the order of the writer's layouts
};

class XdmfWriter {
 public:
  // Collective. `vertices` and `cells` (kept by reference, they must outlive the writer) say which natural ids this
  // rank's values are for; `cells` holds the natural vertex ids of this rank's owned cells (`verticesPerCell` each, in
  // the order of the XDMF `topologyType`) and `rest` its owned vertices' rest positions (x3). With resumeAfterStep >= 0
  // (restart) the existing step files up to that step stay in the index.
  PetscErrorCode open(MPI_Comm comm, const std::string &base, const core::NaturalBlocks &vertices,
                      const core::NaturalBlocks &cells, const std::vector<PetscInt> &topology, int verticesPerCell,
                      const char *topologyType, const std::vector<double> &rest, PetscInt resumeAfterStep = -1);
  // One output step, written field by field so that a rank holds one field at a time: beginStep creates the step file
  // with `positions` (x3, this rank's owned vertices) and the displacement, writeField adds a cell or vertex field
  // (values on this rank's owned cells or vertices), endStep completes the file and the index. All collective.
  PetscErrorCode beginStep(PetscInt step, double time, const std::vector<double> &positions);
  PetscErrorCode writeField(const CellField &field, bool perCell);
  PetscErrorCode endStep();
  const std::string &xmfPath() const { return xmf_; }
  bool isOpen() const { return !base_.empty(); }

 private:
  struct StepEntry {
    PetscInt step;
    double time;
    std::string file;  // relative to the output directory
  };
  PetscErrorCode writeXmf();

  MPI_Comm comm_ = MPI_COMM_NULL;
  std::string base_, dir_, name_, meshFile_, xmf_;
  const core::NaturalBlocks *vertices_ = nullptr, *cells_ = nullptr;
  PetscInt numCells_ = 0, numVertices_ = 0;
  int verticesPerCell_ = 4;
  std::string topologyType_;  // XDMF TopologyType: the element type's (kernels/elements/)
  std::vector<double> restBlock_;  // this rank's block of the rest positions (the displacement's reference)
  std::vector<StepEntry> steps_;
  std::vector<std::pair<std::string, int>> cellFieldLayout_, vertexFieldLayout_;
  struct OpenStep {  // the step file being written (beginStep .. endStep)
    hid_t file = -1;
    bool ok = false;
    PetscInt step = 0;
    double time = 0.0;
    std::string name;  // relative to the output directory
  } open_;
};

}  // namespace aries::io
