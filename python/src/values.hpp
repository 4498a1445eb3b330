#pragma once
//! Python values checked as the data reader checks a file's words (standalone/src/io/
//! data_reader.cpp): nothing is wrapped, truncated or cut short on its way into C++. Every
//! refusal is an InputError (ValueError) naming the value as it was given; a value of the wrong
//! kind (a string for a number) is a TypeError.
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

namespace hardsphere::python {

//! A file path (str, bytes or os.PathLike) as the bytes the operating system sees. Refuses a path
//! with a NUL, where C would end it ("write_data 'victim\x00.data': a path cannot contain a NUL
//! character"), as Python's open() does. `what` names the call.
std::string path_arg(const pybind11::handle& path, const std::string& what);

//! A keyword's text (boundary, precision, title, ...): refuses a NUL, which would cut the
//! library's messages short, and with `one_line` a line break (a data file's title is one line).
std::string text_arg(const pybind11::handle& text, const std::string& what, bool one_line = false);

//! A whole number (a Python or numpy integer, or a float with an integral value; not a bool)
//! in [lo, hi]: "steps = 1.5 is not a whole number", "seed = -1 is out of range (0 to ...)".
std::int64_t whole_arg(const pybind11::handle& v, const std::string& what, std::int64_t lo, std::int64_t hi);
std::uint64_t unsigned_arg(const pybind11::handle& v, const std::string& what);

//! An integer array of shape (n,) (`width` 1) or (n, 3) in C order, every element whole and in
//! [lo, hi]; a refusal names the element: "images[0, 2] = 2147483648 is out of range (32-bit
//! integers)", "ids[1] = 1.9 is not an integer". `range` describes [lo, hi].
std::vector<std::int64_t> whole_array(const pybind11::handle& v, std::size_t n, std::size_t width,
                                      const std::string& what, std::int64_t lo, std::int64_t hi,
                                      const std::string& range);

//! A real array of shape (n,) or (n, 3) (n = kAnyRows: any n) as float64 in C order, or with
//! `scalar` one real number repeated n times. Integers are converted, other kinds (complex,
//! strings, bools, None) refused; finiteness is the library's check (validate_and_wrap).
constexpr std::size_t kAnyRows = std::size_t(-1);
std::vector<double> real_array(const pybind11::handle& v, std::size_t n, std::size_t width, const std::string& what,
                               bool scalar);

//! One real number or three (x, y, z), as Box lengths and cell counts take them.
std::vector<double> one_or_three(const pybind11::handle& v, const std::string& what);

}  // namespace hardsphere::python
