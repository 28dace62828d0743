// The energy registry's list: one line per energy, X(Name) for the descriptor NameEnergy in energies/catalog/
// (descriptor.hpp says what a descriptor holds). EnergyKind::Name is its id; the order is the order of -help, the
// docs tables and the lists in error messages. Adding an energy: its header in energies/catalog/, its line here,
// its row in docs/energies.md and docs/options.md.
#pragma once

#define ARIES_ENERGIES(X) \
  X(Alx)                  \
  X(Iarap)                \
  X(IarapLin)             \
  X(ArapSvd)              \
  X(Ortho)                \
  X(Aniso)                \
  X(Fiber)                \
  X(KimAA)                \
  X(Bw)                   \
  X(Bw46)                 \
  X(Bw461)                \
  X(Bw46s)                \
  X(ShapeTarget)          \
  X(Caricature)           \
  /* one line per energy, above this one */
