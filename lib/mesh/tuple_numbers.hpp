// Sorted tuples of vertex numbers to consecutive numbers in order of first sight, and a tetrahedron's faces: the faces
// and edges of a mesh made from its cells (mesh/mesh_interpolate.cpp) and the cells' face neighbours
// (mesh/mesh_partition.cpp). Internal to lib/mesh.
#pragma once

#include <petscsys.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace aries::fem::loading {

// Sorted N-tuples of vertex points to their number in order of insertion; linear probing in a power-of-two table at
// most half full. Each slot holds its tuple beside its number, so a probe reads one place in memory: with the tuples
// in a second array every probe read two, and the lookups (4 per tetrahedron for the faces, 3 per face for the edges,
// 4 per tetrahedron again for the dual graph on rank 0) were cache misses, about 2.5% of the 1M-tet peer box's samples.
template <int N>
class TupleNumbers {
 public:
  using Key = std::array<PetscInt, N>;
  explicit TupleNumbers(std::size_t expected) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected) capacity *= 2;
    slots_.assign(capacity, Slot{});
    mask_ = capacity - 1;
  }
  // The number of `key` (sorted), a new one (the count so far) if it was not there; *inserted says which.
  PetscInt number(const Key &key, bool *inserted) {
    std::size_t h = hash(key) & mask_;
    for (;; h = (h + 1) & mask_) {
      const Slot &slot = slots_[h];
      if (slot.id < 0) break;
      if (slot.key == key) {
        *inserted = false;
        return slot.id;
      }
    }
    if (2 * (count_ + 1) > slots_.size()) {
      grow();
      return number(key, inserted);
    }
    slots_[h] = Slot{key, static_cast<PetscInt>(count_)};
    *inserted = true;
    return static_cast<PetscInt>(count_++);
  }
  std::size_t size() const { return count_; }

 private:
  struct Slot {
    Key key{};
    PetscInt id = -1;  // -1: empty
  };
  static std::size_t hash(const Key &key) {
    std::uint64_t h = 0x9E3779B97F4A7C15ull;
    for (PetscInt k : key) h = (h ^ static_cast<std::uint64_t>(k)) * 0xBF58476D1CE4E5B9ull;
    return static_cast<std::size_t>(h ^ (h >> 31));
  }
  void grow() {
    std::vector<Slot> old(2 * slots_.size());
    old.swap(slots_);
    mask_ = slots_.size() - 1;
    for (const Slot &slot : old) {
      if (slot.id < 0) continue;
      std::size_t h = hash(slot.key) & mask_;
      while (slots_[h].id >= 0) h = (h + 1) & mask_;
      slots_[h] = slot;
    }
  }
  std::vector<Slot> slots_;
  std::size_t count_ = 0;
  std::size_t mask_ = 0;
};

// A tetrahedron's faces from its vertices, as PETSc's DMPlexGetRawFaces_Internal lists them (the first face's vertices
// follow the right-hand rule with its normal away from the fourth vertex).
constexpr int kTetrahedronFaces[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {2, 1, 3}};

template <std::size_t N>
std::array<PetscInt, N> sortedTuple(std::array<PetscInt, N> t) {
  std::sort(t.begin(), t.end());
  return t;
}

}  // namespace aries::fem::loading
