#pragma once
//! A renumbering of the event-driven engine's spheres: new index k is old index old_of(k). Every
//! part of the engine that keeps per-sphere arrays or stores sphere indices applies it.
#include <cstddef>
#include <utility>
#include <vector>

namespace hardsphere::event {

class Renumbering {
 public:
  explicit Renumbering(std::vector<int> old_of) : old_of_(std::move(old_of)), new_of_(old_of_.size()) {
    for (std::size_t k = 0; k < old_of_.size(); ++k) new_of_[std::size_t(old_of_[k])] = int(k);
  }
  std::size_t size() const { return old_of_.size(); }
  int old_of(std::size_t k) const { return old_of_[k]; }
  int new_of(std::size_t i) const { return new_of_[i]; }
  //! v[k] becomes the old v[old_of(k)].
  template <class V>
  void permute(V& v) const {
    auto w = v;
    for (std::size_t k = 0; k < old_of_.size(); ++k) w[k] = v[std::size_t(old_of_[k])];
    v.swap(w);
  }

 private:
  std::vector<int> old_of_, new_of_;
};

}  // namespace hardsphere::event
