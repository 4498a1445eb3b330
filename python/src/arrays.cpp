// Read-only numpy views: the base object (pybind11's `base` handle) holds the memory, so an array
// may outlive the Python object it came from.
#include "arrays.hpp"

#include <cstdint>

namespace py = pybind11;

namespace hardsphere::python {

namespace {

template <class T>
py::array make(const T* data, std::size_t n, std::size_t width, py::object owner) {
  std::vector<py::ssize_t> shape{py::ssize_t(n)}, strides{py::ssize_t(width * sizeof(T))};
  if (width > 1) shape.push_back(py::ssize_t(width)), strides.push_back(py::ssize_t(sizeof(T)));
  py::array a(py::dtype::of<T>(), shape, strides, data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

}  // namespace

py::array view(const ParticleSystem& s, Field f, py::object owner) {
  static_assert(sizeof(Vec3d) == 3 * sizeof(double), "Vec3d is three packed doubles");
  static_assert(sizeof(std::array<std::int32_t, 3>) == 3 * sizeof(std::int32_t), "images are three packed int32");
  const std::size_t n = s.size();
  switch (f) {
    case Field::Positions:
      return make(n ? &s.pos[0].x : nullptr, n, 3, owner);
    case Field::Velocities:
      return make(n ? &s.vel[0].x : nullptr, n, 3, owner);
    case Field::Radii:
      return make(s.radius.data(), n, 1, owner);
    case Field::Masses:
      return make(s.mass.data(), n, 1, owner);
    case Field::Ids:
      return make(s.id.data(), n, 1, owner);
    case Field::Types:
      return make(s.type.data(), n, 1, owner);
    case Field::Images:
      return make(n ? s.image[0].data() : nullptr, n, 3, owner);
    case Field::Omegas:
      if (s.omega.size() < n) throw std::logic_error("state without angular velocities");
      return make(n ? &s.omega[0].x : nullptr, n, 3, owner);
  }
  throw std::logic_error("unknown field");
}

py::object owner_of(std::shared_ptr<const ParticleSystem> s) {
  auto* held = new std::shared_ptr<const ParticleSystem>(std::move(s));
  return py::capsule(held, [](void* p) { delete static_cast<std::shared_ptr<const ParticleSystem>*>(p); });
}

const char* describe(Field f) {
  switch (f) {
    case Field::Positions:
      return "(N, 3) float64: positions, periodic coordinates wrapped into the box";
    case Field::Velocities:
      return "(N, 3) float64: velocities";
    case Field::Radii:
      return "(N,) float64: radii";
    case Field::Masses:
      return "(N,) float64: masses";
    case Field::Ids:
      return "(N,) int64: atom ids";
    case Field::Types:
      return "(N,) int32: atom types (>= 1)";
    case Field::Images:
      return "(N, 3) int32: periodic images crossed (unwrapped = positions + images * lengths)";
    case Field::Omegas:
      return "(N, 3) float64: angular velocities (rough spheres; zeros for smooth engines)";
  }
  return "";
}

}  // namespace hardsphere::python
