#include "mesh/cell_files.hpp"

#include "core/errors.hpp"
#include "core/options.hpp"
#include "core/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace aries::fem {

using core::parseReal;

namespace {

// The next line that is neither blank nor a '#' comment, split into whitespace-separated tokens.
bool nextDataLine(std::istream &in, long *lineNo, std::string *line, std::vector<std::string> *tok) {
  while (std::getline(in, *line)) {
    ++*lineNo;
    const auto first = line->find_first_not_of(" \t\r");
    if (first == std::string::npos || (*line)[first] == '#') continue;
    std::istringstream fields(*line);
    std::string t;
    tok->clear();
    while (fields >> t) tok->push_back(t);
    return true;
  }
  return false;
}

}  // namespace

PetscErrorCode readCellVectorFile(MPI_Comm comm, const std::string &file, const char *option, PetscInt numCells,
                                  const std::vector<PetscInt> &cells, int comps, std::vector<double> *values) {
  std::string error;
  core::NaturalBlocks cellBlocks;
  PetscFunctionBeginUser;
  PetscCall(cellBlocks.setupBlocks(comm, numCells));
  const PetscInt blockStart = cellBlocks.blockStart(), blockRows = cellBlocks.blockSize();
  std::vector<double> block(static_cast<size_t>(blockRows) * comps, 0.0);
  {
    std::ifstream in(file);
    std::ostringstream err;
    if (!in) {
      err << "cannot open " << option << " file '" << file << "'";
    } else {
      std::string line;
      std::vector<std::string> tok;
      long lineNo = 0, declared = -1, cell = 0;
      while (err.str().empty() && nextDataLine(in, &lineNo, &line, &tok)) {
        if (declared < 0) {
          double n = 0.0;
          if (tok.size() != 1 || !parseReal(tok[0], &n) || n != std::floor(n) || n < 0)
            err << option << " file '" << file << "' line " << lineNo << ": expected the number of cells";
          else if (n != static_cast<double>(numCells))  // compared as doubles: any count converts exactly
            err << option << " file '" << file << "' declares " << tok[0] << " cells but the mesh has " << numCells;
          declared = numCells;
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
        if (cell >= blockStart && cell < blockStart + blockRows)
          for (int k = 0; k < comps; ++k) block[static_cast<size_t>(cell - blockStart) * comps + k] = v[k] / std::sqrt(n2);
        ++cell;
      }
      if (err.str().empty() && declared < 0) err << option << " file '" << file << "' is empty";
      if (err.str().empty() && cell < numCells)
        err << option << " file '" << file << "' has " << cell << " vectors for " << numCells << " cells";
    }
    error = err.str();
  }
  PetscCall(core::collectiveCheck(comm, !error.empty(), error));  // every rank parsed the same lines
  PetscCall(core::fetchFromBlocks(comm, numCells, block, comps, cells, values));
  PetscFunctionReturn(0);
}

PetscErrorCode readTargetKeyframeFile(MPI_Comm comm, const std::string &file, PetscInt numCells,
                                      const std::vector<PetscInt> &cells, int comps, std::vector<double> *times,
                                      std::vector<double> *targets) {
  std::string error;
  core::NaturalBlocks cellBlocks;
  std::vector<double> block;  // this rank's cells: row (cell - blockStart) holds K x comps values
  PetscFunctionBeginUser;
  PetscCall(cellBlocks.setupBlocks(comm, numCells));
  const PetscInt blockStart = cellBlocks.blockStart(), blockRows = cellBlocks.blockSize();
  {
    std::ifstream in(file);
    std::ostringstream err;
    const std::string where = "-target_file '" + file + "'";
    if (!in) err << "cannot open " << where;
    in.seekg(0, std::ios::end);
    const std::streamoff fileBytes = in ? static_cast<std::streamoff>(in.tellg()) : 0;
    in.seekg(0, std::ios::beg);
    std::string line;
    std::vector<std::string> tok;
    long lineNo = 0, keys = -1, key = -1, cell = 0;
    std::vector<double> ts;
    while (err.str().empty() && nextDataLine(in, &lineNo, &line, &tok)) {
      double a = 0, b = 0;
      if (keys < 0) {
        if (tok.size() != 4 || tok[0] != "cells" || tok[2] != "keyframes" || !parseReal(tok[1], &a) ||
            !parseReal(tok[3], &b) || a != std::floor(a) || b != std::floor(b) || b < 1 || b > 2147483647.0) {
          err << where << " line " << lineNo << ": expected 'cells N keyframes K' (1 <= K <= 2147483647)";
          b = 1;
        } else if (a != static_cast<double>(numCells)) {  // compared as doubles: any count converts exactly
          err << where << " declares " << tok[1] << " cells but the mesh has " << numCells;
        }
        // Every keyframe takes at least numCells lines of comps numbers (2 bytes each, "0 "): a count the file
        // cannot hold is refused here, before the targets' storage is sized by it.
        if (err.str().empty() && b * static_cast<double>(numCells) * comps * 2.0 > static_cast<double>(fileBytes))
          err << where << " declares " << tok[3] << " keyframes of " << numCells << " cells, more than its "
              << fileBytes << " bytes can hold";
        keys = static_cast<long>(b);
        if (err.str().empty()) block.assign(static_cast<size_t>(blockRows) * keys * comps, 0.0);
        continue;
      }
      if (tok.size() == 2 && tok[0] == "time") {
        if (key >= 0 && cell < numCells) {
          err << where << " line " << lineNo << ": keyframe " << key + 1 << " has " << cell << " targets for "
              << numCells << " cells";
        } else if (key + 1 >= keys) {
          err << where << " line " << lineNo << ": more than the declared " << keys << " keyframes";
        } else if (!parseReal(tok[1], &a) || !std::isfinite(a)) {
          err << where << " line " << lineNo << ": 'time' needs a number";
        } else if (!ts.empty() && !(a > ts.back())) {
          err << where << " line " << lineNo << ": keyframe times must increase (" << a << " after " << ts.back()
              << ")";
        }
        ts.push_back(a);
        ++key;
        cell = 0;
        continue;
      }
      if (key < 0) {
        err << where << " line " << lineNo << ": expected 'time t' before the first keyframe's targets";
      } else if (cell >= numCells) {
        err << where << " line " << lineNo << ": keyframe " << key + 1 << " has more than " << numCells << " targets";
      } else if (static_cast<int>(tok.size()) != comps) {
        err << where << " line " << lineNo << ": expected " << comps << " numbers (" << (comps == 6 ? "s11 s22 s33 s12 s23 s13" : "s11 s22 s12")
            << "), got " << tok.size();
      } else {
        const bool mine = cell >= blockStart && cell < blockStart + blockRows;
        for (int k = 0; k < comps; ++k) {
          if (!parseReal(tok[k], &a) || !std::isfinite(a)) {
            err << where << " line " << lineNo << ": not a finite number: '" << tok[k] << "'";
            break;
          }
          if (mine) block[(static_cast<size_t>(cell - blockStart) * keys + key) * comps + k] = a;
        }
        ++cell;
      }
    }
    if (err.str().empty() && keys < 0) err << where << " is empty";
    if (err.str().empty() && (key + 1 < keys || cell < numCells))
      err << where << " ends early: " << key + 1 << " of " << keys << " keyframes, the last with " << cell << " of "
          << numCells << " targets";
    error = err.str();
    *times = ts;
  }
  PetscCall(core::collectiveCheck(comm, !error.empty(), error));  // every rank parsed the same lines
  const int keys = static_cast<int>(times->size());
  std::vector<double> local;  // per local cell: K x comps
  PetscCall(core::fetchFromBlocks(comm, numCells, block, keys * comps, cells, &local));
  const size_t nc = cells.size();
  targets->assign(static_cast<size_t>(keys) * nc * comps, 0.0);
  for (size_t c = 0; c < nc; ++c)
    for (int k = 0; k < keys; ++k)
      std::copy_n(&local[(c * keys + k) * comps], comps, &(*targets)[(k * nc + c) * comps]);
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
