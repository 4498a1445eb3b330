// The wall laws' settings as the faces give them: one value for every wall, or per box face.
#include <cerrno>
#include <cstdlib>

#include "hardsphere/errors.hpp"
#include "hardsphere/physics.hpp"

namespace hardsphere {

namespace {

void assign(WallLaw& w, WallSetting setting, double value) {
  switch (setting) {
    case WallSetting::Restitution:
      w.restitution = value;
      break;
    case WallSetting::TangentialRestitution:
      w.tangential_restitution = value;
      break;
    case WallSetting::Friction:
      w.friction = value;
      break;
  }
}

//! The whole of `text` as a number (inf and nan too, which validated() judges), or an InputError.
double number(const std::string& text, const std::string& option, const std::string& whole) {
  errno = 0;
  char* end = nullptr;
  const double x = text.empty() ? 0.0 : std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE)
    throw InputError(option + " '" + whole + "': '" + text +
                     "' is not a number (give one value for every wall, or face=value items, e.g. zlo=0.5,zhi=0.9)");
  return x;
}

}  // namespace

void set_wall_law(Physics& p, PhysicsGiven& given, WallSetting setting, const std::string& face, double value,
                  const std::string& option) {
  if (face.empty()) {
    for (WallLaw& w : p.walls) assign(w, setting, value);
    given.all_walls = true;
    return;
  }
  for (std::size_t f = 0; f < 6; ++f) {
    if (face != kFaceNames[f]) continue;
    assign(p.walls[f], setting, value);
    given.wall_faces[f] = true;
    return;
  }
  throw InputError(option + ": unknown face '" + face + "' (the faces are xlo xhi ylo yhi zlo zhi)");
}

void parse_wall_setting(Physics& p, PhysicsGiven& given, WallSetting setting, const std::string& text,
                        const std::string& option) {
  if (text.find('=') == std::string::npos)
    return set_wall_law(p, given, setting, "", number(text, option, text), option);
  std::size_t start = 0;
  std::string seen;  // the faces of this list: one named twice is a mistake, not an order to pick
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw InputError(option + " '" + text + "': '" + item +
                       "' is not face=value (a list names each face, e.g. zlo=0.5,zhi=0.9)");
    const std::string face = item.substr(0, eq);
    if (face.empty())
      throw InputError(option + " '" + text + "': '" + item +
                       "' names no face (the faces are xlo xhi ylo yhi zlo zhi)");
    if (seen.find(" " + face + " ") != std::string::npos)
      throw InputError(option + " '" + text + "' names face " + face + " twice; give each face once");
    seen += " " + face + " ";
    set_wall_law(p, given, setting, face, number(item.substr(eq + 1), option, text), option);
    start = comma + 1;
  }
}

}  // namespace hardsphere
