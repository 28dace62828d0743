// aries_kernels: the registry's energies as a Python module (docs/python.md).
//
//   import aries_kernels as ak
//   out = ak.evaluate("fiber", F, gamma=50, fiber=[1, 1, 0])   # F: (n, 3, 3), (n, 2, 2) or (n, 3, 2)
//
// Keywords are the solver's material options without their dash, read by the solver's own reader
// (fem/material_options.cpp through core/options.cpp): the same names, defaults, bounds, normalization and one-line
// messages as `aries-matpoint`, by construction. That reader reads PETSc's options database, so the module starts
// PETSc once at import (no MPI launch is needed) and reads each material from a private options database; the
// evaluation itself is the PETSc-free energies library (energies/point_evaluation.hpp, as aries-matpoint -json).
#include "core/options.hpp"
#include "energies/point_evaluation.hpp"
#include "fem/fem_options.hpp"
#include "fem/material_options.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <petscsys.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace py = pybind11;
using namespace aries;
using energies::ElementShape;

namespace {

// ---- PETSc for the option reader ----------------------------------------------------------------------------------

// The first error's message of a failed read (PETSc calls the handler at each level of the traceback).
PetscErrorCode captureMessage(MPI_Comm, int, const char *, const char *, PetscErrorCode n, PetscErrorType p,
                              const char *mess, void *ctx) {
  auto *message = static_cast<std::string *>(ctx);
  if (p == PETSC_ERROR_INITIAL && message->empty() && mess) *message = mess;
  return n;
}

void startPetsc() {
  PetscBool started = PETSC_FALSE;
  PetscInitialized(&started);
  if (started) return;
  // PETSc's signal handlers would take over Python's (Ctrl-C, faults in other extensions).
  static char program[] = "aries_kernels", noSignals[] = "-no_signal_handler";
  static char *args[] = {program, noSignals, nullptr};
  int argc = 2;
  char **argv = args;
  if (PetscInitialize(&argc, &argv, nullptr, nullptr))
    throw std::runtime_error("aries_kernels: PETSc could not be initialized");
  py::module_::import("atexit").attr("register")(py::cpp_function([] {
    PetscBool live = PETSC_FALSE;
    PetscInitialized(&live);
    if (live) PetscFinalize();
  }));
}

// The material and the uniform cell data of `energy` for `shape`, from (option, text) pairs, or a ValueError with
// the reader's message.
struct ReadMaterial {
  energies::Material material;
  energies::UniformCellData cell;
};

ReadMaterial readMaterial(const std::string &energy, ElementShape shape,
                          const std::vector<std::pair<std::string, std::string>> &options) {
  ReadMaterial out;
  std::string message;
  PetscOptions db = nullptr;
  PetscErrorCode ierr = PetscOptionsCreate(&db);
  if (!ierr) ierr = PetscOptionsPush(db);  // the reader reads the default database: make it this one
  if (ierr) throw std::runtime_error("aries_kernels: could not create an options database");
  PetscPushErrorHandler(captureMessage, &message);
  ierr = PetscOptionsSetValue(db, "-energy", energy.c_str());
  for (const auto &[name, text] : options)
    if (!ierr) ierr = PetscOptionsSetValue(db, ("-" + name).c_str(), text.c_str());
  if (!ierr) ierr = fem::readMaterialOptions(nullptr, shape, nullptr, nullptr, false, &out.material, &out.cell);
  if (!ierr) ierr = core::rejectUnusedOptions();
  PetscPopErrorHandler();
  PetscOptionsPop();
  PetscOptionsDestroy(&db);
  if (ierr) throw py::value_error(message.empty() ? "aries_kernels: the material could not be read" : message);
  return out;
}

// ---- keywords ------------------------------------------------------------------------------------------------------

// Whether an option's value is one number or word (a per-point array has shape (n,)) or a list (per point: (n, k)).
// From the declarations: the material and singularity options (fem/fem_options.hpp) and the energies' own.
const std::map<std::string, bool> &listOptions() {
  static const std::map<std::string, bool> table = [] {
    std::map<std::string, bool> t;
    auto add = [&](const core::OptionDecl *d) {
      t[d->name + 1] = d->type == core::OptionType::Reals || d->type == core::OptionType::Words;
    };
    for (const auto *d : fem::opt::kMaterialOptions) add(d);
    for (const auto *d : fem::opt::kSingularityOptions) add(d);
    for (const auto &e : energies::kEnergyRegistry)
      for (int k = 0; k < e.numParams; ++k) {
        const auto &p = e.params[k];
        const bool list = p.kind != energies::ParamKind::Real && p.kind != energies::ParamKind::CellReal;
        t[p.option + 1] = list;
        if (p.option2) t[p.option2 + 1] = list;
      }
    return t;
  }();
  return table;
}

std::string numberText(double x) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.17g", x);
  return buf;
}

std::string joined(const double *v, py::ssize_t k) {
  std::string s;
  for (py::ssize_t i = 0; i < k; ++i) s += (i ? "," : "") + numberText(v[i]);
  return s;
}

// A keyword as the reader's text, uniform or per point (`perPoint` then holds n rows of `width` numbers).
struct Keyword {
  std::string name, text;
  bool perPoint = false;
  py::array_t<double, py::array::c_style | py::array::forcecast> values;
  py::ssize_t width = 1;
};

Keyword toKeyword(const std::string &name, const py::handle &value, py::ssize_t n) {
  Keyword kw;
  kw.name = name;
  if (py::isinstance<py::bool_>(value)) {
    kw.text = value.cast<bool>() ? "true" : "false";
    return kw;
  }
  if (py::isinstance<py::str>(value)) {
    kw.text = value.cast<std::string>();
    return kw;
  }
  auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!array) {
    PyErr_Clear();
    throw py::type_error("parameter " + name + ": expected a number, a list of numbers, an array or a word, got " +
                         std::string(py::str(py::type::handle_of(value).attr("__name__"))));
  }
  const auto known = listOptions().find(name);
  const bool list = known != listOptions().end() && known->second;
  const py::ssize_t dims = array.ndim();
  const bool perPoint = known != listOptions().end() && (list ? dims >= 2 : dims == 1);
  if (!perPoint) {
    if (dims > 1 || (!list && dims == 1 && known != listOptions().end()))
      throw py::value_error("parameter " + name + ": shape " + std::string(py::str(py::tuple(array.attr("shape")))) +
                            " is neither one value (" + (list ? "a list" : "a number") +
                            ") nor one per point (n = " + std::to_string(n) + ")");
    kw.text = joined(array.data(), array.size());
    return kw;
  }
  if (array.shape(0) != n)
    throw py::value_error("parameter " + name + ": " + std::to_string(array.shape(0)) + " per-point values for " +
                          std::to_string(n) + " deformation gradients");
  kw.perPoint = true;
  kw.width = n > 0 ? array.size() / n : 1;
  kw.values = array;
  return kw;
}

// ---- evaluation ----------------------------------------------------------------------------------------------------

struct Filter {
  bool project = true;
  energies::HessianFilter filter;
};

Filter filterFrom(const std::string &projection, const std::string &eigensystem) {
  Filter f;
  if (projection == "clamp") f.filter.filter = kernels::EigenFilter::Clamp;
  else if (projection == "abs") f.filter.filter = kernels::EigenFilter::Abs;
  else if (projection == "none") f.project = false;
  else throw py::value_error("projection: '" + projection + "' is not clamp|abs|none");
  if (eigensystem == "analytic") f.filter.analytic = true;
  else if (eigensystem == "numeric") f.filter.analytic = false;
  else throw py::value_error("eigensystem: '" + eigensystem + "' is not analytic|numeric");
  return f;
}

template <int R, int C>
py::dict evaluateShape(const std::string &energy, const double *F, py::ssize_t n, const std::vector<Keyword> &kws,
                       const Filter &filter, bool rawHessian) {
  constexpr int N = R * C;
  const ElementShape shape = R == C ? (R == 3 ? ElementShape::Tet : ElementShape::Planar) : ElementShape::Cloth;
  // One material per distinct set of per-point values (all points share one when nothing varies).
  std::vector<std::pair<std::string, std::string>> uniform;
  std::vector<const Keyword *> varying;
  for (const auto &kw : kws) {
    if (kw.perPoint) varying.push_back(&kw);
    else uniform.emplace_back(kw.name, kw.text);
  }
  std::vector<ReadMaterial> materials;
  std::vector<int> slot(static_cast<size_t>(n), 0);
  if (varying.empty() || n == 0) {
    materials.push_back(readMaterial(energy, shape, uniform));
  } else {
    std::unordered_map<std::string, int> seen;
    for (py::ssize_t i = 0; i < n; ++i) {
      std::string key;
      for (const auto *kw : varying)
        key.append(reinterpret_cast<const char *>(kw->values.data() + i * kw->width), kw->width * sizeof(double));
      auto [it, added] = seen.emplace(key, static_cast<int>(materials.size()));
      if (added) {
        auto options = uniform;
        for (const auto *kw : varying) options.emplace_back(kw->name, joined(kw->values.data() + i * kw->width, kw->width));
        materials.push_back(readMaterial(energy, shape, options));
      }
      slot[static_cast<size_t>(i)] = it->second;
    }
  }
  const bool hasI4 = energies::reportsI4(materials.front().material.kind);
  const bool hasI6 = energies::reportsI6<R, C>(materials.front().material.kind);

  py::array_t<double> value(n), alpha(n), f(n), I4(hasI4 ? n : 0), I6(hasI6 ? n : 0);
  py::array_t<double> pk1({n, static_cast<py::ssize_t>(R), static_cast<py::ssize_t>(C)});
  const py::ssize_t nRaw = rawHessian ? n : 0;
  py::array_t<double> hess({nRaw, static_cast<py::ssize_t>(N), static_cast<py::ssize_t>(N)});
  py::array_t<double> psd({n, static_cast<py::ssize_t>(N), static_cast<py::ssize_t>(N)});
  double *v = value.mutable_data(), *a = alpha.mutable_data(), *fv = f.mutable_data();
  double *i4 = I4.mutable_data(), *i6 = I6.mutable_data(), *p = pk1.mutable_data();
  double *h = hess.mutable_data(), *hp = psd.mutable_data();
  std::vector<energies::CellData<C>> cells;
  for (const auto &m : materials) cells.push_back(fem::toCellData<C>(m.cell));
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) {
      const int s = slot[static_cast<size_t>(i)];
      const kernels::Mat<R, C> Fi = kernels::unflatten<R, C>(Eigen::Map<const kernels::Vec<N>>(F + i * N));
      const auto point = energies::evaluatePoint<R, C>(materials[s].material, cells[s], Fi,
                                                       filter.project ? &filter.filter : nullptr, rawHessian);
      v[i] = point.derivs.value;
      a[i] = point.alpha;
      fv[i] = point.f;
      if (hasI4) i4[i] = point.I4;
      if (hasI6) i6[i] = point.I6;
      // PK1 row-major (the flattened F-gradient's order), Hessians row-major in that vec order (aries-matpoint -json).
      Eigen::Map<kernels::Vec<N>>(p + i * N) = point.derivs.grad;
      if (rawHessian) Eigen::Map<Eigen::Matrix<double, N, N, Eigen::RowMajor>>(h + i * N * N) = point.derivs.hess;
      Eigen::Map<Eigen::Matrix<double, N, N, Eigen::RowMajor>>(hp + i * N * N) = point.projected;
    }
  }
  py::dict out;
  out["energy"] = value;
  out["pk1"] = pk1;
  if (rawHessian) out["hessian"] = hess;
  out["hessian_psd"] = psd;
  out["f"] = f;
  out["alpha"] = alpha;
  if (hasI4) out["I4"] = I4;
  if (hasI6) out["I6"] = I6;
  out["materials"] = static_cast<py::ssize_t>(materials.size());
  return out;
}

py::dict evaluate(const std::string &energy, const py::object &Fobj, const std::string &projection,
                  const std::string &eigensystem, bool rawHessian, const py::kwargs &params) {
  auto F = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(Fobj);
  if (!F) {
    PyErr_Clear();
    throw py::type_error("F: expected an array of numbers of shape (n, 3, 3), (n, 2, 2) or (n, 3, 2)");
  }
  const std::string shapeText = std::string(py::str(py::tuple(F.attr("shape"))));
  const bool batched = F.ndim() == 3;
  const int R = batched ? static_cast<int>(F.shape(1)) : 0, C = batched ? static_cast<int>(F.shape(2)) : 0;
  if (!batched || !((R == 3 && C == 3) || (R == 2 && C == 2) || (R == 3 && C == 2)))
    throw py::value_error("F: shape " + shapeText + " is not (n, 3, 3), (n, 2, 2) or (n, 3, 2)" +
                          (F.ndim() == 2 ? " (one F: pass F[None])" : ""));
  const py::ssize_t n = F.shape(0);
  const double *data = F.data();
  for (py::ssize_t k = 0; k < F.size(); ++k)
    if (!std::isfinite(data[k]))
      throw py::value_error("F[" + std::to_string(k / (R * C)) + "] has a non-finite entry (" +
                            numberText(data[k]) + ")");
  const Filter filter = filterFrom(projection, eigensystem);
  std::vector<Keyword> kws;
  for (const auto &[key, value] : params) {
    const std::string name = py::str(key);
    if (name == "energy") throw py::type_error("energy is the first argument, not a keyword");
    kws.push_back(toKeyword(name, value, n));
  }
  startPetsc();
  if (R == 3 && C == 3) return evaluateShape<3, 3>(energy, data, n, kws, filter, rawHessian);
  if (R == 2) return evaluateShape<2, 2>(energy, data, n, kws, filter, rawHessian);
  return evaluateShape<3, 2>(energy, data, n, kws, filter, rawHessian);
}

py::dict energyTable() {
  py::dict out;
  for (const auto &e : energies::kEnergyRegistry) {
    py::list shapes;
    if (e.tet) shapes.append("tet");
    if (e.planar) shapes.append("planar");
    if (e.cloth) shapes.append("cloth");
    py::list params;
    for (int k = 0; k < e.numParams; ++k) {
      params.append(e.params[k].option + 1);
      if (e.params[k].option2) params.append(e.params[k].option2 + 1);
    }
    py::dict d;
    d["summary"] = e.summary;
    d["shapes"] = shapes;
    d["parameters"] = params;
    d["fibers"] = e.fibers;
    d["volume"] = e.volume;
    out[e.name] = d;
  }
  return out;
}

}  // namespace

PYBIND11_MODULE(aries_kernels, m) {
  m.doc() =
      "The closed-form, SVD-free energies of aries (TOG 2024, 'Analytic rotation-invariant modelling of anisotropic "
      "finite elements') evaluated on batches of deformation gradients. See docs/python.md.";
  m.def("evaluate", &evaluate, py::arg("energy"), py::arg("F"), py::kw_only(), py::arg("projection") = "clamp",
        py::arg("eigensystem") = "analytic", py::arg("hessian") = true,
        R"doc(evaluate(energy, F, *, projection='clamp', eigensystem='analytic', hessian=True, **params) -> dict

Value, PK1 and Hessian of the energy `energy` (a name `aries -energy` takes) at every F of the batch F:
shape (n, 3, 3) tetrahedra, (n, 2, 2) planar triangles or (n, 3, 2) cloth triangles.

params are the solver's material options without the dash (E, nu, mu, lambda, mu1, mu2, fiber, fiber2, gamma,
beta, ortho_mu, target, curvature, singularity, mollifier_eps, ...), with the solver's defaults, bounds and
normalization (fiber directions are normalized). A number/list is one value for every point; an array with one
more leading axis of length n gives one value per point (E of shape (n,), fiber of shape (n, 3)).

Returns a dict of numpy arrays: energy (n,), pk1 (n, R, C), hessian and hessian_psd (n, RC, RC), f (n,), alpha
(n,), I4 (n,) for energies that read fibers, I6 (n,) for those on cloth, and materials (how many distinct
materials were read). Orderings are aries-matpoint -json's: F and PK1 row-major, the Hessian in the row-major vec
order of F. hessian_psd is the Hessian eigenvalue-filtered as projected Newton does it: projection 'clamp'
(negative eigenvalues to 0; aries-matpoint's and dynamic steps' default), 'abs' (to |lambda|; static solves'
default) or 'none' (the Hessian); eigensystem 'analytic' uses an energy's closed form where it has one.
hessian=False leaves out the unfiltered Hessian: one pass per F gives energy, PK1 and hessian_psd (half the work).
Bad input raises ValueError or TypeError with aries-matpoint's one-line message.)doc");
  m.def("energies", &energyTable,
        "The registered energies: name -> {summary, shapes, parameters (its own), fibers, volume}.");
}
