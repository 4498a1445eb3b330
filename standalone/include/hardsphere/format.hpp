#pragma once
//! Numbers in messages and files, written one way everywhere.
#include <string>

namespace hardsphere {

//! `x` with `digits` significant digits, as printf's %g (the default of an ostream).
std::string format_number(double x, int digits = 6);

//! The shortest decimal that reads back as exactly `x` (values a user may copy into an input).
std::string format_exact(double x);

}  // namespace hardsphere
