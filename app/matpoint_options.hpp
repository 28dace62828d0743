// The options of aries-matpoint (besides the material options of fem/fem_options.hpp and the energies' own),
// declared once: its -help, its readers and docs/options.md's aries-matpoint table come from here.
#pragma once

#include "core/option_decl.hpp"

namespace aries::matpoint::opt {

using namespace core;

inline constexpr OptionDecl F =
    realsOption("-F", "v1,v2,...", "evaluate at this F, row-major: 9 values (3x3 tet), 4 (2x2 planar) or 6 (3x2 cloth)")
        .otherwise("(-F or -path)");
inline constexpr OptionDecl json =
    flagOption("-json", "with -F: one JSON object (energy, pk1, hessian, hessian_psd, f, alpha, I4/I6 where they apply)")
        .byDefault("false");
inline constexpr OptionDecl path =
    choiceOption("-path", "uniaxial|compress|shear",
                 "print a CSV along a path: uniaxial and compress relax the lateral stretches to zero lateral stress; "
                 "shear is simple shear F = I + g e_x e_y")
        .otherwise("(-F or -path)");
inline constexpr OptionDecl maxAmount =
    realOption("-max", "X", "the path's largest strain (compress: < 1) or shear").byDefault("0.1").above(0);
inline constexpr OptionDecl points = intOption("-n", "N", "points along the path").byDefault("10").atLeast(1).atMost(1000000);
inline constexpr OptionDecl shape =
    choiceOption("-shape", "tet|planar|cloth", "the element shape of a -path run").byDefault("tet");

inline constexpr const OptionDecl *kOptions[] = {&F, &json, &path, &maxAmount, &points, &shape};
inline constexpr OptionSection kSection = section("matpoint", "aries-matpoint", kOptions);

}  // namespace aries::matpoint::opt
