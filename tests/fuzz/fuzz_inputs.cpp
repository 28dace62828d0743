// Bounded-time fuzz test of aries' input readers, built with AddressSanitizer + UndefinedBehaviorSanitizer:
//   * the option readers (material options for every element shape, boundary options, strict number/list parsing)
//     on generated option strings: random names from aries' vocabulary with random, malformed or extreme values;
//   * the gmsh structure check on mutations of a valid MSH 2.2 file (line deletion/duplication, truncation, garbage
//     tokens, changed counts, element types and node references, random bytes);
//   * the per-cell vector file reader on generated files (counts, token counts, zero/NaN vectors, junk).
// Every call must return success or a user-input/file error (PETSC_ERR_USER_INPUT, PETSC_ERR_FILE_*); any other
// error code, a crash or a sanitizer report fails the test.
//   aries-fuzz-inputs [-seconds S] [-seed N]     (defaults 20 s, seed 1)
#include "fem/boundary.hpp"
#include "mesh/cell_files.hpp"
#include "mesh/gmsh_check.hpp"
#include "fem/material_options.hpp"
#include "core/options.hpp"

#include <petscsys.h>

#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace aries;

namespace {

const char kValidMesh[] =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 1 \"bottom\"\n3 1 \"body\"\n$EndPhysicalNames\n"
    "$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n$EndNodes\n"
    "$Elements\n3\n1 2 2 1 1 1 2 3\n2 4 2 1 1 1 2 3 4\n3 4 2 1 1 2 3 4 5\n$EndElements\n";

const char *const kOptions[] = {"-energy", "-E", "-nu", "-mu", "-lambda", "-gamma", "-beta", "-mu1", "-mu2",
                                "-fiber", "-fiber2", "-ortho_mu", "-aniso_dirs", "-aniso_mu", "-target", "-curvature",
                                "-singularity", "-mollifier_eps", "-mollifier_proxy", "-barrier_eps",
                                "-barrier_stiffness", "-bc_clamp", "-bc_box", "-bc_ramp_steps", "-bc_clamp_1_translate",
                                "-bc_clamp_1_rotate", "-bc_clamp_1_axis", "-bc_clamp_1_center"};

class Fuzzer {
 public:
  explicit Fuzzer(unsigned seed) : rng_(seed) {}
  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }
  double uniform() { return std::uniform_real_distribution<double>(0, 1)(rng_); }

  std::string number() {
    static const char *const special[] = {"nan", "inf", "-inf", "1e400", "-1e400", "0", "-0", "1e-320", "0x1p3",
                                          "1e4x", "", " ", "--1", "1..2", "+", "-", "e5", "1,", ",", "3.14.15"};
    switch (pick(4)) {
      case 0: return special[pick(sizeof(special) / sizeof(*special))];
      case 1: return std::to_string(pick(2001) - 1000);
      case 2: return std::to_string((uniform() - 0.5) * std::pow(10.0, pick(40) - 20));
      default: return std::to_string(uniform());
    }
  }
  std::string list() {
    std::string s;
    const int n = pick(12);
    for (int i = 0; i < n; ++i) s += (i ? "," : "") + number();
    return s;
  }
  std::string word() {
    static const char *const words[] = {"iarap", "alx", "fiber", "ortho", "aniso", "bw", "bw46s", "shape_target",
                                        "caricature", "kim_aa", "none", "mollifier", "barrier", "bogus", "1", "top",
                                        "1,2,1", "", "\"q\"", "%s%n"};
    return words[pick(sizeof(words) / sizeof(*words))];
  }
  std::string optionString() {
    std::string s;
    const int n = 1 + pick(8);
    for (int i = 0; i < n; ++i) {
      s += std::string(kOptions[pick(sizeof(kOptions) / sizeof(*kOptions))]) + " ";
      const int k = pick(3);
      s += (k == 0 ? number() : k == 1 ? list() : word());
      s += " ";
    }
    return s;
  }
  std::string mutatedMesh() {
    std::vector<std::string> lines;
    std::istringstream in(kValidMesh);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    const int m = 1 + pick(4);
    for (int k = 0; k < m && !lines.empty(); ++k) {
      const int i = pick(static_cast<int>(lines.size()));
      switch (pick(7)) {
        case 0: lines.erase(lines.begin() + i); break;
        case 1: lines.insert(lines.begin() + i, lines[i]); break;
        case 2: lines[i] = number() + " " + number() + " " + number(); break;
        case 3: lines.resize(i); break;
        case 4: lines[i] += " " + number(); break;
        case 5: lines[i] = std::to_string(pick(3) == 0 ? 1000000000 : pick(40)); break;
        default: {
          std::string junk(1 + pick(20), ' ');
          for (char &c : junk) c = static_cast<char>(1 + pick(255));
          lines[i] = junk;
        }
      }
    }
    std::string out;
    for (const auto &l : lines) out += l + "\n";
    if (pick(4) == 0 && !out.empty()) out.resize(pick(static_cast<int>(out.size())));
    return out;
  }
  std::string vectorFile(int *numCells) {
    *numCells = pick(5);
    std::string s = pick(3) ? "# fibers\n" : "";
    s += (pick(5) ? std::to_string(pick(6)) : number()) + "\n";
    const int n = pick(7);
    for (int i = 0; i < n; ++i) {
      const int k = pick(5);
      for (int j = 0; j < k; ++j) s += (pick(4) ? std::to_string(pick(3) - 1) : number()) + " ";
      s += "\n";
    }
    return s;
  }

 private:
  std::mt19937 rng_;
};

bool acceptable(PetscErrorCode ierr) {
  return ierr == 0 || ierr == PETSC_ERR_USER_INPUT || ierr == PETSC_ERR_FILE_OPEN || ierr == PETSC_ERR_FILE_READ ||
         ierr == PETSC_ERR_FILE_UNEXPECTED;
}

}  // namespace

int main(int argc, char **argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr)) return 2;
  PetscReal seconds = 20;
  PetscInt seed = 1;
  PetscOptionsGetReal(nullptr, nullptr, "-seconds", &seconds, nullptr);
  PetscOptionsGetInt(nullptr, nullptr, "-seed", &seed, nullptr);
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);  // errors are results here; nothing to print
  Fuzzer fz(static_cast<unsigned>(seed));
  const std::string dir = "/tmp/aries-fuzz-" + std::to_string(getpid());
  std::error_code fsError;
  std::filesystem::create_directories(dir, fsError);
  if (fsError) {
    std::fprintf(stderr, "aries-fuzz-inputs: cannot create %s: %s\n", dir.c_str(), fsError.message().c_str());
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  long cases[3] = {0, 0, 0}, errors[3] = {0, 0, 0};
  int failures = 0;
  auto report = [&](int kind, PetscErrorCode ierr, const std::string &input) {
    ++cases[kind];
    if (ierr) ++errors[kind];
    if (!acceptable(ierr)) {
      std::fprintf(stderr, "FAIL: reader returned error code %d (not a user-input error) on input:\n%s\n", (int)ierr,
                   input.c_str());
      ++failures;
    }
  };
  while (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < seconds && failures < 5) {
    const int kind = fz.pick(3);
    if (kind == 0) {
      const std::string opts = fz.optionString();
      PetscOptionsClear(nullptr);
      PetscErrorCode ierr = PetscOptionsInsertString(nullptr, opts.c_str());
      if (!ierr) {
        energies::Material m;
        fem::UniformCellData cell;
        const energies::ElementShape shape =
            std::array<energies::ElementShape, 3>{energies::ElementShape::Tet, energies::ElementShape::Planar,
                                                  energies::ElementShape::Cloth}[fz.pick(3)];
        ierr = fem::readMaterialOptions(nullptr, shape, nullptr, nullptr, false, &m, &cell);
        if (acceptable(ierr)) {
          fem::BoundarySpec bc;
          const PetscErrorCode ierr2 = fem::readBoundaryOptions(&bc);
          if (ierr2) ierr = ierr2;
        }
      } else {
        ierr = PETSC_ERR_USER_INPUT;  // PETSc rejected the string itself (e.g. unbalanced quotes): a clean refusal
      }
      report(0, ierr, opts);
    } else if (kind == 1) {
      const std::string text = fz.mutatedMesh(), path = dir + "/m.msh";
      std::ofstream(path) << text;
      fem::GmshFacts facts;
      report(1, fem::validateGmshFile(PETSC_COMM_WORLD, path, &facts), text);
    } else {
      int numCells = 0;
      const std::string text = fz.vectorFile(&numCells), path = dir + "/f.txt";
      std::ofstream(path) << text;
      std::vector<double> values;
      std::vector<PetscInt> cells(numCells > 0 ? numCells : 0);  // every cell on this (single) rank
      for (size_t c = 0; c < cells.size(); ++c) cells[c] = static_cast<PetscInt>(c);
      report(2, fem::readCellVectorFile(PETSC_COMM_WORLD, path, "-fiber_file", numCells, cells, 1 + fz.pick(3), &values),
             text);
    }
  }
  PetscOptionsClear(nullptr);
  std::printf("fuzz: %ld option strings (%ld rejected), %ld meshes (%ld rejected), %ld vector files (%ld rejected) "
              "in %.0f s; %d unacceptable outcomes\n",
              cases[0], errors[0], cases[1], errors[1], cases[2], errors[2], (double)seconds, failures);
  std::filesystem::remove_all(dir, fsError);
  PetscFinalize();
  return failures ? 1 : 0;
}
