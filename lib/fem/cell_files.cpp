#include "fem/cell_files.hpp"

#include "fem/options.hpp"
#include "fem/errors.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

namespace aries::fem {

PetscErrorCode readCellVectorFile(MPI_Comm comm, const std::string &file, const char *option, PetscInt numCells,
                                  int comps, std::vector<double> *values) {
  PetscMPIInt rank;
  std::string error;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  values->assign(static_cast<size_t>(numCells) * comps, 0.0);
  if (rank == 0) {
    std::ifstream in(file);
    std::ostringstream err;
    if (!in) {
      err << "cannot open " << option << " file '" << file << "'";
    } else {
      std::string line;
      long lineNo = 0, declared = -1, cell = 0;
      while (err.str().empty() && std::getline(in, line)) {
        ++lineNo;
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        std::istringstream fields(line);
        std::vector<std::string> tok;
        std::string t;
        while (fields >> t) tok.push_back(t);
        if (declared < 0) {
          double n;
          if (tok.size() != 1 || !parseReal(tok[0], &n) || n != std::floor(n) || n < 0)
            err << option << " file '" << file << "' line " << lineNo << ": expected the number of cells";
          else if (static_cast<PetscInt>(n) != numCells)
            err << option << " file '" << file << "' declares " << static_cast<long>(n) << " cells but the mesh has "
                << numCells;
          declared = static_cast<long>(n);
          continue;
        }
        if (cell >= numCells) {
          err << option << " file '" << file << "' line " << lineNo << ": more than " << numCells << " vectors";
          break;
        }
        if (!(static_cast<int>(tok.size()) == comps || (comps == 2 && tok.size() == 3))) {
          err << option << " file '" << file << "' line " << lineNo << ": expected " << comps << " numbers, got "
              << tok.size();
          break;
        }
        double v[3] = {0, 0, 0}, n2 = 0.0;
        bool ok = true;
        for (size_t k = 0; k < tok.size(); ++k) ok = ok && parseReal(tok[k], &v[k]);
        if (!ok) {
          err << option << " file '" << file << "' line " << lineNo << ": not a number in '" << line << "'";
          break;
        }
        if (comps == 2 && tok.size() == 3 && v[2] != 0.0) {
          err << option << " file '" << file << "' line " << lineNo
              << ": 2D elements take in-plane vectors (z must be 0)";
          break;
        }
        for (int k = 0; k < comps; ++k) n2 += v[k] * v[k];
        if (!(n2 > 0.0) || !std::isfinite(n2)) {
          err << option << " file '" << file << "' line " << lineNo << ": zero-length vector for cell " << cell;
          break;
        }
        for (int k = 0; k < comps; ++k) (*values)[static_cast<size_t>(cell) * comps + k] = v[k] / std::sqrt(n2);
        ++cell;
      }
      if (err.str().empty() && declared < 0) err << option << " file '" << file << "' is empty";
      if (err.str().empty() && cell < numCells)
        err << option << " file '" << file << "' has " << cell << " vectors for " << numCells << " cells";
    }
    error = err.str();
  }
  int len = static_cast<int>(error.size());
  PetscCallMPI(MPI_Bcast(&len, 1, MPI_INT, 0, comm));
  error.resize(len);
  PetscCallMPI(MPI_Bcast(error.data(), len, MPI_CHAR, 0, comm));
  PetscCall(fem::collectiveCheck(comm, !error.empty() && rank == 0, error));
  PetscCallMPI(MPI_Bcast(values->data(), static_cast<int>(values->size()), MPI_DOUBLE, 0, comm));
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
