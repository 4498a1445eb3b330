// Python values into C++ without a silent change: numpy's casts wrap (2**31 -> -2147483648) and
// truncate (1.9 -> 1), C strings end at a NUL. Each value is checked in the kind it was given.
#include "values.hpp"

#include <pybind11/numpy.h>

#include <cmath>
#include <limits>
#include <optional>

#include "hardsphere/errors.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace hardsphere::python {

namespace {

std::string repr_text(const py::handle& v) { return py::repr(v).cast<std::string>(); }

//! A value as messages show it: long ones shortened, as the data reader does (a 300-digit int is
//! not worth repeating).
std::string shown(const py::handle& v) {
  const std::string s = py::str(v).cast<std::string>();
  return s.size() > 64 ? s.substr(0, 64) + "..." : s;
}

std::string type_name(const py::handle& v) { return py::type::handle_of(v).attr("__name__").cast<std::string>(); }

bool is_bool(const py::handle& x) {
  static const py::object np_bool = py::module_::import("numpy").attr("bool_");
  return PyBool_Check(x.ptr()) || py::isinstance(x, np_bool);
}

bool is_real(const py::handle& x) {
  static const py::object real = py::module_::import("numbers").attr("Real");
  return !is_bool(x) && py::isinstance(x, real);
}

enum class Whole { Yes, NotWhole, NotNumber };

//! `x` as a Python int when it is one (Python or numpy integers) or a real with an integral
//! value (floats of any width: int() of a long double is exact).
Whole as_python_int(const py::handle& x, py::object& out) {
  if (is_bool(x)) return Whole::NotNumber;
  if (PyIndex_Check(x.ptr())) {
    out = py::reinterpret_steal<py::object>(PyNumber_Index(x.ptr()));
    if (!out) throw py::error_already_set();
    return Whole::Yes;
  }
  if (!is_real(x)) return Whole::NotNumber;
  const double f = py::float_(py::reinterpret_borrow<py::object>(x)).cast<double>();
  if (!std::isfinite(f)) return Whole::NotWhole;  // nan, inf (a long double past a double is far out of range anyway)
  out = py::int_(py::reinterpret_borrow<py::object>(x));
  return out.equal(x) ? Whole::Yes : Whole::NotWhole;
}

//! A Python int within [lo, hi].
std::optional<std::int64_t> in_range(const py::object& i, std::int64_t lo, std::int64_t hi) {
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (v == -1 && PyErr_Occurred()) throw py::error_already_set();
  if (overflow || v < lo || v > hi) return std::nullopt;
  return v;
}

std::string range_text(std::int64_t lo, std::int64_t hi) { return std::to_string(lo) + " to " + std::to_string(hi); }

//! `v` as numpy makes it; `must` ends the refusal of a ragged list ("have shape (N, 3)").
//! `integers`: a list with an int past int64 becomes float64, which would show (and round) the
//! list's ints; taken as objects they stay as given.
py::array as_array(const py::handle& v, const std::string& what, const std::string& must, bool integers) {
  const py::module_ np = py::module_::import("numpy");
  try {
    py::array a = np.attr("asarray")(v);
    if (integers && !py::isinstance<py::array>(v) && a.dtype().kind() == 'f')
      a = np.attr("asarray")(v, "dtype"_a = np.attr("object_"));
    return a;
  } catch (const py::error_already_set&) {
    throw InputError(what + " must " + must);  // a ragged list
  }
}

//! "what[k]" or "what[i, j]" for element k of the C-order flattening.
std::string element(const std::string& what, std::size_t k, std::size_t width) {
  return width == 1 ? what + "[" + std::to_string(k) + "]"
                    : what + "[" + std::to_string(k / width) + ", " + std::to_string(k % width) + "]";
}

std::string shape_text(std::size_t n, std::size_t width) {
  const std::string rows = n == kAnyRows ? "N" : std::to_string(n);
  return width == 1 ? "(" + rows + ",)" : "(" + rows + ", " + std::to_string(width) + ")";
}

bool has_shape(const py::array& a, std::size_t n, std::size_t width) {
  if (width == 1) return a.ndim() == 1 && (n == kAnyRows || std::size_t(a.shape(0)) == n);
  return a.ndim() == 2 && std::size_t(a.shape(1)) == width && (n == kAnyRows || std::size_t(a.shape(0)) == n);
}

template <class T>
py::array_t<T, py::array::c_style | py::array::forcecast> flat_as(const py::array& a) {
  return py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a.attr("ravel")());
}

}  // namespace

std::string path_arg(const py::handle& path, const std::string& what) {
  py::object bytes;
  try {
    bytes = py::module_::import("os").attr("fsencode")(path);
  } catch (const py::error_already_set& e) {
    if (!e.matches(PyExc_TypeError)) throw;
    throw py::type_error(what + ": a path is a str, bytes or os.PathLike, not " + type_name(path));
  }
  std::string s = bytes.cast<std::string>();
  if (s.find('\0') != std::string::npos)
    throw InputError(what + " " + repr_text(py::module_::import("os").attr("fspath")(path)) +
                     ": a path cannot contain a NUL character (the operating system would end it there)");
  return s;
}

std::string text_arg(const py::handle& text, const std::string& what, bool one_line) {
  if (!py::isinstance<py::str>(text)) throw py::type_error(what + " must be a str, not " + type_name(text));
  std::string s = text.cast<std::string>();
  if (s.find('\0') != std::string::npos) throw InputError(what + " " + repr_text(text) + " contains a NUL character");
  if (one_line && s.find_first_of("\n\r") != std::string::npos)
    throw InputError(what + " " + repr_text(text) + " must be one line (it is a line of the file)");
  return s;
}

namespace {
// The Python int a whole-number argument holds, or the refusal naming it as given.
py::object python_int(const py::handle& v, const std::string& what) {
  py::object i;
  switch (as_python_int(v, i)) {
    case Whole::NotNumber:
      throw py::type_error(what + " must be a whole number, not " + type_name(v));
    case Whole::NotWhole:
      throw InputError(what + " = " + shown(v) + " is not a whole number");
    case Whole::Yes:
      break;
  }
  return i;
}
}  // namespace

std::int64_t whole_arg(const py::handle& v, const std::string& what, std::int64_t lo, std::int64_t hi) {
  const py::object i = python_int(v, what);
  const auto x = in_range(i, lo, hi);
  if (!x) throw InputError(what + " = " + shown(v) + " is out of range (" + range_text(lo, hi) + ")");
  return *x;
}

std::uint64_t unsigned_arg(const py::handle& v, const std::string& what) {
  const py::object i = python_int(v, what);
  const unsigned long long x = PyLong_AsUnsignedLongLong(i.ptr());
  if (PyErr_Occurred()) {
    PyErr_Clear();
    throw InputError(what + " = " + shown(v) + " is out of range (0 to " +
                     std::to_string(std::numeric_limits<std::uint64_t>::max()) + ")");
  }
  return x;
}

std::vector<std::int64_t> whole_array(const py::handle& v, std::size_t n, std::size_t width, const std::string& what,
                                      std::int64_t lo, std::int64_t hi, const std::string& range) {
  const std::string must = "have shape " + shape_text(n, width) + " with N = " + std::to_string(n);
  const py::array a = as_array(v, what, must, true);
  if (!has_shape(a, n, width)) throw InputError(what + " must " + must);
  const char kind = a.dtype().kind();
  const std::size_t size = std::size_t(a.size());
  std::vector<std::int64_t> out(size);
  // The element as given (numpy's str of it: 1e10 is 10000000000.0, a uint64 its own digits).
  auto fail = [&](std::size_t k, const std::string& why) -> void {
    const py::object flat = a.attr("ravel")();
    throw InputError(element(what, k, width) + " = " + shown(flat[py::int_(k)]) + " " + why);
  };
  const std::string out_of_range = "is out of range (" + range + ")";
  if (kind == 'i') {
    const auto b = flat_as<std::int64_t>(a);
    for (std::size_t k = 0; k < size; ++k) {
      if (b.data()[k] < lo || b.data()[k] > hi) fail(k, out_of_range);
      out[k] = b.data()[k];
    }
  } else if (kind == 'u') {
    const auto b = flat_as<std::uint64_t>(a);
    for (std::size_t k = 0; k < size; ++k) {
      const std::uint64_t x = b.data()[k];
      if ((hi >= 0 && x > std::uint64_t(hi)) || hi < 0 || std::int64_t(x) < lo) fail(k, out_of_range);
      out[k] = std::int64_t(x);
    }
  } else if (kind == 'f' && a.dtype().itemsize() <= 8) {
    const auto b = flat_as<double>(a);  // exact for half, single and double
    for (std::size_t k = 0; k < size; ++k) {
      const double x = b.data()[k];
      if (!std::isfinite(x) || x != std::floor(x)) fail(k, "is not an integer");
      // 2^63 (hi = INT64_MAX rounded up) is out of range too.
      if (x < double(lo) || x > double(hi) || x >= 9223372036854775808.0) fail(k, out_of_range);
      out[k] = std::int64_t(x);
    }
  } else if (kind == 'f' || kind == 'O') {
    const py::object flat = a.attr("ravel")();
    for (std::size_t k = 0; k < size; ++k) {
      py::object i;
      const py::object x = flat[py::int_(k)];
      const Whole w = as_python_int(x, i);
      if (w == Whole::NotNumber) fail(k, "is not a number");
      if (w == Whole::NotWhole) fail(k, "is not an integer");
      const auto y = in_range(i, lo, hi);
      if (!y) fail(k, out_of_range);
      out[k] = *y;
    }
  } else {
    throw InputError(what + " must be integers, not an array of " + py::str(a.dtype()).cast<std::string>());
  }
  return out;
}

std::vector<double> real_array(const py::handle& v, std::size_t n, std::size_t width, const std::string& what,
                               bool scalar) {
  const std::string must = (scalar ? "be a number or have shape " : "have shape ") + shape_text(n, width) +
                           (n == kAnyRows ? std::string() : " with N = " + std::to_string(n));
  const py::array a = as_array(v, what, must, false);
  const bool one = scalar && a.ndim() == 0;
  if (!one && !has_shape(a, n, width)) throw InputError(what + " must " + must);
  const char kind = a.dtype().kind();
  const std::size_t size = std::size_t(a.size());
  std::vector<double> out(size);
  auto name = [&](std::size_t k) { return one ? what : element(what, k, width); };
  if (kind == 'f' || kind == 'i' || kind == 'u') {
    const auto b = flat_as<double>(a);
    std::copy(b.data(), b.data() + size, out.begin());
  } else if (kind == 'O') {
    const py::object flat = a.attr("ravel")();
    for (std::size_t k = 0; k < size; ++k) {
      const py::object x = flat[py::int_(k)];
      const std::string given = name(k) + " = " + shown(x);
      if (!is_real(x)) throw InputError(given + " is not a real number");
      try {
        out[k] = py::float_(x).cast<double>();
      } catch (const py::error_already_set& e) {
        if (!e.matches(PyExc_OverflowError)) throw;
        throw InputError(given + " is too large for a double");
      }
    }
  } else {
    throw InputError(what + " must be real numbers, not " +
                     (one ? type_name(v) : "an array of " + py::str(a.dtype()).cast<std::string>()));
  }
  if (one && n != kAnyRows) return std::vector<double>(n * width, out[0]);
  return out;
}

std::vector<double> one_or_three(const py::handle& v, const std::string& what) {
  const py::array a = as_array(v, what, "be one value or three (x, y, z)", false);
  if (!(a.ndim() == 0 || (a.ndim() == 1 && a.shape(0) == 3)))
    throw InputError(what + " needs one value or three (x, y, z)");
  const auto x = real_array(a, a.ndim() == 0 ? 1 : 3, 1, what, true);
  return a.ndim() == 0 ? std::vector<double>{x[0], x[0], x[0]} : x;
}

}  // namespace hardsphere::python
