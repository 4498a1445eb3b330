#pragma once
//! The `hardsphere` command line turned into a RunSpec, apart from main() so that tests and the
//! command-line fuzzer parse exactly what the program parses.
#include <string>

#include "hardsphere/simulation.hpp"

namespace hardsphere::cli {

struct CommandLine {
  bool help = false;      //!< --help or --version was given: print help_text, exit 0, run nothing
  std::string help_text;  //!< of the (sub)command --help was given to
  RunSpec spec;           //!< the run, when !help
  bool quiet = false;     //!< --quiet: no progress line
};

//! Parses argv (argv[0] is the program name). Every refusal is an InputError naming the option
//! and the value: unknown (sub)commands and options, missing or malformed values, numbers out of
//! range (--n above kMaxSpheres, counts that overflow), options that exclude each other, output
//! files that are directories, in missing directories or the same file under two names.
//! Nothing is created or run.
CommandLine parse_command_line(int argc, const char* const* argv);

}  // namespace hardsphere::cli
