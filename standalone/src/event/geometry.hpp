#pragma once
//! The box, the neighbour-list shell and the layout of the cell grid of the event-driven engine:
//! sized and validated once at construction, then only read. Each part of the engine keeps its
//! own copy, so the hot loops read it as their own members.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "hardsphere/event_engine.hpp"
#include "hardsphere/particles.hpp"
#include "scene/size_classes.hpp"

namespace hardsphere::event {

//! Periodic image codes of neighbour-list entries: image = (sx+1) + 3 (sy+1) + 9 (sz+1),
//! s = -1, 0, 1 the box lengths added to the partner's position per axis. The partner's entry
//! for the owner has image kImages - 1 - image (all shifts negated).
constexpr int kImages = 27;

class EventGeometry {
 public:
  EventGeometry() = default;
  //! Throws InputError when a periodic axis (or a user-given cell grid) leaves no room for the
  //! cells and a shell, or when a pair could have two periodic images in range.
  EventGeometry(const ParticleSystem& sys, const EventConfig& cfg, const SizeSplit& split);

  double lo(std::size_t d) const { return lo_[d]; }
  double len(std::size_t d) const { return len_[d]; }
  bool periodic(std::size_t d) const { return periodic_[d]; }
  double shell() const { return shell_; }    //!< neighbour-list shell (length units)
  double exit_r() const { return exit_r_; }  //!< displacement from the list centre that triggers a rebuild
  const std::array<int, 3>& cells() const { return nc_; }
  int cells(std::size_t d) const { return nc_[d]; }
  double width(std::size_t d) const { return width_[d]; }
  int reach() const { return reach_; }       //!< stencil half-width in cells
  double grid_r() const { return grid_r_; }  //!< largest radius of the spheres filed in cells
  const std::array<double, 3>& image_shift(std::uint32_t image) const { return image_shift_[image]; }
  //! The cell holding point (x, y, z) (points outside the box go to the nearest cell).
  std::array<int, 3> cell_of(double x, double y, double z) const {
    const double p[3] = {x, y, z};
    std::array<int, 3> k{};
    for (std::size_t d = 0; d < 3; ++d) k[d] = std::clamp(int(std::floor((p[d] - lo_[d]) / width_[d])), 0, nc_[d] - 1);
    return k;
  }
  int cell_index(const std::array<int, 3>& k) const { return (k[2] * nc_[1] + k[1]) * nc_[0] + k[0]; }
  std::size_t cell_count() const { return std::size_t(nc_[0]) * std::size_t(nc_[1]) * std::size_t(nc_[2]); }
  //! p with its periodic coordinates wrapped into the box.
  Vec3d wrapped(Vec3d p) const;

 private:
  //! The shell (and the exit radius), or InputError where the box leaves no room for one.
  void size_shell(const ParticleSystem& sys, const EventConfig& cfg, const SizeSplit& split);
  //! The box and the cells: as many as fit, within EventConfig::max_cells_per_sphere.
  void size_cells(const ParticleSystem& sys, const EventConfig& cfg, const SizeSplit& split);

  std::array<double, 3> lo_{}, len_{}, width_{};
  std::array<int, 3> nc_{};
  std::array<bool, 3> periodic_{};
  int reach_ = 1;
  double shell_ = 0, exit_r_ = 0, grid_r_ = 0;
  std::array<std::array<double, 3>, kImages> image_shift_{};  // image code -> shift of the partner
};

}  // namespace hardsphere::event
