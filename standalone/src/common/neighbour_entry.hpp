#pragma once
//! One neighbour-list entry packs a partner's index and a periodic image code (0..26, the
//! partner seen from the list's owner) into one word, so reading a list row misses the cache
//! once, not once per array. Used by the stepper's lists (through the
//! contact resolver) and by the event engine's lists; each engine keeps its own image numbering.
#include <cstdint>

#include "hardsphere/limits.hpp"

namespace hardsphere {

//! Image code of a periodic shift (kx, ky, kz) in {-1, 0, 1}^3; 13 means no shift and the
//! mirrored shift of code c is 26 - c.
constexpr std::uint8_t image_code(int kx, int ky, int kz) {
  return std::uint8_t((kx + 1) * 9 + (ky + 1) * 3 + (kz + 1));
}
constexpr std::uint8_t kNoImage = 13;

constexpr int kAdjImageBits = 5;
constexpr std::uint32_t kMaxAdjIndex = (std::uint32_t(1) << (32 - kAdjImageBits)) - 1;  //!< largest partner index
static_assert(std::int64_t(kMaxAdjIndex) + 1 == kMaxSpheres, "kMaxSpheres must match the index bits");
constexpr std::uint32_t adj_entry(std::uint32_t partner, std::uint8_t image) {
  return partner << kAdjImageBits | image;
}
constexpr std::uint32_t adj_partner(std::uint32_t entry) { return entry >> kAdjImageBits; }
constexpr std::uint8_t adj_image(std::uint32_t entry) { return std::uint8_t(entry & ((1u << kAdjImageBits) - 1)); }

}  // namespace hardsphere
